//! `cohesive_forces`: each bonded pair's traction from its separation
//! ([`crate::material::CohesiveLaw`]), added to the internal forces of its two nodes (the
//! traction times the pair's area: $+A t$ on the upper node, $-A t$ on the lower), its damage
//! advanced and its dissipation counted.
//!
//! The pairs are independent and computed on all threads; their forces are then added to
//! the nodes, and their dissipation summed, in pair order, so the result does not depend on
//! the thread count.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::material::{CohesiveLaw, SlidingStep};

/// One cohesive interface's pairs of bonded nodes (the model's
/// `model::cohesive::CohesiveInterface` holds them with its name).
#[derive(Debug, Clone, PartialEq)]
pub struct CohesivePairs {
    pub law: CohesiveLaw,
    /// The pairs' nodes on the first side (`between[0]`) and the second (`between[1]`).
    pub upper: Vec<u32>,
    pub lower: Vec<u32>,
    /// Each pair's tributary area (the mean of its two nodes').
    pub area: Vec<f64>,
    /// Each pair's unit normal, the second side's outward normal there (towards the first
    /// side): the separation $\delta = u_{upper} - u_{lower}$ opens along it.
    pub normal: Vec<[f64; 3]>,
}

impl CohesivePairs {
    /// No pairs yet, of law `law`.
    pub fn new(law: CohesiveLaw) -> Self {
        CohesivePairs {
            law,
            upper: Vec::new(),
            lower: Vec::new(),
            area: Vec::new(),
            normal: Vec::new(),
        }
    }

    /// Adds the pair of nodes `upper` and `lower` with its area and normal.
    pub fn push(&mut self, (upper, lower): (u32, u32), area: f64, normal: [f64; 3]) {
        self.upper.push(upper);
        self.lower.push(lower);
        self.area.push(area);
        self.normal.push(normal);
    }
}

/// The cohesive interfaces' state: each pair's damage, each interface's energy dissipated
/// so far (by damage and by friction), and where an interface has friction each pair's
/// slip (none otherwise) and the interface's stored-energy offset at the last step (the
/// counted pairs' area times [`crate::material::SlidingStep`]'s `stored_offset`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CohesiveState {
    pub damage: Vec<Vec<f64>>,
    pub energy: Vec<f64>,
    pub slip: Vec<Vec<[f64; 3]>>,
    pub stored_offset: Vec<f64>,
}

/// The slips an interface's state holds: one per pair where it has friction.
fn slips(c: &CohesivePairs) -> usize {
    match c.law.friction > 0.0 {
        true => c.area.len(),
        false => 0,
    }
}

/// What an interface reports at a step: its separated area (damage 1), its damaged area
/// (softening or separated) and the energy it has dissipated.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CohesiveReport {
    pub delaminated_area: f64,
    pub damaged_area: f64,
    pub energy: f64,
}

impl CohesiveState {
    /// Every pair of every interface undamaged.
    pub fn new<'a>(interfaces: impl Iterator<Item = &'a CohesivePairs>) -> Self {
        let (damage, slip): (Vec<Vec<f64>>, Vec<Vec<[f64; 3]>>) = interfaces
            .map(|c| (vec![0.0; c.area.len()], vec![[0.0; 3]; slips(c)]))
            .unzip();
        CohesiveState {
            energy: vec![0.0; damage.len()],
            stored_offset: vec![0.0; damage.len()],
            damage,
            slip,
        }
    }

    /// The stored-energy offset of every interface (added to $\tfrac12 u \cdot f$ it gives
    /// the energy the pairs store).
    pub fn stored_offset(&self) -> f64 {
        self.stored_offset.iter().sum()
    }

    /// Whether the state fits `interfaces` (a checkpoint of this model).
    pub fn fits<'a>(
        &self,
        mut interfaces: impl ExactSizeIterator<Item = &'a CohesivePairs>,
    ) -> bool {
        let n = interfaces.len();
        (self.energy.len(), self.slip.len(), self.stored_offset.len()) == (n, n, n)
            && (self.damage.iter().zip(&self.slip)).all(|(d, s)| {
                (interfaces.next()).is_some_and(|c| d.len() == c.area.len() && s.len() == slips(c))
            })
    }

    /// Each interface's report.
    pub fn reports<'a>(
        &self,
        interfaces: impl Iterator<Item = &'a CohesivePairs>,
    ) -> Vec<CohesiveReport> {
        self.reports_counting(interfaces, &|_, _| true)
    }

    /// [`Self::reports`] with the areas of the pairs `counts(interface, pair)` accepts alone
    /// (a rank of a decomposed run counts those it owns; its energy is theirs already).
    pub fn reports_counting<'a>(
        &self,
        interfaces: impl Iterator<Item = &'a CohesivePairs>,
        counts: &dyn Fn(usize, usize) -> bool,
    ) -> Vec<CohesiveReport> {
        (interfaces.zip(&self.damage).zip(&self.energy).enumerate())
            .map(|(k, ((c, d), &energy))| {
                let area = |keep: &dyn Fn(f64) -> bool| {
                    // + 0: an empty sum is -0
                    (c.area.iter().zip(d).enumerate())
                        .filter(|&(p, (_, &d))| keep(d) && counts(k, p))
                        .map(|(_, (a, _))| a)
                        .sum::<f64>()
                        + 0.0
                };
                CohesiveReport {
                    delaminated_area: area(&|d| d >= 1.0),
                    damaged_area: area(&|d| d > 0.0),
                    energy,
                }
            })
            .collect()
    }
}

/// Adds the interfaces' forces at displacement `u` to `f_int`, advances the damage in
/// `state`, and returns the energy the step dissipated.
pub fn cohesive_forces<'a>(
    interfaces: impl Iterator<Item = &'a CohesivePairs>,
    u: &[f64],
    state: &mut CohesiveState,
    f_int: &mut [f64],
) -> f64 {
    cohesive_forces_counting(interfaces, u, (state, f_int), &|_, _| true)
}

/// [`cohesive_forces`] where only the pairs `counts(interface, pair)` accepts add their
/// dissipation to `state.energy` and to the energy returned (a rank of a decomposed run
/// steps every pair at its nodes and counts those it owns).
pub fn cohesive_forces_counting<'a>(
    interfaces: impl Iterator<Item = &'a CohesivePairs>,
    u: &[f64],
    (state, f_int): (&mut CohesiveState, &mut [f64]),
    counts: &dyn Fn(usize, usize) -> bool,
) -> f64 {
    let mut dissipated = 0.0;
    for (k, c) in interfaces.enumerate() {
        let (damage, slip) = (&state.damage[k], &state.slip[k]);
        let steps: Vec<SlidingStep> = (0..c.area.len())
            .into_par_iter()
            .with_min_len(crate::parallel::CHUNK)
            .map(|p| {
                let (a, b) = (3 * c.upper[p] as usize, 3 * c.lower[p] as usize);
                let delta = std::array::from_fn(|i| u[a + i] - u[b + i]);
                match slip.get(p) {
                    Some(&s) => c.law.step_sliding(delta, c.normal[p], (damage[p], s)),
                    None => {
                        SlidingStep::without_friction(c.law.step(delta, c.normal[p], damage[p]))
                    }
                }
            })
            .collect();
        let (mut energy, mut offset) = (0.0, 0.0);
        for (p, s) in steps.iter().enumerate() {
            let (a, b) = (3 * c.upper[p] as usize, 3 * c.lower[p] as usize);
            for i in 0..3 {
                let f = c.area[p] * s.step.traction[i];
                f_int[a + i] += f;
                f_int[b + i] -= f;
            }
            state.damage[k][p] = s.step.damage;
            if let Some(slip) = state.slip[k].get_mut(p) {
                *slip = s.slip;
            }
            if counts(k, p) {
                energy += c.area[p] * (s.step.dissipated + s.friction);
                offset += c.area[p] * s.stored_offset;
            }
        }
        state.energy[k] += energy;
        state.stored_offset[k] = offset;
        dissipated += energy;
    }
    dissipated
}

/// The largest $\omega^2$ a pair's penalty adds to its nodes' equations, $K A (1/m_u +
/// 1/m_l)$ over the pairs, at lumped masses `mass`.
pub fn cohesive_omega2<'a>(
    interfaces: impl Iterator<Item = &'a CohesivePairs>,
    mass: &[f64],
) -> f64 {
    let inv = |n: u32| 1.0 / mass[n as usize];
    interfaces
        .flat_map(|c| {
            (0..c.area.len())
                .map(|p| c.law.stiffness * c.area[p] * (inv(c.upper[p]) + inv(c.lower[p])))
        })
        .fold(0.0, f64::max)
}
