//! [`ContactForm`]: the forms in which the resident step records the device contact
//! iteration. Each runs the same arithmetic in the same order, so the results are the same
//! bits whichever runs; which is fastest depends on the adapter and on the contact zone's
//! size, and the resident solver measures it (`integrate::form_trial`). The sweeps
//! ([`super::impulse_sweeps`]) take their forms and bounds from here.

use super::one_group::ONE_GROUP;

/// A form of the device contact iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ContactForm {
    /// The whole iteration after the search in one workgroup (`contact_zone`) of this many
    /// lanes ([`super::one_group`]).
    Zone(u32),
    /// Staged, each recorded sweep one `contact_relax` dispatch (no rigid body range).
    Relax,
    /// Staged, each recorded sweep a `contact_sweep` and a `contact_apply` dispatch.
    Staged,
}

impl ContactForm {
    /// Its name in `summary.json` and the benchmarks' tables: `zone` (at
    /// [`ONE_GROUP`] lanes, `zone_512` and `zone_1024` wider), `relax` or `staged`.
    pub fn name(self) -> String {
        match self {
            ContactForm::Zone(ONE_GROUP) => "zone".into(),
            ContactForm::Zone(lanes) => format!("zone_{lanes}"),
            ContactForm::Relax => "relax".into(),
            ContactForm::Staged => "staged".into(),
        }
    }

    /// Whether the whole iteration runs in one workgroup.
    pub fn is_zone(self) -> bool {
        matches!(self, ContactForm::Zone(_))
    }
}

/// Pairs up to which a step's iteration runs in one workgroup (`contact_zone`) by default:
/// there one dispatch's latency replaces about twenty, and the workgroup's sweeps are as
/// fast as recorded ones (H100: 2.3 us a sweep at 361 pairs in one workgroup).
pub const ZONE_PAIRS: usize = 2048;

/// Pairs up to which the resident solver's trial times `contact_zone` against the staged
/// forms: four times [`ZONE_PAIRS`], the default's bound, since a card
/// may run a larger zone faster in one workgroup than staged. Past it one workgroup would
/// run every pair's sweeps alone, many times slower than the staged forms on any adapter.
pub const ZONE_TRIAL_PAIRS: usize = 4 * ZONE_PAIRS;
