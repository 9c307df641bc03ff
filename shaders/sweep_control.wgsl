// The start of the contact iteration, one invocation before its first sweep (twin:
// `kernels::sweep_control`): it starts the sweeps, or, with no pair in reach, stops at once
// (0 sweeps, as the host path). After each sweep `contact_apply` applies the stopping rule
// (its `stopping_rule`).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> state: array<u32, 8>;

@compute @workgroup_size(1)
fn sweep_control() {
    // every kernel binds its launch parameters at binding 0; this one needs none of them
    _ = params;
    if (state[STATE_PHASE] == 0u) {
        state[STATE_PHASE] = select(2u, 1u, state[STATE_ACTIVE] != 0u);
    }
}
