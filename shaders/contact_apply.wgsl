// The velocity change of one sweep, one contact node per invocation (twin:
// `kernels::contact_apply`): the impulse changes of the pairs it is the secondary node of,
// minus N_k times those of the pairs on each primary face whose corner k it is, times its
// inverse mass. The node gathers, so no two invocations write one velocity. Dispatched
// indirectly, as `contact_sweep`.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(2) var<storage, read> links: array<u32>;
@group(0) @binding(3) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(4) var<storage, read> starts: array<u32>;
@group(0) @binding(5) var<storage, read> sorted: array<u32>;
@group(0) @binding(6) var<storage, read> dj: array<f32>;
@group(0) @binding(7) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(8) var<storage, read_write> velocity: array<f32>;

// #import contact_apply_node

@compute @workgroup_size(64)
fn contact_apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i < params.count) {
        apply_node(i);
    }
}
