//! CPU twin of `shaders/node_select.wgsl`: the values of listed nodes packed (a rank's
//! surface nodes' state, read back for the contact iteration on the surfaces).

/// `selected[w i..w i + w] = nodal[w n..w n + w]` for each listed node `n = nodes[i]`,
/// `w = width` values per node.
pub fn node_select(nodes: &[u32], width: usize, nodal: &[f64], selected: &mut [f64]) {
    for (i, &n) in nodes.iter().enumerate() {
        let n = n as usize;
        selected[width * i..width * (i + 1)].copy_from_slice(&nodal[width * n..width * (n + 1)]);
    }
}
