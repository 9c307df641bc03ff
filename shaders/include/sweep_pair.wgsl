// included by kernels that bind `step: Step`, `constraints: array<Constraint>` (read_write),
// `pairs: array<ContactPair>`, `velocity: array<f32>` and `dj: array<f32>` (read_write), and
// include `velocity.wgsl`

// Whether pair p's constraint takes part in the sweeps: in reach and enforceable.
fn swept(p: u32) -> bool {
    return constraints[p].in_reach != 0u && constraints[p].compliance > 0.0;
}

// One pair's part of a projected Jacobi sweep (twin: `kernels::contact_sweep`) at its
// relative velocity `rel` (read where the pair is `swept`): from the relative
// velocity at the sweep's start, the normal impulse moves by the residual of
// g_n + dt gdot <= 0 over the compliance and is kept >= 0; under a frictional law the
// tangential impulse that stops the slip is returned onto the law's set. Writes the pair's
// impulses and its impulse change (zero for a pair out of reach or not enforceable) into the
// half of `dj` at `to`, and returns its violation.
fn sweep_with(p: u32, rel: vec3<f32>, to: u32) -> f32 {
    var d = vec3<f32>(0.0);
    var violation = 0.0;
    let c = constraints[p];
    if (c.in_reach != 0u && c.compliance > 0.0) {
        let up = impulse_update(
            c.gap,
            step.dt,
            rel,
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
    let o = to + 3u * p;
    dj[o] = d.x;
    dj[o + 1u] = d.y;
    dj[o + 2u] = d.z;
    return violation;
}

// `sweep_with` at the velocities of `velocity`, the changes into dj[3p].
fn sweep_pair(p: u32) -> f32 {
    var rel = vec3<f32>(0.0);
    if (swept(p)) {
        let c = constraints[p];
        let face = vec4<u32>(c.face[0], c.face[1], c.face[2], c.face[3]);
        let weights = vec4<f32>(c.weights[0], c.weights[1], c.weights[2], c.weights[3]);
        rel = relative_velocity(pairs[p].node, face, weights);
    }
    return sweep_with(p, rel, 0u);
}
