//! The ply failure indices of a step on the device (CPU twin of
//! `shaders/failure_survey.wgsl`): at every evaluation
//! point of [`crate::output::failure_survey`] the ply stress is the point's operator times its
//! cell's corner displacements relative to the first corner (the operator takes no stress
//! from a translation, and relative displacements keep their digits in f32), then the Hashin
//! and maximum-stress indices ([`failure_indices`]). Each workgroup of [`SURVEY_GROUP`] points
//! keeps the largest of each index and its worst point (the largest index there, the lowest
//! point on a tie): its record ([`super::failure_reduce`] merges the records into one).

use super::failure_reduce::{empty, merge, FAILURE_FIELDS};
use crate::material::{failure_indices, Strength};

/// Points per workgroup of `failure_survey`.
pub const SURVEY_GROUP: usize = 64;
/// Columns of an operator: three per corner of a hex8 (a tet4's last 12 are zero).
pub const SURVEY_COLUMNS: usize = 24;

/// An evaluation point: its cell's corners (the first `corners` of `nodes`), its strength and
/// its operator (6 rows of [`SURVEY_COLUMNS`], the stress 11, 22, 33, 12, 23, 13 in the ply's
/// axes per corner displacement).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SurveyPoint {
    pub nodes: [u32; 8],
    pub corners: u32,
    pub strength: u32,
    pub stress_operator: u32,
}

/// The record of point `i` at the displacement `u` (3 per node).
fn point_record(
    i: usize,
    p: &SurveyPoint,
    operators: &[f64],
    strengths: &[Strength],
    u: &[f64],
) -> [f64; FAILURE_FIELDS] {
    let at = |n: u32, a: usize| u[3 * n as usize + a];
    let op = &operators[6 * SURVEY_COLUMNS * p.stress_operator as usize..][..6 * SURVEY_COLUMNS];
    let mut s = [0.0f64; 6];
    for k in 1..p.corners as usize {
        for a in 0..3 {
            let du = at(p.nodes[k], a) - at(p.nodes[0], a);
            for (r, s) in s.iter_mut().enumerate() {
                *s += op[r * SURVEY_COLUMNS + 3 * k + a] * du;
            }
        }
    }
    let f = failure_indices(s, &strengths[p.strength as usize]);
    let (k, v) = (0..5).fold((0, f[0]), |b, k| if f[k] > b.1 { (k, f[k]) } else { b });
    let mut r = [0.0; FAILURE_FIELDS];
    r[..5].copy_from_slice(&f);
    r[5..].copy_from_slice(&[v, i as f64, k as f64]);
    r
}

/// The records of the workgroups of `failure_survey`, [`FAILURE_FIELDS`] each.
pub fn failure_survey(
    points: &[SurveyPoint],
    operators: &[f64],
    strengths: &[Strength],
    u: &[f64],
) -> Vec<f64> {
    points
        .chunks(SURVEY_GROUP)
        .enumerate()
        .flat_map(|(g, chunk)| {
            let mut rec = empty();
            for (j, p) in chunk.iter().enumerate() {
                let i = g * SURVEY_GROUP + j;
                merge(&mut rec, &point_record(i, p, operators, strengths, u));
            }
            rec
        })
        .collect()
}

/// What the device survey needs: its points, their operators (6 x [`SURVEY_COLUMNS`] each,
/// row-major) and the strengths they name.
#[derive(Debug, Clone, Default)]
pub struct SurveySetup {
    pub points: Vec<SurveyPoint>,
    pub operators: Vec<f64>,
    pub strengths: Vec<Strength>,
}
