// The row-sum bound's weight on each node of the contact iteration, one contact node per
// invocation (twin: `kernels::contact_touches`): the number of in-reach pairs it is the
// secondary node of, plus, for each primary face corner k it is, the shape function values
// |N_k| of the in-reach pairs on that face (bucket f holds sorted[starts[f]..starts[f + 1]]),
// plus the in-reach pairs of each rigid body range it carries (weight 1; `links` starts with
// the number of ranges and each range's first and end pair).
// Also counts the pairs in reach into the iteration's state.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(2) var<storage, read> links: array<u32>;
@group(0) @binding(3) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(4) var<storage, read> starts: array<u32>;
@group(0) @binding(5) var<storage, read> sorted: array<u32>;
@group(0) @binding(6) var<storage, read_write> touches: array<f32>;
@group(0) @binding(7) var<storage, read_write> state: array<atomic<u32>, 8>;

// include: node_touches

@compute @workgroup_size(64)
fn contact_touches(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let own = node_touches(i);
    if (own > 0u) {
        atomicAdd(&state[STATE_ACTIVE], own);
    }
}
