// included by kernels that bind `nodes: array<ContactNode>`, `links`, `constraints`,
// `starts`, `sorted`, `dj`, `lumped: array<Lumped>` and `velocity: array<f32>` (read_write)

// Pair p's impulse change in the half of `dj` that starts at `half` (0 but in
// `contact_relax`, which keeps two sweeps' changes).
fn load_dj(p: u32, half: u32) -> vec3<f32> {
    let o = half + 3u * p;
    return vec3<f32>(dj[o], dj[o + 1u], dj[o + 2u]);
}

// The velocity change of a sweep at contact node i (twin: `kernels::contact_apply`): the
// impulse changes of the pairs it is the secondary node of, minus N_k times those of the
// pairs on each primary face whose corner k it is, and minus those gathered on each rigid
// body range it carries (`body_gather`, after the `np` pairs' own), times its inverse mass;
// the changes read from the half of `dj` at `half`.
fn node_change(i: u32, np: u32, half: u32) -> vec3<f32> {
    let cn = nodes[i];
    var delta = vec3<f32>(0.0);
    for (var j = cn.pair_first; j < cn.pair_end; j++) {
        delta += load_dj(links[j], half);
    }
    for (var j = cn.face_first; j < cn.face_end; j++) {
        let f = links[j] / 4u;
        let k = links[j] % 4u;
        for (var b = starts[f]; b < starts[f + 1u]; b++) {
            let q = sorted[b];
            delta -= constraints[q].weights[k] * load_dj(q, half);
        }
    }
    for (var j = cn.body_first; j < cn.body_end; j++) {
        delta -= load_dj(np + links[j], half);
    }
    return delta * vec3_of(lumped[cn.node].inv_mass);
}

// A sweep's velocity change applied at contact node i.
fn apply_node(i: u32, np: u32) {
    let n = nodes[i].node;
    let dv = node_change(i, np, 0u);
    velocity[3u * n] += dv.x;
    velocity[3u * n + 1u] += dv.y;
    velocity[3u * n + 2u] += dv.z;
}
