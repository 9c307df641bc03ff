//! Recursive coordinate bisection: the elements split into parts of equal weight, each cut
//! across the longest side of its elements' centroids.
//!
//! An element weighs one, plus [`CONTACT_WEIGHT`] for each of its corners that is a
//! secondary node of a surface interface: a rank searches the primary faces for the
//! secondary nodes it owns, and that search costs about as much per node as 5.5 elements'
//! forces (measured on the weak-scaling bench's scene, 2-core AMD EPYC: 3 us per secondary
//! node-step against 0.54 us per element-step), shared by the four or so surface elements
//! around the node.
//!
//! Every rank computes the same partition from the same model (the sort breaks ties by the
//! element number), so no rank has to be told another's.

use crate::model::{Model, Primary};

/// The weight a secondary-node corner adds to its element.
pub(crate) const CONTACT_WEIGHT: f64 = 1.4;

/// The partition in words (`summary.json`).
pub(crate) const DESCRIPTION: &str = "recursive coordinate bisection of the element centroids into equal weights (an element weighs 1, plus 1.4 for each secondary-node corner)";

/// The part of every element, in [`crate::mesh::Mesh::elements`] order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Partition {
    pub parts: usize,
    pub part_of: Vec<u32>,
}

impl Partition {
    /// The model's elements cut into `parts` parts by recursive coordinate bisection.
    pub fn bisect(model: &Model, parts: usize) -> Partition {
        let centroids = centroids(model);
        let weights = weights(model);
        let mut part_of = vec![0u32; centroids.len()];
        let mut order: Vec<u32> = (0..centroids.len() as u32).collect();
        let cut = Cut {
            centroids: &centroids,
            weights: &weights,
        };
        cut.split(&mut order, 0, parts.max(1), &mut part_of);
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
    model.mesh.elements().map(|e| mean(e.nodes)).collect()
}

/// Every element's weight, in global order.
pub fn weights(model: &Model) -> Vec<f64> {
    let mut secondary = vec![false; model.mesh.node_count()];
    for itf in &model.interfaces {
        if matches!(itf.primary, Primary::Surface { .. }) {
            for &n in &itf.nodes {
                secondary[n as usize] = true;
            }
        }
    }
    let weight = |nodes: &[u32]| {
        let k = nodes.iter().filter(|&&n| secondary[n as usize]).count();
        1.0 + CONTACT_WEIGHT * k as f64
    };
    model.mesh.elements().map(|e| weight(e.nodes)).collect()
}

/// The elements' centroids and weights the bisection cuts by.
struct Cut<'a> {
    centroids: &'a [[f64; 3]],
    weights: &'a [f64],
}

impl Cut<'_> {
    /// Gives the elements `order` to parts `first..first + parts`: the part counts split in
    /// two halves, the elements sorted along their longest extent and cut where the weight
    /// before the cut is the first half's share.
    fn split(&self, order: &mut [u32], first: usize, parts: usize, part_of: &mut [u32]) {
        if parts == 1 || order.len() <= 1 {
            for &e in order.iter() {
                part_of[e as usize] = first as u32;
            }
            return;
        }
        let c = self.centroids;
        let axis = longest_axis(c, order);
        order.sort_unstable_by(|&i, &j| {
            (c[i as usize][axis].total_cmp(&c[j as usize][axis])).then(i.cmp(&j))
        });
        let left = parts / 2;
        let total: f64 = order.iter().map(|&e| self.weights[e as usize]).sum();
        let share = total * left as f64 / parts as f64;
        let mut before = 0.0;
        let mut cut = 0;
        while cut < order.len() && before + 0.5 * self.weights[order[cut] as usize] <= share {
            before += self.weights[order[cut] as usize];
            cut += 1;
        }
        let (a, b) = order.split_at_mut(cut);
        self.split(a, first, left, part_of);
        self.split(b, first + left, parts - left, part_of);
    }
}

/// The axis along which the centroids of `order` spread the most (the lowest of equals).
fn longest_axis(c: &[[f64; 3]], order: &[u32]) -> usize {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &e in order {
        for a in 0..3 {
            lo[a] = lo[a].min(c[e as usize][a]);
            hi[a] = hi[a].max(c[e as usize][a]);
        }
    }
    (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])).then(b.cmp(&a)))
        .unwrap_or(0)
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

    /// Without contact every element weighs one: the parts are equal to one element.
    #[test]
    fn parts_are_equal_to_one_element_and_cut_along_the_long_side() {
        let model = plate_model(20);
        for parts in [1, 2, 3, 4, 7] {
            let p = Partition::bisect(&model, parts);
            let sizes = p.sizes();
            let (min, max) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
            // a cut at the nearest element to the share, at each of the log2(parts) levels
            assert!(max - min <= 2, "{parts} parts: {sizes:?}");
            assert_eq!(sizes.iter().sum::<usize>(), 60);
        }
        // two parts of a 20 x 3 x 1 plate: the cut is at x = 10
        let p = Partition::bisect(&model, 2);
        for (e, h) in model.mesh.elements().enumerate() {
            let x: f64 = (h.nodes.iter())
                .map(|&n| model.mesh.nodes[n as usize][0])
                .sum::<f64>()
                / 8.0;
            assert_eq!(p.part_of[e], u32::from(x > 10.0), "element {e} at x = {x}");
        }
    }

    /// With contact the elements under the secondary surface weigh more, and the parts are
    /// equal in weight to within the heaviest element at each level of cuts.
    #[test]
    fn parts_are_equal_in_weight_with_contact() {
        let toml = "[run]\nmethod = \"explicit\"\nend_time = 1e-6\n[[material]]\nname = \"steel\"\ndensity = 7.8e-3\nyoungs_modulus = 200.0\npoissons_ratio = 0.3\n[[body]]\nname = \"plate\"\nmaterial = \"steel\"\nbox = { min = [0.0, 0.0, -1.0], max = [8.0, 4.0, 0.0], divisions = [16, 8, 2] }\n[[body]]\nname = \"block\"\nmaterial = \"steel\"\nbox = { min = [1.0, 1.0, 0.0], max = [3.0, 3.0, 2.0], divisions = [4, 4, 4] }\n[[contact]]\nname = \"c\"\nsecondary = { body = \"block\", face = \"z-\" }\nprimary = { body = \"plate\", face = \"z+\" }\n";
        let scene = crate::scene::Scene::parse(toml, std::path::Path::new("c.toml")).unwrap();
        let model = Model::from_scene(&scene).unwrap();
        let w = weights(&model);
        let heaviest = w.iter().copied().fold(0.0, f64::max);
        assert_eq!(
            heaviest,
            1.0 + 4.0 * CONTACT_WEIGHT,
            "a bottom corner cell of the block"
        );
        for parts in [2, 3, 4] {
            let p = Partition::bisect(&model, parts);
            let mut sums = vec![0.0; parts];
            for (e, &q) in p.part_of.iter().enumerate() {
                sums[q as usize] += w[e];
            }
            let (min, max) = sums
                .iter()
                .fold((f64::MAX, 0.0f64), |(a, b), &s| (a.min(s), b.max(s)));
            assert!(max - min <= 2.0 * heaviest, "{parts} parts: {sums:?}");
        }
    }
}
