// One pair's update in a sweep of the contact iteration (see `contact_sweep.wgsl`). The
// kernel declares `step`, `constraints`, `pairs`, `velocity` and `dj` as `contact_sweep`
// does.

fn load_v(n: u32) -> vec3<f32> {
    return vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
}

// Updates pair p's impulses from the relative velocity at the sweep's start, writes its
// impulse change into dj and returns its violation (zero out of reach).
fn sweep_pair(p: u32) -> f32 {
    var violation = 0.0;
    var d = vec3<f32>(0.0);
    let c = constraints[p];
    if (c.in_reach != 0u && c.compliance > 0.0) {
        var rel = load_v(pairs[p].node);
        if (c.face[0] != NO_FACE) {
            rel -= quad_interpolate(
                vec4<f32>(c.weights[0], c.weights[1], c.weights[2], c.weights[3]),
                load_v(c.face[0]),
                load_v(c.face[1]),
                load_v(c.face[2]),
                load_v(c.face[3]),
            );
        }
        let up = impulse_update(
            c.gap,
            step.dt,
            rel,
            vec3_of(c.normal),
            c.compliance,
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
