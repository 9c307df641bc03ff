//! Material axes a mesh file gives its elements: Abaqus's `*ORIENTATION` (rectangular, by
//! coordinates) assigned through `*SOLID SECTION, ORIENTATION=`.

use crate::element::ElementKind;
use crate::material::Rotation;

use super::parse_error::ParseError;

/// The material axes of each element of a body, where its file gives them, a list per
/// element block; empty when the file gives none (the body then takes its scene material's
/// axes).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ElementAxes {
    /// One list per kind (in [`ElementKind::ALL`] order), one entry per element of the
    /// body's block.
    blocks: Vec<Vec<Option<Rotation>>>,
}

impl ElementAxes {
    pub fn is_empty(&self) -> bool {
        self.blocks.iter().flatten().all(Option::is_none)
    }

    /// Appends the axes of the next element of a kind.
    pub fn push(&mut self, kind: ElementKind, axes: Option<Rotation>) {
        if self.blocks.len() <= kind.index() {
            self.blocks.resize(kind.index() + 1, Vec::new());
        }
        self.blocks[kind.index()].push(axes);
    }

    /// The axes of the body's elements of a kind, in order (empty where none were given).
    pub fn of_kind(&self, kind: ElementKind) -> &[Option<Rotation>] {
        self.blocks.get(kind.index()).map_or(&[], Vec::as_slice)
    }
}

/// An `*ORIENTATION` as written: its name, the numbers of its data lines, and its line.
#[derive(Debug, Clone, Default)]
pub(crate) struct AbaqusOrientation {
    pub name: String,
    pub lines: Vec<Vec<f64>>,
    pub line: usize,
}

impl AbaqusOrientation {
    /// The axes: local 1 along a - c, b - c in the local 1-2 plane (first data line
    /// `a1, a2, a3, b1, b2, b3[, c1, c2, c3]`, c the origin by default), then turned by the
    /// second data line's `axis, angle` (degrees, about local axis 1, 2 or 3), if any.
    pub fn axes(&self) -> Result<Rotation, ParseError> {
        let err = |m: String| ParseError::at(self.line, format!("*ORIENTATION {}: {m}", self.name));
        let first = self.lines.first().ok_or_else(|| {
            err("needs a data line `a1, a2, a3, b1, b2, b3[, c1, c2, c3]`".into())
        })?;
        if first.len() != 6 && first.len() != 9 {
            return Err(err(format!(
                "the first data line has {} numbers; it needs 6 (points a and b) or 9 (and the origin c)",
                first.len()
            )));
        }
        let point = |k: usize| [first[3 * k], first[3 * k + 1], first[3 * k + 2]];
        let c = if first.len() == 9 { point(2) } else { [0.0; 3] };
        let minus = |p: [f64; 3]| [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        let axes = Rotation::from_axes(minus(point(0)), minus(point(1))).ok_or_else(|| {
            err("points a and b must lie off the origin and off one line through it".into())
        })?;
        match self.lines.get(1).map(Vec::as_slice) {
            None | Some([]) => Ok(axes),
            Some(&[axis, angle]) if [1.0, 2.0, 3.0].contains(&axis) => {
                let k = axis as usize - 1;
                Ok(axes.turned(axes.axes[k], angle.to_radians()))
            }
            Some(other) => Err(err(format!(
                "the second data line must be `axis, angle` with axis 1, 2 or 3, found {other:?}"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn orientation(lines: Vec<Vec<f64>>) -> Result<Rotation, ParseError> {
        AbaqusOrientation {
            name: "ORI".into(),
            lines,
            line: 7,
        }
        .axes()
    }

    /// Axis 1 along a - c, the plane of b: the global axes turned a quarter about z; the
    /// extra turn about local 3 by 90 degrees brings local 1 onto global -x.
    #[test]
    fn rectangular_axes_from_points() {
        let r = orientation(vec![vec![0.0, 2.0, 0.0, -3.0, 0.0, 0.0]]).unwrap();
        let want = [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        for (a, b) in r.axes.iter().flatten().zip(want.iter().flatten()) {
            assert!((a - b).abs() < 1e-15, "{:?}", r.axes);
        }
        let r = orientation(vec![
            vec![1.0, 3.0, 0.0, 0.0, 4.0, 0.0, 1.0, 1.0, 0.0],
            vec![3.0, 90.0],
        ])
        .unwrap();
        let want = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]];
        for (a, b) in r.axes.iter().flatten().zip(want.iter().flatten()) {
            assert!((a - b).abs() < 1e-15, "{:?}", r.axes);
        }
    }

    #[test]
    fn bad_orientations_name_the_line_and_what_is_wrong() {
        for (lines, part) in [
            (vec![], "needs a data line"),
            (vec![vec![1.0, 0.0, 0.0, 2.0]], "has 4 numbers"),
            (vec![vec![1.0, 0.0, 0.0, 2.0, 0.0, 0.0]], "off one line"),
            (
                vec![vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0], vec![4.0, 30.0]],
                "axis 1, 2 or 3",
            ),
        ] {
            let e = orientation(lines).unwrap_err();
            assert_eq!(e.line, Some(7));
            assert!(e.message.contains(part), "{}", e.message);
            assert!(e.message.contains("*ORIENTATION ORI"), "{}", e.message);
        }
    }
}
