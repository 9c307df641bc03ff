//! One block's damage pass on the CPU (the damage kernels' twin): each damageable element
//! that is damaged, or that the sieve ([`super::damage_sieve`]) cannot rule out, has its
//! points looked at, and where it steps its forces replace the elastic ones.

use rayon::prelude::*;

use super::damage_data::{first_where, DamageBlock};
use super::damage_sieve::{may_reach, remember, stride};
use crate::element::corotation::{self, Mat3};
use crate::element::damage::DamageStep;
use crate::material::damage::Dissipation;

/// What one block's damage pass reads and writes: the block's part of the corner forces
/// (the elastic ones on entry), its state and flags (updated in place where the step
/// advances), its sieve's memory, and each damageable element's dissipation over the step
/// (with its fibre share).
pub(crate) struct BlockPass<'a> {
    pub corner_forces: &'a mut [[f64; 3]],
    pub state: &'a mut [f64],
    pub damaged: &'a mut [bool],
    pub first: &'a mut [[u32; 2]],
    pub memory: &'a mut [f64],
    pub dissipated: &'a mut [Dissipation],
    /// The number of the step the pass takes (its first damage's).
    pub step: u32,
    /// The block's elements' frames, by element, where the kinematics is corotational
    /// ([`super::corotated_forces`]): the pass then works in each element's frame.
    pub frames: Option<&'a [Mat3]>,
}

/// A kind's damageable element (`i`, its number among the block's damageable elements, at
/// corners `x`): its step from displacement `u_prev` to `u` with its points' state (old on
/// entry, new on return), and its largest reach over its points at `u`.
pub(crate) trait ElementDamage<const N: usize>: Sync {
    fn step(
        &self,
        i: usize,
        x: &[[f64; 3]; N],
        u: (&[[f64; 3]; N], &[[f64; 3]; N]),
        state: &mut [f64],
    ) -> DamageStep<N>;

    fn reach(&self, i: usize, x: &[[f64; 3]; N], u: &[[f64; 3]; N]) -> f64;
}

/// Nodal 3-vectors.
type Nodal<'a> = &'a [[f64; 3]];

/// A reach this far below 1 rules out a start (the step's own r has rounding of its own).
const REACH_MARGIN: f64 = 1e-9;

/// One block's damage pass, on all threads (see the module). The step before's
/// displacements are $u - \Delta t\, v$ (`v` the step's mid-step velocities; unused without
/// `advance`, where only damaged elements step, their state kept). `N` is the kind's corner
/// count.
pub(crate) fn damage_pass<const N: usize>(
    block: &DamageBlock,
    corners: &[[u32; N]],
    (reference, u, v, dt): (Nodal, Nodal, Nodal, f64),
    out: BlockPass,
    advance: bool,
    kernel: &dyn ElementDamage<N>,
) {
    // each damageable element's corners and state, as disjoint mutable parts
    let mut forces: Vec<&mut [[f64; 3]]> = Vec::with_capacity(block.len());
    let mut chunks = out.corner_forces.chunks_mut(N).enumerate();
    for &e in &block.elements {
        let (_, c) = chunks
            .find(|(k, _)| *k == e as usize)
            .expect("a damageable element of the block");
        forces.push(c);
    }
    let mut states: Vec<&mut [f64]> = Vec::with_capacity(block.len());
    let mut rest = &mut out.state[..];
    for i in 0..block.len() {
        let (head, tail) = rest.split_at_mut(block.state_range(i).len());
        states.push(head);
        rest = tail;
    }
    let (step, memory) = (out.step, out.memory.par_chunks_mut(stride(N)));
    let frames = out.frames;
    (forces.into_par_iter())
        .zip(states)
        .zip(out.damaged.par_iter_mut())
        .zip(out.first.par_iter_mut())
        .zip(memory)
        .zip(out.dissipated.par_iter_mut())
        .enumerate()
        .with_min_len(4)
        .for_each(
            |(i, (((((f, state), damaged), first), memory), dissipated))| {
                let e = block.elements[i] as usize;
                let nodes = corners[e];
                let x = nodes.map(|n| reference[n as usize]);
                let frame = frames.map(|r| &r[e]);
                // in the element's frame, where it has one: its local displacements and
                // forces
                let ue = nodes.map(|n| u[n as usize]);
                let ue = frame.map_or(ue, |r| corotation::local(r, &x, &ue));
                *dissipated = Dissipation::default();
                if !*damaged {
                    if !advance {
                        return;
                    }
                    // the sieve's elastic forces, in the frame where there is one
                    let turned: Option<[[f64; 3]; N]> = frame.map(|r| corotation::turn_back(r, f));
                    let fe: &[[f64; 3]] = turned.as_ref().map_or(&f[..], |t| &t[..]);
                    if !may_reach(memory, block.sieve[i], (fe, &ue)) {
                        return;
                    }
                    let reach = kernel.reach(i, &x, &ue);
                    if reach < 1.0 - REACH_MARGIN {
                        remember(memory, (fe, &ue), reach);
                        return;
                    }
                }
                // the step before's displacement: u_n = u_{n+1} - dt v_{n+1/2} (in the
                // same frame)
                let before = nodes.map(|n| {
                    let (u, v) = (u[n as usize], v[n as usize]);
                    [u[0] - dt * v[0], u[1] - dt * v[1], u[2] - dt * v[2]]
                });
                let before = frame.map_or(before, |r| corotation::local(r, &x, &before));
                let was_damaged = *damaged;
                // in place: each point reads its old state before it writes its new (an
                // element looked at that stays undamaged keeps its zeros)
                let s = kernel.step(i, &x, (&ue, &before), state);
                if advance && !(s.damaged || was_damaged) {
                    // the elastic forces stand
                    return;
                }
                if advance {
                    if !was_damaged {
                        *first = [step, first_where(state)];
                    }
                    *damaged = true;
                    *dissipated = s.dissipated;
                }
                match frame {
                    Some(r) => {
                        let g = corotation::centre_gradients(&x);
                        f.copy_from_slice(&corotation::turned_forces(r, &g, &ue, &s.forces))
                    }
                    None => f.copy_from_slice(&s.forces),
                }
            },
        );
}
