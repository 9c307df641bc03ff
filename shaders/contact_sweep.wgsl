// One projected Jacobi sweep of the explicit step's contact iteration, one pair per
// invocation (twin: `kernels::contact_sweep`), the host path's sweep (`integrate::explicit`):
// each pair's `sweep_pair`; the sweep's largest violation goes into the state (workgroup
// maximum, then one atomicMax of its bits). Once the iteration has stopped (the stopping
// rule in `contact_apply`), the sweeps recorded after it exit at once; invocation 0 notes
// whether this one ran, for the apply after it.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read> velocity: array<f32>;
@group(0) @binding(5) var<storage, read_write> dj: array<f32>;
@group(0) @binding(6) var<storage, read_write> state: array<atomic<u32>, 8>;

var<workgroup> worst: array<f32, 64>;
var<workgroup> phase: u32;

// include: velocity
// include: sweep_pair
// include: fold_violation

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
        atomicStore(&state[STATE_SWEPT], u32(sweeping));
    }
    if (!sweeping) {
        return;
    }
    var violation = 0.0;
    if (p < params.count) {
        violation = sweep_pair(p);
    }
    fold_violation(local, violation, STATE_VIOLATION);
}
