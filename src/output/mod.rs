//! What a run writes: `history.csv`, `summary.json` and, when asked, VTU frames.

pub mod delamination;
pub mod failure_survey;
pub mod file;
pub mod history;
pub mod plot;
pub mod progress;
pub mod summary;
pub mod vtu;

pub use history::History;
pub use summary::Summary;
