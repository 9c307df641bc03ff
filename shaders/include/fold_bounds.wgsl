// included by kernels that bind `reference`, `displacement`, `faces`, `centres`, `bounds:
// array<atomic<u32>, 3>` and `boxes` (read_write), and include `face_centre.wgsl`

var<workgroup> speeds: array<f32, 64>;
var<workgroup> sides: array<f32, 64>;
var<workgroup> drifts: array<f32, 64>;

// Face i's box side and drift (see `search_bounds.wgsl`); writes its box.
fn face_bounds(i: u32) -> vec2<f32> {
    let f = faces[i];
    let r0 = reference[f.nodes[0]];
    let u0 = displacement[f.nodes[0]];
    var lo = vec3<f32>(0.0);
    var hi = vec3<f32>(0.0);
    for (var k = 1u; k < 4u; k++) {
        let n = f.nodes[k];
        let p = split_difference(reference[n], r0) + split_difference(displacement[n], u0);
        lo = min(lo, p);
        hi = max(hi, p);
    }
    let e = hi - lo;
    boxes[i] = face_box(i);
    let d = abs(face_centre(i) - vec3_of(centres[i]));
    return vec2<f32>(max(e.x, max(e.y, e.z)), max(d.x, max(d.y, d.z)));
}

// The workgroup's largest speed, side and drift folded into bounds[0..3]; every invocation
// of the workgroup calls it (its barriers).
fn fold_bounds(local: u32, speed: f32, side_drift: vec2<f32>) {
    speeds[local] = speed;
    sides[local] = side_drift.x;
    drifts[local] = side_drift.y;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s >>= 1u) {
        if (local < s) {
            speeds[local] = max(speeds[local], speeds[local + s]);
            sides[local] = max(sides[local], sides[local + s]);
            drifts[local] = max(drifts[local], drifts[local + s]);
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        atomicMax(&bounds[0], bitcast<u32>(speeds[0]));
        atomicMax(&bounds[1], bitcast<u32>(sides[0]));
        atomicMax(&bounds[2], bitcast<u32>(drifts[0]));
    }
}
