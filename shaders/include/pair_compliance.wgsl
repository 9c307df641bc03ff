// included by kernels that bind `constraints` (read_write), `touches`, `lumped:
// array<Lumped>`, `pairs` and `dj: array<f32>` (read_write)

fn along(n: u32, nrm: vec3<f32>) -> f32 {
    return dot(nrm * nrm, vec3_of(lumped[n].inv_mass));
}

fn inv_max(n: u32) -> f32 {
    let inv = lumped[n].inv_mass;
    return max(inv.x, max(inv.y, inv.z));
}

// Corner k's share (weight w) of the compliance: along the normal, and the row-sum bound.
fn corner_share(m: u32, w: f32, nrm: vec3<f32>) -> vec2<f32> {
    return abs(w) * vec2<f32>(along(m, nrm), touches[m] * inv_max(m));
}

// Pair p's split compliance (twin: `kernels::contact_compliance`; see
// `contact_compliance.wgsl`), and its warm start's impulse as its impulse change (zero where
// it cannot be enforced, as its impulses then are).
fn pair_compliance(p: u32) {
    let c = constraints[p];
    if (c.in_reach == 0u) {
        dj[3u * p] = 0.0;
        dj[3u * p + 1u] = 0.0;
        dj[3u * p + 2u] = 0.0;
        return;
    }
    let s = pairs[p].node;
    let nrm = vec3_of(c.normal);
    // (along the normal, row-sum bound)
    var sum = vec2<f32>(along(s, nrm), touches[s] * inv_max(s));
    if (c.face[0] != NO_FACE) {
        sum += corner_share(c.face[0], c.weights[0], nrm);
        sum += corner_share(c.face[1], c.weights[1], nrm);
        sum += corner_share(c.face[2], c.weights[2], nrm);
        sum += corner_share(c.face[3], c.weights[3], nrm);
    }
    var j = vec3<f32>(0.0);
    if (sum.x > 0.0) {
        constraints[p].compliance = sum.y;
        j = c.jn * nrm + vec3_of(c.jt);
    } else {
        constraints[p].compliance = 0.0;
        constraints[p].jn = 0.0;
        constraints[p].jt = Float3(0.0, 0.0, 0.0);
    }
    dj[3u * p] = j.x;
    dj[3u * p + 1u] = j.y;
    dj[3u * p + 2u] = j.z;
}
