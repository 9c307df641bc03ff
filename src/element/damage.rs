//! Elements whose plies damage ([`crate::material::damage`]): each ply's integration
//! points carry their damage variables, and the element's corner forces are
//! $f_k = \sum_p w_p \det J_p\, \sigma_p \nabla N_k(p)$ with each point's stress from its
//! ply's law. These are the CPU forms, in f64, of what the damage kernels compute.
//!
//! **Points.** A hex's 2x2x2 Gauss points, per ply over the ply's part of the natural
//! coordinate along the layup's axis (the points of [`super::Section::hex_points`]); a tet's
//! one point.
//!
//! **The incompatible modes** of a hex8i are condensed elastically, $\alpha = A_0 u$
//! ([`super::hex8i::condensation`]), whatever the damage: each point's strain is a fixed
//! operator of the corner displacements, $\bar B = B_u + B_\alpha A_0$ (an assumed strain,
//! the hex8i's own while it is elastic), and the forces $\bar B^T \sigma = B_u^T \sigma +
//! A_0^T B_\alpha^T \sigma$ are the gradient of the points' energy (the second term vanishes
//! while the element is elastic, where $\alpha$ minimises its energy). Condensed with the damaged stiffness instead, the modes let the
//! strain gather at the four points on one side of a softening element, so that its band
//! was half the element: a cube pulled apart along its fibres dissipated 72 of its 133 N mm.
//!
//! **Bands.** A ply's band across a fibre crack is the element's chord through its centre
//! along the fibres (axis 1), across a matrix crack the chord along axis 2: the width a
//! crack normal to that axis cuts out of the element ([`hex_bands`], [`tet_bands`]).

use super::{hex8, hex8i, tet4};
use crate::material::damage::{voigt_apply, Dissipation, PlyDamage, POINT_STATE};
use crate::material::Rotation;

/// The damage laws of a model's material entries: each entry's law (an index of `laws`,
/// [`NO_LAW`] for one that does not damage) and material axes.
#[derive(Debug, Clone, Copy)]
pub struct DamageLaws<'a> {
    pub laws: &'a [PlyDamage],
    pub law_of: &'a [u32],
    pub axes: &'a [Rotation],
}

/// The law index of a material entry that does not damage.
pub const NO_LAW: u32 = u32::MAX;

/// One ply of a damageable element: its material entry, its range of the natural
/// coordinate along the element's layup axis, and its band widths across fibre and matrix
/// cracks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamagePly {
    pub entry: u32,
    pub lo: f64,
    pub hi: f64,
    pub bands: [f64; 2],
}

/// A hex's incompatible modes: none (hex8), or a hex8i's elastic condensation ($A_0$, 9 x 24
/// row-major: mode m's component c in row 3 m + c).
#[derive(Debug, Clone, Copy)]
pub enum Modes<'a> {
    None,
    Elastic(&'a [f64]),
}

/// What a damageable element's step gives: its corner forces, the energy it dissipated
/// (with the fibre modes' share), and whether any of its points holds damage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamageStep<const N: usize> {
    pub forces: [[f64; 3]; N],
    pub dissipated: Dissipation,
    pub damaged: bool,
}

/// A hex's points: per ply, the 2x2x2 Gauss points over its range along `axis`, with their
/// weights (the cube's 1 for a ply spanning the element) and the ply's index.
pub fn hex_points(plies: &[DamagePly], axis: usize) -> Vec<([f64; 3], f64, usize)> {
    let g = 1.0 / 3f64.sqrt();
    let cube = hex8::gauss_points();
    (plies.iter().enumerate())
        .flat_map(|(k, ply)| {
            let (mid, half) = (0.5 * (ply.lo + ply.hi), 0.5 * (ply.hi - ply.lo));
            cube.iter().map(move |&p| {
                let mut q = p;
                q[axis] = mid + half * p[axis].signum() * g;
                (q, half, k)
            })
        })
        .collect()
}

/// The displacement gradient $\sum_k u_k \otimes g_k$ (corner displacements relative to
/// corner 0: the gradients sum to zero).
fn gradient<const N: usize>(g: &[[f64; 3]; N], u: &[[f64; 3]; N]) -> [[f64; 3]; 3] {
    std::array::from_fn(|a| {
        std::array::from_fn(|b| (1..N).map(|k| (u[k][a] - u[0][a]) * g[k][b]).sum())
    })
}

/// One point's step: the ply strains of `h` and of the step before's `h_prev`, the law's
/// step (or, without `advance`, the stress of the old damage) and the global stress, with
/// the point's dissipation per unit volume. `state` is the point's state, old on entry and
/// new on return (with `advance`).
fn point_stress(
    (law, axes): (&PlyDamage, &Rotation),
    (h, h_prev): (&[[f64; 3]; 3], &[[f64; 3]; 3]),
    state: &mut [f64],
    (bands, dt, advance): ([f64; 2], f64, bool),
) -> ([[f64; 3]; 3], Dissipation) {
    let e = axes.strain_to_material(h);
    let old: &[f64; POINT_STATE] = (&*state).try_into().expect("a point's state");
    if !advance {
        let eff = voigt_apply(&law.c0, &e);
        let c = law.ortho(law.acting(old, (eff[0] >= 0.0, eff[1] + eff[2] >= 0.0)));
        return (axes.stress_to_global(&c.apply(&e)), Dissipation::default());
    }
    let step = law.step((&e, &axes.strain_to_material(h_prev)), old, bands, dt);
    state.copy_from_slice(&step.state);
    (
        axes.stress_to_global(&step.stress),
        point_dissipation(&step),
    )
}

/// A point step's dissipation, whole and the fibre modes' share.
fn point_dissipation(step: &crate::material::damage::PointStep) -> Dissipation {
    Dissipation {
        total: step.dissipated,
        fibre: step.fibre,
    }
}

/// The law and axes of a ply.
fn ply_law<'a>(laws: &DamageLaws<'a>, ply: &DamagePly) -> (&'a PlyDamage, &'a Rotation) {
    let e = ply.entry as usize;
    (&laws.laws[laws.law_of[e] as usize], &laws.axes[e])
}

/// A hex point's corner gradients, its $w \det J$ and its modes' gradients.
type PointGeometry = ([[f64; 3]; 8], f64, [[f64; 3]; 3]);

/// Each of a hex's `points`' geometry.
fn hex_geometry(x: &[[f64; 3]; 8], points: &[([f64; 3], f64, usize)]) -> Vec<PointGeometry> {
    let (inv0, det0) = hex8i::centre_jacobian(x);
    (points.iter())
        .map(|&(q, w, _)| {
            let (g, det) = hex8::gradients(x, q);
            let m: [[f64; 3]; 3] =
                std::array::from_fn(|m| inv0[m].map(|v| -2.0 * q[m] * v * det0 / det));
            (g, w * det, m)
        })
        .collect()
}

/// The modes' amplitudes at corner displacements `u` (zero without modes).
fn amplitudes(modes: Modes, u: &[[f64; 3]; 8]) -> [f64; 9] {
    match modes {
        Modes::None => [0.0; 9],
        Modes::Elastic(a0) => std::array::from_fn(|r| {
            (0..24)
                .map(|j| a0[24 * r + j] * (u[j / 3][j % 3] - u[0][j % 3]))
                .sum()
        }),
    }
}

/// A hex point's displacement gradient: its corners' part and its modes' of amplitudes
/// `alpha`.
fn point_gradient(
    (g, m): (&[[f64; 3]; 8], &[[f64; 3]; 3]),
    u: &[[f64; 3]; 8],
    alpha: &[f64; 9],
) -> [[f64; 3]; 3] {
    let mut h = gradient(g, u);
    for (mm, gm) in m.iter().enumerate() {
        for a in 0..3 {
            for b in 0..3 {
                h[a][b] += alpha[3 * mm + a] * gm[b];
            }
        }
    }
    h
}

/// The largest reach ([`PlyDamage::reach`]) over a hex's points at corner displacements
/// `u`, from its corners `x`, each in units of its ply's lowest onset
/// ([`PlyDamage::lowest_onset`]: 1 unless its law lowers its strengths), so that a reach
/// below 1 rules out a start.
pub fn hex_reach(
    x: &[[f64; 3]; 8],
    u: &[[f64; 3]; 8],
    (plies, axis): (&[DamagePly], usize),
    laws: &DamageLaws,
    modes: Modes,
) -> f64 {
    let points = hex_points(plies, axis);
    let alpha = amplitudes(modes, u);
    (hex_geometry(x, &points).iter().zip(&points))
        .map(|((g, _, m), p)| {
            let (law, axes) = ply_law(laws, &plies[p.2]);
            let e = axes.strain_to_material(&point_gradient((g, m), u, &alpha));
            law.reach(&e) / law.lowest_onset(plies[p.2].bands)
        })
        .fold(0.0, f64::max)
}

/// [`hex_reach`] through the element's [`HexOperators`].
pub fn hex_reach_operated(
    ops: &HexOperators,
    u: &[[f64; 3]; 8],
    plies: &[DamagePly],
    laws: &DamageLaws,
) -> f64 {
    let per_ply = ops.volume.len() / plies.len();
    let d = relative(u);
    (ops.strain.iter().enumerate())
        .map(|(i, op)| {
            let ply = &plies[i / per_ply];
            let law = ply_law(laws, ply).0;
            law.reach(&apply_operator(op, &d)) / law.lowest_onset(ply.bands)
        })
        .fold(0.0, f64::max)
}

/// A tet4's reach at corner displacements `u`.
pub fn tet_reach(x: &[[f64; 3]; 4], u: &[[f64; 3]; 4], ply: &DamagePly, laws: &DamageLaws) -> f64 {
    let (g, _) = tet4::gradients(x);
    let (law, axes) = ply_law(laws, ply);
    law.reach(&axes.strain_to_material(&gradient(&g, u))) / law.lowest_onset(ply.bands)
}

/// A hex8 or hex8i element's step ([`DamageStep`]): corners `x`, corner displacements `u`
/// and the step before's `u_prev`, its plies along `axis`, the state of its points (old on
/// entry, new on return: written only with `advance`), its modes, and the step `dt`.
#[allow(clippy::too_many_arguments)]
pub fn hex_damage(
    x: &[[f64; 3]; 8],
    (u, u_prev): (&[[f64; 3]; 8], &[[f64; 3]; 8]),
    (plies, axis): (&[DamagePly], usize),
    laws: &DamageLaws,
    state: &mut [f64],
    modes: Modes,
    (dt, advance): (f64, bool),
) -> DamageStep<8> {
    let points = hex_points(plies, axis);
    let geometry = hex_geometry(x, &points);
    let (alpha, alpha_prev) = (amplitudes(modes, u), amplitudes(modes, u_prev));
    // an element without damage: a point must start to damage for its forces to change
    if advance && !any_damage(state) {
        let starts = (geometry.iter().enumerate()).any(|(i, (g, _, m))| {
            let ply = &plies[points[i].2];
            let (law, axes) = ply_law(laws, ply);
            let e = axes.strain_to_material(&point_gradient((g, m), u, &alpha));
            law.initiates(&e, ply.bands)
        });
        if !starts {
            return DamageStep {
                forces: [[0.0; 3]; 8],
                dissipated: Dissipation::default(),
                damaged: false,
            };
        }
    }
    let mut f = [[0.0; 3]; 8];
    // the modes' forces, B_alpha^T sigma, which the condensation hands to the corners
    let mut r_alpha = [0.0; 9];
    let mut dissipated = Dissipation::default();
    for (i, (g, wdet, m)) in geometry.iter().enumerate() {
        let h = point_gradient((g, m), u, &alpha);
        let h_prev = point_gradient((g, m), u_prev, &alpha_prev);
        let ply = &plies[points[i].2];
        let at = i * POINT_STATE..(i + 1) * POINT_STATE;
        let (s, d) = point_stress(
            ply_law(laws, ply),
            (&h, &h_prev),
            &mut state[at],
            (ply.bands, dt, advance),
        );
        dissipated += d.scaled(*wdet);
        for (fk, gk) in f.iter_mut().zip(g) {
            for a in 0..3 {
                fk[a] += wdet * (s[a][0] * gk[0] + s[a][1] * gk[1] + s[a][2] * gk[2]);
            }
        }
        for (mm, gm) in m.iter().enumerate() {
            for a in 0..3 {
                r_alpha[3 * mm + a] += wdet * (s[a][0] * gm[0] + s[a][1] * gm[1] + s[a][2] * gm[2]);
            }
        }
    }
    if let Modes::Elastic(a0) = modes {
        // f += A_0^T r_alpha: the assumed strain's forces, the gradient of the points' energy
        for j in 0..24 {
            f[j / 3][j % 3] += (0..9).map(|r| a0[24 * r + j] * r_alpha[r]).sum::<f64>();
        }
    }
    DamageStep {
        forces: f,
        dissipated,
        damaged: any_damage(&state[..points.len() * POINT_STATE]),
    }
}

/// A hex's points as linear operators, shared by the elements of one shape and section: each
/// point's ply strain (Voigt order, engineering shears, its ply's axes) per corner
/// displacement relative to corner 0 (corners 1 to 7: 21 columns of 6, stored column by
/// column so that a strain is 21 six-wide multiply-adds; the modes condensed
/// elastically, as [`hex_damage`] has them), and its $w_p \det J_p$. With them an element's
/// step takes 126 products a strain instead of the point's gradients and rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct HexOperators {
    pub strain: Vec<[[f64; 6]; 21]>,
    pub volume: Vec<f64>,
}

/// The [`HexOperators`] of a hex of corners `x` with its plies along `axis`, the axes of each
/// ply's entry and its modes.
pub fn hex_operators(
    x: &[[f64; 3]; 8],
    (plies, axis): (&[DamagePly], usize),
    axes: &dyn Fn(&DamagePly) -> Rotation,
    modes: Modes,
) -> HexOperators {
    let (inv0, det0) = hex8i::centre_jacobian(x);
    let mut out = HexOperators {
        strain: Vec::new(),
        volume: Vec::new(),
    };
    for (q, w, k) in hex_points(plies, axis) {
        let (g, det) = hex8::gradients(x, q);
        let m: [[f64; 3]; 3] =
            std::array::from_fn(|m| inv0[m].map(|v| -2.0 * q[m] * v * det0 / det));
        let r = axes(&plies[k]);
        let op: [[f64; 6]; 21] = std::array::from_fn(|j| {
            let (corner, c) = (1 + j / 3, j % 3);
            // the gradient of a unit displacement of corner `corner` along c, and of the modes
            // it drives
            let mut h = [[0.0; 3]; 3];
            h[c] = g[corner];
            if let Modes::Elastic(a0) = modes {
                for (mm, gm) in m.iter().enumerate() {
                    for a in 0..3 {
                        let amplitude = a0[24 * (3 * mm + a) + 3 * corner + c];
                        for b in 0..3 {
                            h[a][b] += amplitude * gm[b];
                        }
                    }
                }
            }
            r.strain_to_material(&h)
        });
        out.strain.push(op);
        out.volume.push(w * det);
    }
    out
}

/// A point's ply strain from its operator and the relative displacements `d`.
fn apply_operator(op: &[[f64; 6]; 21], d: &[f64; 21]) -> [f64; 6] {
    let mut e = [0.0; 6];
    for (column, &dj) in op.iter().zip(d) {
        for r in 0..6 {
            e[r] += column[r] * dj;
        }
    }
    e
}

/// Corner displacements relative to corner 0, as 21 values.
fn relative(u: &[[f64; 3]; 8]) -> [f64; 21] {
    std::array::from_fn(|j| u[1 + j / 3][j % 3] - u[0][j % 3])
}

/// [`hex_damage`] through the element's [`HexOperators`] `ops` (the same step, to rounding).
pub fn hex_damage_operated(
    ops: &HexOperators,
    (u, u_prev): (&[[f64; 3]; 8], &[[f64; 3]; 8]),
    plies: &[DamagePly],
    laws: &DamageLaws,
    state: &mut [f64],
    (dt, advance): (f64, bool),
) -> DamageStep<8> {
    let points = ops.volume.len();
    let per_ply = points / plies.len();
    let d = relative(u);
    let law_of = |i: usize| ply_law(laws, &plies[i / per_ply]);
    if advance && !any_damage(state) {
        let starts = (0..points).any(|i| {
            let bands = plies[i / per_ply].bands;
            law_of(i)
                .0
                .initiates(&apply_operator(&ops.strain[i], &d), bands)
        });
        if !starts {
            return DamageStep {
                forces: [[0.0; 3]; 8],
                dissipated: Dissipation::default(),
                damaged: false,
            };
        }
    }
    let d_prev = relative(u_prev);
    let mut f = [0.0; 21];
    let mut dissipated = Dissipation::default();
    for i in 0..points {
        let (law, _) = law_of(i);
        let op = &ops.strain[i];
        let e = apply_operator(op, &d);
        let at = i * POINT_STATE..(i + 1) * POINT_STATE;
        let old: [f64; POINT_STATE] = state[at.clone()].try_into().expect("a point's state");
        let stress = match advance {
            true => {
                let ply = &plies[i / per_ply];
                let prev = || apply_operator(op, &d_prev);
                let step = law.step_lazily(&e, prev, &old, ply.bands, dt);
                state[at].copy_from_slice(&step.state);
                dissipated += point_dissipation(&step).scaled(ops.volume[i]);
                step.stress
            }
            false => {
                let eff = voigt_apply(&law.c0, &e);
                let c = law.ortho(law.acting(&old, (eff[0] >= 0.0, eff[1] + eff[2] >= 0.0)));
                c.apply(&e)
            }
        };
        let v = ops.volume[i];
        for (fj, column) in f.iter_mut().zip(op) {
            *fj += v * (0..6).map(|r| column[r] * stress[r]).sum::<f64>();
        }
    }
    let mut forces = [[0.0; 3]; 8];
    for j in 0..21 {
        forces[1 + j / 3][j % 3] = f[j];
        forces[0][j % 3] -= f[j];
    }
    DamageStep {
        forces,
        dissipated,
        damaged: any_damage(&state[..points * POINT_STATE]),
    }
}

/// A tet4 element's step ([`DamageStep`]), as [`hex_damage`] with its one point and ply.
pub fn tet_damage(
    x: &[[f64; 3]; 4],
    (u, u_prev): (&[[f64; 3]; 4], &[[f64; 3]; 4]),
    ply: &DamagePly,
    laws: &DamageLaws,
    state: &mut [f64],
    (dt, advance): (f64, bool),
) -> DamageStep<4> {
    let (g, vol) = tet4::gradients(x);
    let (h, h_prev) = (gradient(&g, u), gradient(&g, u_prev));
    let state = &mut state[..POINT_STATE];
    let (s, d) = point_stress(
        ply_law(laws, ply),
        (&h, &h_prev),
        state,
        (ply.bands, dt, advance),
    );
    let forces =
        g.map(|gk| [0, 1, 2].map(|a| vol * (s[a][0] * gk[0] + s[a][1] * gk[1] + s[a][2] * gk[2])));
    DamageStep {
        forces,
        dissipated: d.scaled(vol),
        damaged: any_damage(state),
    }
}

/// Whether any point of `state` holds damage.
pub fn any_damage(state: &[f64]) -> bool {
    state.iter().any(|&d| d > 0.0)
}

/// The chord through a hex's centre along the unit vector `n`: $2 / \max_i |(J_0^{-1} n)_i|$
/// (the natural coordinates leave $[-1, 1]$ there).
fn hex_chord(inv0: &[[f64; 3]; 3], n: [f64; 3]) -> f64 {
    let rate = (0..3)
        .map(|i| (0..3).map(|j| inv0[i][j] * n[j]).sum::<f64>().abs())
        .fold(0.0, f64::max);
    2.0 / rate
}

/// A hex's bands across fibre and matrix cracks of a ply with `axes`.
pub fn hex_bands(x: &[[f64; 3]; 8], axes: &Rotation) -> [f64; 2] {
    let (inv0, _) = hex8i::centre_jacobian(x);
    [
        hex_chord(&inv0, axes.axes[0]),
        hex_chord(&inv0, axes.axes[1]),
    ]
}

/// A tet's bands: the chords through its centroid along the ply's axes 1 and 2 (the
/// barycentric coordinates, 1/4 there, reach 0 on the faces).
pub fn tet_bands(x: &[[f64; 3]; 4], axes: &Rotation) -> [f64; 2] {
    let (g, _) = tet4::gradients(x);
    let chord = |n: [f64; 3]| {
        let rates: Vec<f64> = g
            .iter()
            .map(|gk| gk[0] * n[0] + gk[1] * n[1] + gk[2] * n[2])
            .collect();
        let ahead = rates
            .iter()
            .filter(|&&r| r < 0.0)
            .map(|r| 0.25 / -r)
            .fold(f64::INFINITY, f64::min);
        let behind = rates
            .iter()
            .filter(|&&r| r > 0.0)
            .map(|r| 0.25 / r)
            .fold(f64::INFINITY, f64::min);
        ahead + behind
    };
    [chord(axes.axes[0]), chord(axes.axes[1])]
}

/// A hex's sieve $\kappa$: twice the largest ratio, over its points and the reach's forms
/// ([`PlyDamage::reach_forms`]), of a point's reach squared to the element's strain energy
/// $\tfrac12 d \cdot K d$, so that its reach is at most $\sqrt{\kappa U}$ everywhere. `k` is
/// its elastic stiffness (a hex8i's modes condensed), `ops` its point operators. Each
/// point's ratio is the largest eigenvalue of $A H_p$, $H_p = E_p K^+ E_p^T$ (6 x 6, $E_p$
/// the point's strain operator, $K^+$ the pseudo-inverse on the corners' displacements
/// relative to corner 0); matrix compression's is $(\sqrt{\lambda_L} +
/// \sqrt{\lambda_Q})^2$. On the coarse drop weight's bricks of twelve plies $\kappa$ is 4.3
/// times below the product of the largest share of the energy a point can hold and the
/// reach per unit energy density (its bound on the reach 2.1 times).
pub fn hex_sieve(
    k: &[[f64; 24]; 24],
    ops: &HexOperators,
    plies: &[DamagePly],
    laws: &DamageLaws,
) -> f64 {
    use nalgebra::{SMatrix, SymmetricEigen};
    let kr = SMatrix::<f64, 21, 21>::from_fn(|i, j| k[3 + i][3 + j]);
    let eig = SymmetricEigen::new(kr);
    let top = eig.eigenvalues.max();
    let mut k_plus = SMatrix::<f64, 21, 21>::zeros();
    for (i, &l) in eig.eigenvalues.iter().enumerate() {
        if l > 1e-10 * top {
            let v = eig.eigenvectors.column(i);
            k_plus += v * v.transpose() / l;
        }
    }
    let per_ply = ops.volume.len() / plies.len();
    let largest = |root: &SMatrix<f64, 6, 6>, a: &crate::material::Voigt| -> f64 {
        let am = SMatrix::<f64, 6, 6>::from_fn(|i, j| a[i][j]);
        SymmetricEigen::new(root * am * root)
            .eigenvalues
            .max()
            .max(0.0)
    };
    let mut worst = 0.0f64;
    for (i, op) in ops.strain.iter().enumerate() {
        let e = SMatrix::<f64, 6, 21>::from_fn(|r, j| op[j][r]);
        let h = e * k_plus * e.transpose();
        let he = SymmetricEigen::new(h);
        let sqrt = he.eigenvalues.map(|l| l.max(0.0).sqrt());
        let root = he.eigenvectors
            * SMatrix::<f64, 6, 6>::from_diagonal(&sqrt)
            * he.eigenvectors.transpose();
        let ply = &plies[i / per_ply];
        let law = ply_law(laws, ply).0;
        let [f, t, l, q] = law.reach_forms();
        let mc = largest(&root, &l).sqrt() + largest(&root, &q).sqrt();
        // the reach in units of the ply's lowest onset
        let onset = law.lowest_onset(ply.bands);
        let point = largest(&root, &f).max(largest(&root, &t)).max(mc * mc);
        worst = worst.max(point / (onset * onset));
    }
    2.0 * worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn box_hex(l: [f64; 3]) -> [[f64; 3]; 8] {
        hex8::CORNERS.map(|c| std::array::from_fn(|a| 0.5 * (c[a] + 1.0) * l[a]))
    }

    /// A distorted hex8i of three IM7/8552 plies (0, 45 and 90 degrees) along z: its law,
    /// the plies' axes, its damage plies, corners and layup.
    fn three_ply_hex() -> (
        PlyDamage,
        Vec<Rotation>,
        Vec<DamagePly>,
        [[f64; 3]; 8],
        crate::material::Layup,
    ) {
        use crate::material::{Elastic, Layup, LayupPly, Orthotropic, PlyDamage, Strength};
        let o = Orthotropic::transversely_isotropic(171420.0, 9080.0, 0.32, 0.52, 5290.0);
        let k = Strength {
            xt: 2326.2,
            xc: 1200.1,
            yt: 62.3,
            yc: 199.8,
            s12: 92.3,
            s23: 75.3,
        };
        let law = PlyDamage::new(o.stiffness(), k, [133.3, 47.5, 0.277, 0.788], 1e-8);
        let axes: Vec<Rotation> = [0.0f64, 45.0, 90.0]
            .map(|a| Rotation::IDENTITY.turned([0.0, 0.0, 1.0], a.to_radians()))
            .to_vec();
        let plies: Vec<DamagePly> = (0..3)
            .map(|k| DamagePly {
                entry: k as u32,
                lo: -1.0 + 2.0 * k as f64 / 3.0,
                hi: -1.0 + 2.0 * (k + 1) as f64 / 3.0,
                bands: [0.6, 0.5],
            })
            .collect();
        let mut x = box_hex([0.6, 0.5, 0.3]);
        x[6] = [0.65, 0.55, 0.31];
        x[1][2] = 0.02;
        let layup = Layup {
            axis: 2,
            plies: (0..3)
                .map(|k| LayupPly {
                    lo: plies[k].lo,
                    hi: plies[k].hi,
                    elastic: Elastic::anisotropic(o.stiffness(), 1.0).rotated(&axes[k]),
                    material: k as u32,
                })
                .collect(),
        };
        (law, axes, plies, x, layup)
    }

    /// The operators' step is the direct one's, to rounding: a distorted hex8i of three plies
    /// (0, 45, 90 degrees), strains past initiation, a random old state.
    #[test]
    fn the_operated_step_is_the_direct_one() {
        let (law, axes, plies, x, layup) = three_ply_hex();
        let laws = DamageLaws {
            laws: &[law],
            law_of: &[0, 0, 0],
            axes: &axes,
        };
        let a0 = hex8i::condensation(&x, crate::element::Section::Layered(&layup));
        let ops = hex_operators(
            &x,
            (&plies, 2),
            &|p| axes[p.entry as usize],
            Modes::Elastic(&a0),
        );
        let u: [[f64; 3]; 8] = std::array::from_fn(|k| {
            let p = x[k];
            [
                0.012 * p[1] - 0.004 * p[2],
                0.009 * p[0] + 0.002 * p[2] * p[0],
                -0.006 * p[0] * p[1],
            ]
        });
        let u_prev = u.map(|c| c.map(|v| 0.98 * v));
        let n = 24 * POINT_STATE;
        let old: Vec<f64> = (0..n).map(|i| if i % 5 == 0 { 0.1 } else { 0.0 }).collect();
        for advance in [true, false] {
            let (mut a, mut b) = (old.clone(), old.clone());
            let direct = hex_damage(
                &x,
                (&u, &u_prev),
                (&plies, 2),
                &laws,
                &mut a,
                Modes::Elastic(&a0),
                (1e-9, advance),
            );
            let operated =
                hex_damage_operated(&ops, (&u, &u_prev), &plies, &laws, &mut b, (1e-9, advance));
            let scale = direct
                .forces
                .iter()
                .flatten()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            for (p, q) in direct
                .forces
                .iter()
                .flatten()
                .zip(operated.forces.iter().flatten())
            {
                assert!((p - q).abs() <= 1e-10 * scale, "{advance}: {p} {q}");
            }
            for (p, q) in a.iter().zip(&b) {
                assert!((p - q).abs() <= 1e-10, "{advance}: state {p} {q}");
            }
            let (p, q) = (direct.dissipated, operated.dissipated);
            let scale = 1e-10 * p.total.abs().max(1e-30);
            assert!((p.total - q.total).abs() <= scale && (p.fibre - q.fibre).abs() <= scale);
            assert_eq!(direct.damaged, operated.damaged);
        }
    }

    /// No displacement of a distorted three-ply hex8i takes a point's reach past the sieve's
    /// bound sqrt(kappa U), and the bound is close: 5,000 random displacements come within
    /// 0.69 of it. So too where the law lowers its strengths in bands of 2 mm (past matrix
    /// tension's and compression's snap-back widths), the reach then in units of each ply's
    /// lowest onset, sqrt(0.358 / 2) = 0.42 of the law's.
    #[test]
    fn the_sieve_bounds_every_points_reach() {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let (law, axes, plies, x, layup) = three_ply_hex();
        let lowered = PlyDamage {
            lower_strength: true,
            ..law
        };
        let wide: Vec<DamagePly> = (plies.iter())
            .map(|p| DamagePly {
                bands: [2.0, 2.0],
                ..*p
            })
            .collect();
        for (law, plies) in [(law, plies), (lowered, wide)] {
            let laws = DamageLaws {
                laws: &[law],
                law_of: &[0, 0, 0],
                axes: &axes,
            };
            let section = crate::element::Section::Layered(&layup);
            let a0 = hex8i::condensation(&x, section);
            let ops = hex_operators(
                &x,
                (&plies, 2),
                &|p| axes[p.entry as usize],
                Modes::Elastic(&a0),
            );
            let k = hex8i::stiffness(&x, section);
            let kappa = hex_sieve(&k, &ops, &plies, &laws);
            let mut rng = StdRng::seed_from_u64(11);
            let mut closest = 0.0f64;
            for _ in 0..5000 {
                let u: [[f64; 3]; 8] =
                    std::array::from_fn(|_| std::array::from_fn(|_| rng.random_range(-1e-3..1e-3)));
                let d: Vec<f64> = u.iter().flatten().copied().collect();
                let energy = 0.5
                    * (0..24)
                        .map(|i| d[i] * (0..24).map(|j| k[i][j] * d[j]).sum::<f64>())
                        .sum::<f64>();
                let reach = hex_reach_operated(&ops, &u, &plies, &laws);
                let bound = (kappa * energy).sqrt();
                assert!(reach <= bound * (1.0 + 1e-9), "{reach} > {bound}");
                closest = closest.max(reach / bound);
            }
            eprintln!(
                "lowered {}: random displacements reach {closest:.3} of the sieve's bound",
                law.lower_strength
            );
            assert!(closest > 0.5, "{closest}");
        }
    }

    /// A box's chords are its sides along the axes, and side / cos along a diagonal within
    /// 45 degrees of one; a tet's along an axis through its centroid are found by hand.
    #[test]
    fn bands_are_the_chords_along_the_ply_axes() {
        let x = box_hex([2.0, 0.5, 0.25]);
        let b = hex_bands(&x, &Rotation::IDENTITY);
        assert!(
            (b[0] - 2.0).abs() < 1e-12 && (b[1] - 0.5).abs() < 1e-12,
            "{b:?}"
        );
        let turned = Rotation::IDENTITY.turned([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_4);
        let cube = box_hex([1.0, 1.0, 1.0]);
        let b = hex_bands(&cube, &turned);
        assert!((b[0] - 2f64.sqrt()).abs() < 1e-12, "{b:?}");
        // the corner tet (0,0,0), (1,0,0), (0,1,0), (0,0,1): centroid (1/4, 1/4, 1/4); along x
        // it runs from x = 0 to the slanted face x + y + z = 1 at x = 1/2
        let t = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let b = tet_bands(&t, &Rotation::IDENTITY);
        assert!(
            (b[0] - 0.5).abs() < 1e-12 && (b[1] - 0.5).abs() < 1e-12,
            "{b:?}"
        );
    }
}
