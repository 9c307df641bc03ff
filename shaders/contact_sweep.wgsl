// One projected Jacobi sweep of the explicit step's contact iteration, one pair per
// invocation (twin: `kernels::contact_sweep`), the host path's sweep (`integrate::explicit`):
// from the relative velocity at the sweep's start, the normal impulse moves by the residual
// of g_n + dt gdot <= 0 over the compliance and is kept >= 0; with friction the tangential
// impulse that stops the slip is returned onto the cone |J_T| <= mu J_N. dj[p] is the
// impulse change (zero for a pair out of reach or not enforceable); the sweep's largest
// violation goes into the state (workgroup maximum, then one atomicMax of its bits).
// Once the iteration has stopped (`contact_apply` applies the stopping rule) the sweep does
// nothing; its first invocation arms the grid of the apply that follows (params.aux,
// params.aux2: its width and height), or empties it once the iteration has stopped.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read> velocity: array<f32>;
@group(0) @binding(5) var<storage, read_write> dj: array<f32>;
@group(0) @binding(6) var<storage, read_write> state: array<atomic<u32>, 4>;
@group(0) @binding(7) var<storage, read_write> apply_args: array<u32, 3>;

var<workgroup> worst: array<f32, 64>;
var<workgroup> phase: u32;

// include: velocity

@compute @workgroup_size(64)
fn contact_sweep(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let p = item_index(gid, params);
    if (local == 0u) {
        phase = atomicLoad(&state[STATE_PHASE]);
    }
    let sweeping = workgroupUniformLoad(&phase) == 1u;
    if (p == 0u) {
        // the apply's grid, or an empty one (0, 1, 1)
        apply_args[0] = select(0u, params.aux, sweeping);
        apply_args[1] = select(1u, params.aux2, sweeping);
        apply_args[2] = 1u;
    }
    if (!sweeping) {
        return;
    }
    var violation = 0.0;
    if (p < params.count) {
        var d = vec3<f32>(0.0);
        let c = constraints[p];
        if (c.in_reach != 0u && c.compliance > 0.0) {
            var rel = load_v(pairs[p].node);
            if (c.face[0] != NO_FACE) {
                rel -= face_interpolate(
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
    }
    worst[local] = violation;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s >>= 1u) {
        if (local < s) {
            worst[local] = max(worst[local], worst[local + s]);
        }
        workgroupBarrier();
    }
    if (local == 0u && worst[0] > 0.0) {
        atomicMax(&state[STATE_VIOLATION], bitcast<u32>(worst[0]));
    }
}
