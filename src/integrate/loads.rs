//! The model's loads over a run ([`crate::model::loads`]), on the nodes an integrator holds
//! (all of them, or a rank's), and the work they do.
//!
//! The integrators keep the loads in their external force vector beside gravity:
//! [`LoadForces::set`] puts each loaded dof's value at a time there. The work of a load of
//! amplitude $a(t)$ and full nodal forces $F$ over a step is the trapezoid
//! $\tfrac12 (a(t_n) + a(t_{n+1}))\, F \cdot (u_{n+1} - u_n)$: exact for the trapezoidal
//! rule, whose forces act at the step's ends. Central difference conserves
//! $\sum_k f_k \cdot (u_{k+1} - u_{k-1})/2$ instead; that is the trapezoid's sum less
//! $\tfrac12 f_{n+1} \cdot (u_{n+1} - u_n)$ ([`LoadForces::centred`]), which for a constant
//! force is the time-centred potential $-f \cdot (u_n + u_{n+1})/2$ gravity has.

use crate::model::Model;

/// The loads' nodal forces on an integrator's nodes.
#[derive(Debug, Clone, Default)]
pub(crate) struct LoadForces {
    /// Each entry's local dof, load, nodal force at full amplitude and whether the work of
    /// the entry is this integrator's to count (a rank counts its owned nodes').
    entries: Vec<Entry>,
    /// The external force at each entry's dof without the loads (gravity's).
    base: Vec<f64>,
}

#[derive(Debug, Clone, Copy)]
struct Entry {
    dof: usize,
    load: usize,
    force: f64,
    counted: bool,
}

impl LoadForces {
    /// The loads on `nodes` (increasing global numbers; all the model's where `None`), whose
    /// work counts where `counted` is true (every node's where `None`); `f_ext` is the
    /// external force on those nodes without the loads.
    pub fn new(
        model: &Model,
        nodes: Option<&[u32]>,
        counted: Option<&[bool]>,
        f_ext: &[f64],
    ) -> Self {
        let mut entries = Vec::new();
        for (load, l) in model.loads.iter().enumerate() {
            for (&d, &force) in l.dofs.iter().zip(&l.force) {
                let node = match nodes {
                    None => Some(d as usize / 3),
                    Some(n) => n.binary_search(&(d / 3)).ok(),
                };
                if let Some(i) = node {
                    entries.push(Entry {
                        dof: 3 * i + d as usize % 3,
                        load,
                        force,
                        counted: counted.is_none_or(|c| c[i]),
                    });
                }
            }
        }
        let base = entries.iter().map(|e| f_ext[e.dof]).collect();
        LoadForces { entries, base }
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The external force at time `t` at the loaded dofs: gravity's and the loads'.
    pub fn set(&self, model: &Model, t: f64, f_ext: &mut [f64]) {
        for (e, &b) in self.entries.iter().zip(&self.base) {
            f_ext[e.dof] = b;
        }
        for e in &self.entries {
            f_ext[e.dof] += model.loads[e.load].amplitude.at(t) * e.force;
        }
    }

    /// Each load's full nodal forces dotted with `x` over the counted entries.
    pub fn dots(&self, model: &Model, x: &[f64]) -> Vec<f64> {
        let mut d = vec![0.0; model.loads.len()];
        for e in self.entries.iter().filter(|e| e.counted) {
            d[e.load] += e.force * x[e.dof];
        }
        d
    }

    /// An explicit step from `t` of `dt`, just drifted from `u_prev` to `u`: puts the loads'
    /// force at its end into `f_ext` and returns their work over it (the trapezoid; 0
    /// without loads). Work counts on the counted entries.
    pub fn explicit_step(
        &self,
        model: &Model,
        (t, dt): (f64, f64),
        (u_prev, u): (&[f64], &[f64]),
        f_ext: &mut [f64],
    ) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let (d0, d1) = (self.dots(model, u_prev), self.dots(model, u));
        let work = Self::step_work(model, (t, t + dt), (&d0, &d1));
        self.set(model, t + dt, f_ext);
        work
    }

    /// The loads' part of central difference's time-centred potential at time `t`, after a
    /// step from `u_prev` to `u`, with the trapezoid sum `work` ([`Self::centred_share`]; 0
    /// without loads).
    pub fn centred_potential(
        &self,
        model: &Model,
        t: f64,
        work: f64,
        (u_prev, u): (&[f64], &[f64]),
    ) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let (d0, d1) = (self.dots(model, u_prev), self.dots(model, u));
        Self::centred_share(model, work, t, (&d0, &d1))
    }

    /// The loads' force at time `t` dotted with the `dots` ([`Self::dots`]) of a vector.
    pub fn at(model: &Model, t: f64, dots: &[f64]) -> f64 {
        (model.loads.iter().zip(dots))
            .map(|(l, d)| l.amplitude.at(t) * d)
            .sum()
    }

    /// The trapezoid work of a step from `t0` to `t1`, with the [`Self::dots`] of the
    /// displacement at its start and end.
    pub fn step_work(model: &Model, (t0, t1): (f64, f64), (d0, d1): (&[f64], &[f64])) -> f64 {
        let step: Vec<f64> = d1.iter().zip(d0).map(|(a, b)| a - b).collect();
        0.5 * (Self::at(model, t0, &step) + Self::at(model, t1, &step))
    }

    /// The loads' part of central difference's time-centred potential after a step that
    /// ends at `t1`, from the trapezoid sum `work` and the step's [`Self::dots`]: their share
    /// of $-f_{ext} \cdot (u_n + u_{n+1})/2$ taken back, less their conserved work
    /// `work` $- \tfrac12 f_{n+1} \cdot (u_{n+1} - u_n)$ (see the module's notes).
    fn centred_share(model: &Model, work: f64, t1: f64, (d0, d1): (&[f64], &[f64])) -> f64 {
        let step: Vec<f64> = d1.iter().zip(d0).map(|(a, b)| a - b).collect();
        let conserved = work - 0.5 * Self::at(model, t1, &step);
        0.5 * (Self::at(model, t1, d0) + Self::at(model, t1, d1)) - conserved
    }

    /// The loads' part of `f_ext` at time `t` dotted with `x`, over the counted entries.
    pub fn in_dot(&self, model: &Model, t: f64, x: &[f64]) -> f64 {
        Self::at(model, t, &self.dots(model, x))
    }
}

/// The body force m g on the free dofs, from the lumped nodal masses `nodal_mass` (the
/// implicit and static solvers' external force without the loads).
pub(crate) fn gravity_force(model: &Model, nodal_mass: &[f64]) -> Vec<f64> {
    let mut f_ext = vec![0.0; model.dofs()];
    for (n, &m) in nodal_mass.iter().enumerate() {
        for a in 0..3 {
            if !model.fixed[3 * n + a] {
                f_ext[3 * n + a] = m * model.gravity[a];
            }
        }
    }
    f_ext
}
