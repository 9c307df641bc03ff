// The constraints of the explicit step's contact iteration, one pair per invocation (twin:
// `kernels::contact_constraints`), as the host path gathers them (`integrate::explicit`):
// a surface pair takes its query's contact point (face, shape functions, normal, gap at u_n)
// and is in reach if a face was found with g >= -margin; a plane pair takes the plane's
// normal and gap and is in reach if g >= -4 dt |v*| (four steps of its node's motion); a
// rigid body's pair takes the gap and normal of the body's surface (`rigid_distance`) and a
// face of one node, the body's, and is in reach if g >= -4 dt |v* - v*_b|.
// The relative velocity at v_{n-1/2} = v* - dt a_n is kept for the friction work and the
// impact loss. The compliance starts at zero, and the impulses at the last step's
// (`results`, the report's) against a face or a rigid body, zero against a plane (the warm
// start; `contact_compliance` keeps them only where the constraint can be enforced). keys[p]: the pair's face for the bucket sort by face (an
// in-reach surface pair), otherwise params.aux (one bucket past the faces).

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> step: Step;
@group(0) @binding(2) var<storage, read> grid: SearchGrid;
@group(0) @binding(3) var<storage, read> reference: array<Split3>;
@group(0) @binding(4) var<storage, read> displacement: array<Split3>;
@group(0) @binding(5) var<storage, read> velocity: array<f32>;
@group(0) @binding(6) var<storage, read> acceleration: array<f32>;
@group(0) @binding(7) var<storage, read> pairs: array<ContactPair>;
@group(0) @binding(8) var<storage, read> points: array<ContactPoint>;
@group(0) @binding(9) var<storage, read> faces: array<Quad>;
@group(0) @binding(10) var<storage, read_write> constraints: array<Constraint>;
@group(0) @binding(11) var<storage, read_write> keys: array<u32>;
@group(0) @binding(12) var<storage, read> rigid: array<RigidSurface>;
@group(0) @binding(13) var<storage, read> results: array<f32>;

// include: velocity
// include: constrain_pair

@compute @workgroup_size(64)
fn contact_constraints(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p < params.count) {
        constrain_pair(p, params.aux);
    }
}
