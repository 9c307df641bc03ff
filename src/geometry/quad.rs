//! The bilinear quad of a primary face in convected coordinates $(\xi^1, \xi^2) \in [-1, 1]^2$.
//!
//! Corner k at `CORNERS[k]`, $N_k = \tfrac14 (1 + \xi^1_k \xi^1)(1 + \xi^2_k \xi^2)$;
//! covariant tangents $\tau_a = \partial y / \partial \xi^a$; unit normal
//! $n = \tau_1 \times \tau_2 / |\tau_1 \times \tau_2|$, outward for the mesh's face quads.

pub(crate) const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

use super::vector::{cross, dot, norm, sub, V3};

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
pub(crate) const NEWTON_ITERATIONS: usize = 16;

/// Below this ratio det(H) / (m_11 m_22) the full Hessian counts as not positive definite and
/// the step falls back to Gauss-Newton on the metric (condition numbers above about 4,000).
pub(crate) const HESSIAN_DEFINITE: f64 = 1e-3;

/// Widest band along the square's edges in which a coordinate whose gradient points out is put
/// onto the edge and held there (the projected Newton method's epsilon-active set: with the box
/// clamp alone, a coupled step can fail to descend from just inside an edge). The band narrows
/// to the coordinate's own gradient step $|f_a| / m_{aa}$, so a minimum just inside stays free.
pub(crate) const HELD_BAND: f64 = 1e-2;

/// A step that the square cuts below this fraction is blocked: the gradient steps instead.
pub(crate) const BLOCKED: f64 = 1e-2;

/// A rise of the squared distance below ROUNDING (|y - x|^2 + m_11 + m_22) is rounding, not an
/// uphill step (the f32 twin uses 1e-5).
pub(crate) const ROUNDING: f64 = 1e-12;

/// Closest point of the quad to x: the xi that minimises |x - y(xi)| over the closed square.
///
/// Projected Newton on $(y(\xi) - x) \cdot \tau_a = 0$ from the face centre with a line search,
/// every iterate kept in the square:
/// - a coordinate at (or, by `HELD_BAND`, near) an edge of the square whose gradient points out
///   of it is put on the edge and held there (the point lies beyond that edge); if both are
///   held, the corner is the answer;
/// - with both coordinates free the direction uses the full Hessian
///   $m_{ab} + (y - x) \cdot \partial_{ab} y$ where it is safely positive definite (always so
///   near a minimum: quadratic convergence) and the metric $m_{ab}$ (Gauss-Newton) where it is
///   not: far under a curved face the full Hessian is indefinite and plain Newton wanders
///   between the corners of the box;
/// - with one coordinate free, y is linear along the edge and one step with $m_{bb}$ is exact;
/// - a step is shortened to stay in the square (which keeps it a descent direction, unlike a
///   clamp); where that leaves almost nothing of it, the metric-scaled gradient steps instead;
/// - a step that increases the distance is halved.
///
/// Should the iteration not converge, the iterate closest to x is kept.
pub fn project(p: &[V3; 4], x: V3) -> [f64; 2] {
    let mut xi = [0.0f64; 2];
    // the last accepted iterate's squared distance, xi and rounding allowance
    let mut last = (f64::INFINITY, xi, 0.0);
    let mut best = (f64::INFINITY, xi);
    for _ in 0..NEWTON_ITERATIONS {
        let (y, t1, t2, t12) = geometry(p, xi);
        let r = sub(y, x);
        let d2 = dot(r, r);
        let uphill = d2.is_nan() || d2 > last.0 + last.2;
        if uphill && last.0.is_finite() {
            // uphill: back to half the step
            xi = [0.5 * (xi[0] + last.1[0]), 0.5 * (xi[1] + last.1[1])];
            continue;
        }
        let (m00, m01, m11) = (dot(t1, t1), dot(t1, t2), dot(t2, t2));
        last = (d2, xi, ROUNDING * (d2 + m00 + m11));
        if d2 < best.0 {
            best = (d2, xi);
        }
        let f = [dot(r, t1), dot(r, t2)];
        // the gradient points out of an edge and the coordinate's own scaled gradient step
        // would reach it (within HELD_BAND): onto the edge
        let m = [m00, m11];
        let held = [0, 1]
            .map(|a| f[a] * xi[a] <= 0.0 && 1.0 - xi[a].abs() <= HELD_BAND.min(f[a].abs() / m[a]));
        let from = xi;
        for a in 0..2 {
            if held[a] {
                xi[a] = xi[a].signum();
            }
        }
        let gradient = [0, 1].map(|a| if held[a] { 0.0 } else { f[a] / m[a] });
        let mut d = match held {
            [true, true] => return xi,
            [false, false] => {
                let mut h01 = m01 + dot(r, t12);
                if m00 * m11 - h01 * h01 <= HESSIAN_DEFINITE * m00 * m11 {
                    h01 = m01;
                }
                let det = m00 * m11 - h01 * h01;
                [
                    (m11 * f[0] - h01 * f[1]) / det,
                    (m00 * f[1] - h01 * f[0]) / det,
                ]
            }
            _ => gradient,
        };
        let mut alpha = box_step(xi, d);
        if alpha < BLOCKED {
            d = gradient;
            alpha = box_step(xi, d);
        }
        let next = [0, 1].map(|a| (xi[a] - alpha * d[a]).clamp(-1.0, 1.0));
        if !next[0].is_finite() || !next[1].is_finite() {
            break;
        }
        let step = (next[0] - from[0]).abs().max((next[1] - from[1]).abs());
        if step < 1e-13 {
            return next;
        }
        xi = next;
    }
    let (y, ..) = geometry(p, xi);
    let r = sub(y, x);
    if dot(r, r) < best.0 {
        xi
    } else {
        best.1
    }
}

/// The largest fraction alpha <= 1 of the step -d from xi that stays in the square.
fn box_step(xi: [f64; 2], d: [f64; 2]) -> f64 {
    let mut alpha = 1.0f64;
    for a in 0..2 {
        if d[a] > 0.0 {
            alpha = alpha.min((xi[a] + 1.0) / d[a]);
        } else if d[a] < 0.0 {
            alpha = alpha.min((xi[a] - 1.0) / d[a]);
        }
    }
    alpha.max(0.0)
}

/// Area of a (possibly warped) quad, by its two triangles (a triangle repeats a corner).
pub fn quad_area(p: &[[f64; 3]; 4]) -> f64 {
    0.5 * (norm(cross(sub(p[1], p[0]), sub(p[2], p[0])))
        + norm(cross(sub(p[2], p[0]), sub(p[3], p[0]))))
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

    /// Random warped faces (corners moved by up to 0.3 of the face size) and points up to 0.6
    /// face sizes above or below them (deep under a curved face, where the full-Hessian Newton
    /// alone wanders between the corners of the box): the projection is never farther than the
    /// best point of a 121 x 121 grid, and inside the square it is a stationary point. Deeper
    /// than about 0.7, such faces give the distance saddles and several minima (20,000 cases:
    /// 10 of them, all deeper than 0.7, end at a local one), far beyond any penetration a
    /// contact run accepts.
    #[test]
    fn projection_of_deep_points_beats_a_grid_search() {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let mut rng = StdRng::seed_from_u64(7);
        let n = 120;
        for case in 0..1000 {
            let mut p = [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ];
            for c in &mut p {
                for v in c.iter_mut() {
                    *v += rng.random_range(-0.3..0.3);
                }
            }
            let x = [
                rng.random_range(-0.7..1.7),
                rng.random_range(-0.7..1.7),
                rng.random_range(-0.6..0.6),
            ];
            let xi = project(&p, x);
            let d2 = dist2(&p, x, xi);
            let mut grid = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=n {
                    let g = [
                        -1.0 + 2.0 * i as f64 / n as f64,
                        -1.0 + 2.0 * j as f64 / n as f64,
                    ];
                    grid = grid.min(dist2(&p, x, g));
                }
            }
            assert!(
                d2 <= grid + 1e-12,
                "case {case}: x {x:?} xi {xi:?} d2 {d2} above the grid's {grid}"
            );
            if xi[0].abs() < 1.0 && xi[1].abs() < 1.0 {
                let (y, t1, t2, _) = geometry(&p, xi);
                let r = sub(y, x);
                let f = dot(r, t1).abs().max(dot(r, t2).abs());
                assert!(f <= 1e-9, "case {case}: gradient {f} at xi {xi:?}");
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
