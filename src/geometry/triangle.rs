//! The linear triangle of a primary face (a tet4 face) in convected coordinates
//! $(\xi^1, \xi^2)$, $\xi^1, \xi^2 \ge 0$, $\xi^1 + \xi^2 \le 1$.
//!
//! $y(\xi) = (1 - \xi^1 - \xi^2)\, p_0 + \xi^1 p_1 + \xi^2 p_2$; the covariant tangents
//! $\tau_1 = p_1 - p_0$, $\tau_2 = p_2 - p_0$ are constant, and so is the unit normal
//! $n = \tau_1 \times \tau_2 / |\tau_1 \times \tau_2|$, outward for a triangle
//! oriented as the mesh's boundary faces are. The fourth shape function (the repeated corner)
//! is zero.

use super::vector::{cross, dot, norm, sub, V3};

/// Shape functions at xi; the fourth, of the repeated corner, is zero.
pub fn shape(xi: [f64; 2]) -> [f64; 4] {
    [1.0 - xi[0] - xi[1], xi[0], xi[1], 0.0]
}

/// Point, covariant tangents and the (zero) mixed second derivative at xi.
pub fn geometry(p: &[V3; 4], xi: [f64; 2]) -> (V3, V3, V3, V3) {
    let (t1, t2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let y = std::array::from_fn(|a| p[0][a] + xi[0] * t1[a] + xi[1] * t2[a]);
    (y, t1, t2, [0.0; 3])
}

/// Unit normal $\tau_1 \times \tau_2 / |\tau_1 \times \tau_2|$ (the same everywhere).
pub fn normal(p: &[V3; 4]) -> V3 {
    let c = cross(sub(p[1], p[0]), sub(p[2], p[0]));
    let l = norm(c);
    c.map(|x| x / l)
}

/// Below this ratio det(m) / (m_11 m_22) (the squared sine of the angle between the
/// tangents: about 0.06 degrees) the free minimum is not solved for: the edges give the
/// closest point, in f32 as in f64.
pub(crate) const SLIVER: f64 = 1e-6;

/// The edges of the triangle as (start corner, end corner, xi at the start, xi's change
/// along the edge).
const EDGES: [(usize, usize, [f64; 2], [f64; 2]); 3] = [
    (0, 1, [0.0, 0.0], [1.0, 0.0]),
    (1, 2, [1.0, 0.0], [-1.0, 1.0]),
    (0, 2, [0.0, 0.0], [0.0, 1.0]),
];

/// Closest point of the triangle to x: the xi that minimises |x - y(xi)| over the closed
/// triangle.
///
/// The distance is a convex quadratic in xi. Its free minimum solves the 2 x 2 normal
/// equations $m_{ab} \xi^b = (x - p_0) \cdot \tau_a$; where that lies outside the triangle,
/// or the triangle is a sliver whose metric is near singular ($\det m \le$ [`SLIVER`]
/// $m_{11} m_{22}$), the minimum is on the boundary: the closest of the three edges' clamped
/// projections.
pub fn project(p: &[V3; 4], x: V3) -> [f64; 2] {
    let (t1, t2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let r = sub(x, p[0]);
    let (m00, m01, m11) = (dot(t1, t1), dot(t1, t2), dot(t2, t2));
    let (f0, f1) = (dot(r, t1), dot(r, t2));
    let det = m00 * m11 - m01 * m01;
    if det > SLIVER * m00 * m11 {
        let xi = [(m11 * f0 - m01 * f1) / det, (m00 * f1 - m01 * f0) / det];
        if xi[0] >= 0.0 && xi[1] >= 0.0 && xi[0] + xi[1] <= 1.0 {
            return xi;
        }
    }
    let mut best = (f64::INFINITY, [0.0; 2]);
    for (a, b, start, along) in EDGES {
        let e = sub(p[b], p[a]);
        let ee = dot(e, e);
        let t = if ee > 0.0 {
            (dot(sub(x, p[a]), e) / ee).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let y: V3 = std::array::from_fn(|k| p[a][k] + t * e[k]);
        let d2 = dot(sub(x, y), sub(x, y));
        if d2 < best.0 {
            best = (d2, [start[0] + t * along[0], start[1] + t * along[1]]);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// A triangle's slots with corners in [-1, 1]^3.
    fn random_triangle(rng: &mut StdRng) -> [V3; 4] {
        let mut p = [[0.0; 3]; 4];
        for c in p.iter_mut().take(3) {
            *c = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        }
        p[3] = p[2];
        p
    }

    fn dist2(p: &[V3; 4], x: V3, xi: [f64; 2]) -> f64 {
        let (y, ..) = geometry(p, xi);
        dot(sub(y, x), sub(y, x))
    }

    /// Random triangles (slivers included) and points around them: the projection lies in
    /// the triangle and is never farther than the best point of a fine grid over it.
    #[test]
    fn projection_beats_a_fine_grid_search() {
        let mut rng = StdRng::seed_from_u64(11);
        let n = 200;
        for case in 0..500 {
            let mut p = random_triangle(&mut rng);
            if case % 5 == 0 {
                // a sliver: the third corner near the first edge
                let t = rng.random_range(0.0..1.0);
                p[2] = std::array::from_fn(|a| {
                    p[0][a] + t * (p[1][a] - p[0][a]) + 1e-3 * rng.random_range(-1.0..1.0)
                });
            }
            p[3] = p[2];
            let x: V3 = std::array::from_fn(|_| rng.random_range(-2.0..2.0));
            let xi = project(&p, x);
            assert!(
                xi[0] >= 0.0 && xi[1] >= 0.0 && xi[0] + xi[1] <= 1.0 + 1e-15,
                "case {case}: xi {xi:?} outside"
            );
            let d2 = dist2(&p, x, xi);
            for i in 0..=n {
                for j in 0..=n - i {
                    let g = [i as f64 / n as f64, j as f64 / n as f64];
                    assert!(
                        d2 <= dist2(&p, x, g) + 1e-12,
                        "case {case}: xi {xi:?} worse than grid {g:?}"
                    );
                }
            }
        }
    }

    /// The shape functions interpolate the corners into the map y(xi): sum_k N_k p_k = y at
    /// random xi (a swap of the two coordinates' functions fails this).
    #[test]
    fn shape_functions_give_the_map() {
        let mut rng = StdRng::seed_from_u64(5);
        for _ in 0..100 {
            let p = random_triangle(&mut rng);
            let a = rng.random_range(0.0..1.0);
            let xi = [a, rng.random_range(0.0..1.0 - a)];
            let n = shape(xi);
            let (y, ..) = geometry(&p, xi);
            for d in 0..3 {
                let sum: f64 = (0..4).map(|k| n[k] * p[k][d]).sum();
                assert!(
                    (sum - y[d]).abs() < 1e-14,
                    "xi {xi:?}: {sum} against {}",
                    y[d]
                );
            }
        }
    }

    /// Inside the triangle the offset to the point is along the normal; a point above a
    /// corner's outside region goes to that corner.
    #[test]
    fn interior_and_corner_projections() {
        let p = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(normal(&p), [0.0, 0.0, 1.0]);
        assert_eq!(project(&p, [0.5, 0.25, -3.0]), [0.25, 0.25]);
        assert_eq!(project(&p, [3.0, -1.0, 0.5]), [1.0, 0.0]);
        assert_eq!(project(&p, [-1.0, -1.0, 0.5]), [0.0, 0.0]);
        let s = shape([0.25, 0.5]);
        assert_eq!(s.iter().sum::<f64>(), 1.0);
        assert_eq!(s[3], 0.0);
    }

    /// A triangle with no area still projects onto its longest edge.
    #[test]
    fn a_degenerate_triangle_projects_onto_its_edge() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        let xi = project(&p, [1.5, 1.0, 0.0]);
        let (y, ..) = geometry(&p, xi);
        assert!((y[0] - 1.5).abs() < 1e-15 && y[1] == 0.0, "{y:?}");
    }
}
