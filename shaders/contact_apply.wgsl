// The velocity change of one sweep, one contact node per invocation (twin:
// `kernels::contact_apply`): the impulse changes of the pairs it is the secondary node of,
// minus N_k times those of the pairs on each primary face whose corner k it is, times its
// inverse mass. The node gathers, so no two invocations write one velocity. Invocation 0
// also applies the iteration's stopping rule after the sweep (twin: `kernels::sweep_control`;
// its inputs, the sweep's violation and count, are final when this dispatch starts): it
// counts the sweep and sets the phase: converged, or stopped at the sweep limit
// (params.aux; params.aux2 the tolerance, f32 bits), or sweeping on. Dispatched indirectly,
// from the grid `contact_sweep` arms: once the iteration has stopped the sweeps recorded
// after it cost two dispatches each and do nothing.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(2) var<storage, read> links: array<u32>;
@group(0) @binding(3) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(4) var<storage, read> starts: array<u32>;
@group(0) @binding(5) var<storage, read> sorted: array<u32>;
@group(0) @binding(6) var<storage, read> dj: array<f32>;
@group(0) @binding(7) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(8) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(9) var<storage, read_write> state: array<u32, 4>;

fn load_dj(p: u32) -> vec3<f32> {
    return vec3<f32>(dj[3u * p], dj[3u * p + 1u], dj[3u * p + 2u]);
}

// The stopping rule after a sweep (twin: `kernels::sweep_control`): it counts the sweep and
// sets the phase, 2 converged, 3 stopped unconverged at the sweep limit, or 1 sweeping on.
fn stopping_rule() {
    let sweeps = state[STATE_SWEEPS] + 1u;
    state[STATE_SWEEPS] = sweeps;
    var phase = 1u;
    if (bitcast<f32>(state[STATE_VIOLATION]) <= bitcast<f32>(params.aux2)) {
        phase = 2u;
    } else if (sweeps >= params.aux) {
        phase = 3u;
    }
    state[STATE_PHASE] = phase;
    state[STATE_VIOLATION] = 0u;
}

@compute @workgroup_size(64)
fn contact_apply(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i == 0u) {
        stopping_rule();
    }
    if (i >= params.count) {
        return;
    }
    let cn = nodes[i];
    var delta = vec3<f32>(0.0);
    for (var j = cn.pair_first; j < cn.pair_end; j++) {
        delta += load_dj(links[j]);
    }
    for (var j = cn.face_first; j < cn.face_end; j++) {
        let f = links[j] / 4u;
        let k = links[j] % 4u;
        for (var b = starts[f]; b < starts[f + 1u]; b++) {
            let q = sorted[b];
            delta -= constraints[q].weights[k] * load_dj(q);
        }
    }
    let n = cn.node;
    let dv = delta * vec3_of(lumped[n].inv_mass);
    velocity[3u * n] += dv.x;
    velocity[3u * n + 1u] += dv.y;
    velocity[3u * n + 2u] += dv.z;
}
