//! One rank's share of a decomposed model: its elements, the nodes they touch, and what it
//! exchanges with the ranks that share nodes with it.
//!
//! A node touched by elements of several ranks is held by each of them, and every holder
//! keeps the same copy of its state: each sums the node's element forces itself, from its
//! own corners and the corners its neighbours send, in the order of the global corner
//! numbers, which is the order the single-process gather adds them in
//! ([`crate::kernels::node_gather`]). So a shared node's force is the same bits on every
//! holder and in a run on one process. The lowest holder owns the node: it alone counts it in
//! the sums of the history, gives its probe values, searches for its contacts as a secondary
//! node and sends it to the ranks whose contacts may reach it as a primary-face node.

use super::partition::Partition;
use crate::element::{CornerLayout, ElementKind};
use crate::kernels::ElementData;
use crate::model::Model;

/// The precision of the corner forces a shared node's sum adds: f64 on the CPU, f32 from a
/// GPU.
pub trait CornerValue: Copy + Default + std::ops::AddAssign + Into<f64> {
    /// A received value, sent as f64 (exactly, for an f32 corner).
    fn of(x: f64) -> Self;
}

impl CornerValue for f64 {
    fn of(x: f64) -> Self {
        x
    }
}

impl CornerValue for f32 {
    fn of(x: f64) -> Self {
        x as f32
    }
}

/// Where one corner force of a shared node's sum comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// A corner of this rank's elements (its index in the local corner forces, or in the
    /// list of [`Subdomain::exchanged_corners`] once
    /// [`Subdomain::pack_corners`] renumbered them).
    Local(u32),
    /// A corner a neighbour sent (its index in the receive buffer, in corners).
    Remote(u32),
}

/// A rank that shares nodes with this one, and the corners each sends the other.
#[derive(Debug, Clone)]
pub struct Neighbour {
    pub rank: usize,
    /// Local corners sent to it, in global corner order (numbered as [`Source::Local`]).
    pub send: Vec<u32>,
    /// Where its corners lie in the receive buffer (in corners).
    pub receive: std::ops::Range<usize>,
}

/// The nodes of the contact surfaces (every interface's secondary nodes and primary face
/// nodes): which the rank holds, and who owns each.
#[derive(Debug, Clone, Default)]
pub struct SurfaceMap {
    /// The surface nodes' global numbers, increasing.
    pub nodes: Vec<u32>,
    /// (surface index, local node) of every surface node this rank holds.
    pub held: Vec<(u32, u32)>,
    /// The owner of each surface node.
    pub owner: Vec<u32>,
}

/// One rank's elements, nodes and exchange lists.
#[derive(Debug, Clone)]
pub struct Subdomain {
    pub rank: usize,
    pub ranks: usize,
    /// Global number of each local node, increasing.
    pub nodes: Vec<u32>,
    /// Whether this rank owns each local node.
    pub owned: Vec<bool>,
    /// The rank's elements in global order, on local node numbers, and their global numbers
    /// (increasing, as [`crate::mesh::Mesh::elements`] numbers them).
    pub data: ElementData,
    pub elements: Vec<u32>,
    pub neighbours: Vec<Neighbour>,
    /// Corners received in all.
    pub received: usize,
    /// The local nodes other ranks also hold; `sources[offsets[i]..offsets[i + 1]]` are the
    /// corners of `shared[i]` in global corner order.
    pub shared: Vec<u32>,
    pub offsets: Vec<u32>,
    pub sources: Vec<Source>,
    /// Whether [`Self::pack_corners`] renumbered the exchanged corners.
    pub packed: bool,
    pub surface: SurfaceMap,
}

/// Every global corner (its corner id, see [`crate::element::CornerLayout`]) with its
/// element and node.
fn corners(model: &Model) -> impl Iterator<Item = (usize, usize, u32)> + '_ {
    (model.mesh.elements().enumerate())
        .flat_map(|(e, el)| el.nodes.iter().map(move |&n| (e, n)))
        .enumerate()
        .map(|(c, (e, n))| (c, e, n))
}

/// The lowest rank holding each node (rank 0 for a node in no element).
pub fn owners(model: &Model, partition: &Partition) -> Vec<u32> {
    let mut owner = vec![u32::MAX; model.mesh.node_count()];
    for (_, e, n) in corners(model) {
        let o = &mut owner[n as usize];
        *o = (*o).min(partition.part_of[e]);
    }
    owner
        .iter()
        .map(|&o| if o == u32::MAX { 0 } else { o })
        .collect()
}

impl Subdomain {
    /// Rank `rank`'s share of `model` under `partition`.
    pub fn new(model: &Model, partition: &Partition, rank: usize) -> Subdomain {
        let part = |e: usize| partition.part_of[e] as usize;
        let owner = owners(model, partition);
        let n_all = model.mesh.node_count();
        let mut held = vec![false; n_all];
        for (_, e, n) in corners(model) {
            held[n as usize] |= part(e) == rank;
        }
        // a node in no element belongs to rank 0
        let mut touched = vec![false; n_all];
        for (_, _, n) in corners(model) {
            touched[n as usize] = true;
        }
        for n in 0..n_all {
            held[n] |= !touched[n] && rank == 0;
        }
        // a cohesive pair's nodes are held together
        let groups = pair_groups(model);
        for g in &groups {
            if g.iter().any(|&n| held[n as usize]) {
                g.iter().for_each(|&n| held[n as usize] = true);
            }
        }
        let nodes: Vec<u32> = (0..n_all as u32).filter(|&n| held[n as usize]).collect();
        let mut local = vec![u32::MAX; n_all];
        for (i, &n) in nodes.iter().enumerate() {
            local[n as usize] = i as u32;
        }
        let (data, corner_local, elements) = local_elements(model, partition, rank, &local);
        let holders = holders(model, partition, &held, &groups);
        let mut sub = Subdomain {
            rank,
            ranks: partition.parts,
            owned: nodes
                .iter()
                .map(|&n| owner[n as usize] as usize == rank)
                .collect(),
            nodes,
            data,
            elements,
            neighbours: Vec::new(),
            received: 0,
            shared: Vec::new(),
            offsets: vec![0],
            sources: Vec::new(),
            packed: false,
            surface: SurfaceMap::default(),
        };
        sub.exchange_lists(model, partition, &held, &holders, &local, &corner_local);
        sub.surface = surface_map(model, &owner, &local);
        sub
    }

    /// The neighbours' send and receive lists and the sources of every shared node.
    fn exchange_lists(
        &mut self,
        model: &Model,
        partition: &Partition,
        held: &[bool],
        holders: &std::collections::BTreeMap<u32, Vec<u32>>,
        local: &[u32],
        corner_local: &[u32],
    ) {
        let (rank, ranks) = (self.rank, self.ranks);
        let part = |e: usize| partition.part_of[e] as usize;
        let mut send = vec![Vec::new(); ranks];
        let mut receive = vec![0usize; ranks];
        for (c, e, n) in corners(model) {
            let q = part(e);
            if q == rank {
                for &h in holders.get(&n).into_iter().flatten() {
                    if h as usize != rank {
                        send[h as usize].push(corner_local[c]);
                    }
                }
            } else if held[n as usize] {
                receive[q] += 1;
            }
        }
        let mut start = vec![0usize; ranks + 1];
        for q in 0..ranks {
            start[q + 1] = start[q] + receive[q];
        }
        self.received = start[ranks];
        let talks: Vec<usize> = (0..ranks)
            .filter(|&q| q != rank && (receive[q] > 0 || !send[q].is_empty()))
            .collect();
        self.neighbours = (talks.into_iter())
            .map(|q| Neighbour {
                rank: q,
                send: std::mem::take(&mut send[q]),
                receive: start[q]..start[q + 1],
            })
            .collect();
        self.shared_sources(model, partition, holders, (local, corner_local), start);
    }

    /// The sources of each shared node, in global corner order; `start` is where each
    /// rank's corners begin in the receive buffer.
    fn shared_sources(
        &mut self,
        model: &Model,
        partition: &Partition,
        holders: &std::collections::BTreeMap<u32, Vec<u32>>,
        (local, corner_local): (&[u32], &[u32]),
        start: Vec<usize>,
    ) {
        let mut lists: std::collections::BTreeMap<u32, Vec<Source>> = holders
            .keys()
            .map(|&n| (local[n as usize], Vec::new()))
            .collect();
        let mut next = start;
        for (c, e, n) in corners(model) {
            let Some(list) = lists.get_mut(&local[n as usize]) else {
                continue;
            };
            let q = partition.part_of[e] as usize;
            list.push(if q == self.rank {
                Source::Local(corner_local[c])
            } else {
                next[q] += 1;
                Source::Remote((next[q] - 1) as u32)
            });
        }
        for (n, list) in lists {
            self.shared.push(n);
            self.sources.extend(list);
            self.offsets.push(self.sources.len() as u32);
        }
    }

    /// Overwrites the force of every shared node (3 per local node in `f`) with the sum of
    /// its corners, local (`corners`) and received (`received`, 3 per corner), in global
    /// corner order. The sum is taken in the corners' own precision: f64 from the CPU, f32
    /// as a GPU computed them (which is how the GPU's own gather adds them).
    pub fn sum_shared<T: CornerValue>(&self, corners: &[[T; 3]], received: &[f64], f: &mut [f64]) {
        for (&n, sum) in self.shared.iter().zip(self.shared_sums(corners, received)) {
            let f = &mut f[3 * n as usize..3 * n as usize + 3];
            for a in 0..3 {
                f[a] = sum[a].into();
            }
        }
    }

    /// Each shared node's sum of its corners, in the order of [`Self::shared`] (see
    /// [`Self::sum_shared`]).
    pub fn shared_sums<T: CornerValue>(&self, corners: &[[T; 3]], received: &[f64]) -> Vec<[T; 3]> {
        (0..self.shared.len())
            .map(|i| {
                let mut sum = [T::default(); 3];
                for s in &self.sources[self.offsets[i] as usize..self.offsets[i + 1] as usize] {
                    let x = match *s {
                        Source::Local(c) => corners[c as usize],
                        Source::Remote(r) => {
                            let r = 3 * r as usize;
                            std::array::from_fn(|a| T::of(received[r + a]))
                        }
                    };
                    for a in 0..3 {
                        sum[a] += x[a];
                    }
                }
                sum
            })
            .collect()
    }

    /// The corners this rank sends each neighbour, in its order, as f64 (an f32 corner
    /// exactly), from the rank's `corners` (as [`Source::Local`] numbers them).
    pub fn sends<T: Copy + Into<f64>>(&self, corners: &[[T; 3]]) -> Vec<Vec<f64>> {
        (self.neighbours.iter())
            .map(|nb| {
                (nb.send.iter())
                    .flat_map(|&c| corners[c as usize].map(Into::into))
                    .collect()
            })
            .collect()
    }

    /// The local corners the exchange reads (those sent to the neighbours and the shared
    /// nodes' local sources), increasing, each once.
    pub fn exchanged_corners(&self) -> Vec<u32> {
        let sent = self
            .neighbours
            .iter()
            .flat_map(|nb| nb.send.iter().copied());
        let summed = self.sources.iter().filter_map(|s| match *s {
            Source::Local(c) => Some(c),
            Source::Remote(_) => None,
        });
        let mut chosen: Vec<u32> = sent.chain(summed).collect();
        chosen.sort_unstable();
        chosen.dedup();
        chosen
    }

    /// Renumbers the exchanged corners by their places in `chosen` (the list of
    /// [`Self::exchanged_corners`]), for a rank whose corner forces stay on its GPU and
    /// come back for those corners alone. Done once: after it the exchange lists index
    /// `chosen`.
    pub fn pack_corners(&mut self, chosen: &[u32]) {
        debug_assert!(!self.packed, "the corners are packed once");
        self.packed = true;
        let at = |c: u32| chosen.binary_search(&c).expect("an exchanged corner") as u32;
        for nb in &mut self.neighbours {
            nb.send.iter_mut().for_each(|c| *c = at(*c));
        }
        for s in &mut self.sources {
            if let Source::Local(c) = s {
                *c = at(*c);
            }
        }
    }

    /// The rank's part of `model` for its frames: its elements and nodes, each body's share
    /// of them and the materials (no interfaces, fixes or probes).
    pub fn piece_model(&self, model: &Model) -> Model {
        let within = |list: &[u32], r: &std::ops::Range<usize>| {
            list.partition_point(|&x| (x as usize) < r.start)
                ..list.partition_point(|&x| (x as usize) < r.end)
        };
        // the rank's elements of a block are those of its global numbers in the block's range
        let local_block = |b: &crate::mesh::BodyMesh, kind: ElementKind| {
            let r = within(
                &self.elements,
                &model.mesh.elements.global(kind, b.of_kind(kind)),
            );
            let o = self.data.elements.offset(kind);
            r.start - o..r.end - o
        };
        let bodies = (model.mesh.bodies.iter())
            .map(|b| crate::mesh::BodyMesh {
                nodes: within(&self.nodes, &b.nodes),
                elements: ElementKind::ALL.map(|k| local_block(b, k)).to_vec(),
                material: b.material,
                boundary: Vec::new(),
                surfaces: Vec::new(),
                node_sets: Vec::new(),
            })
            .collect();
        let d = &self.data;
        Model {
            mesh: crate::mesh::Mesh {
                nodes: d.reference.clone(),
                elements: d.elements.clone(),
                bodies,
            },
            materials: model.materials.clone(),
            layups: model.layups.clone(),
            material_ply: model.material_ply.clone(),
            material_axes: model.material_axes.clone(),
            material_source: model.material_source.clone(),
            strengths: model.strengths.clone(),
            damage_laws: model.damage_laws.clone(),
            body_names: model.body_names.clone(),
            fixed: Vec::new(),
            interfaces: Vec::new(),
            queries: Default::default(),
            probes: Vec::new(),
            fix_nodes: Vec::new(),
            fix_motion: Vec::new(),
            fix_paths: Vec::new(),
            reactions: Vec::new(),
            initial_velocity: Vec::new(),
            gravity: model.gravity,
            // the rank's pairs are its solver's (`RankCohesive`)
            cohesive: Vec::new(),
            // the rank's loads are its solver's (`LoadForces`)
            loads: Vec::new(),
            held_loads: Vec::new(),
            equations: Vec::new(),
            ties: Vec::new(),
            rigid: Vec::new(),
        }
    }

    /// The values of the local nodes (3 per node) taken from a global vector.
    pub fn restrict<T: Copy>(&self, global: &[T]) -> Vec<T> {
        at_nodes(&self.nodes, global)
    }
}

/// The values of `nodes` (3 per node) taken from a vector over every node.
pub fn at_nodes<T: Copy>(nodes: &[u32], x: &[T]) -> Vec<T> {
    (nodes.iter())
        .flat_map(|&n| x[3 * n as usize..3 * n as usize + 3].iter().copied())
        .collect()
}

/// The rank's elements on local node numbers, the local corner of every global corner
/// (`u32::MAX` for another rank's), and the rank's elements' global numbers.
fn local_elements(
    model: &Model,
    partition: &Partition,
    rank: usize,
    local: &[u32],
) -> (ElementData, Vec<u32>, Vec<u32>) {
    let mesh = &model.mesh;
    let mine = |e: usize| partition.part_of[e] as usize == rank;
    let (elements, kept) = mesh.elements.select(mine, |n| local[n as usize]);
    let (global, mine_layout) = (
        CornerLayout::of(&mesh.elements),
        CornerLayout::of(&elements),
    );
    let mut corner_local = vec![u32::MAX; global.count()];
    for (l, &e) in kept.iter().enumerate() {
        let (c, lc) = (global.first_corner(e), mine_layout.first_corner(l));
        for k in 0..mesh.element(e).kind.corners() {
            corner_local[c + k] = (lc + k) as u32;
        }
    }
    let data = ElementData {
        reference: (0..local.len())
            .filter(|&n| local[n] != u32::MAX)
            .map(|n| mesh.nodes[n])
            .collect(),
        elements,
        materials: model.materials.clone(),
        layups: model.layups.clone(),
    };
    (
        data,
        corner_local,
        kept.into_iter().map(|e| e as u32).collect(),
    )
}

/// The ranks holding each node this rank holds with others (global node number to ranks,
/// increasing): those of its elements, and of the elements of every node it is bonded to
/// (`groups`, [`pair_groups`]).
fn holders(
    model: &Model,
    partition: &Partition,
    held: &[bool],
    groups: &[Vec<u32>],
) -> std::collections::BTreeMap<u32, Vec<u32>> {
    let mut all: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for (_, e, n) in corners(model) {
        if held[n as usize] {
            let list = all.entry(n).or_default();
            let q = partition.part_of[e];
            if !list.contains(&q) {
                list.push(q);
            }
        }
    }
    for g in groups.iter().filter(|g| held[g[0] as usize]) {
        let mut union: Vec<u32> = (g.iter())
            .flat_map(|n| all.get(n).into_iter().flatten().copied())
            .collect();
        union.sort_unstable();
        union.dedup();
        for &n in g {
            all.insert(n, union.clone());
        }
    }
    all.retain(|_, l| l.len() > 1);
    for l in all.values_mut() {
        l.sort_unstable();
    }
    all
}

/// The nodes the cohesive interfaces bond, in groups that every rank holds whole or not at
/// all: the connected parts of the graph of their pairs (a pair's two nodes, or more where
/// a node is in pairs of several interfaces), each increasing. A rank steps a pair where it
/// holds its nodes, so it must hold both, and the ranks holding one hold the other: a rank
/// with elements at one node of a group holds the rest too, and sums their forces from the
/// corners the others send, as for any shared node.
pub fn pair_groups(model: &Model) -> Vec<Vec<u32>> {
    let mut parent: std::collections::BTreeMap<u32, u32> = Default::default();
    fn root(parent: &mut std::collections::BTreeMap<u32, u32>, n: u32) -> u32 {
        let mut r = n;
        while let Some(&p) = parent.get(&r).filter(|&&p| p != r) {
            r = p;
        }
        parent.insert(n, r);
        r
    }
    for c in &model.cohesive {
        for (&a, &b) in c.pairs.upper.iter().zip(&c.pairs.lower) {
            parent.entry(a).or_insert(a);
            parent.entry(b).or_insert(b);
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent.insert(ra.max(rb), ra.min(rb));
        }
    }
    let nodes: Vec<u32> = parent.keys().copied().collect();
    let mut groups: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for n in nodes {
        let r = root(&mut parent, n);
        groups.entry(r).or_default().push(n);
    }
    groups.into_values().collect()
}

/// The contact surfaces' nodes and each rank's share of them.
fn surface_map(model: &Model, owner: &[u32], local: &[u32]) -> SurfaceMap {
    let nodes = surface_nodes(model);
    let held = (nodes.iter().enumerate())
        .filter(|(_, &n)| local[n as usize] != u32::MAX)
        .map(|(s, &n)| (s as u32, local[n as usize]))
        .collect();
    SurfaceMap {
        owner: nodes.iter().map(|&n| owner[n as usize]).collect(),
        nodes,
        held,
    }
}

/// Every node a contact interface reads: its secondary nodes, its primary faces' nodes and
/// its rigid body's node, increasing.
pub fn surface_nodes(model: &Model) -> Vec<u32> {
    let bodies = (model.interfaces.iter()).filter_map(|itf| match itf.primary {
        crate::model::Primary::Rigid { node, .. } => Some(node),
        _ => None,
    });
    let mut nodes: Vec<u32> = (model.interfaces.iter())
        .flat_map(|itf| itf.nodes.iter().copied())
        // a node set's areas come from faces with corners outside it
        .chain(
            (model.interfaces.iter())
                .flat_map(|itf| itf.secondary_faces.iter().flat_map(|f| f.slots())),
        )
        .chain(model.queries.faces.iter().flatten().copied())
        .chain(bodies)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}
