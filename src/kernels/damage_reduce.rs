//! CPU twin of `shaders/damage_reduce.wgsl`: the step's energy dissipated by damage, the sum
//! of every damageable element's dissipation (on the device, word 3 of each element's
//! record after the step counter; here the values themselves).

/// The sum of the damageable elements' dissipations over the step.
pub fn damage_reduce(dissipated: &[f64]) -> f64 {
    dissipated.iter().sum()
}
