// The velocity change of one sweep, one contact node per invocation (twin:
// `kernels::contact_apply`): each node's `apply_node`. The node gathers, so no two
// invocations write one velocity. Invocation 0 also applies the iteration's stopping rule
// after the sweep (twin: `kernels::sweep_control`; its inputs, the sweep's violation and
// count, are final when this dispatch starts). After a sweep that did not run (the
// iteration had stopped) the apply exits at once. params.aux: the pairs.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(3) var<storage, read> links: array<u32>;
@group(0) @binding(4) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(5) var<storage, read> starts: array<u32>;
@group(0) @binding(6) var<storage, read> sorted: array<u32>;
@group(0) @binding(7) var<storage, read> dj: array<f32>;
@group(0) @binding(8) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(9) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(10) var<storage, read_write> state: array<u32, 8>;

// include: velocity
// include: apply_node
// include: phase_after
// include: stopping_rule

@compute @workgroup_size(64)
fn contact_apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    // written by the sweep before this dispatch: the same for every invocation
    if (state[STATE_SWEPT] == 0u) {
        return;
    }
    let i = item_index(gid, params);
    if (i == 0u) {
        stopping_rule();
    }
    if (i < params.count) {
        apply_node(i, params.aux);
    }
}
