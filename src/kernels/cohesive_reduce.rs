//! CPU twin of `shaders/cohesive_reduce.wgsl`: each cohesive interface's history values of
//! a step, one workgroup per interface: its separated area (pairs at damage 1), its damaged
//! area (damage above 0), and the sums of its pairs' dissipation and stored-energy offset
//! over the step ([`super::cohesive_pairs`]'s outputs), [`COHESIVE_COLUMNS`] values.

use super::cohesive_pairs::{CohesiveSetup, PairOutput, PairState};

/// Values per interface in a history row.
pub const COHESIVE_COLUMNS: usize = 4;

/// Each interface's values after a step: separated area, damaged area, dissipation and
/// offset.
pub fn cohesive_reduce(
    setup: &CohesiveSetup,
    state: &[PairState],
    out: &[PairOutput],
) -> Vec<[f64; COHESIVE_COLUMNS]> {
    (setup.interfaces.iter())
        .map(|r| {
            let mut v = [0.0; COHESIVE_COLUMNS];
            for p in r.clone() {
                let (a, d) = (setup.pairs[p].area, state[p].damage);
                v[0] += if d >= 1.0 { a } else { 0.0 };
                v[1] += if d > 0.0 { a } else { 0.0 };
                v[2] += out[p].dissipated;
                v[3] += out[p].offset;
            }
            v
        })
        .collect()
}
