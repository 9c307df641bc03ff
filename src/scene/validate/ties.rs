//! `[[tie]]`: a secondary side (a body's face, surface or node set) bonded to a primary
//! surface of a meshed body.

use super::Checker;
use crate::error::Result;
use crate::scene::raw::{RawBody, RawTie};
use crate::scene::{BodySpec, TieSpec};

impl Checker<'_> {
    /// Each tie's sides, its `tolerance` (positive where given) and `adjust` (default
    /// true); two ties of one name are refused.
    pub(super) fn ties(
        &self,
        raw: &[RawTie],
        raw_bodies: &[RawBody],
        bodies: &[BodySpec],
    ) -> Result<Vec<TieSpec>> {
        let mut ties: Vec<TieSpec> = Vec::with_capacity(raw.len());
        for (i, t) in raw.iter().enumerate() {
            let key = |k: &str| format!("tie[{i}].{k} (tie `{}`)", t.name);
            self.name_well_formed(&format!("tie[{i}].name"), &t.name)?;
            if let Some(j) = ties.iter().position(|o| o.name == t.name) {
                return Err(self.err(
                    format!("tie[{i}].name"),
                    format!("`{}` is also the name of tie[{j}]", t.name),
                ));
            }
            if t.primary.rigid_body.is_some() {
                return Err(self.err(
                    key("primary.rigid_body"),
                    "a tie bonds two meshed bodies: give the primary side as `body` with `face` or `surface` (a node on a rigid body moves with it through a [[fix]] of the rigid body instead)",
                ));
            }
            let secondary = self.secondary_side(&key, &t.secondary, raw_bodies, bodies)?;
            let primary = self.surface_ref(&key, "primary", &t.primary, raw_bodies, bodies)?;
            let tolerance = match t.tolerance {
                Some(d) => Some(self.positive(&key("tolerance"), d)?),
                None => None,
            };
            ties.push(TieSpec {
                name: t.name.clone(),
                secondary,
                primary,
                tolerance,
                adjust: t.adjust.unwrap_or(true),
            });
        }
        Ok(ties)
    }
}
