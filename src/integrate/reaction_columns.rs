//! The supports' reactions as history columns of the resident GPU step: each column sums the
//! corner forces at its dofs' nodes (`history_reduce`'s corner op), and the host takes off
//! the dofs' share of the body force. The columns are each named `[[fix]]`'s held
//! components (x, y, z), then one per component and velocity of the moving fixes' dofs, whose
//! sums give the fixes' power (their work in the energy balance; see
//! [`super::explicit::fix_power`]).

use crate::element::CornerLayout;
use crate::kernels::Incidence;
use crate::model::Model;

pub(crate) struct ReactionColumns {
    /// Per column, the corner-force indices it sums (component-major, `a C + s`).
    pub lists: Vec<Vec<u32>>,
    /// Per column, its dofs' body force, $\sum m g_a$.
    body_force: Vec<f64>,
    /// Named fixes (three columns each, first).
    named: usize,
    /// The moving columns' velocities.
    moving: Vec<f64>,
}

impl ReactionColumns {
    /// The columns of `model`'s fixes, with each node's lumped `mass`.
    pub fn new(model: &Model, mass: &[f64]) -> Self {
        let elements = &model.mesh.elements;
        let incidence = Incidence::new(elements, model.mesh.node_count());
        let layout = CornerLayout::of(elements);
        let slots = layout.count();
        let column = |a: usize, dofs: &mut dyn Iterator<Item = usize>| {
            let mut list = Vec::new();
            let mut body = 0.0;
            for d in dofs {
                let n = d / 3;
                body += mass[n] * model.gravity[a];
                let corners = &incidence.corners
                    [incidence.offsets[n] as usize..incidence.offsets[n + 1] as usize];
                list.extend(
                    corners
                        .iter()
                        .map(|&c| (a * slots + layout.to_device(c as usize)) as u32),
                );
            }
            (list, body)
        };
        let mut out = ReactionColumns {
            lists: Vec::new(),
            body_force: Vec::new(),
            named: model.reactions.len(),
            moving: Vec::new(),
        };
        for r in &model.reactions {
            for (a, dofs) in r.dofs.iter().enumerate() {
                let (list, body) = column(a, &mut dofs.iter().map(|&d| d as usize));
                out.lists.push(list);
                out.body_force.push(body);
            }
        }
        // the moving dofs by component and velocity, in the order of their first dof
        let mut groups: Vec<(usize, f64, Vec<usize>)> = Vec::new();
        for &(d, w) in &model.fix_motion {
            match groups.iter_mut().find(|g| g.0 == d % 3 && g.1 == w) {
                Some(g) => g.2.push(d),
                None => groups.push((d % 3, w, vec![d])),
            }
        }
        for (a, w, dofs) in groups {
            let (list, body) = column(a, &mut dofs.into_iter());
            out.lists.push(list);
            out.body_force.push(body);
            out.moving.push(w);
        }
        out
    }

    /// Columns in all.
    pub fn len(&self) -> usize {
        self.lists.len()
    }

    /// The named fixes' reactions from a row's column values.
    pub fn reactions(&self, values: &[f64]) -> Vec<[f64; 3]> {
        (0..self.named)
            .map(|k| std::array::from_fn(|a| values[3 * k + a] - self.body_force[3 * k + a]))
            .collect()
    }

    /// The moving fixes' power from a row's column values.
    pub fn power(&self, values: &[f64]) -> f64 {
        let first = 3 * self.named;
        (self.moving.iter().enumerate())
            .map(|(g, w)| (values[first + g] - self.body_force[first + g]) * w)
            .sum::<f64>()
            // +0 where there is nothing to sum, as on the ranks (`sum` starts at -0, and a
            // checkpoint is compared word for word)
            + 0.0
    }

    /// The power with every internal force zero (the start).
    pub fn power_at_rest(&self) -> f64 {
        self.power(&vec![0.0; self.len()])
    }
}
