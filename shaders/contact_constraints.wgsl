// The constraints of the explicit step's contact iteration, one pair per invocation (twin:
// `kernels::contact_constraints`), as the host path gathers them (`integrate::explicit`):
// a surface pair takes its query's contact point (face, shape functions, normal, gap at u_n)
// and is in reach if a face was found with g >= -margin; a plane pair takes the plane's
// normal and gap and is in reach if g >= -4 dt |v*| (four steps of its node's motion); a
// rigid body's pair takes the gap and normal of the body's surface (`rigid_distance`) and a
// face of one node, the body's, and is in reach if g >= -4 dt |v* - v*_b|.
// The slip at v_{n-1/2} = v* - dt a_n is kept for the friction work. The impulses and the
// compliance start at zero. keys[p]: the pair's face for the bucket sort by face (an
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

// include: velocity

fn load_a(n: u32) -> vec3<f32> {
    return vec3<f32>(acceleration[3u * n], acceleration[3u * n + 1u], acceleration[3u * n + 2u]);
}

@compute @workgroup_size(64)
fn contact_constraints(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p >= params.count) {
        return;
    }
    let pair = pairs[p];
    let n = pair.node;
    var face = vec4<u32>(NO_FACE);
    var w = vec4<f32>(0.0);
    var nrm = vec3<f32>(0.0);
    var gap = 0.0;
    var reach = false;
    var key = params.aux;
    let vn = load_v(n);
    // v_{n-1/2} of the relative motion: v* - dt a_n
    var rel_before = vn - step.dt * load_a(n);
    if (pair.query != NO_FACE) {
        let pt = points[pair.query];
        if (pt.face != NO_FACE) {
            nrm = vec3_of(pt.normal);
            gap = pt.gap;
            reach = gap >= -max(grid.margin, 1e-30);
            if (reach) {
                face = faces[pt.face].nodes;
                w = face_shape(face, vec2<f32>(pt.xi.x, pt.xi.y));
                key = pt.face;
                rel_before -= face_interpolate(
                    w,
                    load_v(face.x) - step.dt * load_a(face.x),
                    load_v(face.y) - step.dt * load_a(face.y),
                    load_v(face.z) - step.dt * load_a(face.z),
                    load_v(face.w) - step.dt * load_a(face.w),
                );
            }
        }
    } else if (pair.body != NO_FACE) {
        let b = rigid[pair.body].node;
        let r = split_difference(reference[n], reference[b])
            + (split_value(displacement[n]) - split_value(displacement[b]));
        let sd = rigid_distance(rigid[pair.body], r);
        nrm = sd.n;
        gap = -sd.d;
        reach = gap >= -4.0 * step.dt * length(vn - load_v(b));
        if (reach) {
            face = vec4<u32>(b);
            w = vec4<f32>(1.0, 0.0, 0.0, 0.0);
            rel_before -= load_v(b) - step.dt * load_a(b);
        }
    } else {
        nrm = vec3_of(pair.normal);
        let x = split_difference(reference[n], pair.point) + split_value(displacement[n]);
        gap = -dot(x, nrm);
        reach = gap >= -4.0 * step.dt * length(vn);
    }
    let slip = rel_before - dot(rel_before, nrm) * nrm;
    let zero = Float3(0.0, 0.0, 0.0);
    constraints[p] = Constraint(
        array<u32, 4>(face.x, face.y, face.z, face.w),
        array<f32, 4>(w.x, w.y, w.z, w.w),
        float3(nrm),
        gap,
        0.0,
        0.0,
        zero,
        float3(slip),
        select(0u, 1u, reach),
    );
    keys[p] = key;
}
