// The contact results of the step, one pair per invocation (twin: `kernels::contact_report`),
// in the plane kernel's layout (`plane_contact.wgsl`), SLOT floats per pair: normal impulse,
// friction impulse (3), active (0/1), sliding (0/1), linearised end-of-step gap (-inf out of
// reach), friction work since the start (the tangential impulse against the mean of the slip
// at v_{n-1/2} and at v_{n+1/2}), the iteration's sweeps (max_iterations + 1 where it
// stopped unconverged at the limit, max_iterations + 2 where it was still sweeping when the
// recorded sweeps ran out: the host then runs the submission again with more), the impulse
// on the secondary node (3: J_N n + J_T), the work of a driven rigid body's driver since
// the start (the impulse against the body's velocity) and the energy the normal impulse took
// since the start (the impact loss: J_N against the mean of the normal velocity at
// v_{n-1/2} and at v_{n+1/2}). Invocation i < params.aux2 also
// drifts contact node i where it `is_late` (its v* is final after the sweeps), as
// `explicit_drift` would. params.aux: the pairs; params.aux2: the contact nodes.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read> velocity: array<f32>;
@group(0) @binding(5) var<storage, read> state: array<u32, 8>;
@group(0) @binding(6) var<storage, read_write> results: array<f32>;
@group(0) @binding(7) var<storage, read> rigid: array<RigidSurface>;
@group(0) @binding(8) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(9) var<storage, read_write> displacement: array<Split3>;
@group(0) @binding(10) var<storage, read> late: array<u32>;

// include: velocity
// include: report_pair
// include: drift
// include: late

@compute @workgroup_size(64)
fn contact_report(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p < params.aux) {
        report_pair(p, reported_sweeps());
    }
    if (p < params.aux2) {
        let n = nodes[p].node;
        if (is_late(n)) {
            drift_by(n, load_v(n));
        }
    }
}
