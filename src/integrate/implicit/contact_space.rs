//! The multiplier iteration on the contact space (`implicit.contact_space = "auto"`).
//!
//! The effective matrix is factorised once and the element forces are linear in u, so once
//! a step's first solve has balanced the effective equation under the first multipliers, a
//! change $\Delta f_c$ of the contact forces moves the iterate by $K_{eff}^{-1} w_f \Delta
//! f_c$; the forces act on the contact equations C alone (the interfaces' secondary nodes,
//! their primary surfaces' nodes, their rigid bodies' nodes), and the kinematics read only
//! those, so each later iteration needs only $(K_{eff}^{-1})_{CC}$, the trailing block of a
//! factor that numbers C last ([`crate::linalg::contact_space`]), and, for the gap rate
//! with a consistent mass, $(M^{-1})_{CC}$ likewise. After the iteration the rest of the
//! model is the first full solve's iterate plus the response to the forces' change, a load
//! on C alone ([`ImplicitSolver::recover`]): the step costs one full solve pair, one
//! recovery and one pass of element forces however many iterations it takes.

use crate::error::Result;
use crate::linalg::Assembled;
use crate::model::{Model, Primary};
use crate::scene::{Acceleration, ContactSpace};

use super::{move_dofs, step_factor, ImplicitSolver, StepConstants};

/// The contact equations, marked in equation order: every free dof of the
/// [`contact_nodes`].
pub(super) fn contact_equations(model: &Model, asm: &Assembled) -> Vec<bool> {
    let node = contact_nodes(model);
    (asm.dof_of.iter()).map(|&d| node[d as usize / 3]).collect()
}

/// The free equations of the [`contact_nodes`], in node order.
pub(super) fn contact_node_equations(model: &Model, asm: &Assembled) -> Vec<u32> {
    let node = contact_nodes(model);
    (0..node.len())
        .filter(|&n| node[n])
        .flat_map(|n| (0..3).map(move |a| asm.equation[3 * n + a]))
        .filter(|&e| e != u32::MAX)
        .collect()
}

/// The contact nodes, marked: the interfaces' secondary nodes, the nodes of their primary
/// surfaces and their rigid bodies' nodes.
pub(super) fn contact_nodes(model: &Model) -> Vec<bool> {
    let mut node = vec![false; model.dofs() / 3];
    for itf in &model.interfaces {
        for &n in &itf.nodes {
            node[n as usize] = true;
        }
        match &itf.primary {
            Primary::Surface { faces, .. } => {
                for f in &model.queries.faces[faces.clone()] {
                    for &n in f {
                        node[n as usize] = true;
                    }
                }
            }
            Primary::Rigid { node: n, .. } => node[*n as usize] = true,
            Primary::Plane { .. } => {}
        }
    }
    node
}

impl ImplicitSolver<'_> {
    /// Whether this step's iteration may run on the contact space: the step's effective
    /// factor has one (the sub-step's shares the run's symbolic analysis, and so its contact
    /// space), and the gap rate with a consistent mass needs the mass factor's too.
    pub(super) fn contact_space_ready(&self, k: &StepConstants, sub: bool) -> bool {
        let mass_ready = match &self.mass_solver {
            Some(m) => k.endpoint || m.contact_space().is_some(),
            None => true,
        };
        self.effective(sub).contact_space().is_some() && mass_ready
    }

    /// One solve of the effective equation on the contact space: u_new's contact equations
    /// move by $(K_{eff}^{-1})_{CC}\, w_f\, (f_c - f_{c,last})$ and w takes $M^{-1} f_c$
    /// there. Returns the largest correction and increment on the contact equations, or
    /// `None` (nothing changed) where the forces changed outside them.
    pub(super) fn contact_equilibrium(
        &mut self,
        k: &StepConstants,
        sub: bool,
    ) -> Result<Option<(f64, f64)>> {
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let (f_c, f_last) = (&self.work.f_c, &self.work.f_last);
        let outside = (self.asm.dof_of.iter().zip(&self.in_space))
            .any(|(&d, &inside)| !inside && f_c[d as usize] != f_last[d as usize]);
        let solver = step_factor(&self.solver, &self.sub_solver, sub);
        let Some(space) = solver.contact_space() else {
            return Ok(None);
        };
        if outside {
            return Ok(None);
        }
        let equations = space.equations();
        let rhs = &mut self.contact_rhs;
        for (r, &e) in rhs.iter_mut().zip(equations) {
            let d = self.asm.dof_of[e] as usize;
            *r = k.force_weight * (f_c[d] - f_last[d]);
        }
        solver.contact_solve_in_place(rhs);
        let dof_of = &self.asm.dof_of;
        let moves = (rhs.iter().zip(equations)).map(|(&x, &e)| (dof_of[e] as usize, x));
        let (corr, size) = move_dofs(&mut self.work.u_new, &self.u, moves);
        if k.mass_term {
            self.contact_mass_inverse();
        }
        self.work.f_last.copy_from_slice(&self.work.f_c);
        Ok(Some((corr, size)))
    }

    /// Whether the iterations of this factor's steps may move the contact nodes by the
    /// flexibility's columns alone ([`Self::flexibility_equilibrium`]): f64 kernels, no
    /// contact space, Newton steps, no friction, and no w during the iterations (the
    /// trapezoidal rule).
    pub(super) fn respond(&self, k: &StepConstants, sub: bool) -> bool {
        k.exact
            && self.settings.contact_space == ContactSpace::Auto
            && self.settings.acceleration == Acceleration::Newton
            && !self.contact.frictional()
            && !k.mass_term
            && !k.endpoint
            && !self.contact_space_ready(k, sub)
    }

    /// One iteration without a solve: where the step's flexibility keeps its columns at the
    /// contact nodes' equations and holds every node whose force changed since the last
    /// solve, the contact nodes of u_new move by $K_{eff}^{-1} w_f (f_c - f_{c,last})$,
    /// read from those columns; the rest of the model waits for the step's recovery
    /// ([`Self::recover`]). Returns as [`Self::contact_equilibrium`], or `None` (nothing
    /// changed) where it cannot.
    pub(super) fn flexibility_equilibrium(
        &mut self,
        k: &StepConstants,
        sub: bool,
    ) -> Option<(f64, f64)> {
        let flex = &self.flexibility[usize::from(sub)];
        if !self.respond(k, sub) || flex.response_equations().is_empty() {
            return None;
        }
        self.contact.forces_into(self.model, &mut self.work.f_c);
        let (f_c, f_last) = (&self.work.f_c, &self.work.f_last);
        let change: Vec<(u32, usize, f64)> = (0..f_c.len())
            .filter(|&d| f_c[d] != f_last[d] && self.asm.equation[d] != u32::MAX)
            .map(|d| ((d / 3) as u32, d % 3, k.force_weight * (f_c[d] - f_last[d])))
            .collect();
        let equations = flex.response_equations();
        let mut delta = vec![0.0; equations.len()];
        if !flex.respond(&change, &mut delta) {
            return None;
        }
        let dof_of = &self.asm.dof_of;
        let moves = (delta.iter().zip(equations)).map(|(&x, &e)| (dof_of[e as usize] as usize, x));
        let (corr, size) = move_dofs(&mut self.work.u_new, &self.u, moves);
        self.accept_forces(k);
        Some((corr, size))
    }

    /// w = M^-1 f_c on the contact equations (the rest waits for the step's last solve).
    fn contact_mass_inverse(&mut self) {
        let Some(space) = self.solver.contact_space() else {
            return;
        };
        let equations = space.equations();
        let f_c = &self.work.f_c;
        match &self.mass_solver {
            None => {
                for &e in equations {
                    let d = self.asm.dof_of[e] as usize;
                    self.work.w[d] = f_c[d] / self.asm.nodal_mass[d / 3];
                }
            }
            Some(ms) => {
                // the same equations, in the mass factor's own trailing order
                let Some(mass_space) = ms.contact_space() else {
                    return;
                };
                let equations = mass_space.equations();
                let rhs = &mut self.contact_rhs;
                for (r, &e) in rhs.iter_mut().zip(equations) {
                    *r = f_c[self.asm.dof_of[e] as usize];
                }
                ms.contact_solve_in_place(rhs);
                for (&x, &e) in rhs.iter().zip(equations) {
                    self.work.w[self.asm.dof_of[e] as usize] = x;
                }
            }
        }
    }
}
