//! The impulse changes of a sweep on each rigid body (CPU twin of
//! `shaders/body_gather.wgsl`): for each body range of `links` (which starts with the number
//! of ranges and each range's first and end pair), the sum over its pairs of their impulse
//! changes times the body's shape function (1 in reach, 0 out), written after the pairs'
//! own impulse changes, where [`super::contact_apply`] takes it for the body's node.

use super::contact_constraints::Constraint;

/// The rigid body ranges of `links`: each range's pairs.
pub fn body_ranges(links: &[u32]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    let count = links.first().copied().unwrap_or(0) as usize;
    (0..count).map(move |r| links[1 + 2 * r] as usize..links[2 + 2 * r] as usize)
}

/// Writes each range's gathered impulse change at `dj[3 (np + r)..]`, `np` the pairs.
pub fn body_gather(links: &[u32], constraints: &[Constraint], dj: &mut [f64]) {
    let np = constraints.len();
    let sums: Vec<[f64; 3]> = body_ranges(links)
        .map(|range| {
            let mut s = [0.0; 3];
            for q in range {
                for (a, s) in s.iter_mut().enumerate() {
                    *s += constraints[q].weights[0] * dj[3 * q + a];
                }
            }
            s
        })
        .collect();
    for (r, s) in sums.iter().enumerate() {
        dj[3 * (np + r)..3 * (np + r) + 3].copy_from_slice(s);
    }
}
