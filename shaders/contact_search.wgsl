// Narrow phase of the GPU contact search, one secondary node per invocation (twin:
// `kernels::contact_search`): the faces of the 27 grid cells around the node (of its own
// interface, faces first..end), or every face of the interface where the grid kept from an
// earlier step no longer holds (grid.all_faces), whose box grown by the margin holds the
// node are its candidates, the same test as the host's broad phase (`contact::search`); of
// those, the closest by projection gives the contact point, as `contact_gap` computes it
// (ties: the lower face index, so the order the faces are visited in does not matter). A
// face whose box (`face_box`, absolute f32 coordinates) grown by the margin and a slack far
// above its rounding misses the node is passed over before its corners are read: the exact
// test, relative to the node, decides the others, so the filter changes no result.
// The margin and all_faces are the grid's, which `search_grid` wrote this step; on a step
// that keeps the faces' last sort, the resident step dispatches no `search_grid` and the
// launch sets params.aux = 1: each invocation does its arithmetic on the bounds
// (`kept_grid.wgsl`), and invocation 0 writes the grid and the bounds' copy as it would.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read_write> grid: SearchGrid;
@group(0) @binding(2) var<storage, read> reference: array<Split3>;
@group(0) @binding(3) var<storage, read> displacement: array<Split3>;
@group(0) @binding(4) var<storage, read> velocity: array<f32>;
// first..end: the faces of the query's interface
@group(0) @binding(5) var<storage, read> queries: array<ContactQuery>;
@group(0) @binding(6) var<storage, read> faces: array<Quad>;
// bucket k holds sorted[starts[k]..starts[k + 1]]
@group(0) @binding(7) var<storage, read> starts: array<u32>;
@group(0) @binding(8) var<storage, read> sorted: array<u32>;
@group(0) @binding(9) var<storage, read_write> points: array<ContactPoint>;
@group(0) @binding(10) var<storage, read> boxes: array<FaceBox>;
@group(0) @binding(11) var<uniform> step: Step;
@group(0) @binding(12) var<storage, read_write> bounds: array<u32, 6>;

// include: velocity

// include: face_state

// include: kept_grid

// The closest candidate so far and its distance.
struct Closest {
    point: ContactPoint,
    distance: f32,
}

// The node's position x in f32, the step's margin and the reach of the box filter around
// the node: the margin and a slack of 1e-5 of the coordinates' size (the box and x are each
// within a few f32 ulps).
struct Probe {
    x: vec3<f32>,
    margin: f32,
    reach: f32,
}

// The step's margin and whether every face of the interface is a candidate.
struct Reach {
    margin: f32,
    all_faces: bool,
}

// The grid's margin and all_faces, or where the launch keeps the last sort (params.aux 1)
// `search_grid`'s arithmetic on the bounds, which invocation q = 0 writes into the grid.
fn step_reach(q: u32) -> Reach {
    if (params.aux == 0u) {
        return Reach(grid.margin, grid.all_faces != 0u);
    }
    let margin = step_margin();
    let need = kept_need(margin);
    if (q == 0u) {
        keep_grid(margin, need);
        copy_bounds();
    }
    return Reach(margin, need >= grid.cell);
}

// `best`, or face fi where it is a candidate of the node (reference rs, displacement us,
// velocity vs, position and filter `at`) and closer (ties: the lower face index).
fn closer(fi: u32, rs: Split3, us: Split3, vs: vec3<f32>, at: Probe, best: Closest) -> Closest {
    let b = boxes[fi];
    if (any(vec3_of(b.lo) - at.reach > at.x) || any(vec3_of(b.hi) + at.reach < at.x)) {
        return best;
    }
    let face = faces[fi].nodes;
    let p = corners_from(face, rs, us);
    let lo = min(min(p.p0, p.p1), min(p.p2, p.p3));
    let hi = max(max(p.p0, p.p1), max(p.p2, p.p3));
    // the candidate test: the grown box holds the node (the origin)
    if (any(lo - at.margin > vec3<f32>(0.0)) || any(hi + at.margin < vec3<f32>(0.0))) {
        return best;
    }
    let hit = face_hit(face, p);
    if (hit.distance < best.distance
        || (hit.distance == best.distance && fi < best.point.face)) {
        return Closest(hit_point(fi, hit, vs - face_velocity(face, hit.xi)), hit.distance);
    }
    return best;
}

@compute @workgroup_size(64)
fn contact_search(@builtin(global_invocation_id) gid: vec3<u32>) {
    let q = item_index(gid, params);
    if (q >= params.count) {
        return;
    }
    let query = queries[q];
    let s = query.secondary;
    let rs = reference[s];
    let us = displacement[s];
    let vs = load_v(s);
    var best = Closest(open_point(), bitcast<f32>(0x7f800000u)); // +inf
    let reach = step_reach(q);
    let x = split_sum(rs, us);
    let size = max(max(abs(x.x), abs(x.y)), abs(x.z)) + reach.margin;
    let at = Probe(x, reach.margin, reach.margin + 1e-5 * size);
    if (reach.all_faces) {
        for (var fi = query.first; fi < query.end; fi++) {
            best = closer(fi, rs, us, vs, at, best);
        }
        points[q] = best.point;
        return;
    }
    let home = cell_of(x, grid.cell);
    for (var c = 0; c < 27; c++) {
        let offset = vec3<i32>(c % 3 - 1, (c / 3) % 3 - 1, c / 9 - 1);
        let key = cell_key(home + offset, query.first, grid.mask);
        for (var j = starts[key]; j < starts[key + 1u]; j++) {
            let fi = sorted[j];
            if (fi >= query.first && fi < query.end) {
                best = closer(fi, rs, us, vs, at, best);
            }
        }
    }
    points[q] = best.point;
}
