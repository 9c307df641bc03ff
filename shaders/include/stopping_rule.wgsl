// included by kernels that bind `step: Step` and `state: array<u32, 8>` (read_write), and
// include `phase_after.wgsl`

// The stopping rule after a sweep (twin: `kernels::sweep_control`; its input, the sweep's
// largest violation, is final): it counts the sweep, sets the phase (`phase_after`) and
// clears the violation for the next sweep.
fn stopping_rule() {
    let sweeps = state[STATE_SWEEPS] + 1u;
    state[STATE_SWEEPS] = sweeps;
    state[STATE_PHASE] = phase_after(sweeps, state[STATE_VIOLATION]);
    state[STATE_VIOLATION] = 0u;
}
