// A primary face of either kind (twin of `src/geometry/face.rs`): a bilinear quad, or a
// linear triangle, read as four slots whose fourth repeats the third (`Face::slots`).

// The four stored corners of a face (positions relative to some origin); a triangle's
// third and fourth are the same.
struct FaceCorners {
    p0: vec3<f32>,
    p1: vec3<f32>,
    p2: vec3<f32>,
    p3: vec3<f32>,
}

// Point y, tangents t1 = dy/dxi1, t2 = dy/dxi2 and the mixed derivative t12 at xi.
struct FaceGeometry {
    y: vec3<f32>,
    t1: vec3<f32>,
    t2: vec3<f32>,
    t12: vec3<f32>,
}

fn face_is_triangle(f: vec4<u32>) -> bool {
    return f.z == f.w;
}

// Shape functions of face f at xi, one per stored corner.
fn face_shape(f: vec4<u32>, xi: vec2<f32>) -> vec4<f32> {
    if (face_is_triangle(f)) {
        return triangle_shape(xi);
    }
    return quad_shape(xi);
}

// Point, tangents and mixed derivative of face f (corners p) at xi.
fn face_geometry(f: vec4<u32>, p: FaceCorners, xi: vec2<f32>) -> FaceGeometry {
    if (face_is_triangle(f)) {
        return triangle_geometry(p, xi);
    }
    return quad_geometry(p, xi);
}

// The value at shape-function weights w of a field whose values at the face's stored
// corners are v0..v3.
fn face_interpolate(
    w: vec4<f32>,
    v0: vec3<f32>,
    v1: vec3<f32>,
    v2: vec3<f32>,
    v3: vec3<f32>,
) -> vec3<f32> {
    return w.x * v0 + w.y * v1 + w.z * v2 + w.w * v3;
}

// Closest point of face f (corners p) to x.
fn face_project(f: vec4<u32>, p: FaceCorners, x: vec3<f32>) -> vec2<f32> {
    if (face_is_triangle(f)) {
        return triangle_project(p, x);
    }
    return quad_project(p, x);
}

// The closest point of face f to the origin (corners p given relative to the point sought):
// its xi, distance, offset y from the point, and the unit outward normal there.
struct FaceHit {
    xi: vec2<f32>,
    distance: f32,
    y: vec3<f32>,
    normal: vec3<f32>,
}

fn face_hit(f: vec4<u32>, p: FaceCorners) -> FaceHit {
    let xi = face_project(f, p, vec3<f32>(0.0));
    let g = face_geometry(f, p, xi);
    var h: FaceHit;
    h.xi = xi;
    h.distance = length(g.y);
    h.y = g.y;
    h.normal = normalize(cross(g.t1, g.t2));
    return h;
}

// A query with no face in reach.
fn open_point() -> ContactPoint {
    var p: ContactPoint;
    p.face = NO_FACE;
    p.xi = Float2(0.0, 0.0);
    p.normal = Float3(0.0, 0.0, 0.0);
    p.gap = bitcast<f32>(0xff800000u); // -inf
    p.gap_rate = 0.0;
    return p;
}

// The contact point of a hit on face `face`, with `rel` the secondary node's velocity less the
// face's at xi: gap g = y . n (> 0 penetration) and gap rate -rel . n.
fn hit_point(face: u32, hit: FaceHit, rel: vec3<f32>) -> ContactPoint {
    var p: ContactPoint;
    p.face = face;
    p.xi = Float2(hit.xi.x, hit.xi.y);
    p.normal = float3(hit.normal);
    p.gap = dot(hit.y, hit.normal);
    p.gap_rate = -dot(rel, hit.normal);
    return p;
}
