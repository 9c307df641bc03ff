// One projected Jacobi update of an explicit contact constraint (twin:
// `kernels::impulse::impulse_update`, which the host path uses too): the step's gap rate in
// forward-increment form, g_n + dt gdot <= 0 with gdot = -rel . n. The normal impulse moves
// by the residual over the split compliance and is kept >= 0; under a frictional law the
// tangential impulse that stops the slip is returned onto the law's set (`law_returned`:
// Coulomb's cone |J_T| <= mu J_N). The violation is
// the residual where pressed or opening too fast, and the slip where sticking.

struct ImpulseUpdate {
    jn: f32,
    jt: vec3<f32>,
    dj: vec3<f32>,
    violation: f32,
}

fn impulse_update(
    gap: f32,
    dt: f32,
    rel: vec3<f32>,
    nrm: vec3<f32>,
    compliance: f32,
    law: u32,
    mu: f32,
    jn: f32,
    jt: vec3<f32>,
) -> ImpulseUpdate {
    var out: ImpulseUpdate;
    let rn = dot(rel, nrm);
    let r = gap / dt - rn;
    out.jn = max(jn + r / compliance, 0.0);
    out.violation = select(max(r, 0.0), abs(r), out.jn > 0.0);
    out.dj = (out.jn - jn) * nrm;
    out.jt = jt;
    if (law_is_frictional(law)) {
        let slip = rel - rn * nrm;
        let trial = jt - slip / compliance;
        let r = law_returned(law, mu, trial, out.jn);
        out.jt = r.t;
        if (r.inside && out.jn > 0.0) {
            out.violation = max(out.violation, length(slip));
        }
        out.dj += out.jt - jt;
    }
    return out;
}
