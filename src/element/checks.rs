//! Checks every element's tests share: a symmetric stiffness with the six rigid modes of
//! free motion, and the exact energy of a uniform strain (the patch test).

use crate::material::Elastic;

/// A transversely isotropic ply turned off every axis: every entry of its stiffness is
/// nonzero.
pub(crate) fn turned_ply() -> Elastic {
    let ply = crate::material::Orthotropic::transversely_isotropic(140.0, 10.0, 0.3, 0.45, 5.0);
    let axes = crate::material::Rotation::from_axes([1.0, 0.4, -0.3], [0.2, 1.0, 0.5]).unwrap();
    Elastic::anisotropic(ply.stiffness(), 1.6).rotated(&axes)
}

/// A uniform strain with every component nonzero.
pub(crate) const STRAIN: [[f64; 3]; 3] = [
    [0.01, 0.002, -0.003],
    [0.002, -0.004, 0.005],
    [-0.003, 0.005, 0.006],
];

/// The displacement u = E x of the uniform strain [`STRAIN`] at the corners x.
pub(crate) fn uniform_strain(x: &[[f64; 3]]) -> Vec<[f64; 3]> {
    (x.iter())
        .map(|p| std::array::from_fn(|a| (0..3).map(|b| STRAIN[a][b] * p[b]).sum()))
        .collect()
}

/// The strain energy of [`STRAIN`] in a volume V: V (lambda tr^2 / 2 + mu E:E).
pub(crate) fn uniform_strain_energy(volume: f64, m: &Elastic) -> f64 {
    let tr = STRAIN[0][0] + STRAIN[1][1] + STRAIN[2][2];
    let ee: f64 = STRAIN.iter().flatten().map(|v| v * v).sum();
    volume * (0.5 * m.lambda * tr * tr + m.mu * ee)
}

/// The strain energy of [`STRAIN`] in a volume V for any material: V sigma:eps / 2.
pub fn strain_energy(volume: f64, m: &Elastic) -> f64 {
    let s = m.stress(&STRAIN);
    let se: f64 = (0..3)
        .map(|i| (0..3).map(|j| s[i][j] * STRAIN[i][j]).sum::<f64>())
        .sum();
    0.5 * volume * se
}

/// Asserts that the element stiffness `k` of corners x is symmetric (to `sym` of its
/// diagonal) and that the three translations and three linearised rotations give no force
/// (to `force` absolute, the corners being of unit size).
pub(crate) fn assert_symmetric_with_rigid_modes<const N: usize>(
    k: &[[f64; N]; N],
    x: &[[f64; 3]],
    sym: f64,
    force: f64,
) {
    for (i, row) in k.iter().enumerate() {
        for (j, kij) in row.iter().enumerate() {
            assert!((kij - k[j][i]).abs() < sym * row[i].abs());
        }
    }
    for mode in 0..6 {
        let u: [f64; N] = std::array::from_fn(|d| {
            let (n, a) = (d / 3, d % 3);
            let p = x[n];
            match mode {
                0..3 => (a == mode) as u8 as f64,
                _ => [[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]][mode - 3][a],
            }
        });
        for row in k {
            let f: f64 = row.iter().zip(&u).map(|(a, b)| a * b).sum();
            assert!(f.abs() < force, "rigid mode {mode} gives force {f}");
        }
    }
}
