// The split compliance of each in-reach constraint, one pair per invocation (twin:
// `kernels::contact_compliance`): the row-sum (Gershgorin) bound of the coupled compliance,
// sum over the constraint's nodes of |weight| x touches x largest inverse mass (the
// secondary node's weight is 1), or zero where the normal meets only prescribed dofs (such a
// constraint cannot be enforced and is left out of the sweeps).
//
// Each pair's impulse change becomes its warm start's impulse (`contact_constraints`), which
// `contact_warm` applies before the first sweep; the warm impulses of a constraint that
// cannot be enforced are zeroed.
//
// Its first invocation also starts the iteration, in the dispatch before the first sweep
// (the rule of `kernels::sweep_control` for an iteration not started): `contact_touches`
// has counted the pairs in reach, and with none the iteration stops at once (0 sweeps, as
// the host path), else it starts sweeping, and notes the warm start for the rigid bodies'
// gathers (`STATE_SWEPT`). After each sweep `contact_apply` applies the stopping rule (its
// `stopping_rule`).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(2) var<storage, read> touches: array<f32>;
@group(0) @binding(3) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(4) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(5) var<storage, read_write> state: array<u32, 8>;
@group(0) @binding(6) var<storage, read_write> dj: array<f32>;

// include: pair_compliance

@compute @workgroup_size(64)
fn contact_compliance(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p == 0u && state[STATE_PHASE] == 0u) {
        let sweeping = state[STATE_ACTIVE] != 0u;
        state[STATE_PHASE] = select(2u, 1u, sweeping);
        state[STATE_SWEPT] = u32(sweeping);
    }
    if (p < params.count) {
        pair_compliance(p);
    }
}
