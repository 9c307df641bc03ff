//! The WGSL source of each kernel: the shared files, then the kernel's own file, as
//! `build.rs` assembles and validates them (with naga) at build time.
//! One constant per kernel, named after it in upper case (`HEX8_FORCES` for
//! `shaders/hex8_forces.wgsl`), and the table [`ALL`].

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The shared struct definitions alone (for the layout test).
pub const TYPES: &str = include_str!("../../shaders/shared/types.wgsl");
