// The contact results of the step, one pair per invocation (twin: `kernels::contact_report`),
// in the plane kernel's layout (`plane_contact.wgsl`), SLOT floats per pair: normal impulse,
// friction impulse (3), active (0/1), sliding (0/1), linearised end-of-step gap (-inf out of
// reach), friction work since the start (the tangential impulse against the mean of the slip
// at v_{n-1/2} and at v_{n+1/2}), the iteration's sweeps (max_iterations + 1 where it
// stopped unconverged at the limit, max_iterations + 2 where it was still sweeping when the
// recorded sweeps ran out: the host then runs the submission again with more), the impulse
// on the secondary node (3: J_N n + J_T) and the work of a driven rigid body's driver since
// the start (the impulse against the body's velocity).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read> velocity: array<f32>;
@group(0) @binding(5) var<storage, read> state: array<u32, 8>;
@group(0) @binding(6) var<storage, read_write> results: array<f32>;
@group(0) @binding(7) var<storage, read> rigid: array<RigidSurface>;


// include: velocity

@compute @workgroup_size(64)
fn contact_report(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p >= params.count) {
        return;
    }
    let o = SLOT * p;
    let c = constraints[p];
    let phase = state[STATE_PHASE];
    var reported = state[STATE_SWEEPS];
    if (phase == 3u) {
        reported = step.max_iterations + 1u;
    } else if (phase == 1u) {
        // still sweeping: a report recorded before the iteration's end
        reported = step.max_iterations + 2u;
    }
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
    if (law_is_frictional(law)) {
        let slip = rel - rn * nrm;
        let before = vec3_of(c.slip);
        results[o + SLOT_FRICTION_WORK] -= dot(jt, 0.5 * (before + slip));
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
