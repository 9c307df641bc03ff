//! [`ContactForm`]: the forms in which the resident step records the device contact
//! iteration. Each runs the same arithmetic in the same order, so the results are the same
//! bits whichever runs; which is fastest depends on the adapter and on the contact zone's
//! size, and the resident solver measures it (`integrate::form_trial`).

/// A form of the device contact iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ContactForm {
    /// The whole iteration after the search in one workgroup (`contact_zone`).
    Zone,
    /// Staged, each recorded sweep one `contact_relax` dispatch (no rigid body range).
    Relax,
    /// Staged, each recorded sweep a `contact_sweep` and a `contact_apply` dispatch.
    Staged,
}

impl ContactForm {
    /// Every form, in the order a trial takes them.
    pub const ALL: [ContactForm; 3] = [ContactForm::Zone, ContactForm::Relax, ContactForm::Staged];

    /// Its name in `summary.json` and the benchmarks' tables.
    pub fn name(self) -> &'static str {
        match self {
            ContactForm::Zone => "zone",
            ContactForm::Relax => "relax",
            ContactForm::Staged => "staged",
        }
    }
}

/// Pairs up to which the resident solver's trial times `contact_zone` against the staged
/// forms: four times [`super::impulse_sweeps::ZONE_PAIRS`], the default's bound, since a card
/// may run a larger zone faster in one workgroup than staged. Past it one workgroup would
/// run every pair's sweeps alone, many times slower than the staged forms on any adapter.
pub const ZONE_TRIAL_PAIRS: usize = 4 * super::impulse_sweeps::ZONE_PAIRS;
