// The internal forces of the nodes a rank of a decomposed run shares with its neighbours,
// one shared node per invocation (twin: `kernels::shared_forces`): each node's sum of its
// corners, the rank's and its neighbours', in the global corner order (summed on the host
// from the corners exchanged, `domain::subdomain`), written over the node gather's sum of
// the rank's corners alone.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> shared_nodes: array<u32>;
@group(0) @binding(2) var<storage, read> sums: array<f32>;
@group(0) @binding(3) var<storage, read_write> forces: array<f32>;

@compute @workgroup_size(64)
fn shared_forces(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let n = shared_nodes[i];
    forces[3u * n] = sums[3u * i];
    forces[3u * n + 1u] = sums[3u * i + 1u];
    forces[3u * n + 2u] = sums[3u * i + 2u];
}
