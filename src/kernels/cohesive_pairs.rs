//! CPU twin of `shaders/cohesive_pairs.wgsl`: each bonded pair's step of the resident
//! explicit path, one pair per invocation. The pair's separation is its upper node's
//! displacement less its lower node's; its law ([`CohesiveLaw::step`], or
//! [`CohesiveLaw::step_sliding`] where the law has friction) gives the traction, the damage
//! and the energy dissipated. The kernel writes the pair's force (its area times the
//! traction, on the upper node; the lower takes its opposite, [`super::cohesive_scatter`]),
//! its dissipation and stored-energy offset times its area
//! ([`super::cohesive_reduce`] sums them), and advances its damage and slip.
//!
//! The device holds every interface's pairs in one list, interface after interface
//! ([`CohesiveSetup`]); the host path's [`super::cohesive_forces`] steps the same law per
//! interface.

use std::ops::Range;

use rayon::prelude::*;

use super::cohesive_forces::CohesivePairs;
use crate::material::{CohesiveLaw, SlidingStep};

/// One bonded pair as the device holds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairRecord {
    pub upper: u32,
    pub lower: u32,
    /// Its interface's law (an index into [`CohesiveSetup::laws`]).
    pub law: u32,
    pub area: f64,
    pub normal: [f64; 3],
}

/// Every interface's pairs in one list, with each interface's law and range of pairs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CohesiveSetup {
    pub laws: Vec<CohesiveLaw>,
    pub pairs: Vec<PairRecord>,
    pub interfaces: Vec<Range<usize>>,
}

impl CohesiveSetup {
    /// The pairs of `interfaces`, in order (each interface its own law).
    pub fn of<'a>(interfaces: impl Iterator<Item = &'a CohesivePairs>) -> Self {
        let mut s = CohesiveSetup::default();
        for c in interfaces {
            let (law, start) = (s.laws.len() as u32, s.pairs.len());
            s.laws.push(c.law);
            s.pairs.extend((0..c.area.len()).map(|p| PairRecord {
                upper: c.upper[p],
                lower: c.lower[p],
                law,
                area: c.area[p],
                normal: c.normal[p],
            }));
            s.interfaces.push(start..s.pairs.len());
        }
        s
    }
}

/// A pair's state between steps: its damage and its slip (zero where its law has no
/// friction).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairState {
    pub damage: f64,
    pub slip: [f64; 3],
}

/// What a pair's step gives: its force on the upper node (area times traction), and its
/// area times the energy per area the step dissipated (damage and friction) and times its
/// stored-energy offset ([`SlidingStep::stored_offset`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairOutput {
    pub force: [f64; 3],
    pub dissipated: f64,
    pub offset: f64,
}

/// One pair's step at displacement `u` from its state `s`.
pub fn pair_step(law: &CohesiveLaw, pair: &PairRecord, u: &[f64], s: PairState) -> SlidingStep {
    let (a, b) = (3 * pair.upper as usize, 3 * pair.lower as usize);
    let delta = std::array::from_fn(|i| u[a + i] - u[b + i]);
    match law.friction > 0.0 {
        true => law.step_sliding(delta, pair.normal, (s.damage, s.slip)),
        false => SlidingStep::without_friction(law.step(delta, pair.normal, s.damage)),
    }
}

/// Every pair's step at displacement `u` (3 per node): their outputs, and, where `advance`,
/// their states moved on.
pub fn cohesive_pairs(
    setup: &CohesiveSetup,
    u: &[f64],
    state: &mut [PairState],
    advance: bool,
) -> Vec<PairOutput> {
    (setup.pairs.par_iter().zip(state.par_iter_mut()))
        .map(|(pair, s)| {
            let law = &setup.laws[pair.law as usize];
            let step = pair_step(law, pair, u, *s);
            if advance {
                *s = PairState {
                    damage: step.step.damage,
                    slip: match law.friction > 0.0 {
                        true => step.slip,
                        false => [0.0; 3],
                    },
                };
            }
            PairOutput {
                force: step.step.traction.map(|t| pair.area * t),
                dissipated: pair.area * (step.step.dissipated + step.friction),
                offset: pair.area * step.stored_offset,
            }
        })
        .collect()
}
