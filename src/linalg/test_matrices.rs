//! Matrices for the linear algebra's tests.

use super::Csc;

/// A small linear congruential generator: values in [0, 1) from a fixed seed.
pub(crate) struct Lcg(pub u64);

impl Lcg {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A 27-point stencil on an m^3 grid with random negative couplings and a diagonal that
/// dominates them by a random shift: symmetric positive definite.
pub(crate) fn grid_matrix(m: usize, seed: u64) -> Csc {
    let mut rng = Lcg(seed);
    let m = m as isize;
    let id = |x: isize, y: isize, z: isize| (x + m * (y + m * z)) as u32;
    let inside = |x: isize, y: isize, z: isize| [x, y, z].iter().all(|&c| (0..m).contains(&c));
    // the 13 offsets after a point in (z, y, x) order: each coupling once
    let offsets: Vec<[isize; 3]> = (0..27)
        .map(|k| [k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1])
        .filter(|&[dx, dy, dz]| (dz, dy, dx) > (0, 0, 0))
        .collect();
    let mut t = Vec::new();
    let mut diag = vec![0.0; (m * m * m) as usize];
    for z in 0..m {
        for y in 0..m {
            for x in 0..m {
                for &[dx, dy, dz] in &offsets {
                    if !inside(x + dx, y + dy, z + dz) {
                        continue;
                    }
                    let (i, j) = (id(x, y, z), id(x + dx, y + dy, z + dz));
                    let a = -(0.5 + rng.next());
                    t.push((i, j, a));
                    t.push((j, i, a));
                    diag[i as usize] -= a;
                    diag[j as usize] -= a;
                }
            }
        }
    }
    for (i, d) in diag.iter().enumerate() {
        t.push((i as u32, i as u32, d + 0.1 + rng.next()));
    }
    Csc::from_triplets(diag.len(), t)
}
