// The warm start's velocity change, one contact node per invocation (twin:
// `kernels::contact_warm`), after `contact_compliance` and before the first sweep: each
// node's `apply_node` of the impulse changes `contact_compliance` set to the pairs' warm
// start impulses (and, on a rigid body's node, the body's gather of them by `body_gather`).
// With no pair in reach (the iteration stopped at its start) it exits at once. Each node's
// velocity after it also goes into slot 1 of `carried` (3 per contact node a slot), where
// `contact_relax` takes it up. params.aux: the pairs.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(2) var<storage, read> links: array<u32>;
@group(0) @binding(3) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(4) var<storage, read> starts: array<u32>;
@group(0) @binding(5) var<storage, read> sorted: array<u32>;
@group(0) @binding(6) var<storage, read> dj: array<f32>;
@group(0) @binding(7) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(8) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(9) var<storage, read> state: array<u32, 8>;
@group(0) @binding(10) var<storage, read_write> carried: array<f32>;

// include: velocity
// include: apply_node

@compute @workgroup_size(64)
fn contact_warm(@builtin(global_invocation_id) gid: vec3<u32>) {
    // written by contact_compliance before this dispatch: the same for every invocation
    if (state[STATE_PHASE] != 1u) {
        return;
    }
    let i = item_index(gid, params);
    if (i < params.count) {
        apply_node(i, params.aux);
        let n = nodes[i].node;
        let o = 3u * (params.count + i);
        carried[o] = velocity[3u * n];
        carried[o + 1u] = velocity[3u * n + 1u];
        carried[o + 2u] = velocity[3u * n + 2u];
    }
}
