// The search grid's bucket of every primary face: the cell of its centre (`face_centre`),
// hashed with its interface (twin: `kernels::face_cells`); the centre is kept, so that the
// steps that keep the grid can measure how far the face has moved (`search_bounds`), and the
// face's box is written for the narrow phase (`face_box`; `search_bounds` writes it on the
// steps that keep the grid). One invocation per face.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> grid: SearchGrid;
@group(0) @binding(2) var<storage, read> reference: array<Split3>;
@group(0) @binding(3) var<storage, read> displacement: array<Split3>;
@group(0) @binding(4) var<storage, read> faces: array<Quad>;
// the first face of each face's interface (the hash's salt)
@group(0) @binding(5) var<storage, read> face_first: array<u32>;
@group(0) @binding(6) var<storage, read_write> keys: array<u32>;
@group(0) @binding(7) var<storage, read_write> centres: array<Float3>;
@group(0) @binding(8) var<storage, read_write> boxes: array<FaceBox>;

// include: face_centre

@compute @workgroup_size(64)
fn face_cells(@builtin(global_invocation_id) gid: vec3<u32>) {
    let f = item_index(gid, params);
    if (f >= params.count) {
        return;
    }
    let c = face_centre(f);
    centres[f] = float3(c);
    boxes[f] = face_box(f);
    keys[f] = cell_key(cell_of(c, grid.cell), face_first[f], grid.mask);
}
