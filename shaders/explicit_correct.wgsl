// Corrector of the explicit step over every body's nodes in one dispatch, one node per
// invocation (twin: `kernels::explicit_correct`, body by body): each body's nodes start at a
// workgroup of their own (`bodies[b]`: its first workgroup, first node and node count;
// `bodies[params.aux].x` the workgroups in all), so that a workgroup's sums are one body's;
// a_{n+1} = a_ext - f_int / m, v_{n+1} = v_{n+1/2} + dt/2 a_{n+1}; and the workgroup's
// share of the body's history values in the time-centred form the host path reports
// (integrate/explicit.rs): kinetic
// 1/2 m v_{n+1/2}^2, strain 1/2 u_n . f_int(u_{n+1}) with u_n = u_{n+1} - dt v_{n+1/2},
// gravity -f_ext . (u_n + u_{n+1}) / 2, and momentum m v_{n+1}: FIELDS floats per workgroup at
// partials[workgroup * FIELDS], body after body.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> forces: array<f32>;
@group(0) @binding(4) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(5) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(6) var<storage, read_write> acceleration: array<f32>;
@group(0) @binding(7) var<storage, read_write> partials: array<f32>;
@group(0) @binding(8) var<storage, read> bodies: array<vec4<u32>>;


// the invocations' sums, FIELDS rows of 64: one barrier, then FIELDS invocations add a row
// each (a tree of barriers per field is much slower on software adapters)
var<workgroup> scratch: array<f32, 384>;

@compute @workgroup_size(64)
fn explicit_correct(
    @builtin(local_invocation_index) local: u32,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
) {
    let group = wid.x + wid.y * groups.x;
    let end = bodies[params.aux].x;
    // the workgroup's body: bodies[b].x <= group < bodies[b + 1].x
    var b = 0u;
    while (b + 1u < params.aux && group >= bodies[b + 1u].x) {
        b++;
    }
    let body = bodies[b];
    let i = (group - body.x) * 64u + local;
    var kinetic = 0.0;
    var strain = 0.0;
    var gravity = 0.0;
    var momentum = vec3<f32>(0.0);
    if (group < end && i < body.z) {
        let n = body.y + i;
        let lm = lumped[n];
        let un1 = split_value(displacement[n]);
        let dt = step.dt;
        let vh = vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
        let f = vec3<f32>(forces[3u * n], forces[3u * n + 1u], forces[3u * n + 2u]);
        let ext = vec3_of(lm.ext_acc);
        let acc = ext - f * vec3_of(lm.inv_mass);
        let v1 = vh + 0.5 * dt * acc;
        acceleration[3u * n] = acc.x;
        acceleration[3u * n + 1u] = acc.y;
        acceleration[3u * n + 2u] = acc.z;
        velocity[3u * n] = v1.x;
        velocity[3u * n + 1u] = v1.y;
        velocity[3u * n + 2u] = v1.z;
        kinetic = 0.5 * lm.mass * dot(vh, vh);
        strain = 0.5 * dot(un1 - dt * vh, f);
        gravity = -lm.mass * dot(ext, un1 - 0.5 * dt * vh);
        momentum = lm.mass * v1;
    }
    scratch[local] = kinetic;
    scratch[64u + local] = strain;
    scratch[128u + local] = gravity;
    scratch[192u + local] = momentum.x;
    scratch[256u + local] = momentum.y;
    scratch[320u + local] = momentum.z;
    workgroupBarrier();
    if (local < FIELDS && group < end) {
        var total = 0.0;
        for (var j = 0u; j < 64u; j++) {
            total += scratch[local * 64u + j];
        }
        partials[group * FIELDS + local] = total;
    }
}
