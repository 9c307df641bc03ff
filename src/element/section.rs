//! What an element is made of: one elastic law, or plies through its thickness
//! ([`Layup`], integrated ply by ply; built for hex8i elements only).

use crate::material::{Elastic, Layup};

#[derive(Debug, Clone, Copy)]
pub enum Section<'a> {
    Solid(&'a Elastic),
    Layered(&'a Layup),
}

impl Section<'_> {
    pub fn density(&self) -> f64 {
        match self {
            Section::Solid(m) => m.density,
            Section::Layered(l) => l.average().density,
        }
    }

    /// The law that stands for the whole section: its own, or the plies' thickness-weighted
    /// mean (for elements that integrate one law; layups are built for hex8i only).
    pub fn elastic(&self) -> Elastic {
        match self {
            Section::Solid(m) => **m,
            Section::Layered(l) => l.average(),
        }
    }

    /// The 2 x 2 x 2 Gauss points of a hex over the section, with their weights and laws: the
    /// cube's, or each ply's along the layup's axis (its range's two points, weighted by half
    /// its width).
    pub fn hex_points(&self) -> Vec<([f64; 3], f64, Elastic)> {
        let g = 1.0 / 3f64.sqrt();
        let cube = super::hex8::gauss_points();
        match self {
            Section::Solid(m) => cube.iter().map(|&p| (p, 1.0, **m)).collect(),
            Section::Layered(l) => (l.plies.iter())
                .flat_map(|ply| {
                    let (mid, half) = (0.5 * (ply.lo + ply.hi), 0.5 * (ply.hi - ply.lo));
                    cube.iter().map(move |&p| {
                        let mut q = p;
                        q[l.axis] = mid + half * p[l.axis].signum() * g;
                        (q, half, ply.elastic)
                    })
                })
                .collect(),
        }
    }
}

impl<'a> From<&'a Elastic> for Section<'a> {
    fn from(m: &'a Elastic) -> Self {
        Section::Solid(m)
    }
}
