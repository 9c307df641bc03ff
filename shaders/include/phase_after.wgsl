// included by kernels that bind `step: Step`

// The phase after the iteration's sweep number `sweeps`, whose largest violation is
// `violation` (f32 bits): 2 converged within step.tolerance, 3 stopped unconverged at
// step.max_iterations sweeps, or 1 sweeping on (twin: `kernels::sweep_control`).
fn phase_after(sweeps: u32, violation: u32) -> u32 {
    if (bitcast<f32>(violation) <= step.tolerance) {
        return 2u;
    } else if (sweeps >= step.max_iterations) {
        return 3u;
    }
    return 1u;
}
