//! The sieve's memory: which damageable elements without damage the damage passes may skip.
//!
//! A point's reach ([`crate::material::PlyDamage::reach`]) is a seminorm of its strain at
//! least every mode's r, so an element whose reach is below 1 at every point cannot start to
//! damage. At a point of strain energy density u the reach is at most $\beta \sqrt{2u}$, and
//! a point's density is at most c times the element's strain energy (the block's sieve
//! $\kappa = 2 \beta^2 c$, [`super::damage_data`]). Where the element's reach $R_c$ was last
//! found at displacement $u_c$, the reach at u is therefore at most
//! $R_c + \sqrt{\kappa\, U(u - u_c)}$, with
//! $U(u - u_c) = U(u) + U(u_c) - f \cdot u_c$ from the elastic forces $f = K u$ the
//! element kernels have just given. An element stays skipped while that stays below 1; when
//! it does not, its reach is found exactly at its points and remembered (or it steps, where
//! it reaches 1). Without a memory ($u_c = 0$, $R_c = 0$) this is the plain sieve
//! $\kappa U < 1$.
//!
//! The memory decides only which elements the pass looks at, never their forces: an element
//! it skips would have kept its elastic forces anyway. So a resumed run, or one on other
//! ranks, which starts with an empty memory, steps to the same bits.

use super::damage_data::DamageData;
use crate::element::ElementKind;

/// The values remembered per element of `n` corners: the displacements of corners 1.. less
/// corner 0's, then $U(u_c)$ and $R_c$.
pub const fn stride(n: usize) -> usize {
    3 * (n - 1) + 2
}

/// Each block's memory, [`stride`] values per damageable element.
#[derive(Debug, Clone, Default)]
pub struct SieveMemory {
    pub blocks: Vec<Vec<f64>>,
}

impl SieveMemory {
    /// An empty memory (every element's $u_c$, $U(u_c)$ and $R_c$ zero).
    pub fn new(data: &DamageData) -> Self {
        let blocks = (ElementKind::ALL.iter().zip(&data.blocks))
            .map(|(kind, b)| vec![0.0; stride(kind.corners()) * b.len()])
            .collect();
        SieveMemory { blocks }
    }
}

/// The elastic strain energy $\tfrac12 f \cdot u$ of an element's forces `f` at corner
/// displacements `u` (the forces sum to zero, so relative to corner 0).
fn energy<const N: usize>(f: &[[f64; 3]], u: &[[f64; 3]; N]) -> f64 {
    0.5 * (1..N)
        .map(|k| (0..3).map(|a| f[k][a] * (u[k][a] - u[0][a])).sum::<f64>())
        .sum::<f64>()
}

/// Whether an element without damage, of sieve `kappa`, elastic forces `f` at `u` and
/// memory `memory`, may have started to damage (an upper bound of its reach is 1 or more).
/// Rounding is covered by $10^{-10}$ of the energies.
pub fn may_reach<const N: usize>(
    memory: &[f64],
    kappa: f64,
    (f, u): (&[[f64; 3]], &[[f64; 3]; N]),
) -> bool {
    let (uc, rest) = memory.split_at(3 * (N - 1));
    let (energy_c, reach_c) = (rest[0], rest[1]);
    let energy_u = energy(f, u);
    let cross: f64 = (1..N)
        .map(|k| (0..3).map(|a| f[k][a] * uc[3 * (k - 1) + a]).sum::<f64>())
        .sum();
    let increment = (energy_u + energy_c - cross).max(0.0) + 1e-10 * (energy_u + energy_c).abs();
    reach_c + (kappa * increment).sqrt() >= 1.0
}

/// Remembers an element's reach `reach`, found at `u` where its elastic forces are `f`.
pub fn remember<const N: usize>(
    memory: &mut [f64],
    (f, u): (&[[f64; 3]], &[[f64; 3]; N]),
    reach: f64,
) {
    for k in 1..N {
        for a in 0..3 {
            memory[3 * (k - 1) + a] = u[k][a] - u[0][a];
        }
    }
    memory[3 * (N - 1)] = energy(f, u);
    memory[3 * (N - 1) + 1] = reach;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bound's increment is the energy of u - u_c: a spring pair's K (one element of two
    /// corners along x, stiffness k) gives it by hand.
    #[test]
    fn the_bound_grows_with_the_energy_of_the_change() {
        let k = 2.0;
        let forces = |u: &[[f64; 3]; 2]| {
            let t = k * (u[1][0] - u[0][0]);
            [[-t, 0.0, 0.0], [t, 0.0, 0.0]]
        };
        let uc = [[0.1, 0.0, 0.0], [0.4, 0.0, 0.0]];
        let mut memory = vec![0.0; stride(2)];
        remember(&mut memory, (&forces(&uc), &uc), 0.5);
        for (m, want) in memory.iter().zip([0.3, 0.0, 0.0, 0.5 * k * 0.09, 0.5]) {
            assert!((m - want).abs() < 1e-15, "{m} {want}");
        }
        // u - u_c stretches by 0.1: energy 0.01, so the bound is 0.5 + sqrt(kappa 0.01)
        let u = [[0.0, 0.0, 0.0], [0.4, 0.0, 0.0]];
        let kappa = 20.0;
        let bound = 0.5 + (kappa * 0.5 * k * 0.01f64).sqrt();
        assert!(bound < 1.0 && bound > 0.9);
        assert!(!may_reach(&memory, kappa, (&forces(&u), &u)));
        assert!(may_reach(&memory, kappa * 1.3, (&forces(&u), &u)));
        // an empty memory is the plain sieve, kappa U < 1
        let empty = vec![0.0; stride(2)];
        let energy_u = 0.5 * k * 0.16;
        assert!(!may_reach(&empty, 0.99 / energy_u, (&forces(&u), &u)));
        assert!(may_reach(&empty, 1.01 / energy_u, (&forces(&u), &u)));
    }
}
