//! Regression: a secondary node over a vertex or edge of a bent primary surface is about
//! equally close to faces with different normals. Within a step's contact iteration the
//! closest of them changed from one iteration to the next with the last bits of u, the
//! contact force flipped direction with it, and the iteration never converged: the tet4 cube
//! on the tet4 plate ended step 1 unconverged at 100 iterations (and at 400), and so did a
//! tet4 cube on the hex8 plate. A node now keeps the face it held in the iteration before
//! while that face is at most 1e-6 face sizes farther than the closest.

mod common;
use common::*;

/// The tet4 cube on the tet4 plate (friction 0.3), implicit: every step converges, and the
/// total energy rises in no step by more than 1e-9 of itself (elastic contact with friction
/// only loses energy).
#[test]
fn tet4_cube_on_tet4_plate_converges_every_step() {
    let (s, h) = run_text("face_flips_tet4", &tet4_cube_on_plate());
    let s = s.expect("run completes");
    eprintln!(
        "iterations per step {:.2} (max {}), unconverged {}",
        s.iterations_mean, s.iterations_max, s.unconverged_steps
    );
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    assert_eq!(s.unconverged_steps, 0);
    let e = h.col("total_energy");
    for w in e.windows(2) {
        assert!(
            w[1] <= w[0] * (1.0 + 1e-9),
            "energy rose {} -> {}",
            w[0],
            w[1]
        );
    }
}

/// The tet4 cube on the hex8 plate (quad faces, the nodes over their vertices): the same.
#[test]
fn tet4_cube_on_hex8_plate_converges_every_step() {
    let text = tet4_cube_on_plate().replace(
        "divisions = [16, 4, 4], element = \"tet4\" }",
        "divisions = [16, 4, 4] }",
    );
    assert_eq!(text.matches("\"tet4\"").count(), 1);
    let (s, _) = run_text("face_flips_tet4_on_hex8", &text);
    let s = s.expect("run completes");
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    assert_eq!(s.unconverged_steps, 0);
}
