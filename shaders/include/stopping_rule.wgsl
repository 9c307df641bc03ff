// included by kernels that bind `step: Step` and `state: array<u32, 8>` (read_write)

// The stopping rule after a sweep (twin: `kernels::sweep_control`; its input, the sweep's
// largest violation, is final): it counts the sweep and sets the phase, 2 converged within
// step.tolerance, 3 stopped unconverged at step.max_iterations sweeps, or 1 sweeping on.
fn stopping_rule() {
    let sweeps = state[STATE_SWEEPS] + 1u;
    state[STATE_SWEEPS] = sweeps;
    var phase = 1u;
    if (bitcast<f32>(state[STATE_VIOLATION]) <= step.tolerance) {
        phase = 2u;
    } else if (sweeps >= step.max_iterations) {
        phase = 3u;
    }
    state[STATE_PHASE] = phase;
    state[STATE_VIOLATION] = 0u;
}
