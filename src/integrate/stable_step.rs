//! The explicit central-difference step's stability limit.
//!
//! Central difference with lumped mass is stable for $\Delta t \le 2/\omega_{max}$, and the
//! largest frequency of the mesh is at most the largest element frequency (Irons' element
//! eigenvalue inequality). Each element's $\omega^2_{max}$ is bounded in turn by Gershgorin's
//! theorem on $M_e^{-1} K_e$ (lumped mass): $\omega^2 \le \max_i \sum_j |K_{ij}| / m_i$. The
//! step is therefore a guaranteed bound, and the unit test measures how tight it is: 0.68 to
//! 0.95 of the element's exact $2/\omega_{max}$ on boxes and distorted elements with Poisson
//! ratios 0 to 0.49.
//!
//! The usual characteristic length of the explicit codes, $V_e / A_{max}$ over the
//! dilatational wave speed, is *not* a bound for the fully integrated hex8: the same test
//! found it up to 1.5 times the element limit at $\nu = 0.49$ (1.22 at 0.3).
//!
//! Elements of the same shape and material (every element of a structured box) share one
//! evaluation, and while there are at most `EXACT_SHAPES` shapes that evaluation is the
//! exact element limit from the 24 x 24 eigenproblem instead of the bound: a structured box
//! of cubes with nu = 0 then gets exactly h / c, the 1D bar's limit. A shape is taken up to
//! its size, and an element's limit is its shape's scaled by the element's extent over the
//! shape's first element's: the stiffness of an element scaled by s goes as s and its mass
//! as s^3, so its limit goes as s, and two bodies meshed at two sizes each get their own.

use std::collections::HashMap;

use rayon::prelude::*;

pub use crate::element::stable_step::{element_critical_step, element_stable_step};
use crate::element::{self, ElementKind, ElementRef};
use crate::error::Result;
use crate::gpu::GpuContext;
use crate::kernels::ElementData;
use crate::model::Model;

/// Up to this many distinct element shapes, each one's limit is its exact eigenvalue;
/// beyond, every element uses the Gershgorin bound (a distorted mesh of a million elements
/// would otherwise spend a minute in eigensolvers). Tet4 shapes count a fifth each (their
/// eigenproblem is 12 x 12), so an unstructured tet mesh of up to 20,480 elements gets the
/// exact limit.
pub(crate) const EXACT_SHAPES: usize = 4096;

/// The smallest element step of the model in its reference configuration, and the element
/// that sets it (index in [`crate::mesh::Mesh::elements`] order).
pub fn stable_step(model: &Model) -> (f64, usize) {
    stable_step_on(model, None).expect("the CPU path cannot fail")
}

/// [`stable_step`], with the Gershgorin bounds of a mesh of many shapes computed by the
/// `stable_step` kernel on `gpu` (the same bound as the CPU, in f32; the smallest element's
/// step is then recomputed in f64, so the result does not depend on the device).
pub fn stable_step_on(model: &Model, gpu: Option<&GpuContext>) -> Result<(f64, usize)> {
    survey(model, gpu).map(|s| (s.step, s.element))
}

/// The mesh's stable step, the element that sets it, and every element's own step (in f32:
/// the model's checks compare them with each other).
pub(crate) struct StepSurvey {
    pub step: f64,
    pub element: usize,
    pub steps: Vec<f32>,
}

/// [`stable_step_on`] with each element's step ([`StepSurvey`]); the step is the elements'
/// lowered by the cohesive interfaces' penalty ([`with_cohesive`]).
pub(crate) fn survey(model: &Model, gpu: Option<&GpuContext>) -> Result<StepSurvey> {
    let mut s = element_survey(model, gpu)?;
    s.step = with_cohesive(model, s.step);
    Ok(s)
}

/// The step `dt_e` of the elements with the cohesive pairs' springs added: the largest
/// eigenvalue of $M^{-1}(K_e + K_c)$ is at most the sum of the two matrices' largest, so
/// $\omega^2 \le (2/\Delta t_e)^2 + \omega_c^2$ with $\omega_c^2 = \max K A (1/m_1 + 1/m_2)$
/// over the pairs (a pair's own frequency, each node in one pair). That bounds a linear
/// spring; a damaged pair switches between K in compression and its secant stiffness in
/// tension, and central difference near a switching spring's limit gains energy at the
/// switches, so the pairs' frequency counts [`COHESIVE_MARGIN`] times:
/// $\Delta t_e / \sqrt{1 + (\Delta t_e\, m \omega_c / 2)^2}$.
pub fn with_cohesive(model: &Model, dt_e: f64) -> f64 {
    if model.cohesive.is_empty() {
        return dt_e;
    }
    let mass = crate::integrate::explicit::lumped_mass(model);
    let pairs = crate::model::cohesive::all_pairs(&model.cohesive);
    let w2 = crate::kernels::cohesive_forces::cohesive_omega2(pairs, &mass);
    let w = COHESIVE_MARGIN * w2.sqrt();
    dt_e / (1.0 + 0.25 * dt_e * dt_e * w * w).sqrt()
}

/// How many times the pairs' own frequency the step allows for: the coarse drop weight's
/// interfaces (30 x 20 x 4 hex8i, 5e5 N/mm^3, split at its two ply changes), where the pairs
/// set the step, gained 23% of the impact's energy in 0.6 ms at 0.9 of the pairs' own limit
/// and kept it to 2e-4 at 0.6 of it (`docs/method-notes.md`, "Cohesive interfaces").
pub const COHESIVE_MARGIN: f64 = 2.0;

/// The elements' own step, as [`survey`] gives it without the cohesive interfaces.
fn element_survey(model: &Model, gpu: Option<&GpuContext>) -> Result<StepSurvey> {
    let shapes = Shapes::of(model);
    let exact = shapes.cost <= 5 * EXACT_SHAPES;
    if let (false, Some(ctx)) = (exact, gpu) {
        let data = model.element_data();
        if crate::gpu::stable_step::covers(&data) {
            return device_survey(model, ctx, &data);
        }
    }
    let limit: Vec<f64> = shapes
        .first
        .par_iter()
        .map(|&e| {
            let el = model.mesh.element(e);
            let x = model.mesh.corners(el.nodes);
            let m = model.section(el.material);
            if exact {
                element_critical_step(el.kind, &x, m)
            } else {
                element_stable_step(el.kind, &x, m)
            }
        })
        .collect();
    let (step, element) = shapes.smallest(model, &limit);
    Ok(StepSurvey {
        step,
        element,
        steps: shapes.each(model, &limit),
    })
}

/// [`survey`] by the `stable_step` kernel: f32 picks the element, f64 gives its step (an
/// element within f32's rounding of the smallest may have been passed over: a relative 1e-6
/// of the step).
fn device_survey(model: &Model, ctx: &GpuContext, data: &ElementData) -> Result<StepSurvey> {
    let steps = crate::gpu::element_steps(ctx, data)?;
    let (e, _) =
        (steps.iter().enumerate()).fold(
            (0, f64::INFINITY),
            |b, (e, &s)| if s < b.1 { (e, s) } else { b },
        );
    let el = model.mesh.element(e);
    let x = model.mesh.corners(el.nodes);
    let step = element_stable_step(el.kind, &x, model.section(el.material));
    Ok(StepSurvey {
        step,
        element: e,
        steps: steps.iter().map(|&s| s as f32).collect(),
    })
}

/// A shape key: the material, the corner count and the corners relative to corner 0 in
/// units of 1e-9 of the element's extent (a kind of fewer corners leaves the rest zero).
type ShapeKey = (u32, ElementKind, [i64; 24]);

fn shape_key(model: &Model, el: ElementRef) -> ShapeKey {
    let x = model.mesh.corners(el.nodes);
    let size = element::extent(&x).max(f64::MIN_POSITIVE);
    let origin = x[0];
    let mut key = [0i64; 24];
    for (k, p) in x.iter().enumerate() {
        for a in 0..3 {
            key[3 * k + a] = ((p[a] - origin[a]) / size * 1e9).round() as i64;
        }
    }
    (el.material, el.kind, key)
}

/// Element `e`'s largest extent along an axis.
fn extent_of(model: &Model, e: usize) -> f64 {
    element::extent(&model.mesh.corners(model.mesh.element(e).nodes))
}

/// The distinct element shapes of a mesh (up to a translation and a scaling, to 1e-9 of the
/// element's size), numbered in the order of their first element.
struct Shapes {
    /// The first element of each shape.
    first: Vec<usize>,
    /// Each block's shapes' numbers, by the block's own numbering.
    global: Vec<Vec<usize>>,
    /// Each element's shape in its block's numbering.
    local: Vec<u32>,
    /// 5 per hex8 shape, 1 per tet4 shape (their eigenproblems' relative cost).
    cost: usize,
}

const SHAPE_BLOCK: usize = 1 << 15;

/// A block's shapes (key, first element) in the order they appear, and each of its elements'
/// shape in that order.
type BlockShapes = (Vec<(ShapeKey, usize)>, Vec<u32>);

impl Shapes {
    /// Blocks of elements find their shapes on all threads; the blocks' lists are then
    /// merged in order, so the numbering is the one a single pass gives.
    fn of(model: &Model) -> Self {
        let n = model.mesh.element_count();
        let blocks: Vec<BlockShapes> = (0..n.div_ceil(SHAPE_BLOCK))
            .into_par_iter()
            .map(|b| {
                let mut seen: HashMap<ShapeKey, u32> = HashMap::new();
                let mut order = Vec::new();
                let local = (b * SHAPE_BLOCK..n.min((b + 1) * SHAPE_BLOCK))
                    .map(|e| {
                        let key = shape_key(model, model.mesh.element(e));
                        let next = seen.len() as u32;
                        *seen.entry(key).or_insert_with(|| {
                            order.push((key, e));
                            next
                        })
                    })
                    .collect();
                (order, local)
            })
            .collect();
        let mut ids: HashMap<ShapeKey, usize> = HashMap::new();
        let mut first = Vec::new();
        let mut cost = 0;
        let mut global = Vec::with_capacity(blocks.len());
        let mut local = Vec::with_capacity(n);
        for (order, block_local) in blocks {
            let map = order
                .into_iter()
                .map(|(key, e)| {
                    *ids.entry(key).or_insert_with(|| {
                        first.push(e);
                        cost += key.1.exact_step_cost();
                        first.len() - 1
                    })
                })
                .collect();
            global.push(map);
            local.extend(block_local);
        }
        Shapes {
            first,
            global,
            local,
            cost,
        }
    }

    /// Element `e`'s limit: its shape's `limit`, scaled by its extent over the extent of the
    /// shape's first element.
    fn limit_of(&self, model: &Model, limit: &[f64], e: usize, l: u32) -> f64 {
        let shape = self.global[e / SHAPE_BLOCK][l as usize];
        let first = self.first[shape];
        if first == e {
            return limit[shape];
        }
        limit[shape] * extent_of(model, e) / extent_of(model, first)
    }

    /// Each element's limit.
    fn each(&self, model: &Model, limit: &[f64]) -> Vec<f32> {
        self.local
            .par_iter()
            .enumerate()
            .map(|(e, &l)| self.limit_of(model, limit, e, l) as f32)
            .collect()
    }

    /// The smallest limit over the elements, and the first element that has it.
    fn smallest(&self, model: &Model, limit: &[f64]) -> (f64, usize) {
        self.local
            .par_iter()
            .enumerate()
            .map(|(e, &l)| (self.limit_of(model, limit, e, l), e))
            .reduce(
                || (f64::INFINITY, 0),
                |a, b| {
                    if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
                        b
                    } else {
                        a
                    }
                },
            )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Elastic;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    /// Boxes stretched 0.2 to 3 times along each axis, and the same with corners moved by up
    /// to 0.2 of the sides: the bound is never above the element limit, and within a factor
    /// 0.65 of it.
    #[test]
    fn gershgorin_step_is_a_tight_bound_of_the_element_limit() {
        let mut rng = StdRng::seed_from_u64(11);
        // the unit cube, corners in hex8 order
        let corners = crate::element::hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0)));
        for case in 0..200 {
            let stretch = [
                rng.random_range(0.2..3.0),
                rng.random_range(0.2..3.0),
                rng.random_range(0.2..3.0),
            ];
            let jitter = if case < 40 { 0.0 } else { 0.2 };
            let x = corners.map(|c| {
                std::array::from_fn(|a| {
                    c[a] * stretch[a] + jitter * rng.random_range(-1.0..1.0) * stretch[a]
                })
            });
            let nu = [0.0, 0.3, 0.45, 0.49][case % 4];
            let m = Elastic::from_engineering(rng.random_range(1.0..1e4), nu, 7.8);
            let hex = ElementKind::Hex8;
            let ratio = element_stable_step(hex, &x, &m) / element_critical_step(hex, &x, &m);
            assert!(
                (0.65..=1.0 + 1e-12).contains(&ratio),
                "case {case}: bound {ratio} of 2/omega (nu {nu})"
            );
            // a tet of four of the same corners (0, 1, 3, 4: a corner tet, distorted)
            let t = [x[0], x[1], x[3], x[4]];
            let tet = ElementKind::Tet4;
            let ratio = element_stable_step(tet, &t, &m) / element_critical_step(tet, &t, &m);
            assert!(
                (0.4..=1.0 + 1e-12).contains(&ratio),
                "case {case}: tet bound {ratio} of 2/omega (nu {nu})"
            );
        }
    }

    /// A uniaxial bar (nu = 0) of cubes: the bound is h / c times a fixed factor, the same
    /// for every element, found once.
    #[test]
    fn structured_box_step_scales_with_the_element_size() {
        let m = Elastic::from_engineering(100.0, 0.0, 0.01);
        let cube = |h: f64| {
            [
                [0.0, 0.0, 0.0],
                [h, 0.0, 0.0],
                [h, h, 0.0],
                [0.0, h, 0.0],
                [0.0, 0.0, h],
                [h, 0.0, h],
                [h, h, h],
                [0.0, h, h],
            ]
        };
        let (a, b) = (
            element_stable_step(ElementKind::Hex8, &cube(1.0), &m),
            element_stable_step(ElementKind::Hex8, &cube(0.25), &m),
        );
        assert!((a / b - 4.0).abs() < 1e-12);
        // the exact element limit of a nu = 0 cube is h / c; the bound is below it
        assert!(a <= 1.0 / m.wave_speed() * (1.0 + 1e-12));
    }
}
