// included by kernels that bind `nodes: array<ContactNode>`, `links`, `constraints`,
// `starts`, `sorted`, `dj`, `lumped: array<Lumped>` and `velocity: array<f32>` (read_write)

fn load_dj(p: u32) -> vec3<f32> {
    return vec3<f32>(dj[3u * p], dj[3u * p + 1u], dj[3u * p + 2u]);
}

// The velocity change of a sweep at contact node i (twin: `kernels::contact_apply`): the
// impulse changes of the pairs it is the secondary node of, minus N_k times those of the
// pairs on each primary face whose corner k it is, and minus those gathered on each rigid
// body range it carries (`body_gather`, after the `np` pairs' own), times its inverse mass.
fn apply_node(i: u32, np: u32) {
    let cn = nodes[i];
    var delta = vec3<f32>(0.0);
    for (var j = cn.pair_first; j < cn.pair_end; j++) {
        delta += load_dj(links[j]);
    }
    for (var j = cn.face_first; j < cn.face_end; j++) {
        let f = links[j] / 4u;
        let k = links[j] % 4u;
        for (var b = starts[f]; b < starts[f + 1u]; b++) {
            let q = sorted[b];
            delta -= constraints[q].weights[k] * load_dj(q);
        }
    }
    for (var j = cn.body_first; j < cn.body_end; j++) {
        delta -= load_dj(np + links[j]);
    }
    let n = cn.node;
    let dv = delta * vec3_of(lumped[n].inv_mass);
    velocity[3u * n] += dv.x;
    velocity[3u * n + 1u] += dv.y;
    velocity[3u * n + 2u] += dv.z;
}
