//! A static step's Coulomb friction: incremental slip with a stick slope (CalculiX's
//! regularised law). Over an increment each pressed row's node moves against its face by
//! $\Delta x = -\sum_j c_j \Delta u_j$ (the row's entries); the trial traction on the node is
//! $\tau^* = P_t \tau_n - k_t P_t \Delta x$, with $P_t = I - n n^T$, $\tau_n$ the traction the
//! last increment ended with and $k_t$ the stick slope (shear stress per unit slip). Within
//! the cone $|\tau^*| \le \mu T$ the node sticks, $\tau = \tau^*$; beyond it it slides,
//! $\tau = \mu T\, \tau^* / |\tau^*|$ (the return to the cone). The matrix takes
//! $k_t A\, c_i c_j P_t$ sticking and $k_t A\, (\mu T / |\tau^*|) c_i c_j (P_t - t t^T)$
//! sliding ($t = \tau^*/|\tau^*|$; the pressure's own change is left out, which keeps it
//! symmetric).

use super::contact::Row;
use crate::geometry::vector::{dot, norm, sub};

type V3 = [f64; 3];

fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// The friction of a static run's interfaces.
#[derive(Debug, Clone)]
pub(super) struct Friction {
    /// Each interface's coefficient (0: frictionless).
    pub mu: Vec<f64>,
    /// Each interface's secondary nodes' stick slope.
    pub slope: Vec<Vec<f64>>,
    /// The traction each node ended the last accepted increment with.
    pub tau: Vec<Vec<V3>>,
}

/// A row's friction at its slip: the traction on the node, and the matrix's factor and
/// the sliding direction where it slides.
pub(super) struct Traction {
    pub tau: V3,
    /// $k_t$ sticking, $k_t \mu T / |\tau^*|$ sliding.
    pub stiffness: f64,
    pub sliding: Option<V3>,
}

impl Friction {
    pub fn is_frictional(&self, interface: usize) -> bool {
        self.mu[interface] > 0.0
    }

    /// The traction of `r` at pressure `t` and its relative motion `dx` over the increment.
    pub fn traction(&self, r: &Row, t: f64, dx: V3) -> Traction {
        let (k, i) = (r.interface, r.point);
        let n = r.normal;
        let tangent = |v: V3| sub(v, scale(n, dot(v, n)));
        let kt = self.slope[k][i];
        let trial = sub(tangent(self.tau[k][i]), scale(tangent(dx), kt));
        let limit = self.mu[k] * t;
        let size = norm(trial);
        if size <= limit || size == 0.0 {
            return Traction {
                tau: trial,
                stiffness: kt,
                sliding: None,
            };
        }
        let dir = scale(trial, 1.0 / size);
        Traction {
            tau: scale(dir, limit),
            stiffness: kt * limit / size,
            sliding: Some(dir),
        }
    }

    /// The matrix block $P_t$ (sticking) or $P_t - t t^T$ (sliding) of a row, entry (a, b).
    pub fn block(r: &Row, sliding: Option<V3>, a: usize, b: usize) -> f64 {
        let id = if a == b { 1.0 } else { 0.0 };
        let p = id - r.normal[a] * r.normal[b];
        match sliding {
            Some(t) => p - t[a] * t[b],
            None => p,
        }
    }
}
