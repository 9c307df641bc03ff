// Corrector of the explicit step over one body's nodes (node params.aux + i), one node per
// invocation (twin: `kernels::explicit_correct`): a_{n+1} = a_ext - f_int / m,
// v_{n+1} = v_{n+1/2} + dt/2 a_{n+1}; and the workgroup's share of the body's history values
// in the time-centred form the host path reports (integrate/explicit.rs): kinetic
// 1/2 m v_{n+1/2}^2, strain 1/2 u_n . f_int(u_{n+1}) with u_n = u_{n+1} - dt v_{n+1/2},
// gravity -f_ext . (u_n + u_{n+1}) / 2, and momentum m v_{n+1}: FIELDS floats per workgroup at
// partials[(params.aux2 + workgroup) * FIELDS].

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> forces: array<f32>;
@group(0) @binding(4) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(5) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(6) var<storage, read_write> acceleration: array<f32>;
@group(0) @binding(7) var<storage, read_write> partials: array<f32>;

const FIELDS: u32 = 6u;

// the invocations' sums, FIELDS rows of 64: one barrier, then FIELDS invocations add a row
// each (a tree of barriers per field is much slower on software adapters)
var<workgroup> scratch: array<f32, 384>;

@compute @workgroup_size(64)
fn explicit_correct(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let i = item_index(gid, params);
    var q = array<f32, 6>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    if (i < params.count) {
        let n = params.aux + i;
        let lm = lumped[n];
        let u = displacement[n];
        let dt = step.dt;
        for (var a = 0u; a < 3u; a++) {
            let d = 3u * n + a;
            let vh = velocity[d];
            let f = forces[d];
            let acc = lm.ext_acc[a] - f * lm.inv_mass[a];
            let v1 = vh + 0.5 * dt * acc;
            acceleration[d] = acc;
            velocity[d] = v1;
            let un1 = u.hi[a] + u.lo[a];
            q[0] += 0.5 * lm.mass * vh * vh;
            q[1] += 0.5 * (un1 - dt * vh) * f;
            q[2] -= lm.mass * lm.ext_acc[a] * (un1 - 0.5 * dt * vh);
            q[3 + a] = lm.mass * v1;
        }
    }
    let group = wid.x + wid.y * groups.x;
    for (var k = 0u; k < FIELDS; k++) {
        scratch[k * 64u + local] = q[k];
    }
    workgroupBarrier();
    if (local < FIELDS) {
        var total = 0.0;
        for (var j = 0u; j < 64u; j++) {
            total += scratch[local * 64u + j];
        }
        partials[(params.aux2 + group) * FIELDS + local] = total;
    }
}
