//! `[[fix]]`es with a `displacement`: held components moved along a path in time, the
//! displacement times an amplitude (a deck's `*BOUNDARY` with a value).

use super::loads::Amplitude;

/// The held dofs a fix moves by a displacement: each dof's displacement at full amplitude,
/// by increasing dof, and the amplitude.
#[derive(Debug, Clone, PartialEq)]
pub struct FixPath {
    pub dofs: Vec<u32>,
    pub value: Vec<f64>,
    pub amplitude: Amplitude,
}

impl FixPath {
    /// The held `components` of `nodes` moved to `value` times `amplitude` (none: a ramp
    /// from 0 at t = 0 to 1 at `end_time`); components with a zero displacement stay held
    /// still.
    pub fn new(
        nodes: &[u32],
        components: [bool; 3],
        value: [f64; 3],
        amplitude: &[[f64; 2]],
        end_time: f64,
    ) -> FixPath {
        let mut dofs = Vec::new();
        let mut values = Vec::new();
        let mut sorted = nodes.to_vec();
        sorted.sort_unstable();
        for n in sorted {
            for a in (0..3).filter(|&a| components[a]) {
                dofs.push(3 * n + a as u32);
                values.push(value[a]);
            }
        }
        let points = match amplitude.is_empty() {
            true => vec![[0.0, 0.0], [end_time, 1.0]],
            false => amplitude.to_vec(),
        };
        FixPath {
            dofs,
            value: values,
            amplitude: Amplitude { points },
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
        let a = self.amplitude.at(t + dt);
        for (&d, &value) in self.dofs.iter().zip(&self.value) {
            if let Some(l) = local(d as usize) {
                let old = v[l];
                v[l] = (value * a - u[l]) / dt;
                each(l, old, v[l]);
            }
        }
    }
}
