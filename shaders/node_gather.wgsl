// Sum of the element corner forces at each node, in the fixed order of the node's incidence
// list, so that the same input gives the same bits on every run (twin: `kernels::node_gather`).
// The corner forces are component-major (see `hex8_forces.wgsl`): component a of corner
// slot s at corner_forces[a C + s], C = params.aux.

@group(0) @binding(0) var<uniform> params: Params;
// incidence[offsets[n]..offsets[n + 1]] are the corner slots that touch node n
@group(0) @binding(1) var<storage, read> offsets: array<u32>;
@group(0) @binding(2) var<storage, read> incidence: array<u32>;
@group(0) @binding(3) var<storage, read> corner_forces: array<f32>;
@group(0) @binding(4) var<storage, read_write> forces: array<f32>;

// include: gather_force

@compute @workgroup_size(64)
fn node_gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = item_index(gid, params);
    if (n >= params.count) {
        return;
    }
    let f = gather_force(n, params.aux);
    forces[3u * n] = f.x;
    forces[3u * n + 1u] = f.y;
    forces[3u * n + 2u] = f.z;
}
