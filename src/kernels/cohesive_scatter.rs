//! CPU twin of `shaders/cohesive_scatter.wgsl`: each bonded node's share of the cohesive
//! pairs' forces, one node per invocation, added to one of its element corners' forces
//! (after the element and damage kernels, before the gather, which then sums it into the
//! node's force). The node sums its pairs' forces in the order of its list: plus a pair's
//! force where it is the pair's upper node, minus where it is the lower. Each node writes
//! its own corner, so the sums do not depend on the order of the invocations.

use std::collections::BTreeMap;

use super::cohesive_pairs::{CohesiveSetup, PairOutput};
use super::node_gather::Incidence;

/// The flag of a link to a pair whose lower node the node is.
pub const LOWER: u32 = 1 << 31;

/// A bonded node: the corner id (twins' slot) its pairs' forces are added to, and its links
/// `links[first..end]` (a pair's number, with [`LOWER`] where the node is its lower node).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BondedNode {
    pub node: u32,
    pub corner: u32,
    pub first: u32,
    pub end: u32,
}

/// The bonded nodes in node order and their links.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BondedNodes {
    pub nodes: Vec<BondedNode>,
    pub links: Vec<u32>,
}

impl BondedNodes {
    /// The nodes of `setup`'s pairs, each with the first corner of its incidence list.
    pub fn new(setup: &CohesiveSetup, incidence: &Incidence) -> Self {
        let mut own: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for (p, pair) in setup.pairs.iter().enumerate() {
            own.entry(pair.upper).or_default().push(p as u32);
            own.entry(pair.lower).or_default().push(p as u32 | LOWER);
        }
        let mut s = BondedNodes::default();
        for (node, links) in own {
            let first = s.links.len() as u32;
            s.links.extend(links);
            s.nodes.push(BondedNode {
                node,
                corner: incidence.corners[incidence.offsets[node as usize] as usize],
                first,
                end: s.links.len() as u32,
            });
        }
        s
    }
}

/// Adds each bonded node's pairs' forces (`out`, [`super::cohesive_pairs`]) to its corner in
/// `corner_forces` (by corner id).
pub fn cohesive_scatter(bonded: &BondedNodes, out: &[PairOutput], corner_forces: &mut [[f64; 3]]) {
    for b in &bonded.nodes {
        let mut f = [0.0; 3];
        for &link in &bonded.links[b.first as usize..b.end as usize] {
            let p = (link & !LOWER) as usize;
            let sign = if link & LOWER != 0 { -1.0 } else { 1.0 };
            for a in 0..3 {
                f[a] += sign * out[p].force[a];
            }
        }
        for a in 0..3 {
            corner_forces[b.corner as usize][a] += f[a];
        }
    }
}
