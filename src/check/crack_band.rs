//! The crack band's snap-back limit: linear softening over a band of width $l^*$ dissipates
//! the fracture energy G per unit crack area only where $l^* \le 2 E G / X^2$; a wider
//! element's equivalent stress drops at once and dissipates its elastic energy at the
//! strength instead, more than G ([`crate::material::damage`]). One warning per material and
//! mode whose elements are wider, with the limit and the five widest; none for a material
//! that lowers those elements' strengths (`snap_back = "lower_strength"`), whose bands then
//! dissipate G.

use super::Warning;
use crate::element::{ElementKind, Elements};
use crate::kernels::damage_data::DamageData;
use crate::material::damage::MODES;
use crate::model::Model;

/// An element past a mode's limit: its global number and its band.
type Past = (usize, f64);

/// The elements of `data` whose band in a mode exceeds the mode's limit (with their widest
/// ply's band), per (law, mode), `keep` choosing which elements count, of the laws that
/// lower their strengths there (`lowering`) or of those that do not.
fn past_limits(
    data: &DamageData,
    elements: &Elements,
    keep: &dyn Fn(usize, usize) -> bool,
    lowering: bool,
) -> Vec<Vec<Vec<Past>>> {
    let mut out = vec![vec![Vec::<Past>::new(); 4]; data.laws.len()];
    for (k, b) in data.blocks.iter().enumerate() {
        let offset = elements.offset(ElementKind::ALL[k]);
        for i in 0..b.len() {
            let e = offset + b.elements[i] as usize;
            for ply in b.plies_of(i) {
                let law = data.law_of[ply.entry as usize] as usize;
                if data.laws[law].lower_strength != lowering {
                    continue;
                }
                for (mode, past) in out[law].iter_mut().enumerate() {
                    let band = ply.bands[mode / 2];
                    let limit = data.laws[law].snap_back_width(mode);
                    if band <= limit || !keep(e, mode) {
                        continue;
                    }
                    // an element once, with its widest ply's band
                    match past.last_mut() {
                        Some(p) if p.0 == e => p.1 = p.1.max(band),
                        _ => past.push((e, band)),
                    }
                }
            }
        }
    }
    out
}

/// The warnings of [`past_limits`]; `names` gives each law's material name, `when` the
/// sentence on what follows.
fn warnings(
    data: &DamageData,
    past: Vec<Vec<Vec<Past>>>,
    names: &[String],
    when: &str,
) -> Vec<Warning> {
    let mut out = Vec::new();
    for (law, modes) in past.into_iter().enumerate() {
        for (mode, mut els) in modes.into_iter().enumerate() {
            if els.is_empty() {
                continue;
            }
            els.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            let l = &data.laws[law];
            let (e, x) = l.mode_constants(mode);
            let worst: Vec<String> = (els.iter().take(5))
                .map(|(el, band)| format!("element {el} ({band:.4} wide)"))
                .collect();
            out.push(Warning::new(
                "crack_band",
                format!(
                    "material `{}`, {}: {} wider across the crack than the snap-back limit 2 E G / X^2 = {} (E {e:.5e}, G {}, X {x}); {when}; the widest: {}",
                    names[law],
                    MODES[mode],
                    match els.len() {
                        1 => "1 element is".to_string(),
                        n => format!("{n} elements are"),
                    },
                    three_figures(l.snap_back_width(mode)),
                    l.energy[mode],
                    worst.join(", ")
                ),
            ));
        }
    }
    out
}

/// `v` to three significant figures (1.30, 0.359, 21.3).
fn three_figures(v: f64) -> String {
    let decimals = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

/// The name of each law's material (laws in the order of the damaging scene materials).
fn law_names(scene: &crate::scene::Scene) -> Vec<String> {
    (scene.materials.iter())
        .filter(|m| m.damage.is_some())
        .map(|m| m.name.clone())
        .collect()
}

/// Before a run: every damageable element past a limit.
pub fn crack_band(scene: &crate::scene::Scene, model: &Model, data: &DamageData) -> Vec<Warning> {
    let past = past_limits(data, &model.mesh.elements, &|_, _| true, false);
    let when = "where they damage in that mode, their softening drops at once and the energy they dissipate is wrong (too large): refine them (box.refine) below the limit, or give the material `snap_back = \"lower_strength\"`";
    warnings(data, past, &law_names(scene), when)
}

/// After a run: the elements past a limit that damaged in that mode (`cells`: each
/// element's acting damage by mode).
pub fn damaged_past_limit(
    scene: &crate::scene::Scene,
    model: &Model,
    data: &DamageData,
    cells: &[[f64; 4]],
) -> Vec<Warning> {
    let keep = |e: usize, mode: usize| cells.get(e).is_some_and(|c| c[mode] > 0.0);
    let past = past_limits(data, &model.mesh.elements, &keep, false);
    let when = "they damaged in that mode, their softening dropped at once and the energy they dissipated is too large: refine them (box.refine) below the limit, or give the material `snap_back = \"lower_strength\"`";
    warnings(data, past, &law_names(scene), when)
}

/// For `impact check`: one line per material and mode whose strength is lowered in elements
/// past its limit (`snap_back = "lower_strength"`), with how many and how far.
pub fn lowered(scene: &crate::scene::Scene, model: &Model, data: &DamageData) -> Vec<String> {
    let past = past_limits(data, &model.mesh.elements, &|_, _| true, true);
    let names = law_names(scene);
    let mut out = Vec::new();
    for (law, modes) in past.into_iter().enumerate() {
        for (mode, els) in modes.into_iter().enumerate() {
            if els.is_empty() {
                continue;
            }
            let l = &data.laws[law];
            let onsets = els.iter().map(|&(_, band)| l.onset(mode, band));
            let (low, high) = onsets.fold((1.0f64, 0.0f64), |(a, b), s| (a.min(s), b.max(s)));
            let x = l.mode_constants(mode).1;
            out.push(format!(
                "material `{}`, {}: strength lowered in {} wider than the snap-back limit {}, to {} to {} of {x} (sqrt(2 E G / l*))",
                names[law],
                MODES[mode],
                match els.len() {
                    1 => "1 element".to_string(),
                    n => format!("{n} elements"),
                },
                three_figures(l.snap_back_width(mode)),
                three_figures(low),
                three_figures(high),
            ));
        }
    }
    out
}
