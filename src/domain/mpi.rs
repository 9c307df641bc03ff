//! The ranks of an MPI job (the `mpi` feature): rsmpi on the system's MPI library.

use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use super::ranks::Ranks;

/// The processes of `MPI_COMM_WORLD`.
pub struct MpiRanks {
    world: SimpleCommunicator,
    /// The rank among the processes that share this one's memory (`MPI_Comm_split_type`
    /// with `MPI_COMM_TYPE_SHARED`, ordered by world rank).
    local: usize,
}

impl MpiRanks {
    pub fn new(world: SimpleCommunicator) -> Self {
        let local = world.split_shared(world.rank()).rank() as usize;
        MpiRanks { world, local }
    }
}

impl Ranks for MpiRanks {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn local_rank(&self) -> usize {
        self.local
    }

    fn exchange(&self, sends: &[(usize, &[f64])], recvs: &mut [(usize, &mut [f64])]) {
        mpi::request::scope(|scope| {
            let mut pending = Vec::with_capacity(sends.len() + recvs.len());
            for (rank, buf) in recvs.iter_mut() {
                let p = self.world.process_at_rank(*rank as i32);
                pending.push(p.immediate_receive_into(scope, &mut **buf));
            }
            for (rank, buf) in sends {
                let p = self.world.process_at_rank(*rank as i32);
                pending.push(p.immediate_send(scope, *buf));
            }
            for r in pending {
                r.wait();
            }
        });
    }

    fn all_gather(&self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        let (counts, displs) = counts_and_displacements(counts);
        let mut partition = PartitionMut::new(out, &counts[..], &displs[..]);
        self.world.all_gather_varcount_into(mine, &mut partition);
    }

    fn gather_to_first(&self, mine: &[f64], counts: &[usize], out: &mut [f64]) {
        let root = self.world.process_at_rank(0);
        if self.world.rank() != 0 {
            root.gather_varcount_into(mine);
            return;
        }
        let (counts, displs) = counts_and_displacements(counts);
        let mut partition = PartitionMut::new(out, &counts[..], &displs[..]);
        root.gather_varcount_into_root(mine, &mut partition);
    }

    fn max(&self, x: f64) -> f64 {
        let mut m = 0.0;
        self.world
            .all_reduce_into(&x, &mut m, SystemOperation::max());
        m
    }
}

/// MPI's counts and the displacements of each rank's part, one after the other.
fn counts_and_displacements(counts: &[usize]) -> (Vec<i32>, Vec<i32>) {
    let counts: Vec<i32> = counts.iter().map(|&c| c as i32).collect();
    let displs: Vec<i32> = (counts.iter())
        .scan(0, |at, &c| {
            let d = *at;
            *at += c;
            Some(d)
        })
        .collect();
    (counts, displs)
}
