// The element corner forces of chosen corner slots, packed three floats per entry, so that a
// rank of a decomposed run reads back only the corners of the nodes it shares
// (twin: `kernels::corner_select`). The corner forces are component-major (see
// `hex8_forces.wgsl`): component a of corner slot s at corner_forces[a C + s], C = params.aux.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> slots: array<u32>;
@group(0) @binding(2) var<storage, read> corner_forces: array<f32>;
@group(0) @binding(3) var<storage, read_write> chosen: array<f32>;

@compute @workgroup_size(64)
fn corner_select(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let c = params.aux;
    let s = slots[i];
    chosen[3u * i] = corner_forces[s];
    chosen[3u * i + 1u] = corner_forces[c + s];
    chosen[3u * i + 2u] = corner_forces[2u * c + s];
}
