// The velocity change of one sweep, one contact node per invocation (twin:
// `kernels::contact_apply`): each node's `apply_node`. The node gathers, so no two
// invocations write one velocity. Invocation 0 also applies the iteration's stopping rule
// after the sweep (twin: `kernels::sweep_control`; its inputs, the sweep's violation and
// count, are final when this dispatch starts) and, while the iteration sweeps on, arms the
// grid of the next sweep and apply (params.aux, params.aux2: its width and height) at its
// entry of `next_args`: sweep k + 1's entry is entry (k + 1) / 2 of the buffer of its
// parity, which the host cleared before the iteration. Dispatched indirectly from its own
// entry, so once the iteration has stopped the sweeps recorded after it are empty.

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
@group(0) @binding(10) var<storage, read_write> state: array<u32, 4>;
@group(0) @binding(11) var<storage, read_write> next_args: array<u32>;

// include: velocity
// include: apply_node

@compute @workgroup_size(64)
fn contact_apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i == 0u && stopping_rule()) {
        let e = 3u * (state[STATE_SWEEPS] / 2u);
        next_args[e] = params.aux;
        next_args[e + 1u] = params.aux2;
        next_args[e + 2u] = 1u;
    }
    if (i < params.count) {
        apply_node(i);
    }
}
