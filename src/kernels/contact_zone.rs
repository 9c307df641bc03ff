//! The whole contact iteration of a step in one workgroup (CPU twin of
//! `shaders/contact_zone.wgsl`): the staged iteration's stages one after another,
//! [`contact_constraints`], the pairs' counting sort by face ([`bucket_count`],
//! [`prefix_sum`], [`bucket_fill`], [`bucket_order`]), [`contact_touches`],
//! [`contact_compliance`] and the start of the sweeps ([`sweep_control`]), the warm start
//! ([`contact_warm`]), the sweeps to the iteration's end ([`contact_finish`]) and
//! [`contact_report`]. (Where the step's predictor ran in the search's bounds, the kernel
//! also drifts the contact nodes at their final $v^*$: that is [`super::explicit_drift`],
//! and `tests/gpu_contact.rs` holds the device's drift to `explicit_drift`'s bits.)

use super::contact_constraints::{contact_constraints, Constraint, ContactPair, RigidSurface};
use super::contact_finish::{contact_finish, SweepInputs};
use super::contact_gap::ContactPoint;
use super::contact_touches::{contact_touches, ContactNode};
use super::contact_warm::contact_warm;
use super::explicit_correct::LumpedNode;
use super::sweep_control::{sweep_control, SweepState};
use super::{
    bucket_count, bucket_fill, bucket_order, contact_compliance, contact_report, prefix_sum,
};

/// What the iteration reads: the step, the model's contact data and the search's points.
pub struct ZoneInputs<'a> {
    pub dt: f64,
    /// The search's margin (the reach of a surface pair).
    pub margin: f64,
    pub tolerance: f64,
    pub max_iterations: u32,
    pub reference: &'a [[f64; 3]],
    /// $u_n$ and $a_n$, 3 per node.
    pub u: &'a [f64],
    pub a: &'a [f64],
    pub pairs: &'a [ContactPair],
    pub points: &'a [ContactPoint],
    pub faces: &'a [[u32; 4]],
    pub rigid: &'a [RigidSurface],
    pub nodes: &'a [ContactNode],
    pub links: &'a [u32],
    pub lumped: &'a [LumpedNode],
}

/// What the iteration leaves besides the velocity and the results: the constraints with
/// their impulses, the sort by face, the row sums (per node of the model) and the state.
#[derive(Debug, Clone)]
pub struct ZoneState {
    pub constraints: Vec<Constraint>,
    pub keys: Vec<u32>,
    pub starts: Vec<u32>,
    pub sorted: Vec<u32>,
    pub touches: Vec<f64>,
    pub state: SweepState,
}

/// Runs the iteration on $v^*$ (`v`, changed in place) from the last step's `results` (the
/// warm start's impulses) and writes the step's results there (the friction and driver work
/// carry over).
pub fn contact_zone(z: &ZoneInputs, v: &mut [f64], results: &mut [f64]) -> ZoneState {
    let (mut constraints, keys) = contact_constraints(
        z.dt,
        z.margin,
        z.reference,
        z.u,
        v,
        z.a,
        z.pairs,
        z.points,
        z.faces,
        z.rigid,
        results,
    );
    let nf = z.faces.len();
    let (mut counts, ranks) = bucket_count(&keys, nf + 1);
    let starts = prefix_sum(&counts);
    let mut sorted = bucket_fill(&keys, &ranks, &starts);
    bucket_order(nf, &starts, &mut sorted, &mut counts);
    let mut touches = vec![0.0; z.reference.len()];
    let active = contact_touches(
        z.nodes,
        z.links,
        &constraints,
        &starts,
        &sorted,
        &mut touches,
    );
    let mut dj = vec![0.0; 3 * (z.pairs.len() + z.rigid.len())];
    contact_compliance(&mut constraints, z.pairs, &touches, z.lumped, &mut dj);
    let mut state = SweepState {
        active,
        ..Default::default()
    };
    sweep_control(&mut state, z.tolerance, z.max_iterations);
    let sweeps = SweepInputs {
        dt: z.dt,
        tolerance: z.tolerance,
        max_iterations: z.max_iterations,
        pairs: z.pairs,
        nodes: z.nodes,
        links: z.links,
        starts: &starts,
        sorted: &sorted,
        lumped: z.lumped,
    };
    contact_warm(&sweeps, &state, &constraints, &mut dj, v);
    contact_finish(&sweeps, &mut state, &mut constraints, &mut dj, v);
    let reported = state.reported(z.max_iterations);
    contact_report(z.dt, reported, (&constraints, z.pairs), z.rigid, v, results);
    ZoneState {
        constraints,
        keys,
        starts,
        sorted,
        touches,
        state,
    }
}
