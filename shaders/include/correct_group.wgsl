// included by kernels that bind `step: Step`, `displacement`, `lumped: array<Lumped>`,
// `velocity` and `acceleration` (read_write), `partials` (read_write) and `bodies`, with
// Params.aux the bodies, and define `node_force(n: u32) -> vec3<f32>`, node n's internal
// force

// the invocations' sums, FIELDS rows of 64: one barrier, then FIELDS invocations add a row
// each (a tree of barriers per field is much slower on software adapters)
var<workgroup> scratch: array<f32, 384>;

// The corrector of workgroup `group`'s nodes and its share of the history sums (see
// `explicit_correct.wgsl`); every invocation of the workgroup calls it (its barrier).
fn correct_group(local: u32, group: u32) {
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
        let f = node_force(n);
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
