//! CPU twin of `shaders/hex8_forces.wgsl`: internal nodal forces of linear elastic hex8
//! elements, $f_e = \sum_g w_g \det J\, B^T \sigma$, with
//! $\sigma = \lambda\, \mathrm{tr}(\varepsilon) I + 2\mu\varepsilon$ and
//! $\varepsilon = \mathrm{sym}(\sum_k u_k \otimes \nabla N_k)$ at each of the 2x2x2 Gauss points.

use rayon::prelude::*;

use super::ElementData;
use crate::element::hex8;

/// Corner forces of one element from its reference corners and corner displacements.
pub fn element_forces(x: &[[f64; 3]; 8], u: &[[f64; 3]; 8], lambda: f64, mu: f64) -> [[f64; 3]; 8] {
    let mut f = [[0.0; 3]; 8];
    for p in hex8::gauss_points() {
        let (g, det) = hex8::gradients(x, p);
        let s = crate::element::stress(&g, u, lambda, mu);
        for k in 0..8 {
            for a in 0..3 {
                f[k][a] += (s[a][0] * g[k][0] + s[a][1] * g[k][1] + s[a][2] * g[k][2]) * det;
            }
        }
    }
    f
}

/// Corner forces of every element: `corner_forces[8 e + k]` is corner k of element e
/// (overwrites it). [`super::node_gather`] sums them to the nodes.
/// Elements run on all threads; each writes its own corners, so the result does not depend
/// on the thread count.
pub fn hex8_forces(data: &ElementData, u: &[[f64; 3]], corner_forces: &mut [[f64; 3]]) {
    corner_forces[..8 * data.hexes.len()]
        .par_chunks_mut(8)
        .with_min_len(ELEMENTS_PER_TASK)
        .zip(data.hexes.par_iter().zip(&data.hex_material))
        .for_each(|(out, (hex, &mat))| {
            let m = data.materials[mat as usize];
            let x = hex.map(|n| data.reference[n as usize]);
            let ue = hex.map(|n| u[n as usize]);
            out.copy_from_slice(&element_forces(&x, &ue, m.lambda, m.mu));
        });
}

/// The fewest elements a thread takes at a time.
pub const ELEMENTS_PER_TASK: usize = 256;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Elastic;

    #[test]
    fn element_forces_equal_stiffness_times_displacement() {
        let mut x = hex8::CORNERS;
        x[6] = [1.2, 0.9, 1.1];
        x[1][2] = -0.8;
        let m = Elastic::from_engineering(10.0, 0.3, 1.0);
        let u: [[f64; 3]; 8] = std::array::from_fn(|k| {
            [
                0.01 * k as f64,
                -0.02 * (k % 3) as f64,
                0.005 * (k * k) as f64,
            ]
        });
        let f = element_forces(&x, &u, m.lambda, m.mu);
        let k = hex8::stiffness(&x, &m);
        for i in 0..24 {
            let want: f64 = (0..24).map(|j| k[i][j] * u[j / 3][j % 3]).sum();
            assert!((f[i / 3][i % 3] - want).abs() < 1e-12 * (1.0 + want.abs()));
        }
    }
}
