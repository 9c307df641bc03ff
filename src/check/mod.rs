//! Checks of a built model before it runs, and the warnings a run ends with.
//!
//! - [`elements`]: inverted, degenerate and repeated-node elements.
//! - [`facing`]: contact surfaces that face the same way.
//! - [`penetration`]: secondary nodes behind their primary surface at t = 0, and a primary
//!   surface inside its secondary body ([`inside`]).
//! - [`memory`]: the memory a scene needs against what the process may use.
//! - [`quality`]: slivers that set the explicit step, and volumetric locking (warnings).
//! - [`crack_band`]: damaging elements wider than their softening's snap-back limit.
//!
//! A check that fails before the run is an error naming the scene key; what only the run
//! can show (unconverged steps, deep penetration, an energy rise) is a [`Warning`], and a run
//! with warnings ends as `completed_with_warnings`.

pub mod crack_band;
pub mod elements;
pub mod facing;
pub mod inside;
pub mod memory;
pub mod penetration;
pub mod quality;

use serde::Serialize;

/// A finding that makes a finished run's result doubtful.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Warning {
    /// A stable name: `unconverged_steps`, `deep_penetration`, `energy_rise`,
    /// `initial_penetration`, `fast_contact`, `element_quality`, `volumetric_locking`,
    /// `crack_band`.
    pub kind: String,
    pub message: String,
}

impl Warning {
    pub fn new(kind: &str, message: String) -> Warning {
        Warning {
            kind: kind.into(),
            message,
        }
    }
}

/// Penetration deeper than this fraction of an interface's face size is a warning.
pub(crate) const DEEP_PENETRATION: f64 = 0.1;

/// An interface's face size: the square root of its secondary faces' mean area (the nodes'
/// tributary areas sum to the faces' area).
pub fn face_size(area: &[f64], faces: usize) -> f64 {
    (area.iter().sum::<f64>() / faces.max(1) as f64).sqrt()
}

/// The warning for steps whose contact iteration hit its cap, if any.
pub fn unconverged(
    count: usize,
    steps: usize,
    first: Option<(usize, f64)>,
    cap: &str,
) -> Option<Warning> {
    let (step, time) = first?;
    (count > 0).then(|| {
        Warning::new(
            "unconverged_steps",
            format!(
                "{count} of {steps} steps ended with the contact iteration unconverged ({cap}); the first was step {step} (t = {time:.6e}): their contact forces do not meet the tolerance"
            ),
        )
    })
}

/// The warning for an interface whose deepest penetration over the run exceeds
/// [`DEEP_PENETRATION`] of its face size.
pub fn deep_penetration(
    interface: &str,
    deepest: f64,
    at: (usize, f64),
    face: f64,
) -> Option<Warning> {
    (deepest > DEEP_PENETRATION * face).then(|| {
        Warning::new(
            "deep_penetration",
            format!(
                "interface `{interface}`: penetration reached {deepest:.4e} at step {} (t = {:.6e}), {:.2} of its face size {face:.4e} (more than {DEEP_PENETRATION}): the contact constraint was not held",
                at.0,
                at.1,
                deepest / face
            ),
        )
    })
}

/// The warning for a total energy that rose above its start by more than `tolerance` of
/// `scale`.
pub(crate) fn energy_rise(initial: f64, max: f64, scale: f64, tolerance: f64) -> Option<Warning> {
    let rise = max - initial;
    (rise > tolerance * scale).then(|| {
        Warning::new(
            "energy_rise",
            format!(
                "the total energy rose from {initial:.6e} to {max:.6e}, {:.3} of the energy scale {scale:.4e} (run.energy_tolerance = {tolerance}); elastic contact can only lose energy",
                rise / scale
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warnings_fire_only_past_their_thresholds() {
        assert!(unconverged(0, 10, None, "max_iterations = 5").is_none());
        assert!(unconverged(2, 10, Some((3, 0.3)), "max_iterations = 5").is_some());
        assert!(deep_penetration("c", 0.09, (1, 0.1), 1.0).is_none());
        assert!(deep_penetration("c", 0.11, (1, 0.1), 1.0).is_some());
        assert!(energy_rise(1.0, 1.04, 1.0, 0.05).is_none());
        assert!(energy_rise(1.0, 1.06, 1.0, 0.05).is_some());
        assert_eq!(face_size(&[1.0, 1.0, 1.0, 1.0], 1), 2.0);
    }
}
