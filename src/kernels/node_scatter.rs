//! CPU twin of `shaders/node_scatter.wgsl`: three values per listed node written into a
//! nodal array (a rank's shared nodes' force sums over the gathered forces, or the surface
//! nodes' velocities after the contact iteration).

/// `nodal[3 n..3 n + 3] = values[i]` for each listed node `n = nodes[i]`.
pub fn node_scatter(nodes: &[u32], values: &[[f64; 3]], nodal: &mut [f64]) {
    for (&n, x) in nodes.iter().zip(values) {
        nodal[3 * n as usize..3 * n as usize + 3].copy_from_slice(x);
    }
}
