//! The distinct shapes of a block's damageable hexes: elements of one material whose
//! corners, relative to corner 0, agree to $2^{-40}$ of the element's extent share their
//! condensation, bands, sieve and point operators ([`crate::element::damage::HexOperators`]).
//! A structured box has a handful of shapes, a refined one a few hundred.
//!
//! Each shape's corners are its key's own (the quantised ones), not those of an element that
//! happens to come first, so an element's data is the same whichever elements a process
//! holds: one process, any number of ranks.

use std::collections::HashMap;

use rayon::prelude::*;

/// Bits of the quantised corners below the element's extent.
const BITS: i32 = 40;

/// A shape: its material index and corners relative to corner 0 (quantised).
pub(crate) type HexShape = (u32, [[f64; 3]; 8]);

/// The shapes of a list of hexes, in the order of their first element, and each element's.
pub(crate) struct HexShapes {
    pub shapes: Vec<HexShape>,
    pub of: Vec<u32>,
}

/// The key of a hex of material `m` and corners `x`: the power of two at or below its
/// extent and its corners relative to corner 0 in units of that over 2^BITS.
type Key = (u32, i32, [i64; 21]);

fn key(m: u32, x: &[[f64; 3]; 8]) -> Key {
    let extent = crate::element::extent(x).max(f64::MIN_POSITIVE);
    let scale = extent.log2().floor() as i32;
    let unit = 2f64.powi(scale - BITS);
    let q = std::array::from_fn(|j| ((x[1 + j / 3][j % 3] - x[0][j % 3]) / unit).round() as i64);
    (m, scale, q)
}

/// The corners a key stands for (corner 0 at the origin).
fn corners((m, scale, q): &Key) -> HexShape {
    let unit = 2f64.powi(scale - BITS);
    let mut x = [[0.0; 3]; 8];
    for (j, v) in q.iter().enumerate() {
        x[1 + j / 3][j % 3] = *v as f64 * unit;
    }
    (*m, x)
}

impl HexShapes {
    /// The shapes of hexes given by their material and corners.
    pub fn of(hexes: &[HexShape]) -> Self {
        let keys: Vec<Key> = hexes.par_iter().map(|(m, x)| key(*m, x)).collect();
        let mut ids: HashMap<&Key, u32> = HashMap::new();
        let mut shapes = Vec::new();
        let of = (keys.iter())
            .map(|k| {
                *ids.entry(k).or_insert_with(|| {
                    shapes.push(corners(k));
                    (shapes.len() - 1) as u32
                })
            })
            .collect();
        HexShapes { shapes, of }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Translated copies of a hex, and copies off by rounding, are one shape whose corners
    /// are within 2^-40 of the extent of theirs; a different size or material is another.
    #[test]
    fn translated_hexes_share_their_shape() {
        let cube: [[f64; 3]; 8] =
            crate::element::hex8::CORNERS.map(|c| c.map(|v| 0.5 * (v + 1.0) * 0.7));
        let moved = |d: f64| cube.map(|p| [p[0] + d, p[1] + 2.0 * d, p[2] - d]);
        let bigger = cube.map(|p| p.map(|v| 1.5 * v));
        let hexes = [
            (0, cube),
            (0, moved(3.1)),
            (0, moved(1e-3)),
            (0, bigger),
            (1, cube),
        ];
        let s = HexShapes::of(&hexes);
        assert_eq!(s.of, vec![0, 0, 0, 1, 2]);
        for (k, p) in s.shapes[0].1.iter().enumerate() {
            for a in 0..3 {
                assert!((p[a] - (cube[k][a] - cube[0][a])).abs() <= 0.7 * 2f64.powi(-40));
            }
        }
    }
}
