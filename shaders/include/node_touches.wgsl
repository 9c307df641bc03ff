// included by kernels that bind `nodes`, `links`, `constraints`, `starts`, `sorted` and
// `touches: array<f32>` (read_write)

// Contact node i's row-sum weight (twin: `kernels::contact_touches`; see
// `contact_touches.wgsl`), written at touches[node]; returns the in-reach pairs it is the
// secondary node of.
fn node_touches(i: u32) -> u32 {
    let cn = nodes[i];
    var own = 0u;
    for (var j = cn.pair_first; j < cn.pair_end; j++) {
        own += constraints[links[j]].in_reach;
    }
    var t = f32(own);
    for (var j = cn.face_first; j < cn.face_end; j++) {
        let f = links[j] / 4u;
        let k = links[j] % 4u;
        for (var b = starts[f]; b < starts[f + 1u]; b++) {
            t += abs(constraints[sorted[b]].weights[k]);
        }
    }
    for (var j = cn.body_first; j < cn.body_end; j++) {
        let r = links[j];
        for (var q = links[1u + 2u * r]; q < links[2u + 2u * r]; q++) {
            t += abs(constraints[q].weights[0]);
        }
    }
    touches[cn.node] = t;
    return own;
}
