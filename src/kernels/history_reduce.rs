//! One history row of the explicit step from the corrector's partial sums, the plane contact
//! results, the probe nodes and the supports' corner forces (CPU twin of
//! `shaders/history_reduce.wgsl`).

/// Sum of the corrector's workgroup partials.
pub(crate) const OP_PARTIALS: u32 = 0;
/// Sum of plane contact results.
pub(crate) const OP_SUM: u32 = 1;
/// Largest plane contact result, and zero.
pub(crate) const OP_MAX: u32 = 2;
/// Displacement component `first` (3 node + axis).
pub(crate) const OP_DISPLACEMENT: u32 = 3;
/// Velocity component `first`.
pub(crate) const OP_VELOCITY: u32 = 4;
/// Sum of the corner forces at the indices `lists[first + k]` (component-major: component a
/// of corner slot s at `a C + s`): a support's reaction.
pub(crate) const OP_CORNERS: u32 = 5;

/// One value: `op` over `count` entries `first + k stride` of its source.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReduceColumn {
    pub first: u32,
    pub count: u32,
    pub stride: u32,
    pub op: u32,
}

pub fn history_reduce(
    columns: &[ReduceColumn],
    partials: &[f64],
    results: &[f64],
    (u, v): (&[f64], &[f64]),
    (corners, lists): (&[f64], &[u32]),
) -> Vec<f64> {
    columns
        .iter()
        .map(|c| {
            let at = |k: u32| (c.first + k * c.stride) as usize;
            match c.op {
                OP_PARTIALS => (0..c.count).map(|k| partials[at(k)]).sum(),
                OP_SUM => (0..c.count).map(|k| results[at(k)]).sum(),
                OP_MAX => (0..c.count).map(|k| results[at(k)]).fold(0.0, f64::max),
                OP_DISPLACEMENT => (0..c.count).map(|k| u[at(k)]).sum(),
                OP_CORNERS => (0..c.count).map(|k| corners[lists[at(k)] as usize]).sum(),
                _ => (0..c.count).map(|k| v[at(k)]).sum(),
            }
        })
        .collect()
}
