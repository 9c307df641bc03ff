// The signed distance from a point to a rigid body's analytic surface (twin:
// `geometry::rigid_shape`, `RigidShape::distance`): positive outside the solid, with the unit
// outward normal at the closest surface point. The point `r` is relative to the body's
// reference point (the body translates, it does not rotate).

struct SignedDistance {
    d: f32,
    n: vec3<f32>,
}

struct PlanarDistance {
    d: f32,
    g: vec2<f32>,
}

// Rust's signum: +1 at +0.
fn signum(x: f32) -> f32 {
    return select(-1.0, 1.0, x >= 0.0);
}

// Distance from `r` to the sphere of `radius` about `c`, and the outward normal (along the
// first axis at the centre itself).
fn sphere_distance(r: vec3<f32>, c: vec3<f32>, radius: f32) -> SignedDistance {
    let d = r - c;
    let l = length(d);
    var n = vec3<f32>(1.0, 0.0, 0.0);
    if (l > 0.0) {
        n = d / l;
    }
    return SignedDistance(l - radius, n);
}

// The length d of (a, b), a and b >= 0 and not both zero, and the unit vector (a, b) / d,
// as (d, a / d, b / d) (twin: `rigid_shape::scaled_hypot`): scaled by the larger part, so
// that parts whose squares are below f32's normal range (flushed to zero on GPU hardware)
// keep a unit direction.
fn scaled_hypot(a: f32, b: f32) -> vec3<f32> {
    let m = max(a, b);
    let r = vec2<f32>(a, b) / m;
    let l = sqrt(dot(r, r));
    return vec3<f32>(m * l, r / l);
}

// The intersection of two solids given by their signed distances and orthogonal unit outward
// gradients: inside both, the larger distance with its normal; outside, the Euclidean
// combination of the positive parts.
fn extruded(a: SignedDistance, b: SignedDistance) -> SignedDistance {
    if (a.d <= 0.0 && b.d <= 0.0) {
        if (a.d >= b.d) {
            return a;
        }
        return b;
    }
    let h = scaled_hypot(max(a.d, 0.0), max(b.d, 0.0));
    return SignedDistance(h.x, h.y * a.n + h.z * b.n);
}

// Signed distance from `p` to the centred rectangle of half-sides `h`, and its unit gradient.
fn rectangle_distance(p: vec2<f32>, h: vec2<f32>) -> PlanarDistance {
    let q = abs(p) - h;
    let s = vec2<f32>(signum(p.x), signum(p.y));
    if (q.x <= 0.0 && q.y <= 0.0) {
        if (q.x >= q.y) {
            return PlanarDistance(q.x, vec2<f32>(s.x, 0.0));
        }
        return PlanarDistance(q.y, vec2<f32>(0.0, s.y));
    }
    let o = scaled_hypot(max(q.x, 0.0), max(q.y, 0.0));
    return PlanarDistance(o.x, s * o.yz);
}

// Signed distance in the plane from `p` to the frame `size` minus the centred `opening`
// (negative on the frame), and its unit gradient.
fn frame_distance(p: vec2<f32>, size: vec2<f32>, opening: vec2<f32>) -> PlanarDistance {
    let outer = rectangle_distance(p, 0.5 * size);
    if (opening.x <= 0.0 || opening.y <= 0.0) {
        return outer;
    }
    let window = rectangle_distance(p, 0.5 * opening);
    if (outer.d >= -window.d) {
        return outer;
    }
    return PlanarDistance(-window.d, -window.g);
}

fn rigid_distance(s: RigidSurface, r: vec3<f32>) -> SignedDistance {
    let axis = vec3_of(s.axis);
    switch s.kind {
        case RIGID_SPHERE: {
            return sphere_distance(r, vec3<f32>(0.0), s.radius);
        }
        case RIGID_CAPSULE: {
            let c = clamp(dot(r, axis), -0.5 * s.length, 0.5 * s.length);
            return sphere_distance(r, c * axis, s.radius);
        }
        case RIGID_CYLINDER: {
            let along = dot(r, axis);
            let radial = r - along * axis;
            let rho = length(radial);
            var e_r = vec3_of(s.e1);
            if (rho > 0.0) {
                e_r = radial / rho;
            }
            return extruded(
                SignedDistance(rho - s.radius, e_r),
                SignedDistance(abs(along) - 0.5 * s.length, signum(along) * axis),
            );
        }
        case RIGID_PLATE: {
            let e1 = vec3_of(s.e1);
            let e2 = vec3_of(s.e2);
            let f = frame_distance(
                vec2<f32>(dot(r, e1), dot(r, e2)),
                vec2<f32>(s.size_a, s.size_b),
                vec2<f32>(s.opening_a, s.opening_b),
            );
            // the solid is the frame extruded to the side opposite the normal
            return extruded(
                SignedDistance(f.d, f.g.x * e1 + f.g.y * e2),
                SignedDistance(dot(r, axis), axis),
            );
        }
        default: {
            // RIGID_PLANE
            return SignedDistance(dot(r, axis), axis);
        }
    }
}
