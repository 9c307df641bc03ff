// The values of listed nodes packed, one listed node per invocation (twin:
// `kernels::node_select`): selected[w i..w i + w] = nodal[w n..w n + w] for n = nodes[i],
// w = params.aux values per node (3 for a velocity, 6 for a split displacement's hi and lo).
// A rank of a decomposed run reads back so the state of the surface nodes it owns, for the
// contact iteration on the surfaces.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<u32>;
@group(0) @binding(2) var<storage, read> nodal: array<f32>;
@group(0) @binding(3) var<storage, read_write> selected: array<f32>;

@compute @workgroup_size(64)
fn node_select(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let w = params.aux;
    let n = nodes[i];
    for (var k = 0u; k < w; k++) {
        selected[w * i + k] = nodal[w * n + k];
    }
}
