// The search grid's bucket of every primary face: the cell of the mean of its four stored
// slots (inside a triangle, whose fourth slot repeats its third, too), hashed with its
// interface (twin: `kernels::face_cells`). One invocation per face.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> grid: SearchGrid;
@group(0) @binding(2) var<storage, read> reference: array<Split3>;
@group(0) @binding(3) var<storage, read> displacement: array<Split3>;
@group(0) @binding(4) var<storage, read> faces: array<Quad>;
// the first face of each face's interface (the hash's salt)
@group(0) @binding(5) var<storage, read> face_first: array<u32>;
@group(0) @binding(6) var<storage, read_write> keys: array<u32>;

@compute @workgroup_size(64)
fn face_cells(@builtin(global_invocation_id) gid: vec3<u32>) {
    let f = item_index(gid, params);
    if (f >= params.count) {
        return;
    }
    var c = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let n = faces[f].nodes[k];
        c += split_sum(reference[n], displacement[n]);
    }
    keys[f] = cell_key(cell_of(0.25 * c, grid.cell), face_first[f], grid.mask);
}
