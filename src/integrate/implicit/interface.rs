//! The contact state of one interface in the implicit path, carried from step to step: the
//! multipliers, the kinematics, the penalties and the friction state.

use crate::contact::augmented_lagrange::{IterationMemory, Penalty};
use crate::contact::friction::Friction;
use crate::geometry::face::Face;
use crate::kernels::ContactPoint;
use crate::linalg::Assembled;
use crate::model::{Model, Primary};
use crate::scene::ImplicitSettings;

use super::super::state::ContactReport;

/// Contact state of one interface, carried from step to step.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct InterfaceState {
    /// Converged pressure of each secondary node over the last step.
    pub lambda: Vec<f64>,
    /// Kinematics at the end of the last step.
    pub points: Vec<ContactPoint>,
    pub penalty: Penalty,
    /// The tangential state, where the interface's law is frictional.
    pub friction: Option<Friction>,
    pub(super) memory: IterationMemory,
    pub(super) candidate: Vec<bool>,
    pub(super) measure: Vec<f64>,
    pub(super) next: Vec<f64>,
    /// Total normal force at the end of the last step (classical endpoint forces only).
    pub(super) endpoint_force: f64,
    /// Total friction force vector of the last step (impulse / step).
    pub(super) tangential: [f64; 3],
    /// Largest normal force reported so far.
    pub(super) peak_force: f64,
    /// Change of the reported normal force over the last step.
    pub(super) last_change: f64,
    /// Normal and tangential penalties as the sub-steps of the last contact event left them.
    pub(super) sub_penalties: Option<(f64, f64)>,
    /// The last step's mean pressure of each node (impulse / (dt A)) when the step was
    /// refined into sub-steps; empty otherwise (then it is `lambda`).
    pub(super) step_pressure: Vec<f64>,
    pub report: ContactReport,
}

impl InterfaceState {
    /// Node i's contact pressure over the last step: its impulse / (dt A).
    pub fn step_pressure(&self, i: usize) -> f64 {
        if self.step_pressure.is_empty() {
            self.lambda[i]
        } else {
            self.step_pressure[i]
        }
    }

    /// Increases and decreases of the normal and tangential penalties so far.
    pub(super) fn penalty_counts(&self) -> [usize; 4] {
        let (ti, td) = self
            .friction
            .as_ref()
            .map_or((0, 0), |f| (f.penalty.increases, f.penalty.decreases));
        [self.penalty.increases, self.penalty.decreases, ti, td]
    }

    pub(super) fn set_penalty_counts(&mut self, c: [usize; 4]) {
        self.penalty.increases = c[0];
        self.penalty.decreases = c[1];
        if let Some(f) = &mut self.friction {
            f.penalty.increases = c[2];
            f.penalty.decreases = c[3];
        }
    }

    /// The normal and tangential penalties (0 for the latter without friction).
    pub(super) fn penalties(&self) -> (f64, f64) {
        let eps_t = self.friction.as_ref().map_or(0.0, |f| f.penalty.eps);
        (self.penalty.eps, eps_t)
    }

    pub(super) fn set_penalties(&mut self, (eps_n, eps_t): (f64, f64)) {
        self.penalty.eps = eps_n;
        if let Some(f) = &mut self.friction {
            f.penalty.eps = eps_t;
        }
    }
}

/// Each interface's multipliers, penalties (eps_N from the scene or estimated, eps_T from
/// the scene or eps_N) and friction state at the start of a run.
pub(super) fn interface_states(
    model: &Model,
    settings: &ImplicitSettings,
    asm: &Assembled,
    dt: f64,
    speed_scale: f64,
) -> Vec<InterfaceState> {
    let mar = settings
        .max_gap_rate
        .unwrap_or(1e-3 * speed_scale.max(f64::MIN_POSITIVE));
    model
        .interfaces
        .iter()
        .map(|itf| {
            let eps = settings
                .penalty_normal
                .unwrap_or_else(|| default_penalty(model, asm, itf, dt));
            let n = itf.nodes.len();
            let friction = itf.law.is_frictional().then(|| {
                let eps_t = settings.penalty_tangential.unwrap_or(eps);
                let p = Penalty::new(eps_t, settings.penalty, mar, settings.max_force_change);
                Friction::new(itf.law, p, &itf.area)
            });
            InterfaceState {
                lambda: vec![0.0; n],
                points: vec![ContactPoint::default(); n],
                penalty: Penalty::new(eps, settings.penalty, mar, settings.max_force_change),
                friction,
                memory: IterationMemory::default(),
                candidate: vec![false; n],
                measure: vec![0.0; n],
                next: vec![0.0; n],
                endpoint_force: 0.0,
                tangential: [0.0; 3],
                peak_force: 0.0,
                last_change: 0.0,
                sub_penalties: None,
                step_pressure: Vec::new(),
                report: ContactReport::default(),
            }
        })
        .collect()
}

/// The initial eps_N when the scene gives none: $1/\hat s$ with the mass-only compliance
/// $\hat s = \Delta t\, A (1/m_s + 1/m_p)$ (median over the interface's nodes, m the
/// lumped mass or the consistent mass's diagonal), the gap-rate
/// change per unit pressure if the elastic stiffness did not resist. The true compliance is
/// smaller, so $\epsilon s \le 1$: inside the stable range, near its centre.
fn default_penalty(model: &Model, asm: &Assembled, itf: &crate::model::Interface, dt: f64) -> f64 {
    let inv_mp = match &itf.primary {
        Primary::Plane { .. } => 0.0,
        Primary::Rigid { node, .. } if model.fixed[3 * *node as usize] => 0.0,
        Primary::Rigid { node, .. } => 1.0 / asm.impulse_mass[*node as usize],
        Primary::Surface { faces, .. } => {
            let primary: Vec<Face> = (model.queries.faces[faces.clone()].iter())
                .map(|&s| Face::from_slots(s))
                .collect();
            let nodes = crate::mesh::Mesh::face_nodes(&primary);
            let mean: f64 = nodes
                .iter()
                .map(|&n| asm.impulse_mass[n as usize])
                .sum::<f64>()
                / nodes.len() as f64;
            1.0 / mean
        }
    };
    let mut s: Vec<f64> = itf
        .nodes
        .iter()
        .zip(&itf.area)
        .map(|(&n, &a)| dt * a * (1.0 / asm.impulse_mass[n as usize] + inv_mp))
        .collect();
    s.sort_by(f64::total_cmp);
    let med = s.get(s.len() / 2).copied().unwrap_or(1.0);
    1.0 / med
}
