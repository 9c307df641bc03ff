// The end of the contact iteration in one workgroup (twin: `kernels::contact_finish`): while
// the iteration sweeps on after the sweeps the host recorded, it runs the remaining sweeps
// itself, each a `sweep_pair` over the pairs (params.count), the stopping rule, the rigid
// bodies' gathers (`gather_bodies`) and an `apply_node` over the contact nodes (params.aux),
// with the workgroup's barriers between them where the recorded sweeps have dispatch
// boundaries. The same arithmetic in the same order as those sweeps, so the results do not
// depend on how many were recorded; a step whose iteration has stopped pays one
// workgroup's check of the phase.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(5) var<storage, read_write> dj: array<f32>;
@group(0) @binding(6) var<storage, read_write> state: array<u32, 8>;
@group(0) @binding(7) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(8) var<storage, read> links: array<u32>;
@group(0) @binding(9) var<storage, read> starts: array<u32>;
@group(0) @binding(10) var<storage, read> sorted: array<u32>;
@group(0) @binding(11) var<storage, read> lumped: array<Lumped>;

const FINISH_SIZE: u32 = 256u;

var<workgroup> worst: array<f32, FINISH_SIZE>;
var<workgroup> phase: u32;
var<workgroup> parts: array<vec3<f32>, 64>;
var<workgroup> ranges: u32;

// include: velocity
// include: sweep_pair
// include: apply_node
// include: gather_range

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

@compute @workgroup_size(256)
fn contact_finish(@builtin(local_invocation_index) local: u32) {
    loop {
        if (local == 0u) {
            phase = state[STATE_PHASE];
        }
        if (workgroupUniformLoad(&phase) != 1u) {
            break;
        }
        var violation = 0.0;
        for (var p = local; p < params.count; p += FINISH_SIZE) {
            violation = max(violation, sweep_pair(p));
        }
        worst[local] = violation;
        workgroupBarrier();
        for (var s = FINISH_SIZE / 2u; s > 0u; s >>= 1u) {
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
        for (var i = local; i < params.aux; i += FINISH_SIZE) {
            apply_node(i, params.count);
        }
        // the velocities are written before the next sweep reads them
        storageBarrier();
        workgroupBarrier();
    }
}
