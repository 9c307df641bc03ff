// included by kernels that bind `step: Step`, `constraints`, `pairs`, `velocity`, `state:
// array<u32, 8>`, `results` (read_write) and `rigid`, and include `velocity.wgsl`

// The sweeps the report gives the iteration: its count, max_iterations + 1 where it stopped
// unconverged at the limit, max_iterations + 2 where it is still sweeping.
fn reported_sweeps() -> u32 {
    let phase = state[STATE_PHASE];
    var reported = state[STATE_SWEEPS];
    if (phase == 3u) {
        reported = step.max_iterations + 1u;
    } else if (phase == 1u) {
        // still sweeping: a report recorded before the iteration's end
        reported = step.max_iterations + 2u;
    }
    return reported;
}

// Pair p's results (twin: `kernels::contact_report`; see `contact_report.wgsl`).
fn report_pair(p: u32, reported: u32) {
    let o = SLOT * p;
    let c = constraints[p];
    results[o + SLOT_SWEEPS] = f32(reported);
    if (c.in_reach == 0u) {
        for (var k = 0u; k < 6u; k++) {
            results[o + k] = 0.0;
        }
        for (var k = 0u; k < 3u; k++) {
            results[o + SLOT_IMPULSE + k] = 0.0;
        }
        results[o + SLOT_GAP] = bitcast<f32>(0xff800000u);
        return;
    }
    let nrm = vec3_of(c.normal);
    let face = vec4<u32>(c.face[0], c.face[1], c.face[2], c.face[3]);
    let weights = vec4<f32>(c.weights[0], c.weights[1], c.weights[2], c.weights[3]);
    let rel = relative_velocity(pairs[p].node, face, weights);
    let rn = dot(rel, nrm);
    let jt = vec3_of(c.jt);
    let law = pairs[p].law;
    results[o + SLOT_NORMAL_IMPULSE] = c.jn;
    results[o + SLOT_FRICTION_IMPULSE] = jt.x;
    results[o + SLOT_FRICTION_IMPULSE + 1u] = jt.y;
    results[o + SLOT_FRICTION_IMPULSE + 2u] = jt.z;
    results[o + SLOT_ACTIVE] = select(0.0, 1.0, c.jn > 0.0);
    let sliding = law_sliding(law, pairs[p].mu, jt, c.jn);
    results[o + SLOT_SLIDING] = select(0.0, 1.0, sliding);
    results[o + SLOT_GAP] = c.gap - step.dt * rn;
    let before = vec3_of(c.before);
    let bn = dot(before, nrm);
    results[o + SLOT_IMPACT_LOSS] -= c.jn * 0.5 * (bn + rn);
    if (law_is_frictional(law)) {
        let slip = rel - rn * nrm;
        let slip_before = before - bn * nrm;
        results[o + SLOT_FRICTION_WORK] -= dot(jt, 0.5 * (slip_before + slip));
    }
    let j = c.jn * nrm + jt;
    results[o + SLOT_IMPULSE] = j.x;
    results[o + SLOT_IMPULSE + 1u] = j.y;
    results[o + SLOT_IMPULSE + 2u] = j.z;
    let body = pairs[p].body;
    if (body != NO_FACE && rigid[body].driven != 0u) {
        results[o + SLOT_DRIVER_WORK] += dot(j, load_v(rigid[body].node));
    }
}
