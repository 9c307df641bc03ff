// Three values per listed node written into a nodal array, one listed node per invocation
// (twin: `kernels::node_scatter`): nodal[3 n..3 n + 3] = values[3 i..3 i + 3] for
// n = nodes[i]. A rank of a decomposed run writes so the sums of its shared nodes' corners
// (its own and its neighbours', added on the host in the global corner order) over the node
// gather's sums of its own corners, and the velocities the contact iteration on the
// surfaces gave the surface nodes it holds.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<u32>;
@group(0) @binding(2) var<storage, read> values: array<f32>;
@group(0) @binding(3) var<storage, read_write> nodal: array<f32>;

@compute @workgroup_size(64)
fn node_scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let n = nodes[i];
    nodal[3u * n] = values[3u * i];
    nodal[3u * n + 1u] = values[3u * i + 1u];
    nodal[3u * n + 2u] = values[3u * i + 2u];
}
