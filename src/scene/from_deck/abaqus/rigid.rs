//! `*RIGID BODY, ELSET=..., REF NODE=...` of an Abaqus/CalculiX deck: a section's element
//! set moving as one rigid body. Its mass, centre of mass and inertia come from its elements
//! (their section's `*DENSITY`); the `*BOUNDARY` and `*INITIAL CONDITIONS` lines on its
//! reference node give its motion: Abaqus's dofs 1-3 are the node's translations and 4-6
//! its rotations; CalculiX's `ROT NODE=` carries the rotations as its dofs 1-3.

use super::{Block, Gathered, Reader};
use crate::error::Result;
use crate::mesh::BodyParts;
use crate::scene::from_deck::{DeckRigid, Spin};

/// A `*RIGID BODY` as the deck gives it.
pub(super) struct RigidDecl {
    pub elset: String,
    /// `REF NODE=` and CalculiX's `ROT NODE=`: node numbers, or sets of one node.
    pub ref_node: String,
    pub rot_node: Option<String>,
    /// `POSITION=CENTER OF MASS`: the reference node moved to the centre of mass.
    pub at_centre: bool,
    pub line: usize,
}

/// The parameters of `*RIGID BODY` read; others (`PIN NSET`, `TIE NSET`, `ANALYTICAL
/// SURFACE`, ...) are refused.
const READ: [&str; 4] = ["ELSET", "REF NODE", "ROT NODE", "POSITION"];

/// The nodes of the deck's `*NODE` and `*NSET` blocks, looked up by number.
pub(super) struct DeckNodes<'b> {
    pub blocks: &'b [Block],
}

impl DeckNodes<'_> {
    /// The coordinates of node `id`.
    fn position(&self, id: u64) -> Option<[f64; 3]> {
        let nodes = self.blocks.iter().filter(|b| b.name == "NODE");
        let mut lines = nodes.flat_map(|b| b.data.iter());
        let (f, _) = lines.find(|(f, _)| f[0].parse::<u64>() == Ok(id))?;
        let x = [1, 2, 3].map(|i| f.get(i).and_then(|v| crate::mesh::abaqus::real(v)));
        let [Some(a), Some(b), Some(c)] = x else {
            return None;
        };
        Some([a, b, c])
    }

    /// Whether `set` (a node number, or a node set's name) holds node `id`.
    fn holds(&self, set: &str, id: u64) -> bool {
        self.holds_once(set, id, &mut Vec::new())
    }

    /// [`Self::holds`], each set's blocks read once however often the sets name it.
    fn holds_once(&self, set: &str, id: u64, seen: &mut Vec<String>) -> bool {
        if let Ok(n) = set.parse::<u64>() {
            return n == id;
        }
        let upper = set.to_ascii_uppercase();
        if seen.contains(&upper) {
            return false;
        }
        seen.push(upper);
        let named = |b: &Block| b.get("NSET").is_some_and(|s| s.eq_ignore_ascii_case(set));
        for b in self.blocks.iter().filter(|b| named(b)) {
            let holds = match b.name.as_str() {
                "NODE" => b.data.iter().any(|(f, _)| f[0].parse::<u64>() == Ok(id)),
                "NSET" if b.params.contains_key("GENERATE") => {
                    b.data.iter().any(|(f, _)| in_range(f, id))
                }
                "NSET" => (b.data.iter())
                    .flat_map(|(f, _)| f.iter())
                    .any(|x| !x.is_empty() && self.holds_once(x, id, seen)),
                _ => false,
            };
            if holds {
                return true;
            }
        }
        false
    }

    /// The node that `set` names: a node number, or a set of that one node (listed,
    /// generated or nested, perhaps more than once).
    fn one(&self, set: &str) -> Option<u64> {
        let mut ids = Vec::new();
        self.members(set, &mut ids, &mut Vec::new());
        match ids[..] {
            [id] => Some(id),
            _ => None,
        }
    }

    /// Adds the distinct nodes of `set` to `ids`, stopping past two (enough to tell one).
    fn members(&self, set: &str, ids: &mut Vec<u64>, seen: &mut Vec<String>) {
        let add = |id: u64, ids: &mut Vec<u64>| {
            if !ids.contains(&id) {
                ids.push(id);
            }
        };
        if let Ok(n) = set.parse::<u64>() {
            return add(n, ids);
        }
        let upper = set.to_ascii_uppercase();
        if seen.contains(&upper) {
            return;
        }
        seen.push(upper);
        let named = |b: &Block| b.get("NSET").is_some_and(|s| s.eq_ignore_ascii_case(set));
        for b in self.blocks.iter().filter(|b| named(b)) {
            for (f, _) in &b.data {
                if ids.len() > 1 {
                    return;
                }
                match b.name.as_str() {
                    "NODE" => f[0].parse().into_iter().for_each(|id| add(id, ids)),
                    "NSET" if b.params.contains_key("GENERATE") => {
                        let at = |i: usize| f.get(i).and_then(|x| x.parse::<u64>().ok());
                        if let (Some(a), Some(z)) = (at(0), at(1)) {
                            add(a, ids);
                            let step = at(2).unwrap_or(1).max(1);
                            if let Some(next) = a.checked_add(step).filter(|&n| n <= z) {
                                add(next, ids);
                            }
                        }
                    }
                    "NSET" => {
                        for x in f.iter().filter(|x| !x.is_empty()) {
                            self.members(x, ids, seen);
                        }
                    }
                    _ => {}
                }
            }
        }
    }
}

/// Whether a `GENERATE` line `first, last[, step]` holds `id`.
fn in_range(f: &[String], id: u64) -> bool {
    let at = |i: usize| f.get(i).and_then(|x| x.parse::<u64>().ok());
    let (Some(a), Some(b)) = (at(0), at(1)) else {
        return false;
    };
    let step = at(2).unwrap_or(1).max(1);
    (a..=b).contains(&id) && (id - a) % step == 0
}

/// The deck's rigid bodies, each with its mesh and its reference and rotation nodes.
pub(super) struct Rigids {
    pub bodies: Vec<(DeckRigid, BodyParts)>,
    nodes: Vec<(u64, Option<u64>)>,
}

impl Rigids {
    /// Whether `set` names a rigid body's reference or rotation node.
    pub(super) fn names_a_node(&self, deck: &DeckNodes, set: &str) -> bool {
        (self.nodes.iter())
            .any(|(r, o)| deck.holds(set, *r) || o.is_some_and(|o| deck.holds(set, o)))
    }

    /// The rigid body (and its surface's name) whose mesh holds surface `name`.
    pub(super) fn with_surface(&self, name: &str) -> Option<(usize, String)> {
        self.bodies.iter().enumerate().find_map(|(i, (_, p))| {
            (p.surfaces.iter())
                .find(|s| s.name.eq_ignore_ascii_case(name))
                .map(|s| (i, s.name.clone()))
        })
    }
}

/// What the deck holds of a rigid body's dofs, or starts it with.
#[derive(Default)]
struct RefDofs {
    /// Translations 1-3 and rotations 1-3 held, each with the line that holds it.
    held: [Option<usize>; 6],
    /// The line of the last `*INITIAL CONDITIONS` on the body.
    velocity_line: Option<usize>,
    /// The velocity of the reference node, then the angular velocity.
    velocity: [f64; 6],
}

impl Reader<'_> {
    /// Reads a `*RIGID BODY` keyword line.
    pub(super) fn rigid_body_keyword(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let read = |k: &String| READ.iter().any(|r| crate::mesh::abaqus::word(r) == *k);
        if let Some(p) = b.params.keys().find(|k| !read(k)) {
            return Err(self.src.err(b.line, format!("*RIGID BODY, {p}=: impact's rigid body is a section's element set about its reference node (ELSET=, REF NODE=, ROT NODE=, POSITION=)")));
        }
        let elset = b.get("ELSET").ok_or_else(|| {
            self.src.err(b.line, "*RIGID BODY needs ELSET=: impact takes a rigid body's mass and inertia from its elements")
        })?;
        let ref_node = (b.get("REF NODE"))
            .ok_or_else(|| self.src.err(b.line, "*RIGID BODY needs REF NODE="))?;
        let at_centre = match b.get("POSITION").map(|p| p.to_ascii_uppercase()) {
            None => false,
            Some(p) if crate::mesh::abaqus::word(&p) == "CENTEROFMASS" => true,
            Some(p) => {
                return Err(self.src.err(b.line, format!("*RIGID BODY, POSITION={p}: impact reads CENTER OF MASS, or the reference node where the deck puts it")))
            }
        };
        if let Some(d) = g.rigid.iter().find(|d| d.elset.eq_ignore_ascii_case(elset)) {
            let first = self.src.line(d.line);
            return Err(self.src.err(
                b.line,
                format!("*RIGID BODY, ELSET={elset} is given twice (first on line {first})"),
            ));
        }
        g.rigid.push(RigidDecl {
            elset: elset.to_string(),
            ref_node: ref_node.to_string(),
            rot_node: b.get("ROT NODE").map(str::to_string),
            at_centre,
            line: b.line,
        });
        Ok(())
    }

    /// The deck's rigid bodies, their mass properties from their elements and their motion
    /// from the lines on their reference nodes.
    pub(super) fn rigid_bodies(&self, g: &Gathered, deck: &DeckNodes) -> Result<Rigids> {
        let mut out = Rigids {
            bodies: Vec::new(),
            nodes: Vec::new(),
        };
        for d in &g.rigid {
            let node = |set: &str| {
                deck.one(set).ok_or_else(|| {
                    self.src.err(
                        d.line,
                        format!("*RIGID BODY: `{set}` is not a node number or a set of one node"),
                    )
                })
            };
            let r = node(&d.ref_node)?;
            let o = d.rot_node.as_deref().map(node).transpose()?;
            let at = deck.position(r).ok_or_else(|| {
                self.src
                    .err(d.line, format!("*RIGID BODY: REF NODE {r} is not a *NODE"))
            })?;
            let (parts, density) = self.rigid_elements(g, d)?;
            let dofs = self.ref_dofs(g, deck, (r, o));
            let rigid = self.rigid_body(d, (&parts, density), &dofs, at)?;
            out.bodies.push((rigid, parts));
            out.nodes.push((r, o));
        }
        Ok(out)
    }

    /// The elements of a rigid body and their section's density.
    fn rigid_elements(&self, g: &Gathered, d: &RigidDecl) -> Result<(BodyParts, f64)> {
        let section = (g.sections.iter()).find(|(e, _, _)| e.eq_ignore_ascii_case(&d.elset));
        let Some((elset, material, _)) = section else {
            return Err(self.src.err(d.line, format!("*RIGID BODY, ELSET={}: the set has no *SOLID SECTION, so no density; impact takes a rigid body's mass from its elements", d.elset)));
        };
        let density = (g.materials.iter())
            .find(|m| m.name.eq_ignore_ascii_case(material))
            .and_then(|m| m.density);
        let Some(density) = density else {
            return Err(self.src.err(d.line, format!("*RIGID BODY, ELSET={}: material `{material}` has no *DENSITY; impact takes a rigid body's mass from its elements", d.elset)));
        };
        let (parts, _) = crate::mesh::import(self.src.path, 1.0, [0.0; 3], Some(elset))?;
        Ok((parts, density))
    }

    /// What the `*BOUNDARY` and `*INITIAL CONDITIONS` lines give the reference node `r`
    /// and the rotation node `o`.
    fn ref_dofs(&self, g: &Gathered, deck: &DeckNodes, (r, o): (u64, Option<u64>)) -> RefDofs {
        let mut out = RefDofs::default();
        // the dofs of the rigid body that dof `k` of the nodes of `set` are: 0-2
        // translations, 3-5 rotations (a set may hold both nodes)
        let dofs = |set: &str, k: usize| -> Vec<usize> {
            let on_ref = deck.holds(set, r).then_some(k - 1);
            let on_rot = (k <= 3 && o.is_some_and(|o| deck.holds(set, o))).then_some(k + 2);
            on_ref.into_iter().chain(on_rot).collect()
        };
        for b in &g.boundaries {
            for &k in &b.dofs {
                for i in dofs(&b.set, k) {
                    out.held[i] = Some(b.line);
                }
            }
        }
        for (set, k, value, line) in &g.velocities {
            for i in dofs(set, *k) {
                out.velocity[i] = *value;
                out.velocity_line = Some(*line);
            }
        }
        out
    }

    /// The rigid body of `d` with its motion: held, free translating (its rotations held),
    /// or free turning about its centre of mass.
    fn rigid_body(
        &self,
        d: &RigidDecl,
        (parts, density): (&BodyParts, f64),
        dofs: &RefDofs,
        at: [f64; 3],
    ) -> Result<DeckRigid> {
        let rotations = &dofs.held[3..];
        let turns = match rotations.iter().flatten().count() {
            0 => true,
            3 => false,
            _ => {
                let line = rotations.iter().flatten().next().copied().unwrap_or(d.line);
                return Err(self.src.err(line, format!("*RIGID BODY, ELSET={}: some of its reference node's rotations are held; impact holds all of a rigid body's rotations or none", d.elset)));
            }
        };
        let mut rigid =
            DeckRigid::of_elements(d.elset.clone(), parts, density, turns).map_err(|e| {
                self.src
                    .err(d.line, format!("*RIGID BODY, ELSET={}: {e}", d.elset))
            })?;
        let held: Vec<&'static str> = (0..3)
            .filter(|&a| dofs.held[a].is_some())
            .map(|a| ["x", "y", "z"][a])
            .collect();
        let held_line = dofs.held[..3].iter().flatten().next().copied();
        // a node held away from the centre of mass of a body free to turn would be a pivot
        let size = parts
            .nodes
            .iter()
            .flatten()
            .fold(0.0f64, |m, x| m.max(x.abs()))
            .max(1.0);
        let off: f64 = (0..3)
            .map(|a| (at[a] - rigid.position[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        if turns && !held.is_empty() && !d.at_centre && off > 1e-9 * size {
            return Err(self.src.err(held_line.unwrap_or(d.line), format!("*RIGID BODY, ELSET={}: its reference node, {off:e} from its centre of mass, is held while the body may turn; impact turns a rigid body about its centre of mass: hold its rotations, or give POSITION=CENTER OF MASS", d.elset)));
        }
        let velocity: [f64; 3] = std::array::from_fn(|a| dofs.velocity[a]);
        let omega: [f64; 3] = std::array::from_fn(|a| dofs.velocity[3 + a]);
        let velocity_line = dofs.velocity_line.unwrap_or(d.line);
        match held.len() {
            3 if !turns => rigid.motion = "fixed",
            _ => rigid.held = held,
        }
        let centre = if d.at_centre { rigid.position } else { at };
        rigid
            .start(velocity, Some(Spin { omega, centre }))
            .map_err(|e| self.src.err(velocity_line, e))?;
        if let Some(a) = (0..3).find(|&a| dofs.held[a].is_some() && rigid.velocity[a] != 0.0) {
            return Err(self.src.err(velocity_line, format!("*RIGID BODY, ELSET={}: *INITIAL CONDITIONS move its centre along {}, which its reference node's *BOUNDARY holds", d.elset, ["x", "y", "z"][a])));
        }
        Ok(rigid)
    }
}
