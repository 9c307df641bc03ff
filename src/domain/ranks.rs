//! What a decomposed run asks of its ranks: point-to-point exchange with the neighbours and
//! a few collectives. [`Single`] is one process on its own; the MPI ranks are in
//! `domain::mpi` (the `mpi` feature).

/// The communication of a decomposed run. Every rank calls each collective at the same
/// point of the run.
pub trait Ranks {
    fn rank(&self) -> usize;
    fn size(&self) -> usize;
    /// This process's index among the job's processes on its machine (it picks the
    /// machine's GPU of a rank that computes on one).
    fn local_rank(&self) -> usize;
    /// Sends `sends[i].1` to rank `sends[i].0` and receives from each rank `recvs[i].0`
    /// into `recvs[i].1` (whose length the receiver knows); the pairs match by rank.
    fn exchange(&self, sends: &[(usize, &[f64])], recvs: &mut [(usize, &mut [f64])]);
    /// Every rank's `mine`, one after the other in rank order, into `out` (`counts` holds
    /// each rank's length).
    fn all_gather(&self, mine: &[f64], counts: &[usize], out: &mut [f64]);
    /// Every rank's `mine`, one after the other in rank order, into rank 0's `out` (`counts`
    /// holds each rank's length; the other ranks' `out` is left as it is).
    fn gather_to_first(&self, mine: &[f64], counts: &[usize], out: &mut [f64]);
    /// The largest `x` over the ranks.
    fn max(&self, x: f64) -> f64;
    /// Every rank's `x` (the same length on each), in rank order.
    fn gather_all(&self, x: &[f64]) -> Vec<Vec<f64>> {
        let n = x.len();
        let mut out = vec![0.0; n * self.size()];
        self.all_gather(x, &vec![n; self.size()], &mut out);
        out.chunks(n.max(1))
            .map(|c| c.to_vec())
            .take(self.size())
            .collect()
    }
    /// Every rank's `mine`, of any length, one after the other in rank order, with each
    /// rank's length (the lengths are gathered first).
    fn gather_varied(&self, mine: &[f64]) -> (Vec<usize>, Vec<f64>) {
        let counts = self.lengths(mine);
        let mut all = vec![0.0; counts.iter().sum()];
        self.all_gather(mine, &counts, &mut all);
        (counts, all)
    }
    /// [`Ranks::gather_varied`] on rank 0 only (`None` on the others).
    fn gather_varied_to_first(&self, mine: &[f64]) -> Option<Vec<f64>> {
        let counts = self.lengths(mine);
        let first = self.rank() == 0;
        let mut all = vec![0.0; if first { counts.iter().sum() } else { 0 }];
        self.gather_to_first(mine, &counts, &mut all);
        first.then_some(all)
    }
    /// Every rank's length of `mine`, in rank order.
    fn lengths(&self, mine: &[f64]) -> Vec<usize> {
        (self.gather_all(&[mine.len() as f64]).iter())
            .map(|c| c[0] as usize)
            .collect()
    }
    /// Every rank's `text`, in rank order.
    fn gather_text(&self, text: &str) -> Vec<String> {
        let mine: Vec<f64> = text.bytes().map(f64::from).collect();
        let (counts, all) = self.gather_varied(&mine);
        let mut at = 0;
        (counts.iter())
            .map(|&c| {
                let bytes: Vec<u8> = all[at..at + c].iter().map(|&b| b as u8).collect();
                at += c;
                String::from_utf8_lossy(&bytes).into_owned()
            })
            .collect()
    }
    /// The sum over the ranks of `x` (the same length on each), added in rank order, so
    /// every rank has the same bits.
    fn sum(&self, x: &[f64]) -> Vec<f64> {
        let mut s = vec![0.0; x.len()];
        for part in self.gather_all(x) {
            for (s, p) in s.iter_mut().zip(part) {
                *s += p;
            }
        }
        s
    }
}

/// `mine`, the outcome of a stage that may fail on some ranks only, once every rank's is
/// known: `Ok` on every rank where every rank succeeded, else on every rank the failed
/// ranks' messages ("rank k of P: ..."), so that no rank goes on to wait for one that
/// stopped.
pub fn agree<T, E: std::fmt::Display>(
    ranks: &dyn Ranks,
    mine: std::result::Result<T, E>,
) -> std::result::Result<T, String> {
    let all = ranks.gather_text(&mine.as_ref().err().map_or(String::new(), E::to_string));
    let failed: Vec<String> = (all.iter().enumerate())
        .filter(|(_, m)| !m.is_empty())
        .map(|(r, m)| format!("rank {r} of {}: {m}", ranks.size()))
        .collect();
    match mine {
        Ok(t) if failed.is_empty() => Ok(t),
        _ => Err(failed.join("; ")),
    }
}

/// The ranks with a clock: the seconds spent in their calls, waiting included.
pub(crate) struct Timed<'a> {
    pub ranks: &'a dyn Ranks,
    pub seconds: &'a std::cell::Cell<f64>,
}

impl Timed<'_> {
    /// `f` on the ranks, its time counted.
    pub fn talk<T>(&self, f: impl FnOnce(&dyn Ranks) -> T) -> T {
        let t = std::time::Instant::now();
        let out = f(self.ranks);
        self.seconds
            .set(self.seconds.get() + t.elapsed().as_secs_f64());
        out
    }
}

/// One process: a run of one rank.
pub struct Single;

impl Ranks for Single {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        1
    }
    fn local_rank(&self) -> usize {
        0
    }
    fn exchange(&self, sends: &[(usize, &[f64])], _recvs: &mut [(usize, &mut [f64])]) {
        debug_assert!(sends.is_empty(), "one rank has no neighbours");
    }
    fn all_gather(&self, mine: &[f64], _counts: &[usize], out: &mut [f64]) {
        out[..mine.len()].copy_from_slice(mine);
    }
    fn gather_to_first(&self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        self.all_gather(mine, counts, out);
    }
    fn max(&self, x: f64) -> f64 {
        x
    }
}
