// One sweep of the staged contact iteration in one dispatch (twin: `kernels::contact_relax`),
// for an iteration with no rigid body ranges to gather. Recorded sweep d (params.aux2; the
// host records d = 1, 2, ... in order) runs the apply of sweep d - 1 and sweep d together:
//
// - every contact node's velocity before sweep d is its velocity before sweep d - 1, kept
//   in the `carried` slot (d - 1) % 2, plus sweep d - 1's change (`node_change` of the
//   `dj` half (d - 1) % 2); the invocations of the contact nodes write it into slot d % 2
//   (before sweep 1 it is the warm start's velocity, which `contact_warm` left in slot 1);
// - five lanes of a pair compute the same velocities at its secondary node and its face's
//   corners, the same arithmetic in the same order (a lane each: the pair waits for one
//   gather, not five in turn), so the pair's `sweep_with` reads the bits `contact_apply`
//   would have left, and writes its impulse change into the `dj` half d % 2. The sweep's
//   largest violation goes into state word STATE_RING + d % 3.
//
// So every buffer a dispatch reads was written by the dispatches before it. Whether sweep d
// runs is the stopping rule after sweep d - 1 (`phase_after`), which every invocation takes
// from the violations' ring; STATE_SWEEPS counts the sweeps that ran. The iteration's state
// words and the velocities are the staged sweeps' again after the settle: the launch with
// SETTLE in params.aux2 (after R recorded sweeps, d = R + 1) writes the contact nodes'
// velocities after the last sweep that ran into `velocity` (where a sweep ran) and its
// invocation 0 sets the phase, so that `contact_finish` and the report go on from there.
// Items: PAIRS_PER_GROUP pairs (params.aux in all) a workgroup, five lanes each, then the
// contact nodes, one a lane.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(3) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(4) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(5) var<storage, read> links: array<u32>;
@group(0) @binding(6) var<storage, read> starts: array<u32>;
@group(0) @binding(7) var<storage, read> sorted: array<u32>;
@group(0) @binding(8) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(9) var<storage, read_write> dj: array<f32>;
@group(0) @binding(10) var<storage, read_write> carried: array<f32>;
@group(0) @binding(11) var<storage, read> contact_of: array<u32>;
@group(0) @binding(12) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(13) var<storage, read_write> state: array<atomic<u32>, 8>;

// include: velocity
// include: apply_node
// include: sweep_pair
// include: phase_after
// include: fold_violation

const SETTLE: u32 = 0x80000000u;
const PAIRS_PER_GROUP: u32 = 12u;
const NO_NODE: u32 = 0xffffffffu;

var<workgroup> worst: array<f32, 64>;
var<workgroup> words: vec3<u32>;
var<workgroup> gathered: array<vec3<f32>, 64>;

// The items of the pairs' workgroups (the contact nodes' come after them).
fn pair_items() -> u32 {
    return 64u * ((params.aux + PAIRS_PER_GROUP - 1u) / PAIRS_PER_GROUP);
}

// Where contact node i's velocity starts in `carried` slot s (3 per contact node a slot).
fn carried_offset(s: u32, i: u32) -> u32 {
    return 3u * (s * (params.count - pair_items()) + i);
}

// Contact node i's velocity in `carried` slot s.
fn carried_at(s: u32, i: u32) -> vec3<f32> {
    let o = carried_offset(s, i);
    return vec3<f32>(carried[o], carried[o + 1u], carried[o + 2u]);
}

// Contact node i's velocity before sweep d (d >= 1).
fn before_sweep(d: u32, i: u32) -> vec3<f32> {
    if (d == 1u) {
        return carried_at(1u, i);
    }
    let s = (d - 1u) % 2u;
    return carried_at(s, i) + node_change(i, params.aux, 3u * params.aux * s);
}

// Lane k's velocity of pair p's nodes before sweep d: k 0 its secondary node, 1 to 4 its
// face's corners (zero where the pair is not swept or has no face).
fn pair_node_velocity(p: u32, k: u32, d: u32) -> vec3<f32> {
    if (!swept(p)) {
        return vec3<f32>(0.0);
    }
    var n = pairs[p].node;
    if (k > 0u) {
        n = constraints[p].face[k - 1u];
        if (constraints[p].face[0] == NO_FACE) {
            return vec3<f32>(0.0);
        }
    }
    return before_sweep(d, contact_of[n]);
}

// Pair p's part of sweep d, as `sweep_pair` at the velocities before it, which its five
// lanes left in `gathered` from `base` on, combined as `relative_velocity` combines them.
fn relax_pair(p: u32, base: u32, d: u32) -> f32 {
    var rel = vec3<f32>(0.0);
    if (swept(p)) {
        let c = constraints[p];
        rel = gathered[base];
        if (c.face[0] != NO_FACE) {
            let w = vec4<f32>(c.weights[0], c.weights[1], c.weights[2], c.weights[3]);
            rel -= face_interpolate(
                w,
                gathered[base + 1u],
                gathered[base + 2u],
                gathered[base + 3u],
                gathered[base + 4u],
            );
        }
    }
    return sweep_with(p, rel, 3u * params.aux * (d % 2u));
}

// The contact node of `item` (an item past the pairs' workgroups), or NO_NODE.
fn node_of(item: u32) -> u32 {
    let first = pair_items();
    if (item < first || item >= params.count) {
        return NO_NODE;
    }
    return item - first;
}

// The settle after the recorded sweeps (d = R + 1): the velocities after the last sweep
// that ran (`last`; its change not yet carried where it is the R-th) and the phase.
fn settle(item: u32, d: u32, last: u32) {
    if (last == 0u) {
        // no sweep ran: `velocity` is the warm start's
        return;
    }
    let i = node_of(item);
    if (i != NO_NODE) {
        var v = carried_at((last + 1u) % 2u, i);
        if (last == d - 1u) {
            v = before_sweep(d, i);
        }
        let n = nodes[i].node;
        velocity[3u * n] = v.x;
        velocity[3u * n + 1u] = v.y;
        velocity[3u * n + 2u] = v.z;
    }
    if (item == 0u) {
        let violation = atomicLoad(&state[STATE_RING + last % 3u]);
        atomicStore(&state[STATE_PHASE], phase_after(last, violation));
    }
}

@compute @workgroup_size(64)
fn contact_relax(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let item = item_index(gid, params);
    let d = params.aux2 & ~SETTLE;
    if (local == 0u) {
        // STATE_SWEEPS only rises to d in this dispatch, and only where sweep d - 1 ran; the
        // ring's word of sweep d - 1 is final
        words = vec3<u32>(
            atomicLoad(&state[STATE_SWEEPS]),
            atomicLoad(&state[STATE_PHASE]),
            atomicLoad(&state[STATE_RING + (d + 2u) % 3u]),
        );
    }
    let w = workgroupUniformLoad(&words);
    let last = w.x;
    if ((params.aux2 & SETTLE) != 0u) {
        settle(item, d, last);
        return;
    }
    let carries = d >= 2u && last >= d - 1u;
    var sweeping = w.y == 1u;
    if (d >= 2u) {
        sweeping = carries && phase_after(d - 1u, w.z) == 1u;
    }
    let i = node_of(item);
    if (carries && i != NO_NODE) {
        let v = before_sweep(d, i);
        let o = carried_offset(d % 2u, i);
        carried[o] = v.x;
        carried[o + 1u] = v.y;
        carried[o + 2u] = v.z;
    }
    if (!sweeping) {
        return;
    }
    if (item == 0u) {
        atomicStore(&state[STATE_RING + (d + 1u) % 3u], 0u);
        atomicStore(&state[STATE_SWEEPS], d);
    }
    // the pairs' lanes: pair p = item / 64 * PAIRS_PER_GROUP + local / 5, node k = local % 5
    let p = item / 64u * PAIRS_PER_GROUP + local / 5u;
    let lane_of_pair = item < pair_items() && local < 5u * PAIRS_PER_GROUP && p < params.aux;
    if (lane_of_pair) {
        gathered[local] = pair_node_velocity(p, local % 5u, d);
    }
    workgroupBarrier();
    var violation = 0.0;
    if (lane_of_pair && local % 5u == 0u) {
        violation = relax_pair(p, local, d);
    }
    fold_violation(local, violation, STATE_RING + d % 3u);
}
