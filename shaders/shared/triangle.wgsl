// The linear triangle of a primary face (a tet4 face, its fourth slot repeating its third)
// in convected coordinates xi1, xi2 >= 0, xi1 + xi2 <= 1 (twin of `src/geometry/triangle.rs`):
// y = p0 + xi1 (p1 - p0) + xi2 (p2 - p0), constant tangents and normal.

// Shape functions at xi, corner k in component k; the repeated corner's is zero.
fn triangle_shape(xi: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(1.0 - xi.x - xi.y, xi.x, xi.y, 0.0);
}

fn triangle_geometry(p: FaceCorners, xi: vec2<f32>) -> FaceGeometry {
    var g: FaceGeometry;
    g.t1 = p.p1 - p.p0;
    g.t2 = p.p2 - p.p0;
    g.y = p.p0 + xi.x * g.t1 + xi.y * g.t2;
    g.t12 = vec3<f32>(0.0);
    return g;
}

// The clamped projection of x onto the edge from a to b: the parameter t in [0, 1] and the
// squared distance.
fn triangle_edge(a: vec3<f32>, b: vec3<f32>, x: vec3<f32>) -> vec2<f32> {
    let e = b - a;
    let ee = dot(e, e);
    let t = select(0.0, clamp(dot(x - a, e) / ee, 0.0, 1.0), ee > 0.0);
    let r = a + t * e - x;
    return vec2<f32>(t, dot(r, r));
}

const TRIANGLE_SLIVER: f32 = 1e-6;

// Closest point of the triangle to x (twin of `triangle::project`): the free minimum of the
// 2 x 2 normal equations where it lies in the triangle and the triangle is no sliver, else the closest of the three edges'
// clamped projections (edges p0-p1, p1-p2, p0-p2, the first of equals kept).
fn triangle_project(p: FaceCorners, x: vec3<f32>) -> vec2<f32> {
    let t1 = p.p1 - p.p0;
    let t2 = p.p2 - p.p0;
    let r = x - p.p0;
    let m00 = dot(t1, t1);
    let m01 = dot(t1, t2);
    let m11 = dot(t2, t2);
    let f = vec2<f32>(dot(r, t1), dot(r, t2));
    let det = m00 * m11 - m01 * m01;
    // a sliver (or no area): the edges give the point (twin: `triangle::SLIVER`)
    if (det > TRIANGLE_SLIVER * m00 * m11) {
        let free = vec2<f32>(m11 * f.x - m01 * f.y, m00 * f.y - m01 * f.x) / det;
        if (free.x >= 0.0 && free.y >= 0.0 && free.x + free.y <= 1.0) {
            return free;
        }
    }
    let e0 = triangle_edge(p.p0, p.p1, x);
    let e1 = triangle_edge(p.p1, p.p2, x);
    let e2 = triangle_edge(p.p0, p.p2, x);
    var xi = vec2<f32>(e0.x, 0.0);
    var d2 = e0.y;
    if (e1.y < d2) {
        xi = vec2<f32>(1.0 - e1.x, e1.x);
        d2 = e1.y;
    }
    if (e2.y < d2) {
        xi = vec2<f32>(0.0, e2.x);
    }
    return xi;
}
