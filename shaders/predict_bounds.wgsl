// The predictor of the explicit step with the bounds of its search grid, in one dispatch
// (twin: `kernels::predict_bounds`): each node's v* = v_n + dt/2 a_n, as `explicit_predict`
// takes it, and its speed from v*, then each face's box side and drift, folded as
// `search_bounds` folds them. A node the contact iteration does not move (not `is_late`)
// has its final v*, so it drifts here too, as `explicit_drift` would after the iteration;
// the iteration drifts the late ones, whose positions the search and the constraints read
// at u_n (every face corner and secondary node is late). A single device's step with a
// device search runs it in place of the three. One invocation per node (params.aux nodes,
// every node of the model) and per face (params.aux2 faces).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> reference: array<Split3>;
@group(0) @binding(3) var<storage, read_write> displacement: array<Split3>;
@group(0) @binding(4) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(5) var<storage, read> acceleration: array<f32>;
@group(0) @binding(6) var<storage, read> faces: array<Quad>;
@group(0) @binding(7) var<storage, read> centres: array<Float3>;
@group(0) @binding(8) var<storage, read_write> bounds: array<atomic<u32>, 3>;
@group(0) @binding(9) var<storage, read_write> boxes: array<FaceBox>;
@group(0) @binding(10) var<storage, read> late: array<u32>;

// include: face_centre
// include: fold_bounds
// include: drift
// include: late

@compute @workgroup_size(64)
fn predict_bounds(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let i = item_index(gid, params);
    var speed = 0.0;
    var side_drift = vec2<f32>(0.0);
    if (i < params.aux) {
        let d = 3u * i;
        let a = vec3<f32>(acceleration[d], acceleration[d + 1u], acceleration[d + 2u]);
        let v = vec3<f32>(velocity[d], velocity[d + 1u], velocity[d + 2u]) + 0.5 * step.dt * a;
        velocity[d] = v.x;
        velocity[d + 1u] = v.y;
        velocity[d + 2u] = v.z;
        speed = length(v);
        if (!is_late(i)) {
            drift_by(i, v);
        }
    }
    if (i < params.aux2) {
        side_drift = face_bounds(i);
    }
    fold_bounds(local, speed, side_drift);
}
