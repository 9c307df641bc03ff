//! `[[fix]]`es with a `displacement`: held components moved along a path in time (a deck's
//! `*BOUNDARY` with a value). A path is the displacement times an amplitude, or, for a
//! step's fix without an amplitude, a ramp from wherever the components are when the step
//! begins to the displacement at the step's end.

use super::loads::Amplitude;

/// How a path's dofs reach their displacement.
#[derive(Debug, Clone, PartialEq)]
pub enum PathShape {
    /// The displacement times the amplitude at each time.
    Scaled(Amplitude),
    /// From the displacement at the start of the step straight to the full displacement at
    /// time `end`, held after it. Each increment covers its share of what remains, so the
    /// path needs no record of where it began (a resumed run follows it too).
    RampTo { end: f64 },
}

/// The held dofs a fix moves by a displacement: each dof's displacement at full amplitude,
/// by increasing dof, and how it gets there.
#[derive(Debug, Clone, PartialEq)]
pub struct FixPath {
    pub dofs: Vec<u32>,
    pub value: Vec<f64>,
    pub shape: PathShape,
}

impl FixPath {
    /// The dofs `dofs` (each with its displacement at full amplitude) moved along `shape`.
    pub fn new(mut dofs: Vec<(u32, f64)>, shape: PathShape) -> FixPath {
        dofs.sort_unstable_by_key(|d| d.0);
        FixPath {
            dofs: dofs.iter().map(|d| d.0).collect(),
            value: dofs.iter().map(|d| d.1).collect(),
            shape,
        }
    }

    /// The displacement at `t1` of a dof whose displacement at full amplitude is `value` and
    /// which is at `u0` at `t0` (on the path).
    pub fn at(&self, value: f64, (t0, t1): (f64, f64), u0: f64) -> f64 {
        match &self.shape {
            PathShape::Scaled(a) => value * a.at(t1),
            // within a hair of the end (rounding of the step sums): the end itself
            PathShape::RampTo { end } if end - t1 <= 1e-9 * end.abs().max(t1 - t0) => value,
            PathShape::RampTo { end } => u0 + (value - u0) * (t1 - t0) / (end - t0),
        }
    }

    /// Sets each moved dof's velocity in `v` (3 per node, numbered by `local`: the dof of a
    /// model dof, `None` where it is not held here) so that a step of `dt` from `u` ends on
    /// the path at `t + dt`; `each` sees every dof set, with its velocity before and after.
    pub fn drive(
        &self,
        (t, dt): (f64, f64),
        u: &[f64],
        v: &mut [f64],
        local: impl Fn(usize) -> Option<usize>,
        mut each: impl FnMut(usize, f64, f64),
    ) {
        for (&d, &value) in self.dofs.iter().zip(&self.value) {
            if let Some(l) = local(d as usize) {
                let old = v[l];
                v[l] = (self.at(value, (t, t + dt), u[l]) - u[l]) / dt;
                each(l, old, v[l]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp followed increment by increment, of any lengths, from anywhere on it, lands
    /// where the straight line from its start does, and at the end exactly.
    #[test]
    fn ramp_increments_follow_the_line() {
        let path = FixPath::new(vec![(0, 2.0)], PathShape::RampTo { end: 3.0 });
        let (start, u_start) = (1.0, 0.5);
        let line = |t: f64| u_start + (2.0 - u_start) * (t - start) / (3.0 - start);
        let mut u = u_start;
        let mut t = start;
        for h in [0.1, 0.35, 0.05, 0.5, 0.2, 0.3, 0.5] {
            u = path.at(2.0, (t, t + h), u);
            t += h;
            assert!(
                (u - line(t)).abs() < 1e-14,
                "t = {t}: {u} against {}",
                line(t)
            );
        }
        assert_eq!(path.at(2.0, (t, t + 1.0), u), 2.0);
    }
}
