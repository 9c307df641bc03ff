//! Parses and validates every WGSL kernel with naga, so that a broken shader fails
//! `cargo build` rather than a user's run. Each kernel is compiled as the shared files
//! (`shaders/shared/`) followed by the kernel's own file, exactly as `src/gpu/shaders.rs`
//! assembles it.

const SHARED: [&str; 4] = [
    "shaders/shared/types.wgsl",
    "shaders/shared/quad.wgsl",
    "shaders/shared/element.wgsl",
    "shaders/shared/contact.wgsl",
];
const KERNELS: [&str; 26] = [
    "hex8_forces",
    "tet4_forces",
    "node_gather",
    "contact_gap",
    "slip_rate",
    "explicit_predict",
    "plane_contact",
    "explicit_drift",
    "explicit_correct",
    "history_reduce",
    "stable_step",
    "face_cells",
    "bucket_count",
    "prefix_sum",
    "bucket_fill",
    "contact_search",
    "search_bounds",
    "search_grid",
    "contact_constraints",
    "contact_touches",
    "contact_compliance",
    "contact_sweep",
    "contact_apply",
    "sweep_control",
    "contact_report",
    "bucket_order",
];

fn main() {
    println!("cargo:rerun-if-changed=shaders");
    let mut shared = String::new();
    for f in SHARED {
        println!("cargo:rerun-if-changed={f}");
        shared.push_str(&std::fs::read_to_string(f).unwrap_or_else(|e| panic!("{f}: {e}")));
    }
    for k in KERNELS {
        let path = format!("shaders/{k}.wgsl");
        println!("cargo:rerun-if-changed={path}");
        let own = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let source = format!("{shared}{own}");
        // line numbers count through the shared files first, then the kernel
        let path = format!("shaders/shared/*.wgsl + {path}");
        let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| {
            panic!(
                "{path}: WGSL parse error:\n{}",
                e.emit_to_string_with_path(&source, &path)
            )
        });
        let mut validator = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        );
        if let Err(e) = validator.validate(&module) {
            panic!(
                "{path}: WGSL validation error:\n{}",
                e.emit_to_string_with_path(&source, &path)
            );
        }
        if !module.entry_points.iter().any(|ep| ep.name == k) {
            panic!("{path}: no entry point named `{k}` (the file, entry point and twin share one name)");
        }
    }
}
