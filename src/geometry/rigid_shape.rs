//! The surfaces of rigid bodies: a sphere, a cylinder (flat or round ends), a plane, a flat
//! plate with a centred rectangular window, and a meshed surface ([`super::rigid_mesh`]).
//!
//! Every shape is placed by its body's reference point: [`RigidShape::distance`] takes the
//! point relative to it and returns the signed distance to the surface (positive outside the
//! solid) and the unit outward normal at the closest surface point. A secondary node's contact
//! gap is minus the distance ([`crate::model::Primary`]: positive when it penetrates), and the
//! normal is the direction the surface pushes it.

use super::vector::{cross, dot, norm, sub};

type V3 = [f64; 3];

/// A rigid body's surface, in its body's frame (the body translates, it does not rotate).
#[derive(Debug, Clone, PartialEq)]
pub enum RigidShape {
    /// A ball of `radius` centred on the reference point.
    Sphere { radius: f64 },
    /// A cylinder of `radius` along the unit `axis`, its straight part `length` long and
    /// centred on the reference point; `round` ends are hemispheres of `radius` beyond it
    /// (a capsule), otherwise the ends are flat discs.
    Cylinder {
        radius: f64,
        axis: V3,
        length: f64,
        round: bool,
    },
    /// A flat face through the reference point with unit `normal` into the free side; the
    /// solid fills the other side.
    Plane { normal: V3 },
    /// A flat support through the reference point with unit `normal` into the free side:
    /// `size[0]` x `size[1]` along the in-plane axes `axes`, minus a centred window of
    /// `opening[0]` x `opening[1]` (zeros for none); the solid fills the side opposite the
    /// normal below that region.
    Plate {
        normal: V3,
        axes: [V3; 2],
        size: [f64; 2],
        opening: [f64; 2],
    },
    /// A meshed surface (a mesh file's named surface), its coordinates relative to the
    /// reference point; the solid is on the side opposite its faces' outward normals.
    Mesh(std::sync::Arc<super::rigid_mesh::RigidMesh>),
}

impl RigidShape {
    /// Half the solid's thinnest width (a ball's or a cylinder's radius, half a closed meshed
    /// shape's smallest extent); `None` for the flat shapes and open meshed surfaces, whose
    /// solid fills the space behind them.
    pub fn half_thickness(&self) -> Option<f64> {
        match self {
            RigidShape::Sphere { radius } | RigidShape::Cylinder { radius, .. } => Some(*radius),
            RigidShape::Mesh(m) if !m.is_closed() => None,
            RigidShape::Mesh(m) => {
                let (lo, hi) = m.bounds();
                Some((0..3).map(|a| hi[a] - lo[a]).fold(f64::INFINITY, f64::min) / 2.0)
            }
            RigidShape::Plane { .. } | RigidShape::Plate { .. } => None,
        }
    }

    /// The plate's in-plane axes for a unit `normal`: the first of x, y, z that is not
    /// parallel to the normal, projected into the plane, then normal x that axis.
    pub fn plate_axes(normal: V3) -> [V3; 2] {
        let first = (0..3)
            .map(|a| {
                let mut e = [0.0; 3];
                e[a] = 1.0;
                let along = dot(e, normal);
                std::array::from_fn(|k| e[k] - along * normal[k])
            })
            .find(|p: &V3| norm(*p) > 1e-6)
            .expect("a unit normal leaves two axes out of its plane");
        let l = norm(first);
        let e1 = first.map(|x| x / l);
        [e1, cross(normal, e1)]
    }

    /// Signed distance from the point `r` (relative to the reference point) to the surface,
    /// positive outside the solid, and the unit outward normal at the closest point.
    pub fn distance(&self, r: V3) -> (f64, V3) {
        match *self {
            RigidShape::Mesh(ref m) => m.distance(r),
            RigidShape::Sphere { radius } => from_point(r, [0.0; 3], radius),
            RigidShape::Cylinder {
                radius,
                axis,
                length,
                round,
            } => {
                let s = dot(r, axis);
                if round {
                    let c = s.clamp(-0.5 * length, 0.5 * length);
                    return from_point(r, axis.map(|a| c * a), radius);
                }
                let radial = sub(r, axis.map(|a| s * a));
                let rho = norm(radial);
                let e_r = if rho > 0.0 {
                    radial.map(|x| x / rho)
                } else {
                    RigidShape::plate_axes(axis)[0]
                };
                let e_s = axis.map(|a| s.signum() * a);
                extruded((rho - radius, e_r), (s.abs() - 0.5 * length, e_s))
            }
            RigidShape::Plane { normal } => (dot(r, normal), normal),
            RigidShape::Plate {
                normal,
                axes,
                size,
                opening,
            } => {
                let p = [dot(r, axes[0]), dot(r, axes[1])];
                let (d2, g2) = window_frame(p, size, opening);
                let g = std::array::from_fn(|k| g2[0] * axes[0][k] + g2[1] * axes[1][k]);
                // the solid is the frame extruded to the side opposite the normal
                extruded((d2, g), (dot(r, normal), normal))
            }
        }
    }
}

/// Distance from `r` to the sphere of `radius` about `c`, and the outward normal (along the
/// first axis at the centre itself).
fn from_point(r: V3, c: V3, radius: f64) -> (f64, V3) {
    let d = sub(r, c);
    let l = norm(d);
    let n = if l > 0.0 {
        d.map(|x| x / l)
    } else {
        [1.0, 0.0, 0.0]
    };
    (l - radius, n)
}

/// The signed distance of the intersection of two solids given by their signed distances
/// and unit outward gradients: inside both, the larger distance with its normal; outside,
/// the Euclidean combination of the positive parts (the gradients are orthogonal).
fn extruded((a, ga): (f64, V3), (b, gb): (f64, V3)) -> (f64, V3) {
    if a <= 0.0 && b <= 0.0 {
        return if a >= b { (a, ga) } else { (b, gb) };
    }
    let (d, ca, cb) = scaled_hypot(a.max(0.0), b.max(0.0));
    (d, std::array::from_fn(|k| ca * ga[k] + cb * gb[k]))
}

/// The length d of (a, b), a and b >= 0 and not both zero, and the unit vector (a, b) / d,
/// as (d, a / d, b / d): scaled by the larger part, as the device computes it (there, parts
/// whose squares are below f32's normal range are flushed to zero).
fn scaled_hypot(a: f64, b: f64) -> (f64, f64, f64) {
    let m = a.max(b);
    let (ra, rb) = (a / m, b / m);
    let l = (ra * ra + rb * rb).sqrt();
    (m * l, ra / l, rb / l)
}

/// Signed distance in the plane from `p` to the frame `size` minus the centred `opening`
/// (negative on the frame), and its unit gradient.
fn window_frame(p: [f64; 2], size: [f64; 2], opening: [f64; 2]) -> (f64, [f64; 2]) {
    let outer = rectangle(p, [0.5 * size[0], 0.5 * size[1]]);
    if opening[0] <= 0.0 || opening[1] <= 0.0 {
        return outer;
    }
    let (dw, gw) = rectangle(p, [0.5 * opening[0], 0.5 * opening[1]]);
    // the frame is the outer rectangle without the window: max(outer, -window)
    if outer.0 >= -dw {
        outer
    } else {
        (-dw, gw.map(|x| -x))
    }
}

/// Signed distance from `p` to the centred rectangle of half-sides `h`, and its unit gradient.
fn rectangle(p: [f64; 2], h: [f64; 2]) -> (f64, [f64; 2]) {
    let q = [p[0].abs() - h[0], p[1].abs() - h[1]];
    let sign = [p[0].signum(), p[1].signum()];
    if q[0] <= 0.0 && q[1] <= 0.0 {
        return if q[0] >= q[1] {
            (q[0], [sign[0], 0.0])
        } else {
            (q[1], [0.0, sign[1]])
        };
    }
    let (d, c0, c1) = scaled_hypot(q[0].max(0.0), q[1].max(0.0));
    (d, [sign[0] * c0, sign[1] * c1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    fn close3(a: V3, b: V3) -> bool {
        (0..3).all(|k| close(a[k], b[k]))
    }

    /// The distance's gradient by central differences, which must be the normal.
    fn gradient(s: &RigidShape, r: V3) -> V3 {
        let h = 1e-6;
        std::array::from_fn(|k| {
            let (mut a, mut b) = (r, r);
            a[k] += h;
            b[k] -= h;
            (s.distance(a).0 - s.distance(b).0) / (2.0 * h)
        })
    }

    #[test]
    fn sphere_and_plane() {
        let s = RigidShape::Sphere { radius: 2.0 };
        let (d, n) = s.distance([0.0, 3.0, 4.0]);
        assert!(close(d, 3.0) && close3(n, [0.0, 0.6, 0.8]));
        assert!(close(s.distance([0.0, 0.0, 0.5]).0, -1.5));
        let p = RigidShape::Plane {
            normal: [0.0, 0.0, 1.0],
        };
        assert_eq!(p.distance([5.0, -2.0, -0.25]), (-0.25, [0.0, 0.0, 1.0]));
    }

    #[test]
    fn capsule_is_a_sphere_about_the_nearest_axis_point() {
        let s = RigidShape::Cylinder {
            radius: 1.0,
            axis: [0.0, 0.0, 1.0],
            length: 4.0,
            round: true,
        };
        // beside the straight part, then beyond the lower end
        assert!(close(s.distance([3.0, 0.0, 1.5]).0, 2.0));
        let (d, n) = s.distance([0.0, 0.0, -3.5]);
        assert!(close(d, 0.5) && close3(n, [0.0, 0.0, -1.0]));
    }

    #[test]
    fn flat_cylinder_edges_faces_and_inside() {
        let s = RigidShape::Cylinder {
            radius: 1.0,
            axis: [0.0, 0.0, 1.0],
            length: 2.0,
            round: false,
        };
        // off the rim: distance to the circular edge
        let (d, n) = s.distance([4.0, 0.0, 5.0]);
        assert!(close(d, 5.0) && close3(n, [0.6, 0.0, 0.8]));
        // on the axis above the end face
        assert!(close3(s.distance([0.0, 0.0, 1.5]).1, [0.0, 0.0, 1.0]));
        // inside, nearer the side than the ends
        let (d, n) = s.distance([0.0, 0.9, 0.0]);
        assert!(close(d, -0.1) && close3(n, [0.0, 1.0, 0.0]));
    }

    #[test]
    fn plate_frame_around_its_window() {
        let normal = [0.0, 0.0, 1.0];
        let s = RigidShape::Plate {
            normal,
            axes: RigidShape::plate_axes(normal),
            size: [10.0, 6.0],
            opening: [4.0, 2.0],
        };
        // above the frame: the plane's distance
        let (d, n) = s.distance([3.0, 0.0, 0.5]);
        assert!(close(d, 0.5) && close3(n, [0.0, 0.0, 1.0]));
        // above the window's middle, below the face: the window's wall is the nearest
        let (d, n) = s.distance([0.0, 0.0, -0.5]);
        assert!(close(d, 1.0) && (close3(n, [0.0, -1.0, 0.0]) || close3(n, [0.0, 1.0, 0.0])));
        // pressed into the frame near the window's edge: pushed up
        let (d, n) = s.distance([2.5, 0.0, -0.1]);
        assert!(close(d, -0.1) && close3(n, [0.0, 0.0, 1.0]));
        // over the window, above the face: distance to the rim's edge
        let (d, _) = s.distance([1.7, 0.0, 0.4]);
        assert!(close(d, 0.5));
    }

    #[test]
    fn normals_are_the_distances_gradients() {
        let normal = [0.6, 0.0, 0.8];
        let shapes = [
            RigidShape::Sphere { radius: 1.3 },
            RigidShape::Cylinder {
                radius: 0.7,
                axis: [0.0, 0.6, 0.8],
                length: 1.1,
                round: true,
            },
            RigidShape::Cylinder {
                radius: 0.7,
                axis: [0.0, 0.6, 0.8],
                length: 1.1,
                round: false,
            },
            RigidShape::Plate {
                normal,
                axes: RigidShape::plate_axes(normal),
                size: [3.0, 2.0],
                opening: [1.0, 0.8],
            },
        ];
        let mut rng = StdRng::seed_from_u64(7);
        let mut next = || rng.random_range(-2.0..2.0);
        for s in &shapes {
            for _ in 0..200 {
                let r = [next(), next(), next()];
                let (_, n) = s.distance(r);
                let g = gradient(s, r);
                assert!((norm(n) - 1.0).abs() < 1e-12, "{s:?} at {r:?}");
                // away from the medial surfaces (where the gradient jumps) they agree
                if (0..3).all(|k| (g[k] - n[k]).abs() < 1e-4) {
                    continue;
                }
                let near_ridge = (norm(g) - 1.0).abs() > 1e-3;
                assert!(near_ridge, "{s:?} at {r:?}: normal {n:?}, gradient {g:?}");
            }
        }
    }
}
