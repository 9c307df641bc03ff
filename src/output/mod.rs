//! What a run writes: `history.csv` and `summary.json`.

pub mod history;
pub mod summary;

pub use history::History;
pub use summary::Summary;
