// Each bonded node's share of the cohesive pairs' forces, one node per invocation (twin:
// `kernels::cohesive_scatter`): the sum of its pairs' forces in the order of its links, plus
// where it is a pair's upper node and minus where it is the lower, added to one of its
// element corners' forces (after the element and damage kernels; the gather then sums it
// into the node's force). Each node writes its own corner. Params.aux: the corner slots.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<BondedNode>;
@group(0) @binding(2) var<storage, read> links: array<u32>;
@group(0) @binding(3) var<storage, read> outputs: array<PairOutput>;
@group(0) @binding(4) var<storage, read_write> corner_forces: array<f32>;

@compute @workgroup_size(64)
fn cohesive_scatter(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let b = nodes[i];
    var f = vec3<f32>(0.0);
    for (var k = b.first; k < b.end; k++) {
        let link = links[k];
        let force = vec3_of(outputs[link & ~LOWER].force);
        if ((link & LOWER) != 0u) {
            f -= force;
        } else {
            f += force;
        }
    }
    let c = params.aux;
    corner_forces[b.corner] += f.x;
    corner_forces[c + b.corner] += f.y;
    corner_forces[2u * c + b.corner] += f.z;
}
