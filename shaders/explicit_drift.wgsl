// Position update of the explicit step, one node per invocation: u_{n+1} = u_n + dt v_{n+1/2}
// (twin: `kernels::explicit_drift`). The displacement is a split pair (hi + lo) and the
// increment is added with Knuth's two-sum (`drift_by`). A single device's step whose
// predictor runs in the search's bounds does not dispatch it: `predict_bounds` drifts the
// nodes the contact iteration does not move, and the iteration (`contact_zone`, or
// `contact_report` after the staged sweeps) drifts the rest.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> velocity: array<f32>;
@group(0) @binding(3) var<storage, read_write> displacement: array<Split3>;

// include: drift

@compute @workgroup_size(64)
fn explicit_drift(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = item_index(gid, params);
    if (n >= params.count) {
        return;
    }
    let v = vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
    drift_by(n, v);
}
