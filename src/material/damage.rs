//! Ply damage: Hashin initiation, linear softening over the crack band, and the stiffness
//! degraded in the MLT form extended to 3D (Matzenmiller, Lubliner and Taylor 1995; Lapczyk
//! and Hurtado 2007), for an orthotropic ply in its material axes 1 (fibres), 2, 3.
//!
//! **Modes.** Four damage variables, fibre tension and compression, matrix tension and
//! compression ([`MODES`]), each driven by its Hashin index $F$ of the effective stress
//! $\hat\sigma = M \sigma$, each stress component divided by one minus its damage
//! (Lapczyk and Hurtado; [`effective`]), with the damage of the step before: on an undamaged
//! ply $C_0 \varepsilon$. The matrix and fibre compression indices are Hashin's
//! ([`super::failure_indices`]); fibre tension is $(\hat\sigma_{11}/X_T)^2$ alone, without Hashin's shear term,
//! so that in-plane shear cannot soften the fibres (see `docs/method-notes.md`). The signs
//! that choose between tension and compression are those of $C_0 \varepsilon$.
//!
//! **Softening.** The mode's equivalent strain, in units of its value at initiation, is
//! $r = \sqrt F$ (the index is quadratic in the effective stress, so $r$ is linear in the
//! strain along any path of fixed direction; in a mode's uniaxial state, $\varepsilon / (X/E)$
//! whatever the damage); matrix compression's index has a linear part, and its $r$ is the
//! inverse of the load factor that brings the index to 1. Its equivalent stress falls linearly from the
//! strength at $r = 1$ to zero at $r_f$, which gives the damage
//! $d = r_f (r - 1) / (r (r_f - 1))$, never decreasing. The band: an element dissipates
//! $G / l^*$ per unit volume, $l^*$ its width across the crack, so that the energy per unit
//! crack area is the fracture energy $G$ whatever the element size (Bažant and Oh 1983). In
//! the mode's uniaxial state (stress $X$ alone, modulus $E = 1/S$ from the compliance) the
//! area under the curve is $\tfrac12 X^2 S\, r_f$, so
//! $r_f = 2 E G / (l^* X^2)$ ([`PlyDamage::softening_end`]); $r_f \le 1$ is the snap-back
//! of an element wider than $2 E G / X^2$, whose drop is then vertical (and its energy too
//! large: `impact check` warns). With [`PlyDamage::lower_strength`] such an element's mode
//! starts instead at the strength its band dissipates G with, $X' = \sqrt{2 E G / l^*}$
//! (Bažant and Oh 1983): the mode starts at $r = X'/X$ ([`PlyDamage::onset`]), every index
//! being of degree one in the stress, and drops at once from there with the energy
//! $\tfrac12 X'^2 / E \cdot l^* = G$ per unit crack area.
//!
//! **Stiffness.** The compliance's fibre term divided by $1 - d_f$, its shear terms by
//! $1 - d_s$, with $d_f$ the fibre tension or compression damage by the sign of
//! $\tilde\sigma_{11}$ and $d_s = 1 - \prod_i (1 - d_i)$. The matrix damage acts by the sign
//! of $\tilde\sigma_{22} + \tilde\sigma_{33}$: in tension (an open crack) the matrix and
//! through-thickness terms are divided by $1 - d_{mt}$; in compression (a crushed matrix,
//! a shear fracture across the ply) only the transverse deviatoric part softens: the
//! compliance gains $c\, v v^T$ with $v = (0, 1, -1)$ and $c = S_{22} d_{mc} / (1 - d_{mc})$,
//! which divides $S_{22}$ by $1 - d_{mc}$ (the uniaxial crush and its energy are as in
//! tension) and keeps the compliance to a transverse pressure, $\sigma_{22} = \sigma_{33}$: a
//! crushed ply still bears the tup's pressure where it is confined. That deviatoric part
//! stays in tension (the crush's fracture plane does not heal when it opens), added to
//! the open crack's terms: the sign is the pressure's, which the deviatoric strain a crush
//! runs into does not move, so a crushed point whose pressure turns faintly to tension
//! keeps the stiffness of what it is deformed in. Every variable is capped at [`D_MAX`].
//!
//! **Viscosity** (Duvaut-Lions): with a time $\eta > 0$ the variables that act lag the
//! ones the softening gives, $\dot d_v = (d - d_v)/\eta$, integrated backwards over a step.
//!
//! **Dissipation.** Over a step from strain $\varepsilon_n$ to $\varepsilon_{n+1}$ the law
//! releases $\tfrac12 \varepsilon_n : (C_n - C_{n+1}) : \varepsilon_{n+1}$ per unit volume,
//! $C_n$ the stiffness the step before had (its damage, its strain's signs): exactly what
//! central difference's conserved energy, $\tfrac12 u_n K_{n+1} u_{n+1}$ in its strain term,
//! loses when the secant stiffness changes, so that the balance with it closes to rounding.
//! At fixed strain it is the release of stored energy, never negative (the compliance only
//! grows); along a path it is that to first order in the strain's change.
//!
//! **By kind.** The release is split in two by a stiffness between the two: $C_m$, with
//! the fibre variables of the step's end and the matrix variables of its start (the shear
//! damage $d_s$ formed from those). The fibre modes released
//! $\tfrac12 \varepsilon_n : (C_n - C_m) : \varepsilon_{n+1}$, the matrix modes
//! $\tfrac12 \varepsilon_n : (C_m - C_{n+1}) : \varepsilon_{n+1}$: the two sum to the
//! whole, and where only one kind grows over the step the whole is that kind's.

use super::failure::{matrix_compression_parts, Strength};
use super::Voigt;

/// The damage modes, in the order of a point's variables.
pub const MODES: [&str; 4] = [
    "fibre_tension",
    "fibre_compression",
    "matrix_tension",
    "matrix_compression",
];

/// The largest damage: a ply keeps 1e-4 of its stiffness in a failed mode, so that a fully
/// damaged element keeps a positive definite stiffness (no mode of it becomes free).
pub const D_MAX: f64 = 0.9999;

/// Values of a point's state: the four variables the softening gives (their history's
/// largest), then the four that act (equal to them without viscosity).
pub const POINT_STATE: usize = 8;

/// A ply's damage law: its undamaged compliance and stiffness in its own axes, strengths,
/// fracture energies and viscosity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlyDamage {
    /// The undamaged compliance's normal block (11, 22, 33).
    pub normal: [[f64; 3]; 3],
    /// The undamaged shear compliances (23, 13, 12: Voigt order).
    pub shear: [f64; 3],
    /// The undamaged stiffness (Voigt order).
    pub c0: Voigt,
    pub strength: Strength,
    /// Energy per unit crack area of each mode ([`MODES`] order).
    pub energy: [f64; 4],
    /// The Duvaut-Lions time (0: none).
    pub viscosity: f64,
    /// The ply damages by its in-plane stresses alone (11, 22, 12), and its damage softens
    /// only its in-plane stiffness: the through-thickness stresses are left to the
    /// laminate's interfaces (`damage_stresses = "in_plane"`).
    pub in_plane: bool,
    /// A band wider than a mode's snap-back width starts to damage at the strength that
    /// width dissipates G with, $\sqrt{2 E G / l^*}$, below the law's (Bažant and Oh 1983;
    /// `snap_back = "lower_strength"`), instead of dropping at once from the law's.
    pub lower_strength: bool,
}

/// One point's step: its new state, its stress (Voigt order, ply axes) and the energy its
/// law dissipated over the step per unit volume, with the fibre modes' share of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointStep {
    pub state: [f64; POINT_STATE],
    pub stress: [f64; 6],
    pub dissipated: f64,
    pub fibre: f64,
}

/// Energy the plies' damage dissipated: the whole, and the share of the fibre modes (the
/// matrix modes' is the rest, [`Dissipation::matrix`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Dissipation {
    pub total: f64,
    pub fibre: f64,
}

impl Dissipation {
    /// The matrix modes' share.
    pub fn matrix(&self) -> f64 {
        self.total - self.fibre
    }

    /// Both parts times `w`.
    pub fn scaled(self, w: f64) -> Dissipation {
        Dissipation {
            total: self.total * w,
            fibre: self.fibre * w,
        }
    }
}

impl std::ops::AddAssign for Dissipation {
    fn add_assign(&mut self, o: Dissipation) {
        self.total += o.total;
        self.fibre += o.fibre;
    }
}

impl std::iter::Sum for Dissipation {
    fn sum<I: Iterator<Item = Dissipation>>(it: I) -> Dissipation {
        it.fold(Dissipation::default(), |mut a, b| {
            a += b;
            a
        })
    }
}

impl PlyDamage {
    /// The law of a ply of stiffness `c0` (its own axes; orthotropic, so its normal and
    /// shear blocks are apart).
    pub fn new(c0: Voigt, strength: Strength, energy: [f64; 4], viscosity: f64) -> Self {
        let n = nalgebra::Matrix3::from_fn(|i, j| c0[i][j]);
        let s = n.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
        PlyDamage {
            normal: std::array::from_fn(|i| std::array::from_fn(|j| s[(i, j)])),
            shear: std::array::from_fn(|k| 1.0 / c0[3 + k][3 + k]),
            c0,
            strength,
            energy,
            viscosity,
            in_plane: false,
            lower_strength: false,
        }
    }

    /// The uniaxial modulus and strength of mode `k`: $E_1$ with $X_T$ or $X_C$ for the
    /// fibre modes, $E_2$ with $Y_T$ or $Y_C$ for the matrix ones.
    pub fn mode_constants(&self, k: usize) -> (f64, f64) {
        let s = &self.strength;
        match k {
            0 => (1.0 / self.normal[0][0], s.xt),
            1 => (1.0 / self.normal[0][0], s.xc),
            2 => (1.0 / self.normal[1][1], s.yt),
            _ => (1.0 / self.normal[1][1], s.yc),
        }
    }

    /// The widest band of mode `k` that softens without snapping back, $2 E G / X^2$.
    pub fn snap_back_width(&self, k: usize) -> f64 {
        let (e, x) = self.mode_constants(k);
        2.0 * e * self.energy[k] / (x * x)
    }

    /// The r at which mode `k` starts to damage in a band of width `l`: 1, or with
    /// [`Self::lower_strength`] in a band wider than the snap-back width $w$,
    /// $\sqrt{w / l}$ (the strength lowered to $\sqrt{2 E G / l}$).
    pub fn onset(&self, k: usize, l: f64) -> f64 {
        match self.lower_strength {
            true => (self.snap_back_width(k) / l).min(1.0).sqrt(),
            false => 1.0,
        }
    }

    /// $r_f$ of mode `k` in a band of width `l`, in units of its [`Self::onset`], at least
    /// just above 1 (a snap-back drops at once).
    pub fn softening_end(&self, k: usize, l: f64) -> f64 {
        let s = self.onset(k, l);
        (self.snap_back_width(k) / (l * s * s)).max(1.0 + 1e-6)
    }

    /// The lowest [`Self::onset`] of any mode of a ply with bands `bands` (across fibre and
    /// matrix cracks): its reach in these units bounds every mode's r over its onset.
    pub fn lowest_onset(&self, bands: [f64; 2]) -> f64 {
        (0..4)
            .map(|k| self.onset(k, bands[k / 2]))
            .fold(1.0, f64::min)
    }

    /// $\beta^2$: the largest $r^2$ of any mode per unit $\sigma \cdot S \sigma$ (twice the
    /// strain energy density) at an undamaged point, so that $r \le \beta \sqrt{2u}$ there
    /// (the damage kernels' sieve, `kernels::damage_data`). Each quadratic index's bound is
    /// the largest eigenvalue of its form against the compliance; matrix compression's $r$
    /// is at most its linear part's dual norm plus the square root of its quadratic part's.
    pub fn sieve_factor(&self) -> f64 {
        let k = &self.strength;
        let mut compliance = nalgebra::SMatrix::<f64, 6, 6>::zeros();
        for i in 0..3 {
            for j in 0..3 {
                compliance[(i, j)] = self.normal[i][j];
            }
            compliance[(3 + i, 3 + i)] = self.shear[i];
        }
        let Some(l) = compliance.cholesky().map(|c| c.l()) else {
            return f64::INFINITY;
        };
        let Some(l_inv) = l.try_inverse() else {
            return f64::INFINITY;
        };
        let largest = |q: nalgebra::SMatrix<f64, 6, 6>| {
            let m = l_inv * q * l_inv.transpose();
            nalgebra::SymmetricEigen::new(m).eigenvalues.max().max(0.0)
        };
        let diagonal = |entries: &[(usize, usize, f64)]| {
            let mut q = nalgebra::SMatrix::<f64, 6, 6>::zeros();
            for &(i, j, v) in entries.iter().filter(|(i, j, _)| self.counts(*i, *j)) {
                q[(i, j)] = v;
                q[(j, i)] = v;
            }
            q
        };
        let (t2, l2) = (1.0 / (k.s23 * k.s23), 1.0 / (k.s12 * k.s12));
        let shear = [(3, 3, t2), (4, 4, l2), (5, 5, l2)];
        let ft = largest(diagonal(&[(0, 0, 1.0 / (k.xt * k.xt))]));
        let fc = largest(diagonal(&[(0, 0, 1.0 / (k.xc * k.xc))]));
        let y = 1.0 / (k.yt * k.yt);
        let mt = largest(diagonal(
            &[&[(1, 1, y), (2, 2, y), (1, 2, y - 0.5 * t2)][..], &shear].concat(),
        ));
        let h = 0.25 * t2;
        let quadratic = largest(diagonal(
            &[&[(1, 1, h), (2, 2, h), (1, 2, h - 0.5 * t2)][..], &shear].concat(),
        ));
        let r = k.yc / (2.0 * k.s23);
        let a = (r * r - 1.0) / k.yc;
        // the linear part a (s22 + s33): its largest value per unit norm, sqrt(c . C0 c)
        let c0 = &self.c0;
        let through = if self.in_plane { 0.0 } else { 1.0 };
        let dual = (a * a * (c0[1][1] + through * (2.0 * c0[1][2] + c0[2][2])))
            .max(0.0)
            .sqrt();
        let mc = (dual + quadratic.sqrt()).powi(2);
        ft.max(fc).max(mt).max(mc)
    }

    /// The reach of an undamaged point of strain `e` (ply axes): with $\sigma = C_0
    /// \varepsilon$, the largest of $|\sigma_{11}| / \min(X_T, X_C)$, the square root of
    /// matrix tension's quadratic form and matrix compression's $|a (\sigma_{22} +
    /// \sigma_{33})|$ plus the square root of its quadratic part: a seminorm of the strain
    /// that is at least every mode's r, whatever the stress's signs, and at most
    /// $\beta \sqrt{2u}$ ([`Self::sieve_factor`]). Being a seminorm, the reach at $u$ is at
    /// most the reach at $u_c$ plus that of $u - u_c$ (the sieve's memory,
    /// `kernels::damage_data`). Infinite where matrix tension's form is indefinite
    /// ($2 S_{23} < Y_T$), which no seminorm bounds.
    pub fn reach(&self, e: &[f64; 6]) -> f64 {
        let k = &self.strength;
        if 2.0 * k.s23 < k.yt {
            return f64::INFINITY;
        }
        let s = self.counted(voigt_apply(&self.c0, e));
        let (t2, l2) = (1.0 / (k.s23 * k.s23), 1.0 / (k.s12 * k.s12));
        let shear = t2 * s[3] * s[3] + l2 * (s[4] * s[4] + s[5] * s[5]);
        let (sum, product) = (s[1] + s[2], s[1] * s[2]);
        let mt = sum * sum / (k.yt * k.yt) - t2 * product + shear;
        let quadratic = 0.25 * t2 * sum * sum - t2 * product + shear;
        let r = k.yc / (2.0 * k.s23);
        let a = (r * r - 1.0) / k.yc;
        let mc = (a * sum).abs() + quadratic.max(0.0).sqrt();
        let fibre = s[0].abs() / k.xt.min(k.xc);
        fibre.max(mt.max(0.0).sqrt()).max(mc)
    }

    /// The reach's quadratic forms in the strain (ply axes, Voigt order): the fibre term's,
    /// matrix tension's, and matrix compression's linear part (squared) and quadratic part,
    /// so that the reach is the largest of $\sqrt{e \cdot F e}$, $\sqrt{e \cdot T e}$ and
    /// $\sqrt{e \cdot L e} + \sqrt{e \cdot Q e}$ (each form $C_0 A C_0$ of its form A in the
    /// stress). The sieve's bound of an element is their largest ratio to its strain energy.
    pub fn reach_forms(&self) -> [Voigt; 4] {
        let k = &self.strength;
        let (t2, l2) = (1.0 / (k.s23 * k.s23), 1.0 / (k.s12 * k.s12));
        let in_strain = |q: &Voigt| -> Voigt {
            let q: &Voigt = &std::array::from_fn(|i| {
                std::array::from_fn(|j| match self.counts(i, j) {
                    true => q[i][j],
                    false => 0.0,
                })
            });
            let qc: Voigt = std::array::from_fn(|i| voigt_apply(q, &self.c0[i]));
            // C0 (Q C0): C0 is symmetric, so row i of Q C0 is Q applied to C0's column i
            std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..6).map(|m| self.c0[i][m] * qc[j][m]).sum())
            })
        };
        let matrix = |y: f64| -> Voigt {
            let mut q = [[0.0; 6]; 6];
            q[1][1] = y;
            q[2][2] = y;
            q[1][2] = y - 0.5 * t2;
            q[2][1] = y - 0.5 * t2;
            q[3][3] = t2;
            q[4][4] = l2;
            q[5][5] = l2;
            q
        };
        let outer = |g: [f64; 6]| -> Voigt {
            std::array::from_fn(|i| std::array::from_fn(|j| g[i] * g[j]))
        };
        let x = k.xt.min(k.xc);
        let fibre: [f64; 6] = std::array::from_fn(|j| self.c0[0][j] / x);
        let r = k.yc / (2.0 * k.s23);
        let a = (r * r - 1.0) / k.yc;
        let through = if self.in_plane { 0.0 } else { 1.0 };
        let linear: [f64; 6] =
            std::array::from_fn(|j| a * (self.c0[1][j] + through * self.c0[2][j]));
        [
            outer(fibre),
            in_strain(&matrix(1.0 / (k.yt * k.yt))),
            outer(linear),
            in_strain(&matrix(0.25 * t2)),
        ]
    }

    /// Whether a point of strain `e` (ply axes) without damage, in bands `bands`, starts to
    /// damage: some mode's r of $C_0 \varepsilon$ above its onset (what [`Self::step`]
    /// would find).
    pub fn initiates(&self, e: &[f64; 6], bands: [f64; 2]) -> bool {
        let r = self.index_ratios(&voigt_apply(&self.c0, e));
        (0..4).any(|k| r[k] / self.onset(k, bands[k / 2]) > 1.0)
    }

    /// The damage that acts at a point of state `s`, with the signs of the effective fibre
    /// stress and of the effective transverse stresses' sum: fibre (tension or compression),
    /// matrix tension (zero in compression), shear, and matrix compression. In plane, matrix
    /// compression acts in compression alone, as tension does in tension: both soften the
    /// one modulus $E_2$, so the sign that closes one opens the other. In 3D it acts in
    /// tension too: the crushed matrix's compliance is deviatoric (`ortho`), and the sign
    /// is the transverse pressure's, which a deviatoric strain does not move; a crush that
    /// went its whole way deforms in that mode alone, and the faintest transverse tension
    /// then restored its stiffness to the whole of that deformation (a cube crushed across
    /// its fibres, its free face's inertia pulling, took 2.7 times the work it was given).
    /// The fracture plane of a crush does not heal when it opens.
    pub fn acting(&self, s: &[f64; POINT_STATE], (fibre, matrix): (bool, bool)) -> [f64; 4] {
        let v = &s[4..];
        let df = if fibre { v[0] } else { v[1] };
        let (dt, dc) = match (matrix, self.in_plane) {
            (true, true) => (v[2], 0.0),
            (true, false) => (v[2], v[3]),
            (false, _) => (0.0, v[3]),
        };
        let ds = 1.0 - (1.0 - v[0]) * (1.0 - v[1]) * (1.0 - v[2]) * (1.0 - v[3]);
        [df, dt, ds.min(D_MAX), dc]
    }

    /// The stiffness (Voigt, ply axes) with the fibre, matrix tension, shear and matrix
    /// compression damage `d` that act ([`Self::acting`]; the undamaged one itself where `d`
    /// is zero).
    pub fn stiffness(&self, d: [f64; 4]) -> Voigt {
        self.ortho(d).voigt()
    }

    /// [`Self::stiffness`] in its orthotropic form: the normal block and the shear moduli
    /// (the rest of the Voigt matrix is zero), the form a point's step works with.
    pub fn ortho(&self, [df, dt, ds, dc]: [f64; 4]) -> Ortho {
        if df == 0.0 && dt == 0.0 && ds == 0.0 && dc == 0.0 {
            return Ortho::of(&self.c0);
        }
        let (scale, crush) = if self.in_plane {
            // the in-plane terms alone: S_22 over one minus the matrix damage
            let dm = 1.0 / ((1.0 - dt) * (1.0 - dc));
            ([1.0 / (1.0 - df), dm, 1.0], [[0.0; 3]; 3])
        } else {
            // the crushed matrix's deviatoric compliance c v v^T, v = (0, 1, -1)
            let c = self.normal[1][1] * dc / (1.0 - dc);
            let scale = [1.0 / (1.0 - df), 1.0 / (1.0 - dt), 1.0 / (1.0 - dt)];
            (scale, [[0.0, 0.0, 0.0], [0.0, c, -c], [0.0, -c, c]])
        };
        let s = nalgebra::Matrix3::from_fn(|i, j| {
            self.normal[i][j] * if i == j { scale[i] } else { 1.0 } + crush[i][j]
        });
        let n = s.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
        Ortho {
            normal: std::array::from_fn(|i| std::array::from_fn(|j| n[(i, j)])),
            // in plane, the 12 term alone softens
            shear: std::array::from_fn(|i| {
                let keep = if self.in_plane && i < 2 {
                    1.0
                } else {
                    1.0 - ds
                };
                keep / self.shear[i]
            }),
        }
    }

    /// One point's step from strain `e` (ply axes, engineering shears, Voigt order) and the
    /// step before's `prev`, its old state, its band widths across fibre and matrix cracks,
    /// and the step `dt`.
    pub fn step(
        &self,
        (e, prev): (&[f64; 6], &[f64; 6]),
        old: &[f64; POINT_STATE],
        bands: [f64; 2],
        dt: f64,
    ) -> PointStep {
        self.step_lazily(e, || *prev, old, bands, dt)
    }

    /// [`Self::step`] with the step before's strain `prev` formed only where the damage
    /// grows (the released energy needs it; elsewhere it is zero), and the stress of the
    /// standing damage reused: the same bits as [`Self::step`].
    pub fn step_lazily(
        &self,
        e: &[f64; 6],
        prev: impl FnOnce() -> [f64; 6],
        old: &[f64; POINT_STATE],
        bands: [f64; 2],
        dt: f64,
    ) -> PointStep {
        let eff = Ortho::of(&self.c0).apply(e);
        let signs = (eff[0] >= 0.0, eff[1] + eff[2] >= 0.0);
        let d_old = self.acting(old, signs);
        let before = self.ortho(d_old);
        let stress_before = before.apply(e);
        let r = self.index_ratios(&effective(&stress_before, d_old, signs.1));
        let mut state = *old;
        for k in 0..4 {
            // r in units of the mode's onset
            let rk = r[k] / self.onset(k, bands[k / 2]);
            let trial = if rk > 1.0 {
                let rf = self.softening_end(k, bands[k / 2]);
                (rf * (rk - 1.0) / (rk * (rf - 1.0))).min(D_MAX)
            } else {
                0.0
            };
            state[k] = old[k].max(trial);
            state[4 + k] = if self.viscosity > 0.0 {
                let a = dt / self.viscosity;
                ((old[4 + k] + a * state[k]) / (1.0 + a)).min(D_MAX)
            } else {
                state[k]
            };
        }
        let d_new = self.acting(&state, signs);
        if d_new == d_old {
            return PointStep {
                state,
                stress: stress_before,
                dissipated: 0.0,
                fibre: 0.0,
            };
        }
        let after = self.ortho(d_new);
        let stress = after.apply(e);
        let prev = prev();
        // the energy the damage's growth released, both stiffnesses at this step's signs:
        // a crack that closes (the acting damage switching from a tension mode to a
        // compression one) releases nothing, and it stores nothing back
        let released = |a: &Ortho, b: &Ortho| -> f64 {
            let change = a.less(b).apply(e);
            let r: f64 = (0..6).map(|i| prev[i] * change[i]).sum();
            0.5 * r
        };
        let dissipated = released(&before, &after);
        // the fibre modes' share, through the stiffness between (module docs, "By kind")
        let fibre = match (fibre_grew(old, &state), matrix_grew(old, &state)) {
            (false, _) => 0.0,
            (true, false) => dissipated,
            (true, true) => {
                let mut mid = *old;
                for k in [0, 1, 4, 5] {
                    mid[k] = state[k];
                }
                released(&before, &self.ortho(self.acting(&mid, signs)))
            }
        };
        PointStep {
            state,
            stress,
            dissipated,
            fibre,
        }
    }

    /// Whether the stress components `i` and `j` (Voigt order) enter the indices: every one,
    /// or in plane 11, 22 and 12 alone.
    fn counts(&self, i: usize, j: usize) -> bool {
        let through = |k: usize| (2..5).contains(&k);
        !(self.in_plane && (through(i) || through(j)))
    }

    /// The stress `s` (Voigt order) as the indices see it: in plane, its 33, 23 and 13
    /// components left out.
    fn counted(&self, s: [f64; 6]) -> [f64; 6] {
        std::array::from_fn(|i| if self.counts(i, i) { s[i] } else { 0.0 })
    }

    /// $r$ of each mode at the effective stress `s` (Voigt order): $\sqrt F$, and for matrix
    /// compression, whose index has a part linear in the stress, the inverse of the factor
    /// on `s` that brings the index to 1 (the same where the linear part vanishes). Either is
    /// of degree one in the stress, and 1 exactly where the index is.
    fn index_ratios(&self, s: &[f64; 6]) -> [f64; 4] {
        let k = &self.strength;
        let s = &self.counted(*s);
        let (i1, fibre) = (s[1] + s[2], s[0]);
        let ft = if fibre >= 0.0 { fibre / k.xt } else { 0.0 };
        let fc = if fibre < 0.0 { -fibre / k.xc } else { 0.0 };
        if i1 >= 0.0 {
            // Hashin's matrix tension index (`failure_indices`'), its square root
            let long = (s[5] * s[5] + s[4] * s[4]) / (k.s12 * k.s12);
            let trans = (s[3] * s[3] - s[1] * s[2]) / (k.s23 * k.s23);
            let mt = (i1 / k.yt).powi(2) + trans + long;
            return [ft, fc, mt.max(0.0).sqrt(), 0.0];
        }
        // failure's order is (11, 22, 33, 12, 23, 13)
        let (a, b) = matrix_compression_parts([s[0], s[1], s[2], s[5], s[3], s[4]], k);
        // the load factor that brings this stress to the index 1, inverted:
        // F(r^-1 s) = 1 with F = a + b, linear and quadratic parts
        let mc = match b > 0.0 {
            true => 0.5 * (a + (a * a + 4.0 * b).sqrt()),
            false => a.max(0.0),
        };
        [ft, fc, 0.0, mc]
    }
}

/// An orthotropic stiffness in the ply axes: its normal block (11, 22, 33) and its shear
/// moduli (23, 13, 12); the other terms of its Voigt matrix are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ortho {
    pub normal: [[f64; 3]; 3],
    pub shear: [f64; 3],
}

impl Ortho {
    /// The orthotropic part of the Voigt matrix `c`.
    pub fn of(c: &Voigt) -> Ortho {
        Ortho {
            normal: std::array::from_fn(|i| std::array::from_fn(|j| c[i][j])),
            shear: std::array::from_fn(|i| c[3 + i][3 + i]),
        }
    }

    /// The Voigt matrix.
    pub fn voigt(&self) -> Voigt {
        let mut c = [[0.0; 6]; 6];
        for i in 0..3 {
            c[i][..3].copy_from_slice(&self.normal[i]);
            c[3 + i][3 + i] = self.shear[i];
        }
        c
    }

    /// The stress of strain `e` (Voigt order): the Voigt matrix's product, whose zero terms
    /// add nothing.
    pub fn apply(&self, e: &[f64; 6]) -> [f64; 6] {
        std::array::from_fn(|i| match i < 3 {
            true => (0..3).map(|j| self.normal[i][j] * e[j]).sum(),
            false => self.shear[i - 3] * e[i],
        })
    }

    /// This stiffness less `b`, term by term.
    fn less(&self, b: &Ortho) -> Ortho {
        Ortho {
            normal: std::array::from_fn(|i| {
                std::array::from_fn(|j| self.normal[i][j] - b.normal[i][j])
            }),
            shear: std::array::from_fn(|i| self.shear[i] - b.shear[i]),
        }
    }
}

/// Whether a fibre mode's acting damage grew from state `old` to `new`.
fn fibre_grew(old: &[f64; POINT_STATE], new: &[f64; POINT_STATE]) -> bool {
    new[4] != old[4] || new[5] != old[5]
}

/// Whether a matrix mode's acting damage grew from state `old` to `new`.
fn matrix_grew(old: &[f64; POINT_STATE], new: &[f64; POINT_STATE]) -> bool {
    new[6] != old[6] || new[7] != old[7]
}

/// The effective stress of the stress `s` under the acting damage ([`PlyDamage::acting`])
/// with the transverse stresses' sum in tension (`open`) or not: each component divided by
/// its one minus damage (Lapczyk and Hurtado's $M\sigma$), which in a mode's uniaxial state
/// is the undamaged modulus times the strain, Poisson's ratios and all. The transverse terms'
/// damage is the sign's own mode's, matrix tension's or compression's.
pub fn effective(s: &[f64; 6], [df, dt, ds, dc]: [f64; 4], open: bool) -> [f64; 6] {
    let dm = if open { dt } else { dc };
    let d = [df, dm, dm, ds, ds, ds];
    std::array::from_fn(|i| s[i] / (1.0 - d[i]))
}

/// `c` times `e`.
pub(crate) fn voigt_apply(c: &Voigt, e: &[f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| (0..6).map(|j| c[i][j] * e[j]).sum())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Orthotropic;

    /// IM7/8552 (NASA CompDam's constants, MPa and N/mm).
    pub(crate) fn im7() -> PlyDamage {
        let o = Orthotropic::transversely_isotropic(171_420.0, 9_080.0, 0.32, 0.52, 5_290.0);
        let k = Strength {
            xt: 2326.2,
            xc: 1200.1,
            yt: 62.3,
            yc: 199.8,
            s12: 92.3,
            s23: 75.3,
        };
        PlyDamage::new(o.stiffness(), k, [133.3, 47.5, 0.277, 0.788], 0.0)
    }

    fn in_plane(law: PlyDamage) -> PlyDamage {
        PlyDamage {
            in_plane: true,
            ..law
        }
    }

    /// The compliance (normal block) of the stiffness with damage `d` acting.
    fn compliance(law: &PlyDamage, d: [f64; 4]) -> nalgebra::Matrix3<f64> {
        let c = law.stiffness(d);
        nalgebra::Matrix3::from_fn(|i, j| c[i][j])
            .try_inverse()
            .unwrap()
    }

    /// A crushed matrix (matrix compression damage at its cap) is soft to a uniaxial
    /// transverse stress, by 1 / (1 - d) as an open crack is, and keeps its compliance to a
    /// transverse pressure (sigma_22 = sigma_33) to rounding: a crushed ply still bears the
    /// pressure of what confines it. In plane, only S_22 and the 12 modulus soften, and the
    /// through-thickness terms are the undamaged ones.
    #[test]
    fn a_crushed_matrix_keeps_its_transverse_bulk_stiffness() {
        let law = im7();
        let s0 = compliance(&law, [0.0; 4]);
        let s = compliance(&law, [0.0, 0.0, 0.0, D_MAX]);
        let uniaxial = s[(1, 1)] * (1.0 - D_MAX) / s0[(1, 1)];
        assert!((uniaxial - 1.0).abs() < 1e-6, "uniaxial {uniaxial}");
        let pressure = |s: &nalgebra::Matrix3<f64>| s[(1, 1)] + s[(1, 2)] + s[(2, 1)] + s[(2, 2)];
        let ratio = pressure(&s) / pressure(&s0);
        assert!((ratio - 1.0).abs() < 1e-6, "pressure compliance x {ratio}");
        assert!((s[(0, 0)] / s0[(0, 0)] - 1.0).abs() < 1e-6);
        // in plane: S_22 alone, either matrix damage; 33, 23 and 13 untouched
        let flat = in_plane(im7());
        for d in [[0.0, 0.5, 0.75, 0.0], [0.0, 0.0, 0.75, 0.5]] {
            let s = compliance(&flat, d);
            assert!((s[(1, 1)] * 0.5 / s0[(1, 1)] - 1.0).abs() < 1e-9);
            assert!((s[(2, 2)] / s0[(2, 2)] - 1.0).abs() < 1e-9);
            let c = flat.stiffness(d);
            assert_eq!((c[3][3], c[4][4]), (law.c0[3][3], law.c0[4][4]));
            assert!((c[5][5] / law.c0[5][5] - 0.25).abs() < 1e-12);
        }
    }

    /// A crushed point (3D) whose transverse pressure turns to a faint tension keeps the
    /// stiffness of its deviatoric strain: the stress of a strain along v = (0, 1, -1) is
    /// the same with either sign's acting damage (to rounding), where the crushed part
    /// closing would restore the undamaged stiffness to the whole strain. In plane the
    /// crush and the open crack soften the one modulus E2, and matrix compression acts in
    /// compression alone.
    #[test]
    fn a_crushed_matrix_keeps_its_deviatoric_compliance_in_tension() {
        let law = im7();
        let mut s = [0.0; POINT_STATE];
        s[3] = 0.99;
        s[7] = 0.99;
        let e = [0.0, -0.05, 0.05, 0.0, 0.0, 0.0];
        let closed = law.stiffness(law.acting(&s, (true, false)));
        let open = law.stiffness(law.acting(&s, (true, true)));
        let (a, b) = (voigt_apply(&closed, &e), voigt_apply(&open, &e));
        let undamaged = voigt_apply(&law.c0, &e);
        for i in 0..6 {
            assert!(
                (a[i] - b[i]).abs() <= 1e-9 * undamaged[1].abs(),
                "{a:?} {b:?}"
            );
        }
        // the crushed stress is what d_mc leaves of the undamaged one
        assert!(
            a[1].abs() <= 0.02 * undamaged[1].abs(),
            "{a:?} {undamaged:?}"
        );
        let plane = in_plane(law);
        assert_eq!(plane.acting(&s, (true, true))[3], 0.0);
        assert_eq!(plane.acting(&s, (true, false))[3], 0.99);
    }

    /// Through-thickness compression far past Y_C damages a ply whose indices count every
    /// stress, and not one that counts its in-plane stresses alone; in-plane shear past S_12
    /// damages both.
    #[test]
    fn in_plane_plies_damage_by_their_in_plane_stresses_alone() {
        let (full, flat) = (im7(), in_plane(im7()));
        let (e2, yc) = full.mode_constants(3);
        let e = uniaxial(&full, [0.0; 4], 2, -2.0 * yc / e2);
        assert!(full.initiates(&e, [0.5, 0.5]));
        assert!(!flat.initiates(&e, [0.5, 0.5]));
        let step = flat.step((&e, &e), &[0.0; POINT_STATE], [0.5, 0.5], 1.0);
        assert_eq!(step.state, [0.0; POINT_STATE]);
        let shear = 2.0 * full.strength.s12 * full.shear[2];
        let mut e = [0.0; 6];
        e[5] = shear;
        assert!(full.initiates(&e, [0.5, 0.5]) && flat.initiates(&e, [0.5, 0.5]));
        e = [0.0; 6];
        e[4] = shear;
        assert!(full.initiates(&e, [0.5, 0.5]) && !flat.initiates(&e, [0.5, 0.5]));
    }

    /// The uniaxial stress state of strain `eps` along axis `a` (lateral stresses free),
    /// found with the law's current stiffness: the strain vector.
    fn uniaxial(law: &PlyDamage, d: [f64; 4], a: usize, eps: f64) -> [f64; 6] {
        // the lateral strains of a uniaxial stress: -S_ja / S_aa times eps, with the
        // damaged compliance
        let c = law.stiffness(d);
        let n = nalgebra::Matrix3::from_fn(|i, j| c[i][j]);
        let s = n.try_inverse().unwrap();
        let mut e = [0.0; 6];
        for j in 0..3 {
            e[j] = s[(j, a)] / s[(a, a)] * eps;
        }
        e
    }

    /// A point pulled along the fibres (or across them) through its whole softening, in
    /// uniaxial stress, by the strain of the band: the energy it takes per unit volume,
    /// times the band, is the fracture energy within 0.5% (the rest is the path's
    /// discretisation); the peak stress is the strength; the stress ends at zero. So too
    /// past the snap-back width where the law lowers its strength: the peak is then
    /// $\sqrt{2 E G / l}$, and the law's own dissipation of its drop at once is G less what
    /// the damaged stiffness holds at the drop's strain (below).
    #[test]
    fn a_band_pulled_apart_dissipates_its_fracture_energy() {
        let lowered = PlyDamage {
            lower_strength: true,
            ..im7()
        };
        for (mode, axis, l, law) in [
            (0, 0, 0.5, im7()),
            (2, 1, 0.5, im7()),
            (2, 1, 1.2, im7()),
            (1, 0, 0.5, im7()),
            (3, 1, 0.25, im7()),
            // past the snap-back widths (1.30 and 0.36 mm), the strengths lowered
            (2, 1, 2.0, lowered),
            (3, 1, 1.41, lowered),
            // within it, a lowering law is the law itself
            (2, 1, 1.2, lowered),
        ] {
            let sign = if mode % 2 == 1 { -1.0 } else { 1.0 };
            let (e_mod, x) = law.mode_constants(mode);
            let rf = law.softening_end(mode, l);
            // the strength: the law's, or the one its band dissipates G with
            let x = x * law.onset(mode, l);
            let end = 1.05 * rf * x / e_mod;
            let steps = 20_000;
            let mut state = [0.0; POINT_STATE];
            let (mut work, mut dissipated, mut peak, mut last) = (0.0, 0.0, 0.0f64, 0.0);
            let mut fibre = 0.0;
            let mut prev = (0.0, 0.0);
            let mut e_prev = [0.0; 6];
            for i in 1..=steps {
                let eps = sign * end * i as f64 / steps as f64;
                let d = law.acting(&state, (sign > 0.0, sign > 0.0));
                let e = uniaxial(&law, d, axis, eps);
                let p = law.step((&e, &e_prev), &state, [l, l], 1.0);
                e_prev = e;
                state = p.state;
                let s = sign * p.stress[axis];
                work += 0.5 * (s + prev.1) * (sign * eps - prev.0);
                dissipated += p.dissipated;
                fibre += p.fibre;
                prev = (sign * eps, s);
                peak = peak.max(s);
                last = s;
            }
            let g = law.energy[mode];
            eprintln!(
                "mode {mode}, band {l}: work x l {:.5} (G {g}), dissipated x l {:.5}, peak {peak:.2} (X {x}), end {last:.3e}",
                work * l,
                dissipated * l
            );
            assert!((work * l - g).abs() <= 5e-3 * g, "work {}", work * l);
            // a drop at once happens within one step of the path, at the lateral strains of
            // the stiffness before it: what the damaged stiffness still holds at that strain
            // is released by the next steps' strain with no damage growing. Pulled, 0.6% of
            // G; crushed, the pressure the crushed matrix keeps its stiffness to holds 24%
            let (low, high) = match (rf < 1.0 + 1e-3, mode) {
                (false, _) => (0.995, 1.005),
                (true, 3) => (0.7, 1.0),
                (true, _) => (0.99, 1.0),
            };
            assert!(
                dissipated * l >= low * g && dissipated * l <= high * g,
                "dissipated {}",
                dissipated * l
            );
            assert!((peak - x).abs() <= 2e-3 * x, "peak {peak}");
            // one kind grows: the whole is its share
            let share = if mode < 2 { dissipated } else { 0.0 };
            assert_eq!(fibre, share, "mode {mode}: the fibre modes' share");
            // what D_MAX leaves: 1e-4 of the stiffness at 1.05 r_f
            assert!(last.abs() <= 1.1e-4 * rf * x, "end {last}");
        }
    }

    /// A point crushed along its fibres while pulled across them, both kinds softening over
    /// the same steps: each step's fibre and matrix shares are at least zero and sum to the
    /// whole (by construction), and each kind's share is what the same step releases with the
    /// other kind's damage held at its start (to rounding), whichever is taken first.
    #[test]
    fn both_kinds_growing_share_the_release() {
        let law = im7();
        let (e1, xc) = law.mode_constants(1);
        let (e2, yt) = law.mode_constants(2);
        let path = |t: f64| [-1.5 * t * xc / e1, 1.5 * t * yt / e2, 0.0, 0.0, 0.0, 0.0];
        let mut state = [0.0; POINT_STATE];
        let mut prev = [0.0; 6];
        let (mut both, mut fibre, mut matrix) = (0, 0.0, 0.0);
        for i in 1..=400 {
            let e = path(i as f64 / 400.0);
            let step = law.step((&e, &prev), &state, [0.5, 0.5], 1.0);
            let grew = |k: usize| step.state[4 + k] > state[4 + k];
            if (grew(0) || grew(1)) && (grew(2) || grew(3)) {
                both += 1;
                // the matrix's share taken first: its growth alone, then the fibres'
                let mut mid = state;
                for k in [2, 3, 6, 7] {
                    mid[k] = step.state[k];
                }
                let eff = voigt_apply(&law.c0, &e);
                let signs = (eff[0] >= 0.0, eff[1] + eff[2] >= 0.0);
                let c = |s: &[f64; POINT_STATE]| law.stiffness(law.acting(s, signs));
                let release = |a: &Voigt, b: &Voigt| -> f64 {
                    let r: f64 = (0..6)
                        .map(|i| prev[i] * (0..6).map(|j| (a[i][j] - b[i][j]) * e[j]).sum::<f64>())
                        .sum();
                    0.5 * r
                };
                let matrix_first = release(&c(&state), &c(&mid));
                let scale = step.dissipated.abs();
                assert!(
                    step.fibre >= 0.0 && step.dissipated - step.fibre >= 0.0,
                    "{step:?}"
                );
                // the order matters only to second order in the step's growth
                assert!(
                    (step.dissipated - step.fibre - matrix_first).abs() <= 0.05 * scale,
                    "step {i}: matrix {} against {matrix_first}",
                    step.dissipated - step.fibre
                );
            }
            fibre += step.fibre;
            matrix += step.dissipated - step.fibre;
            (state, prev) = (step.state, e);
        }
        eprintln!("{both} steps grew both kinds: fibre {fibre:.4e}, matrix {matrix:.4e}");
        assert!(
            both > 10 && fibre > 0.0 && matrix > 0.0,
            "{both} {fibre} {matrix}"
        );
    }

    /// Unloading keeps the damage (secant unloading to the origin), and reloading follows the
    /// secant up to where the softening left off; closing a fibre crack (compression) gives
    /// the fibres their compressive stiffness back.
    #[test]
    fn damage_never_heals_and_a_closed_crack_bears_compression() {
        let law = im7();
        let (e1, xt) = law.mode_constants(0);
        let eps0 = xt / e1;
        let mut state = [0.0; POINT_STATE];
        for eps in [0.5, 1.0, 1.5, 2.0] {
            let e = uniaxial(&law, law.acting(&state, (true, true)), 0, eps * eps0);
            state = law.step((&e, &e), &state, [0.5, 0.5], 1.0).state;
        }
        let d = state[0];
        assert!(d > 0.0);
        let e = uniaxial(&law, law.acting(&state, (true, true)), 0, 0.5 * eps0);
        let back = law.step((&e, &e), &state, [0.5, 0.5], 1.0);
        assert_eq!(back.state[0], d, "unloading keeps the damage");
        assert_eq!(back.dissipated, 0.0);
        let secant = back.stress[0] / (0.5 * eps0);
        assert!(
            (secant / e1 - (1.0 - d)).abs() < 0.02,
            "secant {}",
            secant / e1
        );
        let e = uniaxial(&law, [0.0; 4], 0, -0.5 * eps0);
        let closed = law.step((&e, &e), &state, [0.5, 0.5], 1.0);
        assert!((closed.stress[0] / (-0.5 * eps0) / e1 - 1.0).abs() < 1e-9);
    }

    /// A matrix crack opened, then closed by a pressure across the other transverse axis
    /// (the crack's opening strain still positive, the transverse stresses' sum turned
    /// negative) and opened again, step by step through the closure: every step's
    /// dissipation is at least zero, none where the damage does not grow (the closure's and
    /// the reopening's steps among them).
    #[test]
    fn a_crack_closing_and_opening_again_stores_no_energy_back() {
        let law = im7();
        let (e2, yt) = law.mode_constants(2);
        let eps0 = yt / e2;
        let at = |a: f64, b: f64| [0.0, a * eps0, b * eps0, 0.0, 0.0, 0.0];
        let open = (0..=40).map(|i| at(1.6 * i as f64 / 40.0, 0.0));
        let unload = (1..=20).map(|i| at(1.6 - 1.3 * i as f64 / 20.0, 0.0));
        let press = (1..=40).map(|i| at(0.3, -0.8 * i as f64 / 40.0));
        let release = (1..=40).map(|i| at(0.3, -0.8 + 0.8 * i as f64 / 40.0));
        let mut state = [0.0; POINT_STATE];
        let (mut prev, mut opened, mut closed) = ([0.0; 6], 0.0, 0);
        for (k, e) in open.chain(unload).chain(press).chain(release).enumerate() {
            let step = law.step((&e, &prev), &state, [0.5, 0.5], 1.0);
            let grew = (0..8).any(|m| step.state[m] > state[m]);
            assert!(step.dissipated >= 0.0, "step {k}: {}", step.dissipated);
            match k <= 40 {
                true => opened += step.dissipated,
                false => assert!(!grew && step.dissipated == 0.0, "step {k}: {step:?}"),
            }
            let eff = voigt_apply(&law.c0, &e);
            closed += usize::from(eff[1] + eff[2] < 0.0);
            (state, prev) = (step.state, e);
        }
        assert!(state[2] > 0.3 && opened > 0.0, "{state:?}");
        assert!(closed > 10, "the crack closed on {closed} steps");
    }

    /// With a viscosity the acting damage lags the softening's by dt / eta per step, and
    /// reaches it when held.
    #[test]
    fn viscous_damage_lags_and_catches_up() {
        let mut law = im7();
        law.viscosity = 1e-3;
        let (e2, yt) = law.mode_constants(2);
        let e = uniaxial(&law, [0.0; 4], 1, 2.0 * yt / e2);
        let mut state = [0.0; POINT_STATE];
        state = law.step((&e, &e), &state, [0.5, 0.5], 1e-4).state;
        let target = state[2];
        assert!((state[6] - target / 11.0).abs() < 1e-12, "{state:?}");
        for _ in 0..200 {
            state = law.step((&e, &e), &state, [0.5, 0.5], 1e-4).state;
        }
        assert!((state[6] - target).abs() < 1e-6 * target);
    }

    /// The sieve's bound holds: on random strains r of every mode is at most
    /// beta sqrt(2 u), and some strain comes within 10% of it.
    #[test]
    fn the_sieve_bounds_every_mode() {
        for law in [im7(), in_plane(im7())] {
            sieve_bounds_every_mode(&law);
        }
    }

    fn sieve_bounds_every_mode(law: &PlyDamage) {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let beta = law.sieve_factor().sqrt();
        let mut rng = StdRng::seed_from_u64(3);
        let mut closest = 0.0f64;
        for _ in 0..20_000 {
            let e: [f64; 6] = std::array::from_fn(|_| rng.random_range(-1e-2..1e-2));
            let s = voigt_apply(&law.c0, &e);
            let u2: f64 = (0..6).map(|i| s[i] * e[i]).sum();
            let r = law.index_ratios(&s);
            let worst = r.iter().fold(0.0f64, |m, &x| m.max(x));
            let bound = beta * u2.sqrt();
            assert!(worst <= bound * (1.0 + 1e-12), "{worst} > {bound}");
            closest = closest.max(worst / bound);
        }
        eprintln!("sieve: the closest random strain reaches {closest:.3} of the bound");
        assert!(closest > 0.5, "{closest}");
    }

    /// On random strains the reach is at least every mode's r and at most the sieve's bound,
    /// and is subadditive: reach(a + b) <= reach(a) + reach(b).
    #[test]
    fn the_reach_is_a_seminorm_between_the_modes_and_the_sieve() {
        for law in [im7(), in_plane(im7())] {
            reach_is_a_seminorm(&law);
        }
    }

    fn reach_is_a_seminorm(law: &PlyDamage) {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let beta = law.sieve_factor().sqrt();
        let mut rng = StdRng::seed_from_u64(5);
        let mut strain = || -> [f64; 6] { std::array::from_fn(|_| rng.random_range(-1e-2..1e-2)) };
        for _ in 0..20_000 {
            let (a, b) = (strain(), strain());
            let s = voigt_apply(&law.c0, &a);
            let u2: f64 = (0..6).map(|i| s[i] * a[i]).sum();
            let worst = law.index_ratios(&s).iter().fold(0.0f64, |m, &x| m.max(x));
            let reach = law.reach(&a);
            assert!(worst <= reach * (1.0 + 1e-12), "{worst} > {reach}");
            assert!(reach <= beta * u2.sqrt() * (1.0 + 1e-12), "{reach}");
            let sum: [f64; 6] = std::array::from_fn(|i| a[i] + b[i]);
            assert!(law.reach(&sum) <= (reach + law.reach(&b)) * (1.0 + 1e-12));
        }
    }

    /// The reach is its forms' combination, to rounding.
    #[test]
    fn the_reach_is_its_forms() {
        for law in [im7(), in_plane(im7())] {
            reach_is_its_forms(&law);
        }
    }

    fn reach_is_its_forms(law: &PlyDamage) {
        use rand::{rngs::StdRng, Rng, SeedableRng};
        let [f, t, l, q] = law.reach_forms();
        let form = |a: &Voigt, e: &[f64; 6]| -> f64 {
            (0..6)
                .map(|i| e[i] * (0..6).map(|j| a[i][j] * e[j]).sum::<f64>())
                .sum::<f64>()
                .max(0.0)
                .sqrt()
        };
        let mut rng = StdRng::seed_from_u64(9);
        for _ in 0..2000 {
            let e: [f64; 6] = std::array::from_fn(|_| rng.random_range(-1e-2..1e-2));
            let by_forms = form(&f, &e)
                .max(form(&t, &e))
                .max(form(&l, &e) + form(&q, &e));
            let reach = law.reach(&e);
            assert!(
                (by_forms - reach).abs() <= 1e-9 * reach,
                "{by_forms} {reach}"
            );
        }
    }

    /// The snap-back width of IM7/8552 in matrix tension, 2 E2 G / YT^2: 1.30 mm.
    #[test]
    fn the_matrix_snap_back_width_of_im7_8552() {
        let w = im7().snap_back_width(2);
        assert!((w - 1.296).abs() < 0.005, "{w}");
    }
}
