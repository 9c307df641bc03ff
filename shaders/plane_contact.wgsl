// Contact impulses of the explicit step against analytic rigid planes, one secondary node per
// invocation (twin: `kernels::plane_contact`). The step's constraint is the paper's gap rate
// in Carpenter, Taylor and Katona's forward-increment form: g_n + dt gdot_{n+1/2} <= 0,
// J_N >= 0, complementary. A node's planes couple only through the node itself, so the
// node solves its own constraints by the projected Jacobi sweeps of the host path (the
// row-sum compliance: the node's plane count times its largest inverse mass), with
// Coulomb friction returned onto the cone |J_T| <= mu J_N in the same sweep. A plane enters
// the step if the node is within four steps of its motion of it (g >= -4 dt |v*|); the
// others keep zero impulses.
//
// Results, SLOT floats per (plane node, plane): normal impulse, friction impulse (3), active
// (0/1), sliding (0/1), linearised end-of-step gap, friction work since the start, and the
// node's sweeps (max_iterations + 1 where it did not converge).

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

const SLOT: u32 = 9u;
const MAX_PLANES: u32 = 8u;

fn vec3_of(a: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(a[0], a[1], a[2]);
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
    let lm = lumped[n];
    let inv = vec3_of(lm.inv_mass);
    var vel = vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
    let acc = vec3<f32>(acceleration[3u * n], acceleration[3u * n + 1u], acceleration[3u * n + 2u]);
    // v_{n-1/2} = v* - dt a_n: the slip before the step, for the friction work
    let before = vel - dt * acc;
    let u = displacement[n];
    let un = vec3_of(u.hi) + vec3_of(u.lo);
    var gap: array<f32, 8>;
    var normal: array<vec3<f32>, 8>;
    var jn: array<f32, 8>;
    var jt: array<vec3<f32>, 8>;
    // the planes in reach: those the node could meet within four steps of its motion
    let reach = -4.0 * dt * length(vel);
    var mask = 0u;
    var touches = 0.0;
    for (var p = 0u; p < np; p++) {
        jn[p] = 0.0;
        jt[p] = vec3<f32>(0.0);
        normal[p] = vec3<f32>(0.0);
        gap[p] = 0.0;
        if ((pn.planes & (1u << p)) != 0u) {
            let pl = planes[p];
            let nrm = vec3_of(pl.normal);
            // x - point with the split reference: the plane's and the node's large parts cancel
            let rel = split_difference(reference[n], pl.point) + un;
            normal[p] = nrm;
            gap[p] = -dot(rel, nrm);
            if (gap[p] >= reach) {
                mask |= 1u << p;
                touches += 1.0;
            }
        }
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
            let nrm = normal[p];
            // a normal that meets only prescribed dofs cannot be enforced
            if (dot(nrm * nrm, inv) <= 0.0) {
                continue;
            }
            let up = impulse_update(
                gap[p],
                dt,
                vel,
                nrm,
                touches * inv_max,
                planes[p].mu,
                jn[p],
                jt[p],
            );
            violation = max(violation, up.violation);
            jn[p] = up.jn;
            jt[p] = up.jt;
            let dj = up.dj;
            dv += dj * inv;
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
            results[o + 6u] = bitcast<f32>(0xff800000u);
            continue;
        }
        let nrm = normal[p];
        let mu = planes[p].mu;
        let rn = dot(vel, nrm);
        results[o] = jn[p];
        results[o + 1u] = jt[p].x;
        results[o + 2u] = jt[p].y;
        results[o + 3u] = jt[p].z;
        results[o + 4u] = select(0.0, 1.0, jn[p] > 0.0);
        let sliding = mu > 0.0 && jn[p] > 0.0 && length(jt[p]) >= mu * jn[p] * (1.0 - 1e-6);
        results[o + 5u] = select(0.0, 1.0, sliding);
        results[o + 6u] = gap[p] - dt * rn;
        var work = results[o + 7u];
        if (mu > 0.0) {
            let slip = vel - rn * nrm;
            let slip_before = before - dot(before, nrm) * nrm;
            work -= dot(jt[p], 0.5 * (slip_before + slip));
        }
        results[o + 7u] = work;
        results[o + 8u] = reported;
    }
}
