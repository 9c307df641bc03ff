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

const NEWTON_ITERATIONS: u32 = 12u;

// Closest point of the quad to x (twin of `quad::project`): Newton with the full Hessian from
// the centre; if it leaves the square or does not converge, clamp and slide along the edges.
fn quad_project(p: array<vec3<f32>, 4>, x: vec3<f32>) -> vec2<f32> {
    var xi = vec2<f32>(0.0);
    var converged = false;
    // tolerance scaled to f32 (the twin uses 1e-13 in f64)
    for (var it = 0u; it < NEWTON_ITERATIONS; it++) {
        let g = quad_geometry(p, xi);
        let r = g.y - x;
        let f = vec2<f32>(dot(r, g.t1), dot(r, g.t2));
        let h01 = dot(g.t1, g.t2) + dot(r, g.t12);
        let h00 = dot(g.t1, g.t1);
        let h11 = dot(g.t2, g.t2);
        let det = h00 * h11 - h01 * h01;
        if (abs(det) <= 1e-30) {
            break;
        }
        let d = vec2<f32>((h11 * f.x - h01 * f.y) / det, (h00 * f.y - h01 * f.x) / det);
        xi = clamp(xi - d, vec2<f32>(-3.0), vec2<f32>(3.0));
        if (max(abs(d.x), abs(d.y)) < 1e-6) {
            converged = true;
            break;
        }
    }
    if (converged && abs(xi.x) <= 1.0 && abs(xi.y) <= 1.0) {
        return xi;
    }
    xi = clamp(xi, vec2<f32>(-1.0), vec2<f32>(1.0));
    // NaN guard: a NaN compares false both ways
    if (!(abs(xi.x) <= 1.0) || !(abs(xi.y) <= 1.0)) {
        xi = vec2<f32>(0.0);
    }
    for (var sweep = 0u; sweep < 2u; sweep++) {
        for (var free = 0u; free < 2u; free++) {
            let fixed = 1u - free;
            if (abs(xi[fixed]) < 1.0) {
                continue;
            }
            for (var it = 0u; it < NEWTON_ITERATIONS; it++) {
                let g = quad_geometry(p, xi);
                var t = g.t1;
                if (free == 1u) {
                    t = g.t2;
                }
                let step = dot(g.y - x, t) / dot(t, t);
                let next = clamp(xi[free] - step, -1.0, 1.0);
                let done = abs(next - xi[free]) < 1e-7;
                xi[free] = next;
                if (done) {
                    break;
                }
            }
        }
    }
    return xi;
}
