//! The WGSL source of each kernel: the shared files, then the kernel's own file (the same
//! assembly `build.rs` validates with naga).

macro_rules! kernel_source {
    ($name:literal) => {
        concat!(
            include_str!("../../shaders/shared/types.wgsl"),
            include_str!("../../shaders/shared/quad.wgsl"),
            include_str!("../../shaders/shared/element.wgsl"),
            include_str!("../../shaders/shared/contact.wgsl"),
            include_str!(concat!("../../shaders/", $name, ".wgsl"))
        )
    };
}

pub const HEX8_FORCES: &str = kernel_source!("hex8_forces");
pub const NODE_GATHER: &str = kernel_source!("node_gather");
pub const CONTACT_GAP: &str = kernel_source!("contact_gap");
pub const SLIP_RATE: &str = kernel_source!("slip_rate");
pub const TET4_FORCES: &str = kernel_source!("tet4_forces");
pub const EXPLICIT_PREDICT: &str = kernel_source!("explicit_predict");
pub const PLANE_CONTACT: &str = kernel_source!("plane_contact");
pub const EXPLICIT_DRIFT: &str = kernel_source!("explicit_drift");
pub const EXPLICIT_CORRECT: &str = kernel_source!("explicit_correct");
pub const HISTORY_REDUCE: &str = kernel_source!("history_reduce");
pub const STABLE_STEP: &str = kernel_source!("stable_step");
pub const FACE_CELLS: &str = kernel_source!("face_cells");
pub const BUCKET_COUNT: &str = kernel_source!("bucket_count");
pub const PREFIX_SUM: &str = kernel_source!("prefix_sum");
pub const BUCKET_FILL: &str = kernel_source!("bucket_fill");
pub const CONTACT_SEARCH: &str = kernel_source!("contact_search");
pub const SEARCH_BOUNDS: &str = kernel_source!("search_bounds");
pub const SEARCH_GRID: &str = kernel_source!("search_grid");
pub const CONTACT_CONSTRAINTS: &str = kernel_source!("contact_constraints");
pub const CONTACT_TOUCHES: &str = kernel_source!("contact_touches");
pub const CONTACT_COMPLIANCE: &str = kernel_source!("contact_compliance");
pub const CONTACT_SWEEP: &str = kernel_source!("contact_sweep");
pub const CONTACT_APPLY: &str = kernel_source!("contact_apply");
pub const SWEEP_CONTROL: &str = kernel_source!("sweep_control");
pub const CONTACT_REPORT: &str = kernel_source!("contact_report");
pub const BUCKET_ORDER: &str = kernel_source!("bucket_order");

/// Every kernel: its name (the entry point) and its source.
pub const ALL: [(&str, &str); 26] = [
    ("hex8_forces", HEX8_FORCES),
    ("node_gather", NODE_GATHER),
    ("contact_gap", CONTACT_GAP),
    ("slip_rate", SLIP_RATE),
    ("tet4_forces", TET4_FORCES),
    ("explicit_predict", EXPLICIT_PREDICT),
    ("plane_contact", PLANE_CONTACT),
    ("explicit_drift", EXPLICIT_DRIFT),
    ("explicit_correct", EXPLICIT_CORRECT),
    ("history_reduce", HISTORY_REDUCE),
    ("stable_step", STABLE_STEP),
    ("face_cells", FACE_CELLS),
    ("bucket_count", BUCKET_COUNT),
    ("prefix_sum", PREFIX_SUM),
    ("bucket_fill", BUCKET_FILL),
    ("contact_search", CONTACT_SEARCH),
    ("search_bounds", SEARCH_BOUNDS),
    ("search_grid", SEARCH_GRID),
    ("contact_constraints", CONTACT_CONSTRAINTS),
    ("contact_touches", CONTACT_TOUCHES),
    ("contact_compliance", CONTACT_COMPLIANCE),
    ("contact_sweep", CONTACT_SWEEP),
    ("contact_apply", CONTACT_APPLY),
    ("sweep_control", SWEEP_CONTROL),
    ("contact_report", CONTACT_REPORT),
    ("bucket_order", BUCKET_ORDER),
];

/// The shared struct definitions alone (for the layout test).
pub const TYPES: &str = include_str!("../../shaders/shared/types.wgsl");
