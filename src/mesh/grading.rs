//! The node coordinates of a structured box along one axis: evenly spaced, or refined in a
//! zone (`box.refine`) with the spacing growing geometrically away from it.
//!
//! Inside the zone the cells are equal and at most the zone's size h. On each side of it the
//! $n$ cells grow by one ratio $r \in [1, $ [`GROWTH`]$]$ from the zone's cells until they
//! reach the spacing that `divisions` gives, $H = (max - min) / divisions$, and stay at it:
//! $s_k = \min(h r^k, H)$. The count $n$ is the fewest whose largest reach (at the largest
//! ratio) covers the side, and $r$ makes them end exactly at the box's face. A side too short
//! for any such cells (it would need a ratio below 1: a side under about four zone cells)
//! joins the zone.

/// The largest ratio of neighbouring cells outside a refined zone.
pub const GROWTH: f64 = 1.25;

/// A zone of an axis, `lo..hi`, whose cells are at most `size`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisZone {
    pub lo: f64,
    pub hi: f64,
    pub size: f64,
}

/// The node coordinates from `min` to `max` (both exact): `n` even cells, or, with a zone
/// that overlaps the box and asks for cells finer than the even ones, the refined grading.
pub fn axis_nodes(min: f64, max: f64, n: usize, zone: Option<AxisZone>) -> Vec<f64> {
    let even = (max - min) / n as f64;
    match zone {
        Some(z) if z.hi.min(max) > z.lo.max(min) && z.size < even => graded(min, max, even, z),
        _ => even_nodes(min, max, n),
    }
}

/// `n` even cells from `min` to `max`, the far end exactly at `max` (so that faces of
/// touching boxes coincide bit for bit).
fn even_nodes(min: f64, max: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            if t == 1.0 {
                max
            } else {
                min + t * (max - min)
            }
        })
        .collect()
}

/// The refined grading of [`axis_nodes`]: the zone clipped to the box (grown over a side too
/// short to grade) in even cells of at most `z.size`, then each side's cells.
fn graded(min: f64, max: f64, even: f64, z: AxisZone) -> Vec<f64> {
    let (mut lo, mut hi) = (z.lo.max(min), z.hi.min(max));
    loop {
        // a zone of 3.0000000001 sizes takes 3 cells, not 4
        let cells = (((hi - lo) / z.size) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
        let h = (hi - lo) / cells as f64;
        let (left, right) = (side(lo - min, h, even), side(max - hi, h, even));
        match (left, right) {
            (None, _) => lo = min,
            (_, None) => hi = max,
            (Some(left), Some(right)) => {
                return assemble((min, max), (lo, hi, cells), &left, &right)
            }
        }
    }
}

/// The nodes of the left side's cells (from the zone outwards), the zone's `cells` even
/// cells from `lo` to `hi` and the right side's cells, the box's ends exact.
fn assemble(
    (min, max): (f64, f64),
    (lo, hi, cells): (f64, f64, usize),
    left: &[f64],
    right: &[f64],
) -> Vec<f64> {
    let mut x = Vec::with_capacity(left.len() + cells + right.len() + 1);
    let mut at = lo;
    x.push(lo);
    for s in left {
        at -= s;
        x.push(at);
    }
    x.reverse();
    x[0] = min;
    x.extend_from_slice(&even_nodes(lo, hi, cells)[1..]);
    let mut at = hi;
    for s in right {
        at += s;
        x.push(at);
    }
    *x.last_mut().expect("nodes") = max;
    x
}

/// The cells of a side of `length` next to zone cells of `h` (from the zone outwards), or
/// `None` where no count of cells growing by a ratio in 1..[`GROWTH`] fills it.
fn side(length: f64, h: f64, even: f64) -> Option<Vec<f64>> {
    if length <= 1e-12 * even {
        return Some(Vec::new());
    }
    let sizes = |n: usize, r: f64| -> Vec<f64> {
        let mut s = h;
        (0..n)
            .map(|_| {
                s = (s * r).min(even);
                s
            })
            .collect()
    };
    let reach = |n: usize, r: f64| sizes(n, r).iter().sum::<f64>();
    let n = (1..).find(|&n| reach(n, GROWTH) >= length)?;
    if reach(n, 1.0) > length * (1.0 + 1e-12) {
        return None;
    }
    // the ratio that fills the side exactly, by bisection (the reach grows with it)
    let (mut a, mut b) = (1.0, GROWTH);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if reach(n, m) < length {
            a = m;
        } else {
            b = m;
        }
    }
    let cells = sizes(n, b);
    let scale = length / cells.iter().sum::<f64>();
    Some(cells.iter().map(|s| s * scale).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cells of a node list.
    fn cells(x: &[f64]) -> Vec<f64> {
        x.windows(2).map(|w| w[1] - w[0]).collect()
    }

    #[test]
    fn without_a_zone_the_cells_are_even_and_the_ends_exact() {
        let x = axis_nodes(-0.3, 0.7, 7, None);
        assert_eq!(x.len(), 8);
        assert_eq!((x[0], x[7]), (-0.3, 0.7));
        for c in cells(&x) {
            assert!((c - 1.0 / 7.0).abs() < 1e-15);
        }
        // a zone no finer than the even cells, or outside the box, changes nothing
        let coarse = AxisZone {
            lo: 0.0,
            hi: 0.2,
            size: 0.5,
        };
        assert_eq!(axis_nodes(-0.3, 0.7, 7, Some(coarse)), x);
        let outside = AxisZone {
            lo: 2.0,
            hi: 3.0,
            size: 0.01,
        };
        assert_eq!(axis_nodes(-0.3, 0.7, 7, Some(outside)), x);
    }

    /// A zone in the middle, at an edge and covering the whole box: inside, cells of at most
    /// the size, with nodes at the zone's ends; outside, no cell above the even spacing and no
    /// neighbour more than 1.25 times another; the ends exact.
    #[test]
    fn a_refined_zone_grades_geometrically_to_the_even_spacing() {
        let (min, max, n) = (0.0, 76.2, 8);
        let even = (max - min) / n as f64;
        for (lo, hi) in [
            (28.1, 48.1),
            (-5.0, 10.0),
            (0.0, 76.2),
            (60.0, 90.0),
            (0.3, 76.0),
        ] {
            let size = 0.9;
            let x = axis_nodes(min, max, n, Some(AxisZone { lo, hi, size }));
            assert_eq!((x[0], *x.last().unwrap()), (min, max));
            let c = cells(&x);
            // a side shorter than a few zone cells joins the zone
            let (mut zlo, mut zhi) = (lo.max(min), hi.min(max));
            if zlo - min < 4.0 * size {
                zlo = min;
            }
            if max - zhi < 4.0 * size {
                zhi = max;
            }
            assert!(x.iter().any(|&p| (p - zlo).abs() < 1e-12), "node at {zlo}");
            assert!(x.iter().any(|&p| (p - zhi).abs() < 1e-12), "node at {zhi}");
            for (i, w) in c.iter().enumerate() {
                let mid = 0.5 * (x[i] + x[i + 1]);
                if mid > zlo && mid < zhi {
                    assert!(*w <= size * (1.0 + 1e-12), "{w} inside the zone");
                } else {
                    assert!(*w <= even * (1.0 + 1e-12), "{w} outside");
                }
                assert!(*w > 0.0);
            }
            for p in c.windows(2) {
                let r = p[1].max(p[0]) / p[1].min(p[0]);
                assert!(r <= GROWTH * (1.0 + 1e-9), "ratio {r} in {c:?}");
            }
            // growing away from the zone: a cell beyond it is no smaller than the one before
            for (i, p) in c.windows(2).enumerate() {
                if x[i + 1] >= zhi - 1e-12 {
                    assert!(
                        p[1] >= p[0] * (1.0 - 1e-9),
                        "shrinks right of the zone: {c:?}"
                    );
                }
                if x[i + 1] <= zlo + 1e-12 {
                    assert!(
                        p[0] >= p[1] * (1.0 - 1e-9),
                        "shrinks left of the zone: {c:?}"
                    );
                }
            }
            eprintln!("zone {lo}..{hi}: {} cells", c.len());
        }
    }
}
