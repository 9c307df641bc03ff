//! The rotation of rigid bodies on the explicit path. A body that rotates carries, besides
//! its node's translation, its orientation (body to world) and, where it is free, its angular
//! momentum about its reference point (its centre of mass: gravity gives no torque there).
//!
//! Between contact impulses a free body's angular momentum is constant; its angular
//! velocity is $\omega = I_w^{-1} L$ with the world inertia $I_w = R I R^T$. A step's
//! contact impulse $J$ on a secondary node at arm $r$ from the reference point gives the body
//! $-J$ and the angular impulse $r \times (-J)$; the orientation then turns by
//! $\exp(\Delta t\, \omega_{n+1/2})$ (Rodrigues) with the step's angular velocity. A
//! prescribed body spins at its angular velocity whatever the forces. The rotational
//! kinetic energy is $\tfrac12 \omega_{n+1/2} \cdot L$.

use crate::model::Model;

type M3 = [[f64; 3]; 3];

const IDENTITY: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// One body's rotation state (a body that does not rotate keeps the identity and zeros).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodySpin {
    /// Body to world.
    pub rotation: M3,
    /// Angular momentum about the reference point (a free body's).
    pub momentum: [f64; 3],
    /// Angular velocity now, and over the last step (the energy's).
    pub omega: [f64; 3],
    pub omega_half: [f64; 3],
}

impl Default for BodySpin {
    fn default() -> Self {
        BodySpin {
            rotation: IDENTITY,
            momentum: [0.0; 3],
            omega: [0.0; 3],
            omega_half: [0.0; 3],
        }
    }
}

/// Every rigid body's rotation, in the model's order.
#[derive(Debug, Clone)]
pub struct Spins {
    pub bodies: Vec<BodySpin>,
    /// The inverse inertia in the body's axes, where the body is free to rotate.
    inv_inertia: Vec<Option<M3>>,
    /// The largest eigenvalue of the inverse inertia (the row-sum bound of the contact's
    /// rotational compliance), zero where the body is not free to rotate.
    pub inv_max: Vec<f64>,
    rotates: Vec<bool>,
}

fn mul(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn transpose(a: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

fn apply(a: &M3, x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| (0..3).map(|k| a[i][k] * x[k]).sum())
}

/// exp of the skew matrix of `w` (Rodrigues).
fn exp_skew(w: [f64; 3]) -> M3 {
    let theta = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if theta == 0.0 {
        return IDENTITY;
    }
    let k = w.map(|x| x / theta);
    let kx: M3 = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]];
    let kx2 = mul(&kx, &kx);
    let (s, c) = theta.sin_cos();
    std::array::from_fn(|i| {
        std::array::from_fn(|j| IDENTITY[i][j] + s * kx[i][j] + (1.0 - c) * kx2[i][j])
    })
}

impl Spins {
    /// Every body at rest in its reference orientation, with its initial angular velocity.
    pub fn new(model: &Model) -> Self {
        let mut s = Spins {
            bodies: Vec::with_capacity(model.rigid.len()),
            inv_inertia: Vec::with_capacity(model.rigid.len()),
            inv_max: Vec::with_capacity(model.rigid.len()),
            rotates: model.rigid.iter().map(|b| b.rotates()).collect(),
        };
        for b in &model.rigid {
            let inv = b.inertia.map(|i| {
                let m = nalgebra::Matrix3::from_fn(|a, c| i[a][c]);
                let inv = m
                    .try_inverse()
                    .expect("a positive definite inertia (scene checks)");
                std::array::from_fn(|a| std::array::from_fn(|c| inv[(a, c)]))
            });
            let max = b.inertia.map_or(0.0, |i| {
                let m = nalgebra::Matrix3::from_fn(|a, c| i[a][c]);
                1.0 / m.symmetric_eigenvalues().min()
            });
            let momentum = b
                .inertia
                .map_or([0.0; 3], |i| apply(&i, b.angular_velocity));
            s.bodies.push(BodySpin {
                momentum,
                omega: b.angular_velocity,
                omega_half: b.angular_velocity,
                ..Default::default()
            });
            s.inv_inertia.push(inv);
            s.inv_max.push(max);
        }
        s
    }

    /// Whether any body rotates.
    pub fn any(&self) -> bool {
        self.rotates.iter().any(|&r| r)
    }

    /// Whether body `b` rotates.
    pub fn rotates(&self, b: usize) -> bool {
        self.rotates[b]
    }

    /// Whether body `b` is free to rotate (it has an inertia).
    pub fn is_free(&self, b: usize) -> bool {
        self.inv_inertia[b].is_some()
    }

    /// Its angular velocity now.
    pub fn omega(&self, b: usize) -> [f64; 3] {
        self.bodies[b].omega
    }

    /// Its orientation (body to world).
    pub fn rotation(&self, b: usize) -> &M3 {
        &self.bodies[b].rotation
    }

    /// The angular velocity of a free body from its momentum: $(R I^{-1} R^T) L$.
    fn omega_of(&self, b: usize) -> [f64; 3] {
        let s = &self.bodies[b];
        let inv = self.inv_inertia[b].as_ref().expect("a free body");
        let r = &s.rotation;
        apply(r, apply(inv, apply(&transpose(r), s.momentum)))
    }

    /// Adds the angular impulse `dl` (about its reference point) to free body `b`.
    pub fn add_angular_impulse(&mut self, b: usize, dl: [f64; 3]) {
        for (l, d) in self.bodies[b].momentum.iter_mut().zip(dl) {
            *l += d;
        }
        self.bodies[b].omega = self.omega_of(b);
    }

    /// Turns every rotating body over a step of `dt` at its angular velocity now (the
    /// step's, after the contact impulses); a free body's angular velocity then follows
    /// its new orientation.
    pub fn drift(&mut self, dt: f64) {
        for b in 0..self.bodies.len() {
            if !self.rotates[b] {
                continue;
            }
            let s = &mut self.bodies[b];
            s.omega_half = s.omega;
            s.rotation = mul(&exp_skew(s.omega.map(|w| w * dt)), &s.rotation);
            if self.inv_inertia[b].is_some() {
                self.bodies[b].omega = self.omega_of(b);
            }
        }
    }

    /// The kinetic energy of the free bodies' rotation over the last step,
    /// $\tfrac12 \omega_{n+1/2} \cdot L$.
    pub fn kinetic(&self) -> f64 {
        (self.bodies.iter().zip(&self.inv_inertia))
            .filter(|(_, inv)| inv.is_some())
            .map(|(s, _)| 0.5 * (0..3).map(|a| s.omega_half[a] * s.momentum[a]).sum::<f64>())
            .sum()
    }

    /// The rotation vector of body `b`'s orientation (its axis times its angle, in radians).
    pub fn rotation_vector(&self, b: usize) -> [f64; 3] {
        let r = &self.bodies[b].rotation;
        let m = nalgebra::Matrix3::from_fn(|i, j| r[i][j]);
        let v = nalgebra::Rotation3::from_matrix_unchecked(m).scaled_axis();
        [v.x, v.y, v.z]
    }

    /// The states a checkpoint keeps: every body's where any rotates, none otherwise.
    pub fn saved(&self) -> Vec<BodySpin> {
        match self.any() {
            true => self.bodies.clone(),
            false => Vec::new(),
        }
    }

    /// Each rotating body's rotation vector and angular velocity (the history's columns).
    pub fn columns(&self) -> Vec<crate::integrate::ProbeValues> {
        (0..self.bodies.len())
            .filter(|&b| self.rotates[b])
            .map(|b| (self.rotation_vector(b), self.omega(b)))
            .collect()
    }

    /// Continues from a checkpoint's states (one per body).
    pub fn restore(&mut self, bodies: Vec<BodySpin>) {
        if bodies.len() == self.bodies.len() {
            self.bodies = bodies;
        }
    }
}
