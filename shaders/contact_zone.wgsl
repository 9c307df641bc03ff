// The whole contact iteration of a step in one workgroup, for small contact zones (twin:
// `kernels::contact_zone`). The stages the staged iteration dispatches one after another
// run here each over its items in steps of the workgroup, with the workgroup's barriers
// where the staged iteration has dispatch boundaries: the same arithmetic in the same order,
// so the results are the staged iteration's bits. The stages: `contact_constraints`, the
// pairs' counting sort by face (`bucket_count`, the scan of the bucket sizes, `bucket_fill`,
// `bucket_order`, which clears the sizes, the state words and the search bounds),
// `contact_touches`, `contact_compliance` (which starts the sweeps), the warm start's
// `body_gather` and `contact_warm`, the sweeps as `contact_finish` runs them, and
// `contact_report` (with the drift of the late contact nodes). One dispatch in place of
// about twenty: on a small zone the staged iteration's dispatches, not their work, set the
// step's time.
// params.count: the pairs; params.aux: the contact nodes; params.aux2: the primary faces
// (the bucket of a pair on no face).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> grid: SearchGrid;
@group(0) @binding(3) var<storage, read> reference: array<Split3>;
@group(0) @binding(4) var<storage, read_write> displacement: array<Split3>;
@group(0) @binding(5) var<storage, read_write> velocity: array<f32>;
@group(0) @binding(6) var<storage, read> acceleration: array<f32>;
@group(0) @binding(7) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(8) var<storage, read> points: array<ContactPoint>;
@group(0) @binding(9) var<storage, read> faces: array<Quad>;
@group(0) @binding(10) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(11) var<storage, read_write> keys: array<u32>;
@group(0) @binding(12) var<storage, read> rigid: array<RigidSurface>;
@group(0) @binding(13) var<storage, read_write> counts: array<atomic<u32>>;
@group(0) @binding(14) var<storage, read_write> ranks: array<u32>;
@group(0) @binding(15) var<storage, read_write> starts: array<u32>;
@group(0) @binding(16) var<storage, read_write> sorted: array<u32>;
@group(0) @binding(17) var<storage, read_write> state: array<u32, 8>;
@group(0) @binding(18) var<storage, read> nodes: array<ContactNode>;
@group(0) @binding(19) var<storage, read> links: array<u32>;
@group(0) @binding(20) var<storage, read_write> touches: array<f32>;
@group(0) @binding(21) var<storage, read> lumped: array<Lumped>;
@group(0) @binding(22) var<storage, read_write> dj: array<f32>;
@group(0) @binding(23) var<storage, read_write> results: array<f32>;
@group(0) @binding(24) var<storage, read> late: array<u32>;
@group(0) @binding(25) var<storage, read_write> bounds: array<u32, 6>;

// include: velocity
// include: constrain_pair
// include: order_bucket
// include: node_touches
// include: pair_compliance
// include: sweep_pair
// include: apply_node
// include: phase_after
// include: stopping_rule
// include: gather_range
// include: sweep_loop
// include: report_pair
// include: drift
// include: late

var<workgroup> sums: array<u32, ONE_GROUP>;
var<workgroup> zone_active: atomic<u32>;

// A stage's writes, to storage and workgroup memory, before the next stage reads them.
fn stage_end() {
    storageBarrier();
    workgroupBarrier();
}

// The bucket starts from the sizes of buckets 0..nb, as `prefix_sum` gives them
// (starts[nb] the total): each invocation sums a run of neighbouring sizes, the workgroup
// scans the runs' sums, and each invocation writes its run's starts.
fn scan_counts(local: u32, nb: u32) {
    let run = (nb + ONE_GROUP - 1u) / ONE_GROUP;
    let first = min(local * run, nb);
    let end = min(first + run, nb);
    var sum = 0u;
    for (var k = first; k < end; k++) {
        sum += atomicLoad(&counts[k]);
    }
    sums[local] = sum;
    workgroupBarrier();
    for (var s = 1u; s < ONE_GROUP; s <<= 1u) {
        var before = 0u;
        if (local >= s) {
            before = sums[local - s];
        }
        workgroupBarrier();
        sums[local] += before;
        workgroupBarrier();
    }
    var at = sums[local] - sum;
    for (var k = first; k < end; k++) {
        starts[k] = at;
        at += atomicLoad(&counts[k]);
    }
    if (local == ONE_GROUP - 1u) {
        starts[nb] = sums[local];
    }
}

// The pairs sorted by primary face into buckets 0..nf (nf: pairs on no face), each face's
// bucket in pair order; the sizes, the state words and the search bounds cleared after, as
// `bucket_order` leaves them.
fn sort_pairs(local: u32, np: u32, nf: u32) {
    for (var p = local; p < np; p += ONE_GROUP) {
        ranks[p] = atomicAdd(&counts[keys[p]], 1u);
    }
    stage_end();
    scan_counts(local, nf + 1u);
    stage_end();
    for (var p = local; p < np; p += ONE_GROUP) {
        sorted[starts[keys[p]] + ranks[p]] = p;
    }
    stage_end();
    for (var b = local; b < nf; b += ONE_GROUP) {
        atomicStore(&counts[b], 0u);
        order_bucket(b);
    }
    if (local == 0u) {
        atomicStore(&counts[nf], 0u);
        for (var w = 0u; w < 8u; w++) {
            state[w] = 0u;
        }
        for (var k = 0u; k < 3u; k++) {
            bounds[k] = 0u;
        }
    }
}

// The row sums and the compliance; the first invocation starts the sweeps (or stops the
// iteration with no pair in reach), as `contact_compliance` does.
fn row_sums(local: u32, np: u32, nc: u32) {
    for (var i = local; i < nc; i += ONE_GROUP) {
        let own = node_touches(i);
        if (own > 0u) {
            atomicAdd(&zone_active, own);
        }
    }
    stage_end();
    if (local == 0u) {
        let in_reach = atomicLoad(&zone_active);
        state[STATE_ACTIVE] = in_reach;
        state[STATE_PHASE] = select(2u, 1u, in_reach != 0u);
        state[STATE_SWEPT] = u32(in_reach != 0u);
    }
    for (var p = local; p < np; p += ONE_GROUP) {
        pair_compliance(p);
    }
}

// The warm start's velocity change where the iteration sweeps, as `body_gather` and
// `contact_warm` make it.
fn warm_start(local: u32, np: u32, nc: u32) {
    if (local == 0u) {
        phase = state[STATE_PHASE];
    }
    if (workgroupUniformLoad(&phase) != 1u) {
        return;
    }
    gather_bodies(local);
    storageBarrier();
    for (var i = local; i < nc; i += ONE_GROUP) {
        apply_node(i, np);
    }
}

@compute @workgroup_size(ONE_GROUP)
fn contact_zone(@builtin(local_invocation_index) local: u32) {
    let np = params.count;
    if (local == 0u) {
        atomicStore(&zone_active, 0u);
    }
    for (var p = local; p < np; p += ONE_GROUP) {
        constrain_pair(p, params.aux2);
    }
    stage_end();
    sort_pairs(local, np, params.aux2);
    stage_end();
    row_sums(local, np, params.aux);
    stage_end();
    warm_start(local, np, params.aux);
    stage_end();
    sweep_while_sweeping(local);
    stage_end();
    let reported = reported_sweeps();
    for (var p = local; p < np; p += ONE_GROUP) {
        report_pair(p, reported);
    }
    for (var i = local; i < params.aux; i += ONE_GROUP) {
        let n = nodes[i].node;
        if (is_late(n)) {
            drift_by(n, load_v(n));
        }
    }
}
