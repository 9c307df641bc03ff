//! CPU twin of `shaders/node_gather.wgsl`: the nodal sum of element corner forces, in the
//! fixed order of each node's incidence list (so the GPU result is the same bits every run).

use rayon::prelude::*;

use crate::element::Elements;

/// For every node, the element corners that touch it, in CSR form, by corner id (the twins'
/// slot of [`crate::element::CornerLayout`]).
#[derive(Debug, Clone, Default)]
pub struct Incidence {
    /// `corners[offsets[n]..offsets[n + 1]]` belong to node n.
    pub offsets: Vec<u32>,
    pub corners: Vec<u32>,
}

impl Incidence {
    /// The incidence table of the elements over `nodes` nodes, corners in increasing order
    /// for each node.
    pub fn new(elements: &Elements, nodes: usize) -> Self {
        let corner_nodes = || elements.corner_nodes();
        let mut count = vec![0u32; nodes + 1];
        for n in corner_nodes() {
            count[n as usize + 1] += 1;
        }
        for n in 0..nodes {
            count[n + 1] += count[n];
        }
        let offsets = count.clone();
        let mut next = count;
        let mut corners = vec![0u32; elements.corner_count()];
        for (c, n) in corner_nodes().enumerate() {
            corners[next[n as usize] as usize] = c as u32;
            next[n as usize] += 1;
        }
        Incidence { offsets, corners }
    }

    pub fn nodes(&self) -> usize {
        self.offsets.len() - 1
    }
}

/// Nodal forces from the corner forces (overwrites `forces`).
pub fn node_gather(incidence: &Incidence, corner_forces: &[[f64; 3]], forces: &mut [[f64; 3]]) {
    let nodes = incidence.nodes();
    forces[..nodes]
        .par_iter_mut()
        .with_min_len(crate::parallel::CHUNK)
        .enumerate()
        .for_each(|(n, f)| {
            let mut sum = [0.0; 3];
            for &c in
                &incidence.corners[incidence.offsets[n] as usize..incidence.offsets[n + 1] as usize]
            {
                for a in 0..3 {
                    sum[a] += corner_forces[c as usize][a];
                }
            }
            *f = sum;
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_corner_appears_once_in_increasing_order() {
        let mut hexes = Elements::default();
        let hex8 = crate::element::ElementKind::Hex8;
        hexes.push(hex8, &[0, 1, 2, 3, 4, 5, 6, 7], 0);
        hexes.push(hex8, &[1, 8, 9, 2, 5, 10, 11, 6], 0);
        let inc = Incidence::new(&hexes, 12);
        let mut seen = inc.corners.clone();
        seen.sort();
        assert_eq!(seen, (0..16).collect::<Vec<u32>>());
        assert_eq!(
            &inc.corners[inc.offsets[1] as usize..inc.offsets[2] as usize],
            &[1, 8]
        );
        let corner: Vec<[f64; 3]> = (0..16).map(|c| [c as f64, 0.0, 1.0]).collect();
        let mut f = vec![[0.0; 3]; 12];
        node_gather(&inc, &corner, &mut f);
        assert_eq!(f[1], [9.0, 0.0, 2.0]);
        assert_eq!(f[0], [0.0, 0.0, 1.0]);
    }
}
