//! CPU twin of `shaders/damage_reduce.wgsl`: the step's energy dissipated by damage, the sums
//! of every damageable element's dissipation and of its fibre share (on the device, words 3
//! and 4 of each element's record after the step counter; here the values themselves).

use crate::material::damage::Dissipation;

/// The sum of the damageable elements' dissipations over the step.
pub fn damage_reduce(dissipated: &[Dissipation]) -> Dissipation {
    dissipated.iter().copied().sum()
}
