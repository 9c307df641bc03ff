//! CPU twin of `shaders/shared_forces.wgsl`: the shared nodes' internal forces of a rank of
//! a decomposed run, their sums over the rank's and the neighbours' corners in the global
//! corner order, written over the node gather's sums of the rank's corners alone.

/// `forces[3 n..3 n + 3] = sums[i]` for each shared node `n = shared_nodes[i]`.
pub fn shared_forces(shared_nodes: &[u32], sums: &[[f64; 3]], forces: &mut [f64]) {
    for (&n, s) in shared_nodes.iter().zip(sums) {
        forces[3 * n as usize..3 * n as usize + 3].copy_from_slice(s);
    }
}
