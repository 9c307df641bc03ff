// included by kernels that bind `links`, `constraints` and `dj: array<f32>` (read_write)
// and declare `var<workgroup> parts: array<vec3<f32>, 64>`

// Lane `lane`'s part of rigid body range r's gather (`links` starts with the number of
// ranges and each range's first and end pair): the impulse changes of the pairs lane,
// lane + 64, ... of the range, weighted by the body's shape function (1 in reach, 0 out).
// Every kernel that gathers a range adds these 64 parts by the same tree, so the sum is the
// same bits wherever it is taken.
fn gather_range_part(r: u32, lane: u32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    let end = links[2u + 2u * r];
    for (var q = links[1u + 2u * r] + lane; q < end; q += 64u) {
        sum += constraints[q].weights[0] * vec3<f32>(dj[3u * q], dj[3u * q + 1u], dj[3u * q + 2u]);
    }
    return sum;
}

// Rigid body range r's gather, written at dj[3 (np + r)]: the 64 parts already in `parts`
// summed by a fixed tree. Every invocation of the workgroup calls it (its barriers).
fn gather_range(r: u32, np: u32, local: u32) {
    workgroupBarrier();
    for (var s = 32u; s > 0u; s >>= 1u) {
        if (local < s) {
            parts[local] += parts[local + s];
        }
        workgroupBarrier();
    }
    if (local == 0u) {
        let o = 3u * (np + r);
        dj[o] = parts[0].x;
        dj[o + 1u] = parts[0].y;
        dj[o + 2u] = parts[0].z;
    }
}
