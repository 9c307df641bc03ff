//! The implicit multiplier iteration on the contact space (`implicit.contact_space =
//! "auto"`) against the same iteration on the whole model: a block dropped on a held rigid
//! floor, with the consistent and the lumped mass. The histories agree to the iteration's
//! tolerance, the iteration counts nearly so, and the summary shows two full solves a step
//! with the rest on the contact space.

mod common;
use common::*;

use impact::output::Summary;

/// The implicit bench's block of `n` x `n` x `n` cells dropped on a rigid floor, for
/// `steps` steps; `extra` goes under `[implicit]`.
fn block_drop(n: usize, steps: usize, extra: &str) -> String {
    implicit_block_drop([n; 3], steps, extra)
}

/// Runs `text` with the contact space and without; returns both summaries and histories.
fn both(tag: &str, text: &str) -> [(Summary, History); 2] {
    ["auto", "off"].map(|mode| {
        let t = text.replace(
            "[implicit]\n",
            &format!("[implicit]\ncontact_space = \"{mode}\"\n"),
        );
        let (s, h) = run_text(&format!("{tag}_{mode}"), &t);
        let s = s.unwrap_or_else(|e| panic!("{tag} {mode}: {e}"));
        assert_eq!(s.status, "completed", "{tag} {mode}");
        (s, h)
    })
}

/// Every column of `a` against `b`'s, relative to the column's largest magnitude (absolute
/// below `floor`): the largest difference.
fn worst(a: &History, b: &History, floor: f64) -> (String, f64) {
    let mut out = (String::new(), 0.0f64);
    for c in a.columns.iter().filter(|c| *c != "step") {
        let (x, y) = (a.col(c), b.col(c));
        let scale = y.iter().fold(floor, |m, v| m.max(v.abs()));
        let d = x
            .iter()
            .zip(&y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
            / scale;
        if d > out.1 {
            out = (c.clone(), d);
        }
    }
    out
}

/// Checks the run of `text` on the contact space against the run on the whole model: at
/// most two full solves a step or sub-step (`substeps` of them in each step refined at a
/// contact event), and the same history; returns the steps refined.
fn check(tag: &str, text: &str, steps: usize, substeps: usize) -> usize {
    let [(sa, ha), (so, ho)] = both(tag, text);
    let ls = sa.linear_solver.as_ref().expect("an implicit run");
    eprintln!(
        "{tag}: {} contact equations, {} full solves and {} contact-space solves against {} full solves; {:.3} s against {:.3} s",
        ls.contact_equations,
        ls.solves,
        ls.contact_solves,
        so.linear_solver.as_ref().unwrap().solves,
        sa.wall_seconds,
        so.wall_seconds
    );
    assert!(
        ls.contact_equations > 0 && ls.contact_solves > 0,
        "{tag}: the iteration ran on the contact space"
    );
    let (solves, events) = (ls.solves, sa.event_steps);
    assert!(
        solves <= 2 * (steps + events * substeps),
        "{tag}: {solves} full solves in {steps} steps, {events} of them refined"
    );
    assert_eq!(events, so.event_steps, "{tag}: the same steps refined");
    let (column, d) = worst(&ha, &ho, 1e-9);
    eprintln!("{tag}: largest difference {d:.2e} in {column}");
    assert!(d <= 1e-6, "{tag}: {column} differs by {d:e}");
    events
}

#[test]
fn a_block_dropped_on_a_rigid_floor_iterates_on_its_bottom_face() {
    // two full solves a step at most (the step's first iteration and its last solve)
    let plain = "event_substeps = 1";
    check("contact_space_drop", &block_drop(10, 12, plain), 12, 0);
    let lumped = format!("{plain}\nmass = \"lumped\"");
    check(
        "contact_space_drop_lumped",
        &block_drop(10, 12, &lumped),
        12,
        0,
    );
    // with the default 4 event sub-steps, which iterate on the contact space too (their
    // factor shares the run's symbolic analysis)
    let refined = check(
        "contact_space_drop_substeps",
        &block_drop(10, 12, ""),
        12,
        4,
    );
    assert!(refined > 0, "the impact is refined");
    // Newmark with numerical damping (gamma > 1/2): w = M^-1 f_c moves the velocity, so
    // every iteration forms it, on the contact space too
    let damped = format!("{plain}\nbeta = 0.3025\ngamma = 0.6");
    check(
        "contact_space_drop_damped",
        &block_drop(10, 12, &damped),
        12,
        0,
    );
}

/// Where the contact space does not pay (a flat plate: its bottom face is a third of the
/// model), "auto" iterates on the whole model: after each step's first iteration the
/// contact nodes move by the flexibility's columns at them (or, where a node whose force
/// changed has none yet, by a solve for the change of the contact forces alone), and one
/// solve at the step's end recovers the rest; "off" re-forms the residual every iteration.
/// The two give the same history to the iteration's tolerance.
#[test]
fn without_a_contact_space_the_iterations_solve_for_the_change_of_the_forces() {
    let [(sa, ha), (so, ho)] = both(
        "contact_space_declined",
        &implicit_block_drop([8, 8, 2], 30, ""),
    );
    let ls = sa.linear_solver.as_ref().expect("an implicit run");
    assert_eq!(ls.contact_equations, 0, "the contact space is declined");
    let newton = sa.newton.as_ref().expect("Newton steps");
    assert!(
        newton.steps > 0 && newton.flexibility_moves > 0,
        "{newton:?}"
    );
    let off = so.newton.as_ref().expect("Newton steps");
    assert_eq!(off.flexibility_moves, 0, "off re-forms the residual");
    let solves = |s: &Summary| s.linear_solver.as_ref().map_or(0, |l| l.solves);
    // a move replaces a solve; the recovery adds one a step
    assert!(
        solves(&sa) <= solves(&so),
        "{} full solves against {}",
        solves(&sa),
        solves(&so)
    );
    let (column, d) = worst(&ha, &ho, 1e-9);
    eprintln!(
        "declined: largest difference {d:.2e} in {column}; {:.2} and {:.2} iterations a step",
        sa.iterations_mean, so.iterations_mean
    );
    assert!(d <= 1e-6, "{column} differs by {d:e}");
    assert_eq!(sa.unconverged_steps, 0);
}
