//! Whether the VTU frames can be read back by an independent reader (Python's meshio).

use std::process::Command;

/// Whether python3 can import meshio; where it cannot, says so, and fails the test when
/// `IMPACT_REQUIRE_MESHIO` is set (as CI sets it).
pub fn meshio_available(tag: &str) -> bool {
    let found = Command::new("python3")
        .args(["-c", "import meshio"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        assert!(
            std::env::var_os("IMPACT_REQUIRE_MESHIO").is_none(),
            "meshio is missing and IMPACT_REQUIRE_MESHIO is set: python3 -m pip install meshio"
        );
        println!("{tag}: skipped: python3 cannot import meshio (python3 -m pip install meshio to read the frames back)");
    }
    found
}
