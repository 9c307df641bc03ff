//! The stopping rule of the device contact iteration (CPU twin of the start that
//! `contact_compliance`'s first invocation makes and of `contact_apply`'s `stopping_rule`),
//! run once before the first sweep and once after each:
//! no pair in reach stops it at once (0 sweeps); otherwise it stops, converged, after the
//! first sweep whose violation is within the tolerance, or, not converged, at the sweep
//! limit. The host path's loop (`integrate::explicit`), one decision at a time.

/// Phases of the iteration (`STATE_PHASE` in `shaders/shared/types.wgsl`).
pub(crate) const NOT_STARTED: u32 = 0;
pub(crate) const SWEEPING: u32 = 1;
pub(crate) const CONVERGED: u32 = 2;
pub(crate) const STOPPED: u32 = 3;

/// The positions of the state words (`STATE_*` in `shaders/shared/types.wgsl`).
pub mod word {
    pub const VIOLATION: usize = 0;
    pub const ACTIVE: usize = 1;
    pub const SWEEPS: usize = 2;
    pub const PHASE: usize = 3;
    /// Whether the last sweep dispatched ran (the device's alone: the apply after it reads it).
    pub const SWEPT: usize = 4;
    /// The first of three words that hold sweep k's largest violation at `RING + k % 3`
    /// (`contact_relax`: the sweep after it reads it while the next is gathered).
    pub const RING: usize = 5;
    /// Words of the state buffer.
    pub const WORDS: usize = 8;
}

/// The iteration's state (the `state` words of the shaders).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SweepState {
    /// Largest violation of the last sweep.
    pub violation: f64,
    /// Pairs in reach.
    pub active: u32,
    pub sweeps: u32,
    pub phase: u32,
}

impl SweepState {
    /// Whether the next sweep runs.
    pub fn sweeping(&self) -> bool {
        self.phase == SWEEPING
    }

    /// Sweeps to report: `max_iterations + 1` where the iteration stopped unconverged at
    /// the limit, `max_iterations + 2` where it was still sweeping (a report recorded
    /// before the iteration's end; a step's `contact_finish` runs it to its end).
    pub fn reported(&self, max_iterations: u32) -> u32 {
        match self.phase {
            SWEEPING => max_iterations + 2,
            STOPPED => max_iterations + 1,
            _ => self.sweeps,
        }
    }
}

pub fn sweep_control(state: &mut SweepState, tolerance: f64, max_iterations: u32) {
    match state.phase {
        NOT_STARTED => {
            state.phase = if state.active == 0 {
                CONVERGED
            } else {
                SWEEPING
            };
        }
        SWEEPING => {
            state.sweeps += 1;
            state.phase = phase_after(state.sweeps, state.violation, tolerance, max_iterations);
            state.violation = 0.0;
        }
        _ => {}
    }
}

/// The phase after sweep number `sweeps`, whose largest violation is `violation` (CPU twin
/// of `shaders/include/phase_after.wgsl`): converged within `tolerance`, stopped at the
/// sweep limit, or sweeping on.
pub fn phase_after(sweeps: u32, violation: f64, tolerance: f64, max_iterations: u32) -> u32 {
    if violation <= tolerance {
        CONVERGED
    } else if sweeps >= max_iterations {
        STOPPED
    } else {
        SWEEPING
    }
}
