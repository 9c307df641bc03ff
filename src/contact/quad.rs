//! The bilinear quad of a primary face in convected coordinates $(\xi^1, \xi^2) \in [-1, 1]^2$.
//!
//! Corner k at `CORNERS[k]`, $N_k = \tfrac14 (1 + \xi^1_k \xi^1)(1 + \xi^2_k \xi^2)$;
//! covariant tangents $\tau_a = \partial y / \partial \xi^a$; unit normal
//! $n = \tau_1 \times \tau_2 / |\tau_1 \times \tau_2|$, outward for the mesh's face quads.

pub const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

pub type V3 = [f64; 3];

#[inline]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
pub fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// Shape functions at xi.
pub fn shape(xi: [f64; 2]) -> [f64; 4] {
    CORNERS.map(|c| 0.25 * (1.0 + c[0] * xi[0]) * (1.0 + c[1] * xi[1]))
}

/// Point, covariant tangents and the mixed second derivative at xi.
pub fn geometry(p: &[V3; 4], xi: [f64; 2]) -> (V3, V3, V3, V3) {
    let n = shape(xi);
    let mut y = [0.0; 3];
    let mut t1 = [0.0; 3];
    let mut t2 = [0.0; 3];
    let mut t12 = [0.0; 3];
    for k in 0..4 {
        let c = CORNERS[k];
        let d1 = 0.25 * c[0] * (1.0 + c[1] * xi[1]);
        let d2 = 0.25 * (1.0 + c[0] * xi[0]) * c[1];
        let d12 = 0.25 * c[0] * c[1];
        for a in 0..3 {
            y[a] += n[k] * p[k][a];
            t1[a] += d1 * p[k][a];
            t2[a] += d2 * p[k][a];
            t12[a] += d12 * p[k][a];
        }
    }
    (y, t1, t2, t12)
}

/// Unit normal $\tau_1 \times \tau_2 / |\tau_1 \times \tau_2|$ at xi.
pub fn normal(p: &[V3; 4], xi: [f64; 2]) -> V3 {
    let (_, t1, t2, _) = geometry(p, xi);
    let c = cross(t1, t2);
    let l = norm(c);
    [c[0] / l, c[1] / l, c[2] / l]
}

/// Iterations of the projection's Newton solve.
pub const NEWTON_ITERATIONS: usize = 12;

/// Closest point of the quad to x: the xi that minimises |x - y(xi)| over the closed square.
///
/// Newton on $(y(\xi) - x) \cdot \tau_a = 0$ with the full Hessian
/// $m_{ab} + (y - x) \cdot \partial_{ab} y$ from the face centre. If it leaves the square (the
/// point lies beyond an edge) or fails to converge, the robust fallback clamps xi to the
/// square and minimises along the edge it landed on (1D Newton on the free coordinate, clamped),
/// which finds the closest point of an edge or a corner.
pub fn project(p: &[V3; 4], x: V3) -> [f64; 2] {
    let mut xi = [0.0f64; 2];
    let mut converged = false;
    for _ in 0..NEWTON_ITERATIONS {
        let (y, t1, t2, t12) = geometry(p, xi);
        let r = sub(y, x);
        let f = [dot(r, t1), dot(r, t2)];
        let h = [
            [dot(t1, t1), dot(t1, t2) + dot(r, t12)],
            [dot(t1, t2) + dot(r, t12), dot(t2, t2)],
        ];
        let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
        if det.abs() <= 1e-300 {
            break;
        }
        let d = [
            (h[1][1] * f[0] - h[0][1] * f[1]) / det,
            (h[0][0] * f[1] - h[1][0] * f[0]) / det,
        ];
        xi = [
            (xi[0] - d[0]).clamp(-3.0, 3.0),
            (xi[1] - d[1]).clamp(-3.0, 3.0),
        ];
        if d[0].abs().max(d[1].abs()) < 1e-13 {
            converged = true;
            break;
        }
    }
    if converged && xi[0].abs() <= 1.0 && xi[1].abs() <= 1.0 {
        return xi;
    }
    // fallback: clamp, then slide along the edge(s) the clamp put us on
    let mut xi = [xi[0].clamp(-1.0, 1.0), xi[1].clamp(-1.0, 1.0)];
    if !xi[0].is_finite() || !xi[1].is_finite() {
        xi = [0.0, 0.0];
    }
    for _ in 0..2 {
        for free in 0..2 {
            let fixed = 1 - free;
            if xi[fixed].abs() < 1.0 {
                continue;
            }
            for _ in 0..NEWTON_ITERATIONS {
                let (y, t1, t2, _) = geometry(p, xi);
                let t = if free == 0 { t1 } else { t2 };
                // y is linear in one coordinate along an edge: one exact Newton step
                let r = sub(y, x);
                let step = dot(r, t) / dot(t, t);
                let next = (xi[free] - step).clamp(-1.0, 1.0);
                let done = (next - xi[free]).abs() < 1e-14;
                xi[free] = next;
                if done {
                    break;
                }
            }
        }
    }
    xi
}

#[cfg(test)]
mod tests {
    use super::*;

    fn warped() -> [V3; 4] {
        [
            [0.0, 0.0, 0.0],
            [1.1, 0.1, 0.05],
            [1.0, 0.9, -0.1],
            [-0.1, 1.0, 0.08],
        ]
    }

    fn dist2(p: &[V3; 4], x: V3, xi: [f64; 2]) -> f64 {
        let (y, ..) = geometry(p, xi);
        dot(sub(y, x), sub(y, x))
    }

    #[test]
    fn projection_beats_a_fine_grid_search() {
        let p = warped();
        let pts = [
            [0.4, 0.5, 0.3],
            [0.4, 0.5, -0.3],
            [1.6, 0.5, 0.2],
            [-0.7, -0.4, 0.1],
            [0.5, 1.8, -0.2],
            [0.99, 0.1, 0.0],
        ];
        for x in pts {
            let xi = project(&p, x);
            let best = dist2(&p, x, xi);
            let n = 400;
            for i in 0..=n {
                for j in 0..=n {
                    let g = [
                        -1.0 + 2.0 * i as f64 / n as f64,
                        -1.0 + 2.0 * j as f64 / n as f64,
                    ];
                    assert!(
                        best <= dist2(&p, x, g) + 1e-9,
                        "x {x:?}: xi {xi:?} d2 {best} worse than grid {g:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn normal_of_a_counter_clockwise_square_is_plus_z() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let n = normal(&p, [0.3, -0.2]);
        assert!((n[2] - 1.0).abs() < 1e-15);
        assert_eq!(project(&p, [0.25, 0.75, 5.0]), [-0.5, 0.5]);
    }
}
