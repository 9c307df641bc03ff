//! Recursive coordinate bisection: the elements split into parts of equal count, each cut
//! across the longest side of its elements' centroids.
//!
//! Every rank computes the same partition from the same model (the sort breaks ties by the
//! element number), so no rank has to be told another's.

use crate::model::Model;

/// The part of every element: hex8s first (`0..hexes`), then tet4s, as
/// [`crate::mesh::Mesh`] numbers them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Partition {
    pub parts: usize,
    pub part_of: Vec<u32>,
}

impl Partition {
    /// The model's elements cut into `parts` parts by recursive coordinate bisection.
    pub fn bisect(model: &Model, parts: usize) -> Partition {
        let centroids = centroids(model);
        let mut part_of = vec![0u32; centroids.len()];
        let mut order: Vec<u32> = (0..centroids.len() as u32).collect();
        split(&centroids, &mut order, 0, parts.max(1), &mut part_of);
        Partition {
            parts: parts.max(1),
            part_of,
        }
    }

    /// The number of elements of each part.
    pub fn sizes(&self) -> Vec<usize> {
        let mut n = vec![0; self.parts];
        for &p in &self.part_of {
            n[p as usize] += 1;
        }
        n
    }
}

/// The centroid of every element, hex8s then tet4s.
fn centroids(model: &Model) -> Vec<[f64; 3]> {
    let x = &model.mesh.nodes;
    let mean = |nodes: &[u32]| -> [f64; 3] {
        let mut c = [0.0; 3];
        for &n in nodes {
            for a in 0..3 {
                c[a] += x[n as usize][a];
            }
        }
        c.map(|s| s / nodes.len() as f64)
    };
    (model.mesh.hexes.iter().map(|h| mean(h)))
        .chain(model.mesh.tets.iter().map(|t| mean(t)))
        .collect()
}

/// Gives the elements `order` to parts `first..first + parts`: the part counts split in
/// two halves, the elements sorted along their longest extent and cut in the same ratio.
fn split(c: &[[f64; 3]], order: &mut [u32], first: usize, parts: usize, part_of: &mut [u32]) {
    if parts == 1 || order.len() <= 1 {
        for &e in order.iter() {
            part_of[e as usize] = first as u32;
        }
        return;
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &e in order.iter() {
        for a in 0..3 {
            lo[a] = lo[a].min(c[e as usize][a]);
            hi[a] = hi[a].max(c[e as usize][a]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])).then(b.cmp(&a)))
        .unwrap_or(0);
    order.sort_unstable_by(|&i, &j| {
        (c[i as usize][axis].total_cmp(&c[j as usize][axis])).then(i.cmp(&j))
    });
    let left = parts / 2;
    let cut = order.len() * left / parts;
    let (a, b) = order.split_at_mut(cut);
    split(c, a, first, left, part_of);
    split(c, b, first + left, parts - left, part_of);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plate_model(n: usize) -> Model {
        let toml = format!(
            "[run]\nmethod = \"explicit\"\nend_time = 1e-6\n[[material]]\nname = \"steel\"\ndensity = 7.8e-3\nyoungs_modulus = 200.0\npoissons_ratio = 0.3\n[[body]]\nname = \"plate\"\nmaterial = \"steel\"\nbox = {{ min = [0.0, 0.0, 0.0], max = [{n}.0, 3.0, 1.0], divisions = [{n}, 3, 1] }}\n"
        );
        let scene = crate::scene::Scene::parse(&toml, std::path::Path::new("plate.toml"))
            .expect("a valid scene");
        Model::from_scene(&scene).expect("a model")
    }

    #[test]
    fn parts_are_equal_to_one_element_and_cut_along_the_long_side() {
        let model = plate_model(20);
        for parts in [1, 2, 3, 4, 7] {
            let p = Partition::bisect(&model, parts);
            let sizes = p.sizes();
            let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
            assert!(max - min <= 1, "{parts} parts: {sizes:?}");
            assert_eq!(sizes.iter().sum::<usize>(), 60);
        }
        // two parts of a 20 x 3 x 1 plate: the cut is at x = 10
        let p = Partition::bisect(&model, 2);
        for (e, h) in model.mesh.hexes.iter().enumerate() {
            let x: f64 = h
                .iter()
                .map(|&n| model.mesh.nodes[n as usize][0])
                .sum::<f64>()
                / 8.0;
            assert_eq!(p.part_of[e], u32::from(x > 10.0), "element {e} at x = {x}");
        }
    }
}
