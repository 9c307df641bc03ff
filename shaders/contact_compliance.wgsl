// The split compliance of each in-reach constraint, one pair per invocation (twin:
// `kernels::contact_compliance`): the row-sum (Gershgorin) bound of the coupled compliance,
// sum over the constraint's nodes of |weight| x touches x largest inverse mass (the
// secondary node's weight is 1), or zero where the normal meets only prescribed dofs (such a
// constraint cannot be enforced and is left out of the sweeps).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(2) var<storage, read> touches: array<f32>;
@group(0) @binding(3) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(4) var<storage, read> pairs: array<ContactPair>;

fn along(n: u32, nrm: vec3<f32>) -> f32 {
    let inv = lumped[n].inv_mass;
    return nrm.x * nrm.x * inv[0] + nrm.y * nrm.y * inv[1] + nrm.z * nrm.z * inv[2];
}

fn inv_max(n: u32) -> f32 {
    let inv = lumped[n].inv_mass;
    return max(inv[0], max(inv[1], inv[2]));
}

@compute @workgroup_size(64)
fn contact_compliance(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p >= params.count) {
        return;
    }
    let c = constraints[p];
    if (c.in_reach == 0u) {
        return;
    }
    let s = pairs[p].node;
    let nrm = vec3<f32>(c.normal[0], c.normal[1], c.normal[2]);
    var a = along(s, nrm);
    var bound = touches[s] * inv_max(s);
    if (c.face[0] != NO_FACE) {
        for (var k = 0u; k < 4u; k++) {
            let m = c.face[k];
            let w = abs(c.weights[k]);
            a += w * along(m, nrm);
            bound += w * touches[m] * inv_max(m);
        }
    }
    constraints[p].compliance = select(0.0, bound, a > 0.0);
}
