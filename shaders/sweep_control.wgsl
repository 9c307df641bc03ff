// The start of the contact iteration, one invocation before its first sweep (twin:
// `kernels::sweep_control`): it starts the sweeps and arms the first sweep's grid
// (params.aux, params.aux2: its width and height; entry 0 of the even sweeps' `args`), or,
// with no pair in reach, stops at once (0 sweeps, as the host path) and leaves the grid
// empty. After each sweep `contact_apply` applies the stopping rule (its `stopping_rule`).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> state: array<u32, 4>;
@group(0) @binding(2) var<storage, read_write> args: array<u32>;

@compute @workgroup_size(1)
fn sweep_control() {
    if (state[STATE_PHASE] == 0u) {
        let sweeping = state[STATE_ACTIVE] != 0u;
        state[STATE_PHASE] = select(2u, 1u, sweeping);
        if (sweeping) {
            args[0] = params.aux;
            args[1] = params.aux2;
            args[2] = 1u;
        }
    }
}
