// The sweeps of the explicit step's contact iteration in one workgroup (twin:
// `kernels::contact_solve`): `contact_sweep`'s update of every pair, `contact_apply`'s
// gather at every contact node and `sweep_control`'s stopping rule, repeated until the
// iteration stops, with barriers between the phases instead of a dispatch each. Once it has
// converged no further sweep is run, and a step costs one dispatch however many sweeps it
// takes. The same updates in the same order as the three kernels, so the same bits; the
// contact set must be small enough that one workgroup sweeps it faster than three
// dispatches would (the host chooses). params.count pairs, params.aux contact nodes;
// SOLVE_GROUP invocations, a power of two (set when the pipeline is built).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(5) var<storage, read_write> dj: array<f32>;
@group(0) @binding(6) var<storage, read_write> state: array<u32, 4>;
@group(0) @binding(7) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(8) var<storage, read> links: array<u32>;
@group(0) @binding(9) var<storage, read> starts: array<u32>;
@group(0) @binding(10) var<storage, read> sorted: array<u32>;
@group(0) @binding(11) var<storage, read> lumped: array<Lumped>;

override SOLVE_GROUP: u32 = 256u;

var<workgroup> worst: array<f32, 1024>;
var<workgroup> sweeping: u32;

// #import contact_sweep_pair
// #import contact_apply_node

@compute @workgroup_size(SOLVE_GROUP)
fn contact_solve(@builtin(local_invocation_index) local: u32) {
    // the setup's sweep_control has decided whether to sweep at all
    if (local == 0u) {
        sweeping = select(0u, 1u, state[STATE_PHASE] == 1u);
    }
    loop {
        if (workgroupUniformLoad(&sweeping) == 0u) {
            break;
        }
        var violation = 0.0;
        for (var p = local; p < params.count; p += SOLVE_GROUP) {
            violation = max(violation, sweep_pair(p));
        }
        worst[local] = violation;
        storageBarrier();
        workgroupBarrier();
        for (var i = local; i < params.aux; i += SOLVE_GROUP) {
            apply_node(i);
        }
        for (var s = SOLVE_GROUP / 2u; s > 0u; s >>= 1u) {
            if (local < s) {
                worst[local] = max(worst[local], worst[local + s]);
            }
            workgroupBarrier();
        }
        storageBarrier();
        // sweep_control after a sweep
        if (local == 0u) {
            let sweeps = state[STATE_SWEEPS] + 1u;
            state[STATE_SWEEPS] = sweeps;
            if (worst[0] <= step.tolerance) {
                state[STATE_PHASE] = 2u;
            } else if (sweeps >= step.max_iterations) {
                state[STATE_PHASE] = 3u;
            }
            state[STATE_VIOLATION] = 0u;
            sweeping = select(0u, 1u, state[STATE_PHASE] == 1u);
        }
    }
}
