// Position update of the explicit step, one node per invocation: u_{n+1} = u_n + dt v_{n+1/2}
// (twin: `kernels::explicit_drift`). The displacement is a split pair (hi + lo) and the
// increment is added with Knuth's two-sum, so that u keeps ~14 digits over many small steps
// (an f32 sum would lose the increments' last digits at every step).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> velocity: array<f32>;
@group(0) @binding(3) var<storage, read_write> displacement: array<Split3>;

// (hi, lo) + d renormalised, componentwise: hi the f32 nearest the sum, lo the rest.
fn split_add(u: Split3, d: vec3<f32>) -> Split3 {
    let hi = vec3_of(u.hi);
    let s = hi + d;
    let bp = s - hi;
    let err = (hi - (s - bp)) + (d - bp);
    let l = vec3_of(u.lo) + err;
    let h2 = s + l;
    return Split3(float3(h2), float3(l - (h2 - s)));
}

@compute @workgroup_size(64)
fn explicit_drift(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = item_index(gid, params);
    if (n >= params.count) {
        return;
    }
    let v = vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
    displacement[n] = split_add(displacement[n], step.dt * v);
}
