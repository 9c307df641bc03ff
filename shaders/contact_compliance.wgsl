// The split compliance of each in-reach constraint, one pair per invocation (twin:
// `kernels::contact_compliance`): the row-sum (Gershgorin) bound of the coupled compliance,
// sum over the constraint's nodes of |weight| x touches x largest inverse mass (the
// secondary node's weight is 1), or zero where the normal meets only prescribed dofs (such a
// constraint cannot be enforced and is left out of the sweeps).
//
// Its first invocation also starts the iteration, in the dispatch before the first sweep
// (the rule of `kernels::sweep_control` for an iteration not started): `contact_touches`
// has counted the pairs in reach, and with none the iteration stops at once (0 sweeps, as
// the host path), else it starts sweeping. After each sweep `contact_apply` applies the
// stopping rule (its `stopping_rule`).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(2) var<storage, read> touches: array<f32>;
@group(0) @binding(3) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(4) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(5) var<storage, read_write> state: array<u32, 8>;

fn along(n: u32, nrm: vec3<f32>) -> f32 {
    return dot(nrm * nrm, vec3_of(lumped[n].inv_mass));
}

fn inv_max(n: u32) -> f32 {
    let inv = lumped[n].inv_mass;
    return max(inv.x, max(inv.y, inv.z));
}

// Corner k's share (weight w) of the compliance: along the normal, and the row-sum bound.
fn corner_share(m: u32, w: f32, nrm: vec3<f32>) -> vec2<f32> {
    return abs(w) * vec2<f32>(along(m, nrm), touches[m] * inv_max(m));
}

@compute @workgroup_size(64)
fn contact_compliance(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p == 0u && state[STATE_PHASE] == 0u) {
        state[STATE_PHASE] = select(2u, 1u, state[STATE_ACTIVE] != 0u);
    }
    if (p >= params.count) {
        return;
    }
    let c = constraints[p];
    if (c.in_reach == 0u) {
        return;
    }
    let s = pairs[p].node;
    let nrm = vec3_of(c.normal);
    // (along the normal, row-sum bound)
    var sum = vec2<f32>(along(s, nrm), touches[s] * inv_max(s));
    if (c.face[0] != NO_FACE) {
        sum += corner_share(c.face[0], c.weights[0], nrm);
        sum += corner_share(c.face[1], c.weights[1], nrm);
        sum += corner_share(c.face[2], c.weights[2], nrm);
        sum += corner_share(c.face[3], c.weights[3], nrm);
    }
    constraints[p].compliance = select(0.0, sum.y, sum.x > 0.0);
}
