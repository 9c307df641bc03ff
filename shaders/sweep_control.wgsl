// The stopping rule of the contact iteration, one invocation after each sweep and once
// before the first (twin: `kernels::sweep_control`). Before the first sweep (phase 0) it
// loads the sweep and apply grids from `full` into the indirect arguments `args`, or, with
// no pair in reach, stops at once (0 sweeps, as the host path). After a sweep it counts it,
// stops (converged) when the sweep's violation is within the tolerance or (not converged) at
// the sweep limit, and resets the violation. A stopped iteration empties both grids, so the
// sweeps recorded after it do no work (each still costs a dispatch). params.aux: the sweep
// limit; params.aux2: the tolerance (f32 bits).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> state: array<u32, 4>;
@group(0) @binding(2) var<storage, read_write> args: array<u32, 6>;
@group(0) @binding(3) var<storage, read> full: array<u32, 6>;

fn stop(phase: u32) {
    state[STATE_PHASE] = phase;
    for (var k = 0u; k < 6u; k++) {
        args[k] = select(1u, 0u, k % 3u == 0u);
    }
}

@compute @workgroup_size(1)
fn sweep_control() {
    let phase = state[STATE_PHASE];
    if (phase == 0u) {
        if (state[STATE_ACTIVE] == 0u) {
            stop(2u);
        } else {
            state[STATE_PHASE] = 1u;
            for (var k = 0u; k < 6u; k++) {
                args[k] = full[k];
            }
        }
        return;
    }
    if (phase != 1u) {
        return;
    }
    let sweeps = state[STATE_SWEEPS] + 1u;
    state[STATE_SWEEPS] = sweeps;
    if (bitcast<f32>(state[STATE_VIOLATION]) <= bitcast<f32>(params.aux2)) {
        stop(2u);
    } else if (sweeps >= params.aux) {
        stop(3u);
    }
    state[STATE_VIOLATION] = 0u;
}
