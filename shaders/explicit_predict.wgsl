// Predictor of the explicit step, one dof per invocation: v* = v_n + dt/2 a_n
// (twin: `kernels::explicit_predict`).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> acceleration: array<f32>;
@group(0) @binding(3) var<storage, read_write> velocity: array<f32>;

@compute @workgroup_size(64)
fn explicit_predict(@builtin(global_invocation_id) gid: vec3<u32>) {
    let d = item_index(gid, params);
    if (d >= params.count) {
        return;
    }
    velocity[d] += 0.5 * step.dt * acceleration[d];
}
