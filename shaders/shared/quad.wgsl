// The bilinear quad of a primary face in convected coordinates (twin of
// `src/contact/quad.rs`). Corners at (-1,-1), (1,-1), (1,1), (-1,1).

const QUAD_CORNERS: array<vec2<f32>, 4> = array<vec2<f32>, 4>(
    vec2<f32>(-1.0, -1.0),
    vec2<f32>(1.0, -1.0),
    vec2<f32>(1.0, 1.0),
    vec2<f32>(-1.0, 1.0),
);

fn quad_shape(xi: vec2<f32>) -> vec4<f32> {
    var n: vec4<f32>;
    for (var k = 0u; k < 4u; k++) {
        let c = QUAD_CORNERS[k];
        n[k] = 0.25 * (1.0 + c.x * xi.x) * (1.0 + c.y * xi.y);
    }
    return n;
}

// Point y, tangents t1 = dy/dxi1, t2 = dy/dxi2 and the mixed derivative t12 at xi.
struct QuadGeometry {
    y: vec3<f32>,
    t1: vec3<f32>,
    t2: vec3<f32>,
    t12: vec3<f32>,
}

fn quad_geometry(p: array<vec3<f32>, 4>, xi: vec2<f32>) -> QuadGeometry {
    var g: QuadGeometry;
    g.y = vec3<f32>(0.0);
    g.t1 = vec3<f32>(0.0);
    g.t2 = vec3<f32>(0.0);
    g.t12 = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let c = QUAD_CORNERS[k];
        let nk = 0.25 * (1.0 + c.x * xi.x) * (1.0 + c.y * xi.y);
        let d1 = 0.25 * c.x * (1.0 + c.y * xi.y);
        let d2 = 0.25 * (1.0 + c.x * xi.x) * c.y;
        let d12 = 0.25 * c.x * c.y;
        g.y += nk * p[k];
        g.t1 += d1 * p[k];
        g.t2 += d2 * p[k];
        g.t12 += d12 * p[k];
    }
    return g;
}

const NEWTON_ITERATIONS: u32 = 16u;
const HESSIAN_DEFINITE: f32 = 1e-3;
const HELD_BAND: f32 = 1e-2;
const BLOCKED: f32 = 1e-2;
// f32 rounding allowance and step tolerance (the twin uses 1e-12 and 1e-13 in f64)
const ROUNDING: f32 = 1e-5;
const STEP_TOLERANCE: f32 = 1e-6;

// The largest fraction alpha <= 1 of the step -d from xi that stays in the square.
fn quad_box_step(xi: vec2<f32>, d: vec2<f32>) -> f32 {
    var alpha = 1.0;
    for (var a = 0u; a < 2u; a++) {
        if (d[a] > 0.0) {
            alpha = min(alpha, (xi[a] + 1.0) / d[a]);
        } else if (d[a] < 0.0) {
            alpha = min(alpha, (xi[a] - 1.0) / d[a]);
        }
    }
    return max(alpha, 0.0);
}

// Closest point of the quad to x (twin of `quad::project`): projected Newton from the centre
// with a line search, every iterate in the square; coordinates near an edge with the gradient
// pointing out are held on it; full Hessian where safely positive definite, else the metric;
// steps shortened to the square, the scaled gradient where that blocks them; uphill steps
// halved; the closest iterate kept if it does not converge.
fn quad_project(p: array<vec3<f32>, 4>, x: vec3<f32>) -> vec2<f32> {
    var xi = vec2<f32>(0.0);
    var last_d2 = bitcast<f32>(0x7f800000u); // +inf
    var last_xi = xi;
    var last_allowance = 0.0;
    var best_d2 = bitcast<f32>(0x7f800000u);
    var best_xi = xi;
    var have_last = false;
    for (var it = 0u; it < NEWTON_ITERATIONS; it++) {
        let g = quad_geometry(p, xi);
        let r = g.y - x;
        let d2 = dot(r, r);
        if (have_last && !(d2 <= last_d2 + last_allowance)) {
            // uphill: back to half the step
            xi = 0.5 * (xi + last_xi);
            continue;
        }
        let m00 = dot(g.t1, g.t1);
        let m01 = dot(g.t1, g.t2);
        let m11 = dot(g.t2, g.t2);
        have_last = true;
        last_d2 = d2;
        last_xi = xi;
        last_allowance = ROUNDING * (d2 + m00 + m11);
        if (d2 < best_d2) {
            best_d2 = d2;
            best_xi = xi;
        }
        let f = vec2<f32>(dot(r, g.t1), dot(r, g.t2));
        let m = vec2<f32>(m00, m11);
        var held = vec2<bool>(false, false);
        for (var a = 0u; a < 2u; a++) {
            held[a] = f[a] * xi[a] <= 0.0 && 1.0 - abs(xi[a]) <= min(HELD_BAND, abs(f[a]) / m[a]);
        }
        let start = xi;
        for (var a = 0u; a < 2u; a++) {
            if (held[a]) {
                xi[a] = sign(xi[a]);
            }
        }
        if (held.x && held.y) {
            return xi;
        }
        let gradient = select(f / m, vec2<f32>(0.0), held);
        var d = gradient;
        if (!held.x && !held.y) {
            var h01 = m01 + dot(r, g.t12);
            if (m00 * m11 - h01 * h01 <= HESSIAN_DEFINITE * m00 * m11) {
                h01 = m01;
            }
            let det = m00 * m11 - h01 * h01;
            d = vec2<f32>((m11 * f.x - h01 * f.y) / det, (m00 * f.y - h01 * f.x) / det);
        }
        var alpha = quad_box_step(xi, d);
        if (alpha < BLOCKED) {
            d = gradient;
            alpha = quad_box_step(xi, d);
        }
        let next = clamp(xi - alpha * d, vec2<f32>(-1.0), vec2<f32>(1.0));
        // NaN guard: a NaN compares false both ways
        if (!(abs(next.x) <= 1.0) || !(abs(next.y) <= 1.0)) {
            break;
        }
        let step = max(abs(next.x - start.x), abs(next.y - start.y));
        if (step < STEP_TOLERANCE) {
            return next;
        }
        xi = next;
    }
    let g = quad_geometry(p, xi);
    let r = g.y - x;
    if (dot(r, r) < best_d2) {
        return xi;
    }
    return best_xi;
}

// The closest point of quad p to the origin (corners given relative to the point sought):
// its xi, distance, offset y from the point, and the unit outward normal there.
struct FaceHit {
    xi: vec2<f32>,
    distance: f32,
    y: vec3<f32>,
    normal: vec3<f32>,
}

fn face_hit(p: array<vec3<f32>, 4>) -> FaceHit {
    let xi = quad_project(p, vec3<f32>(0.0));
    let g = quad_geometry(p, xi);
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
    p.xi = array<f32, 2>(0.0, 0.0);
    p.normal = array<f32, 3>(0.0, 0.0, 0.0);
    p.gap = bitcast<f32>(0xff800000u); // -inf
    p.gap_rate = 0.0;
    return p;
}

// The contact point of a hit on face `face`, with `rel` the secondary node's velocity less the
// face's at xi: gap g = y . n (> 0 penetration) and gap rate -rel . n.
fn hit_point(face: u32, hit: FaceHit, rel: vec3<f32>) -> ContactPoint {
    var p: ContactPoint;
    p.face = face;
    p.xi = array<f32, 2>(hit.xi.x, hit.xi.y);
    p.normal = array<f32, 3>(hit.normal.x, hit.normal.y, hit.normal.z);
    p.gap = dot(hit.y, hit.normal);
    p.gap_rate = -dot(rel, hit.normal);
    return p;
}
