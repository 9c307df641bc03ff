//! The fill-reducing ordering of the implicit factorisation changes only the rounding: the
//! same scene with nested dissection (the default) and with AMD gives the same history, and
//! the summary reports each factor's ordering, size and costs.

mod common;
use common::*;

/// The paper's cube on the plate (oblique impact, friction 0.3, contact events refined)
/// with `ordering`, its multiplier iteration run to a relative change of 1e-9.
fn cube_on_plate(tag: &str, ordering: &str) -> (impact::output::Summary, History) {
    let text = format!(
        "{}\n[implicit]\nordering = \"{ordering}\"\ntolerance = 1e-9\nmax_iterations = 2000\n",
        scene_text("cube_on_plate.toml")
    );
    let (s, h) = run_text(tag, &text);
    let s = s.expect("runs");
    assert_eq!(s.status, "completed", "{:?}", s.warnings);
    (s, h)
}

#[test]
fn nested_dissection_and_amd_give_the_same_history() {
    let (nd, h_nd) = cube_on_plate("ordering_nd", "nested_dissection");
    let (amd, h_amd) = cube_on_plate("ordering_amd", "amd");
    assert_eq!(h_nd.columns, h_amd.columns);
    assert_eq!(h_nd.rows.len(), h_amd.rows.len());
    let mut worst = (0.0f64, String::new());
    for c in &h_nd.columns {
        let (a, b) = (h_nd.col(c), h_amd.col(c));
        // a vector's components share one scale (a component that stays at rounding level,
        // like the plate's vy, is measured against the vector's size)
        let family: &[&str] = match c.rsplit_once('.').map(|(_, f)| &f[..1]) {
            Some("v") => &[".vx", ".vy", ".vz"],
            Some("u") => &[".ux", ".uy", ".uz"],
            _ => &[],
        };
        let own = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let scale = own.max(family_scale(&h_nd, family));
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        // the penetration is itself the constraint's residual, left by an iteration that
        // stops at a small relative change: it moves by more of its own size
        let scale = if c.ends_with("max_penetration") {
            10.0 * scale
        } else {
            scale
        };
        if scale > 0.0 && diff / scale > worst.0 {
            worst = (diff / scale, c.clone());
        }
    }
    eprintln!(
        "largest difference: {:.2e} of the scale of {}",
        worst.0, worst.1
    );
    // the multiplier iteration stops at a relative change of 1e-9: two roundings may stop
    // it an iteration apart, which moves a column by a few times that (6.7e-9 measured)
    assert!(
        worst.0 < 1e-7,
        "{} differs by {:.2e} of its scale",
        worst.1,
        worst.0
    );

    for (s, name) in [(&nd, "nested_dissection"), (&amd, "amd")] {
        let f = s
            .linear_solver
            .as_ref()
            .expect("an implicit run reports its factor");
        assert_eq!(f.ordering.name(), name);
        assert_eq!(f.equations, s.free_dofs);
        // a Cholesky factor holds at least the lower triangle of the matrix
        assert!(f.factor_nonzeros >= (f.matrix_nonzeros + f.equations) / 2);
        assert_eq!(
            f.factorizations,
            s.factorizations - s.mass_factor.as_ref().map_or(0, |m| m.factorizations)
        );
        // one solve pair per multiplier iteration, on the step's or the sub-step's factor
        assert_eq!(f.solves, s.iterations_total);
        assert!(f.factorization_seconds > 0.0 && f.solve_seconds > 0.0);
    }
}
