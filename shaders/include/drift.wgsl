// included by kernels that bind `step: Step` and `displacement: array<Split3>` (read_write)

// (hi, lo) + d renormalised, componentwise: hi the f32 nearest the sum, lo the rest.
fn split_add(u: Split3, d: vec3<f32>) -> Split3 {
    let hi = vec3_of(u.hi);
    let s = hi + d;
    let bp = s - hi;
    let err = (hi - (s - bp)) + (d - bp);
    let l = vec3_of(u.lo) + err;
    let h2 = s + l;
    return Split3(float3(h2), float3(l - (h2 - s)));
}

// Node n's position update at its v_{n+1/2} `v` (twin: `kernels::explicit_drift`):
// u_{n+1} = u_n + dt v, the increment added to the split pair by two-sum, so that u keeps
// ~14 digits over many small steps (an f32 sum would lose the increments' last digits at
// every step).
fn drift_by(n: u32, v: vec3<f32>) {
    displacement[n] = split_add(displacement[n], step.dt * v);
}
