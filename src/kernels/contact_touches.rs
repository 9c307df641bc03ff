//! The row-sum bound's weight on each node of the device contact iteration (CPU twin of
//! `shaders/contact_touches.wgsl`): the in-reach pairs a node is the secondary node of, plus
//! the shape function values $|N_k|$ of the in-reach pairs on each primary face whose corner
//! k it is, and the in-reach pairs of the interfaces whose rigid body it carries (the body's
//! one-node face, weight 1). Also the number of pairs in reach.

use super::contact_constraints::Constraint;

/// A node the contact iteration moves: the pairs it is the secondary node of,
/// `links[pair_first..pair_end]`, the face corners it is, `links[face_first..face_end]`
/// (each `4 face + corner`), and, where it carries a rigid body, the body's ranges,
/// `links[body_first..body_end]` (each a range's number: `links` starts with the number of
/// ranges and each range's first and end pair, one range per interface of the body).
///
/// A body takes its interfaces' pairs by range, not through the buckets by face: they are
/// many (every node of a coupon's face against a tup or a support), and
/// [`super::body_gather`] sums each range on a workgroup.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ContactNode {
    pub node: u32,
    pub pair_first: u32,
    pub pair_end: u32,
    pub face_first: u32,
    pub face_end: u32,
    pub body_first: u32,
    pub body_end: u32,
}

impl ContactNode {
    /// The pairs of the interfaces whose rigid body this node carries, in order.
    pub fn body_pairs<'a>(&self, links: &'a [u32]) -> impl Iterator<Item = usize> + 'a {
        let ranges: Vec<std::ops::Range<usize>> = super::body_gather::body_ranges(links).collect();
        links[self.body_first as usize..self.body_end as usize]
            .iter()
            .flat_map(move |&r| ranges[r as usize].clone())
    }
}

/// Writes `touches[node]` of every contact node; returns the pairs in reach. Bucket f of the
/// sort by face holds `sorted[starts[f]..starts[f + 1]]`.
pub fn contact_touches(
    nodes: &[ContactNode],
    links: &[u32],
    constraints: &[Constraint],
    starts: &[u32],
    sorted: &[u32],
    touches: &mut [f64],
) -> u32 {
    let mut active = 0;
    for cn in nodes {
        let own = links[cn.pair_first as usize..cn.pair_end as usize]
            .iter()
            .filter(|&&p| constraints[p as usize].in_reach)
            .count() as u32;
        let mut t = own as f64;
        for &l in &links[cn.face_first as usize..cn.face_end as usize] {
            let (f, k) = ((l / 4) as usize, (l % 4) as usize);
            for &q in &sorted[starts[f] as usize..starts[f + 1] as usize] {
                t += constraints[q as usize].weights[k].abs();
            }
        }
        for q in cn.body_pairs(links) {
            t += constraints[q].weights[0].abs();
        }
        touches[cn.node as usize] = t;
        active += own;
    }
    active
}
