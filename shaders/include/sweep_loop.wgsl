// included by kernels that bind what `sweep_pair`, `apply_node`, `stopping_rule` and
// `gather_range` need, include those files and `velocity.wgsl`, and run ONE_GROUP
// invocations a workgroup

// The invocations of the one-workgroup kernels (the host builds them wider where the
// adapter allows: `src/gpu/one_group.rs`; nothing they compute depends on it).
const ONE_GROUP: u32 = 256u;

var<workgroup> worst: array<f32, ONE_GROUP>;
var<workgroup> phase: u32;
var<workgroup> parts: array<vec3<f32>, 64>;
var<workgroup> ranges: u32;

// Each rigid body range's gather after a sweep, as `body_gather` takes it: its 64 parts on
// the first 64 lanes, then the same tree; written after the pairs' impulse changes.
fn gather_bodies(local: u32) {
    if (local == 0u) {
        ranges = links[0];
    }
    let count = workgroupUniformLoad(&ranges);
    for (var r = 0u; r < count; r++) {
        if (local < 64u) {
            parts[local] = gather_range_part(r, local);
        }
        gather_range(r, params.count, local);
        workgroupBarrier();
    }
}

// The iteration's sweeps in one workgroup while it sweeps on (see `contact_finish.wgsl`);
// every invocation of the workgroup calls it (its barriers).
fn sweep_while_sweeping(local: u32) {
    loop {
        if (local == 0u) {
            phase = state[STATE_PHASE];
        }
        if (workgroupUniformLoad(&phase) != 1u) {
            break;
        }
        var violation = 0.0;
        for (var p = local; p < params.count; p += ONE_GROUP) {
            violation = max(violation, sweep_pair(p));
        }
        worst[local] = violation;
        workgroupBarrier();
        for (var s = ONE_GROUP / 2u; s > 0u; s >>= 1u) {
            if (local < s) {
                worst[local] = max(worst[local], worst[local + s]);
            }
            workgroupBarrier();
        }
        // the sweep's impulse changes and impulses are written before any node gathers them
        storageBarrier();
        if (local == 0u) {
            state[STATE_VIOLATION] = max(state[STATE_VIOLATION], bitcast<u32>(worst[0]));
            stopping_rule();
        }
        gather_bodies(local);
        storageBarrier();
        for (var i = local; i < params.aux; i += ONE_GROUP) {
            apply_node(i, params.count);
        }
        // the velocities are written before the next sweep reads them
        storageBarrier();
        workgroupBarrier();
    }
}
