//! Ply failure indices from the stress in a ply's material axes (1 along the fibres, 2
//! across them in the ply's plane, 3 through the thickness): Hashin's four modes (1980) and
//! the maximum stress criterion. An index of 1 or more marks failure in its mode. They are
//! reported only: the laminate stays elastic (no stiffness is degraded when an index
//! reaches 1).
//!
//! Hashin's criteria (quadratic in the stresses), each where its sign condition holds
//! (zero elsewhere), with $I_1 = \sigma_{22} + \sigma_{33}$, $\tau_L^2 = \sigma_{12}^2 +
//! \sigma_{13}^2$ and $\tau_T^2 = \sigma_{23}^2 - \sigma_{22}\sigma_{33}$:
//! - fibre tension ($\sigma_{11} \ge 0$): $(\sigma_{11}/X_T)^2 + \tau_L^2/S_{12}^2$;
//! - fibre compression ($\sigma_{11} < 0$): $(\sigma_{11}/X_C)^2$;
//! - matrix tension ($I_1 \ge 0$): $(I_1/Y_T)^2 + \tau_T^2/S_{23}^2 + \tau_L^2/S_{12}^2$;
//! - matrix compression ($I_1 < 0$): $[(Y_C/2S_{23})^2 - 1] I_1/Y_C + (I_1/2S_{23})^2 +
//!   \tau_T^2/S_{23}^2 + \tau_L^2/S_{12}^2$.
//!
//! Maximum stress (linear in the stresses): the largest of $\sigma_{11}/X_T$ or
//! $-\sigma_{11}/X_C$, $\sigma_{22}/Y_T$ or $-\sigma_{22}/Y_C$, the same for $\sigma_{33}$
//! (the transverse strengths), $|\sigma_{12}|/S_{12}$, $|\sigma_{13}|/S_{12}$ and
//! $|\sigma_{23}|/S_{23}$.

/// A ply's strengths (positive, stress units): along the fibres in tension and compression,
/// across them in tension and compression, in-plane shear and transverse shear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strength {
    pub xt: f64,
    pub xc: f64,
    pub yt: f64,
    pub yc: f64,
    pub s12: f64,
    pub s23: f64,
}

/// The indices, in order: Hashin's fibre tension, fibre compression, matrix tension and
/// matrix compression, and the maximum stress index.
pub const INDICES: [&str; 5] = [
    "fibre_tension",
    "fibre_compression",
    "matrix_tension",
    "matrix_compression",
    "max_stress",
];

/// The failure indices ([`INDICES`]) of the stress `s` = (11, 22, 33, 12, 23, 13) in the
/// ply's material axes.
pub fn failure_indices(s: [f64; 6], k: &Strength) -> [f64; 5] {
    let [s11, s22, s33, s12, s23, s13] = s;
    let long = (s12 * s12 + s13 * s13) / (k.s12 * k.s12);
    let trans = (s23 * s23 - s22 * s33) / (k.s23 * k.s23);
    let i1 = s22 + s33;
    let fibre_tension = if s11 >= 0.0 {
        (s11 / k.xt).powi(2) + long
    } else {
        0.0
    };
    let fibre_compression = if s11 < 0.0 { (s11 / k.xc).powi(2) } else { 0.0 };
    let matrix_tension = if i1 >= 0.0 {
        (i1 / k.yt).powi(2) + trans + long
    } else {
        0.0
    };
    let matrix_compression = if i1 < 0.0 {
        let (linear, quadratic) = matrix_compression_parts(s, k);
        linear + quadratic
    } else {
        0.0
    };
    let normal = |v: f64, t: f64, c: f64| if v >= 0.0 { v / t } else { -v / c };
    let max_stress = [
        normal(s11, k.xt, k.xc),
        normal(s22, k.yt, k.yc),
        normal(s33, k.yt, k.yc),
        s12.abs() / k.s12,
        s13.abs() / k.s12,
        s23.abs() / k.s23,
    ]
    .into_iter()
    .fold(0.0, f64::max);
    [
        fibre_tension,
        fibre_compression,
        matrix_tension,
        matrix_compression,
        max_stress,
    ]
}

/// Hashin's matrix compression index of the stress `s` (order as [`failure_indices`]) in
/// its part linear in the stress, $[(Y_C/2S_{23})^2 - 1] I_1/Y_C$, and its quadratic part.
pub(crate) fn matrix_compression_parts(s: [f64; 6], k: &Strength) -> (f64, f64) {
    let [_, s22, s33, s12, s23, s13] = s;
    let long = (s12 * s12 + s13 * s13) / (k.s12 * k.s12);
    let trans = (s23 * s23 - s22 * s33) / (k.s23 * k.s23);
    let i1 = s22 + s33;
    let r = k.yc / (2.0 * k.s23);
    (
        (r * r - 1.0) * i1 / k.yc,
        (i1 / (2.0 * k.s23)).powi(2) + trans + long,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A carbon/epoxy's strengths (MPa), all distinct so that a wrong one shows.
    const K: Strength = Strength {
        xt: 2000.0,
        xc: 1200.0,
        yt: 50.0,
        yc: 200.0,
        s12: 80.0,
        s23: 60.0,
    };

    fn at(i: usize, v: f64) -> [f64; 6] {
        let mut s = [0.0; 6];
        s[i] = v;
        s
    }

    fn close(got: [f64; 5], want: [f64; 5]) {
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-12, "{got:?} against {want:?}");
        }
    }

    /// Each uniaxial stress at its strength reaches 1 in its own modes and the hand-computed
    /// values in the others.
    #[test]
    fn uniaxial_stresses_at_their_strengths() {
        // fibre tension at XT: Hashin's fibre tension and the maximum stress reach 1; the
        // matrix (I1 = 0) sees nothing
        close(
            failure_indices(at(0, 2000.0), &K),
            [1.0, 0.0, 0.0, 0.0, 1.0],
        );
        // fibre compression at XC
        close(
            failure_indices(at(0, -1200.0), &K),
            [0.0, 1.0, 0.0, 0.0, 1.0],
        );
        // transverse tension at YT: fibre tension sees s11 = 0 (>= 0, zero value)
        close(failure_indices(at(1, 50.0), &K), [0.0, 0.0, 1.0, 0.0, 1.0]);
        // transverse compression at YC: [(YC/2S23)^2 - 1] (-1) + (YC/2S23)^2 = 1
        close(
            failure_indices(at(1, -200.0), &K),
            [0.0, 0.0, 0.0, 1.0, 1.0],
        );
        // through-thickness compression at YC, the same (I1 = s33)
        close(
            failure_indices(at(2, -200.0), &K),
            [0.0, 0.0, 0.0, 1.0, 1.0],
        );
        // in-plane shear at S12: both tension modes (s11 = I1 = 0) and the maximum stress
        close(failure_indices(at(3, 80.0), &K), [1.0, 0.0, 1.0, 0.0, 1.0]);
        // transverse shear at S23: the matrix mode and the maximum stress
        close(failure_indices(at(4, 60.0), &K), [0.0, 0.0, 1.0, 0.0, 1.0]);
        // out-of-plane shear 13 counts with S12
        close(failure_indices(at(5, -80.0), &K), [1.0, 0.0, 1.0, 0.0, 1.0]);
    }

    /// Half the strength: a quarter in the quadratic modes, a half in the maximum stress.
    #[test]
    fn half_the_strength_gives_a_quarter_and_a_half() {
        close(
            failure_indices(at(0, 1000.0), &K),
            [0.25, 0.0, 0.0, 0.0, 0.5],
        );
        // matrix compression at YC/2: [(200/120)^2 - 1] (-100/200) + (100/120)^2
        let r = 200.0f64 / 120.0;
        let mc = (r * r - 1.0) * (-0.5) + (100.0f64 / 120.0).powi(2);
        close(failure_indices(at(1, -100.0), &K), [0.0, 0.0, 0.0, mc, 0.5]);
    }

    /// Combined stresses: fibre tension with in-plane shear adds the quadratic terms; biaxial
    /// transverse stress enters the matrix mode through I1 and tau_T.
    #[test]
    fn combined_stresses_add_their_terms() {
        let s = [1000.0, 0.0, 0.0, 40.0, 0.0, 0.0];
        let want_ft = 0.25 + 0.25;
        let want_mt = 0.25;
        close(failure_indices(s, &K), [want_ft, 0.0, want_mt, 0.0, 0.5]);
        let s = [0.0, 20.0, 10.0, 0.0, 0.0, 0.0];
        let mt = (30.0f64 / 50.0).powi(2) + (0.0 - 200.0) / 3600.0;
        close(failure_indices(s, &K), [0.0, 0.0, mt, 0.0, 0.4]);
    }
}
