// Contact impulses of the explicit step against analytic rigid planes, one secondary node per
// invocation (twin: `kernels::plane_contact`). The step's constraint is the paper's gap rate
// in Carpenter, Taylor and Katona's forward-increment form: g_n + dt gdot_{n+1/2} <= 0,
// J_N >= 0, complementary. A node's planes couple only through the node itself, so the
// node solves its own constraints by the projected Jacobi sweeps of the host path (the
// row-sum compliance: the node's plane count times its largest inverse mass), with the
// tangential impulse returned onto the law's set (`law_returned`) in the same sweep. A plane
// enters the step if the node is within four steps of its motion of it (g >= -4 dt |v*|);
// the others keep zero impulses.
//
// Results, SLOT floats per (plane node, plane): normal impulse, friction impulse (3), active
// (0/1), sliding (0/1), linearised end-of-step gap, friction work since the start, and the
// node's sweeps (max_iterations + 1 where it did not converge), the impulse J_N n + J_T (3)
// a driver's work (zero: a plane does not move) and the impact loss since the start (the
// normal impulse against the mean of the normal velocity before and after the step).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> reference: array<Split3>;
@group(0) @binding(3) var<storage, read> displacement: array<Split3>;
@group(0) @binding(4) var<storage, read> acceleration: array<f32>;
@group(0) @binding(5) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(6) var<storage, read> planes: array<Plane>;
@group(0) @binding(7) var<storage, read> plane_nodes: array<PlaneNode>;
@group(0) @binding(8) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(9) var<storage, read_write> results: array<f32>;


// While the node iterates, its slot of plane p holds that constraint's state: the impulses
// J_N and J_T in the first four floats and the gap at u_n where the end-of-step gap goes.

fn load3(o: u32) -> vec3<f32> {
    return vec3<f32>(results[o], results[o + 1u], results[o + 2u]);
}

fn store3(o: u32, v: vec3<f32>) {
    results[o] = v.x;
    results[o + 1u] = v.y;
    results[o + 2u] = v.z;
}

@compute @workgroup_size(64)
fn plane_contact(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    // params.aux planes
    let np = min(params.aux, MAX_PLANES);
    let pn = plane_nodes[i];
    let n = pn.node;
    let dt = step.dt;
    let inv = vec3_of(lumped[n].inv_mass);
    var vel = vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
    let acc = vec3<f32>(acceleration[3u * n], acceleration[3u * n + 1u], acceleration[3u * n + 2u]);
    // v_{n-1/2} = v* - dt a_n: the velocity before the step, for the friction work and the
    // impact loss
    let before = vel - dt * acc;
    let un = split_value(displacement[n]);
    // the planes in reach: those the node could meet within four steps of its motion
    let reach = -4.0 * dt * length(vel);
    var mask = 0u;
    var touches = 0.0;
    for (var p = 0u; p < np; p++) {
        let o = SLOT * (i * np + p);
        results[o] = 0.0;
        store3(o + 1u, vec3<f32>(0.0));
        var gap = 0.0;
        if ((pn.planes & (1u << p)) != 0u) {
            // x - point with the split reference: the plane's and the node's large parts cancel
            let rel = split_difference(reference[n], planes[p].point) + un;
            gap = -dot(rel, vec3_of(planes[p].normal));
            if (gap >= reach) {
                mask |= 1u << p;
                touches += 1.0;
            }
        }
        results[o + SLOT_GAP] = gap;
    }
    // the largest inverse mass bounds |n_p . M^-1 n_q| (Gershgorin), prescribed dofs included
    let inv_max = max(inv.x, max(inv.y, inv.z));
    var sweeps = 0u;
    // a node with no plane in reach takes no sweep (as the host path, which has no
    // constraint for it)
    var converged = mask == 0u;
    loop {
        if (converged || sweeps >= step.max_iterations) {
            break;
        }
        sweeps++;
        var violation = 0.0;
        var dv = vec3<f32>(0.0);
        for (var p = 0u; p < np; p++) {
            if ((mask & (1u << p)) == 0u) {
                continue;
            }
            let nrm = vec3_of(planes[p].normal);
            // a normal that meets only prescribed dofs cannot be enforced
            if (dot(nrm * nrm, inv) <= 0.0) {
                continue;
            }
            let o = SLOT * (i * np + p);
            let up = impulse_update(
                results[o + SLOT_GAP],
                dt,
                vel,
                nrm,
                touches * inv_max,
                planes[p].law,
                planes[p].mu,
                results[o],
                load3(o + 1u),
            );
            violation = max(violation, up.violation);
            results[o] = up.jn;
            store3(o + 1u, up.jt);
            dv += up.dj * inv;
        }
        vel += dv;
        if (violation <= step.tolerance) {
            converged = true;
            break;
        }
    }
    velocity[3u * n] = vel.x;
    velocity[3u * n + 1u] = vel.y;
    velocity[3u * n + 2u] = vel.z;
    let reported = f32(select(step.max_iterations + 1u, sweeps, converged));
    for (var p = 0u; p < np; p++) {
        let o = SLOT * (i * np + p);
        if ((pn.planes & (1u << p)) == 0u) {
            for (var k = 0u; k < SLOT; k++) {
                results[o + k] = 0.0;
            }
            // no gap: below any penetration
            results[o + SLOT_GAP] = bitcast<f32>(0xff800000u);
            continue;
        }
        let nrm = vec3_of(planes[p].normal);
        let law = planes[p].law;
        let rn = dot(vel, nrm);
        let jn = results[o];
        let jt = load3(o + 1u);
        results[o + SLOT_ACTIVE] = select(0.0, 1.0, jn > 0.0);
        let sliding = law_sliding(law, planes[p].mu, jt, jn);
        results[o + SLOT_SLIDING] = select(0.0, 1.0, sliding);
        results[o + SLOT_GAP] -= dt * rn;
        let bn = dot(before, nrm);
        results[o + SLOT_IMPACT_LOSS] -= jn * 0.5 * (bn + rn);
        if (law_is_frictional(law)) {
            let slip = vel - rn * nrm;
            let slip_before = before - bn * nrm;
            results[o + SLOT_FRICTION_WORK] -= dot(jt, 0.5 * (slip_before + slip));
        }
        results[o + SLOT_SWEEPS] = reported;
        let j = jn * nrm + jt;
        results[o + SLOT_IMPULSE] = j.x;
        results[o + SLOT_IMPULSE + 1u] = j.y;
        results[o + SLOT_IMPULSE + 2u] = j.z;
    }
}
