// The bilinear quad of a primary face in convected coordinates (twin of
// `src/geometry/quad.rs`). Corners at (-1,-1), (1,-1), (1,1), (-1,1).

// Shape functions at xi, corner k in component k.
fn quad_shape(xi: vec2<f32>) -> vec4<f32> {
    let a = 1.0 - xi;
    let b = 1.0 + xi;
    return 0.25 * vec4<f32>(a.x * a.y, b.x * a.y, b.x * b.y, a.x * b.y);
}

// Point, tangents and mixed derivative at xi.
fn quad_geometry(p: FaceCorners, xi: vec2<f32>) -> FaceGeometry {
    let n = quad_shape(xi);
    let a = 1.0 - xi;
    let b = 1.0 + xi;
    var g: FaceGeometry;
    g.y = n.x * p.p0 + n.y * p.p1 + n.z * p.p2 + n.w * p.p3;
    // dN_k/dxi1 = c_k.x (1 + c_k.y xi2) / 4, dN_k/dxi2 = (1 + c_k.x xi1) c_k.y / 4
    g.t1 = 0.25 * (a.y * (p.p1 - p.p0) + b.y * (p.p2 - p.p3));
    g.t2 = 0.25 * (a.x * (p.p3 - p.p0) + b.x * (p.p2 - p.p1));
    g.t12 = 0.25 * ((p.p0 - p.p1) + (p.p2 - p.p3));
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
    // per axis: the distance to the side the step moves towards, over the step
    let room = select(select(vec2<f32>(1.0), xi - 1.0, d < vec2<f32>(0.0)), xi + 1.0, d > vec2<f32>(0.0));
    let limit = select(vec2<f32>(1.0), room / d, d != vec2<f32>(0.0));
    return max(min(1.0, min(limit.x, limit.y)), 0.0);
}

// Closest point of the quad to x (twin of `quad::project`): projected Newton from the centre
// with a line search, every iterate in the square; coordinates near an edge with the gradient
// pointing out are held on it; full Hessian where safely positive definite, else the metric;
// steps shortened to the square, the scaled gradient where that blocks them; uphill steps
// halved; the closest iterate kept if it does not converge.
fn quad_project(p: FaceCorners, x: vec3<f32>) -> vec2<f32> {
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
        let held = f * xi <= vec2<f32>(0.0)
            & vec2<f32>(1.0) - abs(xi) <= min(vec2<f32>(HELD_BAND), abs(f) / m);
        let start = xi;
        xi = select(xi, sign(xi), held);
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
