// included by kernels that bind `step: Step`, `constraints: array<Constraint>` (read_write),
// `pairs: array<ContactPair>`, `velocity: array<f32>` and `dj: array<f32>` (read_write), and
// include `velocity.wgsl`

// One pair's part of a projected Jacobi sweep (twin: `kernels::contact_sweep`): from the
// relative velocity at the sweep's start, the normal impulse moves by the residual of
// g_n + dt gdot <= 0 over the compliance and is kept >= 0; under a frictional law the
// tangential impulse that stops the slip is returned onto the law's set. Writes the pair's
// impulses and its impulse change dj[p] (zero for a pair out of reach or not enforceable)
// and returns its violation.
fn sweep_pair(p: u32) -> f32 {
    var d = vec3<f32>(0.0);
    var violation = 0.0;
    let c = constraints[p];
    if (c.in_reach != 0u && c.compliance > 0.0) {
        let face = vec4<u32>(c.face[0], c.face[1], c.face[2], c.face[3]);
        let weights = vec4<f32>(c.weights[0], c.weights[1], c.weights[2], c.weights[3]);
        let up = impulse_update(
            c.gap,
            step.dt,
            relative_velocity(pairs[p].node, face, weights),
            vec3_of(c.normal),
            c.compliance,
            pairs[p].law,
            pairs[p].mu,
            c.jn,
            vec3_of(c.jt),
        );
        violation = up.violation;
        d = up.dj;
        constraints[p].jn = up.jn;
        constraints[p].jt = float3(up.jt);
    }
    dj[3u * p] = d.x;
    dj[3u * p + 1u] = d.y;
    dj[3u * p + 2u] = d.z;
    return violation;
}
