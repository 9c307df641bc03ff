// included by kernels that bind `offsets`, `incidence` and `corner_forces`

// The sum of the element corner forces at node n in the order of its incidence list
// (twin: `kernels::node_gather`; see `node_gather.wgsl`); component a of corner slot s at
// corner_forces[a c + s].
fn gather_force(n: u32, c: u32) -> vec3<f32> {
    var f = vec3<f32>(0.0);
    for (var i = offsets[n]; i < offsets[n + 1u]; i++) {
        let s = incidence[i];
        f += vec3<f32>(corner_forces[s], corner_forces[c + s], corner_forces[2u * c + s]);
    }
    return f;
}
