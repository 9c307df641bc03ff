//! The WGSL source of each kernel: the shared files, then the kernel's own file, as
//! `build.rs` assembles and validates them (with naga) at build time.
//! One constant per kernel, named after it in upper case (`HEX8_FORCES` for
//! `shaders/hex8_forces.wgsl`), and the table [`ALL`].

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The shared struct definitions alone (for the layout test).
pub const TYPES: &str = include_str!("../../shaders/shared/types.wgsl");

/// The assembled source of the kernel `name` (a name of [`ALL`]).
pub fn source(name: &str) -> &'static str {
    ALL.iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
        .unwrap_or_else(|| {
            panic!("no shaders/{name}.wgsl (the kernel table names a file that is not there)")
        })
}
