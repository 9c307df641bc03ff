// The bounds of the step's search grid (twin: `kernels::search_bounds`): the fastest node's
// speed, the largest box side of a primary face at u_n and the largest move of a face's
// centre since the faces were last sorted (`face_cells` wrote the centres), folded into
// bounds[0..3] (cleared by the last step's `search_grid`) by atomicMax on their f32 bits (non-negative floats order as
// their bits); and each face's box for the narrow phase (`face_box`). One invocation per node
// (params.aux nodes) and per face (params.aux2 faces); each workgroup reduces in workgroup
// memory, then takes one atomic per bound.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> reference: array<Split3>;
@group(0) @binding(2) var<storage, read> displacement: array<Split3>;
@group(0) @binding(3) var<storage, read> velocity: array<f32>;
@group(0) @binding(4) var<storage, read> faces: array<Quad>;
@group(0) @binding(5) var<storage, read> centres: array<Float3>;
@group(0) @binding(6) var<storage, read_write> bounds: array<atomic<u32>, 3>;
@group(0) @binding(7) var<storage, read_write> boxes: array<FaceBox>;

// include: face_centre
// include: fold_bounds

@compute @workgroup_size(64)
fn search_bounds(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let i = item_index(gid, params);
    var speed = 0.0;
    var side_drift = vec2<f32>(0.0);
    if (i < params.aux) {
        speed = length(vec3<f32>(velocity[3u * i], velocity[3u * i + 1u], velocity[3u * i + 2u]));
    }
    if (i < params.aux2) {
        side_drift = face_bounds(i);
    }
    fold_bounds(local, speed, side_drift);
}
