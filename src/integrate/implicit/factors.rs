//! The implicit path's factors, planned before any is computed: the effective matrix's, the
//! consistent mass's and the event sub-step's, each ordered and analysed symbolically, so
//! that what their numeric factorisations will hold together is known exactly and checked
//! against the memory this process may use before a value is allocated (`impact check`
//! reports the same figures), with the Newton step's flexibilities at their largest.

use std::fmt::Write as _;

use crate::error::{bytes, ImpactError, Result};
use crate::limits::{host_limit, process_bytes};
use crate::linalg::{Assembled, SpdAnalysis};
use crate::model::Model;
use crate::scene::{
    Acceleration, ConstraintMeasure, ContactSpace, ImplicitSettings, CONTACT_SPACE_MAX,
};

use super::contact_space::{contact_equations, contact_node_equations, contact_nodes};
use super::flexibility::{MAX_NODES, RESPONSE_MAX_VALUES};

/// The symbolic analyses of a model's implicit factors.
pub(crate) struct FactorPlan {
    pub effective: SpdAnalysis,
    pub mass: Option<SpdAnalysis>,
    /// The contact equations (all false without a contact space).
    pub in_space: Vec<bool>,
    /// Whether a contact event refactorises the effective matrix for its sub-steps (a
    /// second factor of the effective matrix's size, made at the first event).
    pub substeps: bool,
    /// The most nodes the Newton step's flexibilities may hold (0 without Newton steps):
    /// the contact nodes, at most [`MAX_NODES`]; one flexibility per effective factor.
    pub flexibility_nodes: usize,
    /// The most values a flexibility's columns keep at the contact nodes' equations
    /// (without a contact space, f64 kernels: the iterations' moves without solves).
    pub response_values: usize,
}

impl FactorPlan {
    /// Orders and analyses the factors of the assembled `asm`: with the contact equations
    /// numbered last where `contact_space` allows it and the kernels are `exact` (f64).
    pub fn new(
        model: &Model,
        settings: &ImplicitSettings,
        asm: &Assembled,
        exact: bool,
    ) -> Result<FactorPlan> {
        let in_space = match settings.contact_space {
            ContactSpace::Auto if exact => contact_equations(model, asm),
            _ => vec![false; asm.dof_of.len()],
        };
        let count = in_space.iter().filter(|&&c| c).count();
        let space = count > 0 && count <= CONTACT_SPACE_MAX;
        let analyse = |a| match space {
            true => SpdAnalysis::for_contact(a, &in_space, settings.ordering),
            false => SpdAnalysis::new(a, settings.ordering),
        };
        let effective = analyse(&asm.effective)?;
        let mass = match &asm.consistent_mass {
            Some(m) => Some(analyse(m)?),
            None => None,
        };
        let substeps = settings.event_substeps > 1
            && settings.constraint == ConstraintMeasure::GapRate
            && !model.interfaces.is_empty();
        let newton = settings.acceleration == Acceleration::Newton
            && !model.interfaces.iter().any(|i| i.law.is_frictional());
        let flexibility_nodes = match newton {
            true => contact_nodes(model)
                .iter()
                .filter(|&&c| c)
                .count()
                .min(MAX_NODES),
            false => 0,
        };
        // without a contact space (none asked for, or declined)
        let respond = exact
            && settings.contact_space == ContactSpace::Auto
            && effective.contact_equations() == 0;
        let response_values = match respond && flexibility_nodes > 0 {
            true => (3 * flexibility_nodes)
                .saturating_mul(contact_node_equations(model, asm).len())
                .min(RESPONSE_MAX_VALUES),
            false => 0,
        };
        Ok(FactorPlan {
            effective,
            mass,
            in_space,
            substeps,
            flexibility_nodes,
            response_values,
        })
    }

    /// The bytes the factors hold together at their peak (the sub-step's factor counted
    /// where it can be made), with the Newton step's flexibilities at their largest.
    pub fn bytes(&self) -> u64 {
        let mass = self.mass.as_ref().map_or(0, SpdAnalysis::bytes);
        let effective = self.effective.bytes();
        let effective_factors = 1 + u64::from(self.substeps);
        let flexibility =
            9 * 8 * (self.flexibility_nodes as u64).pow(2) + 8 * self.response_values as u64;
        effective
            .saturating_mul(effective_factors)
            .saturating_add(mass)
            .saturating_add(flexibility.saturating_mul(effective_factors))
    }

    /// What the factors hold, one clause each.
    pub fn describe(&self) -> String {
        let mut out = format!("effective matrix {} values", self.effective.values());
        if let Some(m) = &self.mass {
            let _ = write!(out, ", consistent mass {} values", m.values());
        }
        if self.substeps {
            let _ = write!(
                out,
                ", the event sub-step's {} values",
                self.effective.values()
            );
        }
        if self.flexibility_nodes > 0 {
            let _ = write!(
                out,
                ", the Newton step's flexibilities on up to {} nodes",
                self.flexibility_nodes
            );
            if self.response_values > 0 {
                let _ = write!(
                    out,
                    " with up to {} values at the contact nodes",
                    self.response_values
                );
            }
        }
        out
    }

    /// Refuses factors that, with what the process holds now, exceed what it may use: the
    /// figures named, before any value is allocated.
    pub fn check(&self) -> Result<()> {
        let Some((_, source)) = host_limit(0) else {
            return Ok(());
        };
        let held = process_bytes(&source);
        let Some((limit, source)) = host_limit(held) else {
            return Ok(());
        };
        let needed = held.saturating_add(self.bytes());
        if needed <= limit {
            return Ok(());
        }
        Err(ImpactError::TooLarge {
            // the run names the scene
            path: Default::default(),
            what: format!(
                "the sparse Cholesky factors known from the symbolic analysis and the contact iteration's dense matrices, {} ({}, with their workspace), on top of the {} the process holds",
                bytes(self.bytes()),
                self.describe(),
                bytes(held)
            ),
            estimate: needed,
            limit,
            limit_source: source,
        })
    }
}
