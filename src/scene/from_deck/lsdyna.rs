//! An LS-DYNA keyword file read as a scene. The mesh keywords (`*NODE`, `*ELEMENT_SOLID`,
//! `*SET_NODE_LIST`, `*SET_SEGMENT`) stay the mesh reader's ([`crate::mesh::lsdyna`]); this
//! reader takes `*TITLE`, `*PART` (each part a body), `*SECTION_SOLID`, `*MAT_ELASTIC`,
//! `*BOUNDARY_SPC_SET`, `*INITIAL_VELOCITY_GENERATION` (a part's) and `*INITIAL_VELOCITY`
//! (a node set's), the node-to-surface and surface-to-surface contacts on segment sets with
//! their static friction, `*RIGIDWALL_PLANAR`, `*CONTROL_TERMINATION` and
//! `*CONTROL_IMPLICIT_GENERAL`. Units are the deck's own.

use std::path::Path;

use super::{
    fixes_of, give_velocity, holders, DeckBody, DeckContact, DeckFile, DeckFix, DeckMaterial,
    DeckPlane, DeckRigid, DeckScene, DeckStep, DeckVelocity, Elastic, Holder, Origin, PrimarySide,
    Select, Spin,
};
use crate::error::Result;
use crate::mesh::deck::Dialect;
use crate::mesh::lsdyna::{card, keyword};
use crate::mesh::BodyParts;

/// Keywords the mesh reader takes.
const MESH: [&str; 7] = [
    "NODE",
    "ELEMENT_SOLID",
    "SET_NODE_LIST",
    "SET_NODE_LIST_TITLE",
    "SET_SEGMENT",
    "SET_SEGMENT_TITLE",
    "KEYWORD",
];

/// The contacts read (each on segment sets, with its static friction).
const CONTACTS: [&str; 4] = [
    "CONTACT_AUTOMATIC_SURFACE_TO_SURFACE",
    "CONTACT_AUTOMATIC_NODES_TO_SURFACE",
    "CONTACT_SURFACE_TO_SURFACE",
    "CONTACT_NODES_TO_SURFACE",
];

/// A keyword and its data cards (comment cards left out, blank cards kept: LS-DYNA reads a
/// blank card as one of defaults), with their lines.
struct Block {
    name: String,
    line: usize,
    cards: Vec<(String, usize)>,
}

impl Block {
    /// The cards of a keyword that repeats its cards, without the blank ones at its end.
    fn repeated(&self) -> &[(String, usize)] {
        let n = (self.cards.iter())
            .rposition(|(t, _)| !t.trim().is_empty())
            .map_or(0, |i| i + 1);
        &self.cards[..n]
    }
}

/// The file's keywords up to `*END` (the cards after it are not read), or the line of a
/// card that is not in a keyword's block and what is wrong with it.
fn blocks(text: &str) -> std::result::Result<Vec<Block>, (usize, String)> {
    let mut out: Vec<Block> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        if raw.starts_with('$') {
            continue;
        }
        if raw.starts_with('*') {
            let name = keyword(raw);
            if name == "END" {
                break;
            }
            out.push(Block {
                name,
                line: i + 1,
                cards: Vec::new(),
            });
        } else if raw.trim_start().starts_with('*') {
            return Err((i + 1, crate::mesh::lsdyna::misplaced_keyword(raw)));
        } else if let Some(b) = out.last_mut() {
            b.cards.push((raw.to_string(), i + 1));
        } else if !raw.trim().is_empty() {
            return Err((
                i + 1,
                format!("`{}`: a data card before the first keyword", raw.trim()),
            ));
        }
    }
    Ok(out)
}

/// A planar rigid wall: the node set it stops (0: every node), its point (the tail),
/// normal (tail to head), friction and line.
struct Wall {
    nsid: u64,
    point: [f64; 3],
    normal: [f64; 3],
    friction: f64,
    line: usize,
}

/// An elastic material: its id, density, constants and axes (`*MAT_ORTHOTROPIC_ELASTIC`'s,
/// as the scene's `orientation = { axes = [a, d] }`).
struct ElasticMaterial {
    mid: u64,
    ro: f64,
    elastic: Elastic,
    axes: Option<[[f64; 3]; 2]>,
    line: usize,
}

/// A `*MAT_RIGID`: its id, density, and its constraints (CMO, CON1, CON2), with the line of
/// the constraints' card.
struct RigidMaterial {
    mid: u64,
    ro: f64,
    constraints: [f64; 3],
    line: usize,
    /// The line of its first card (its id).
    id_line: usize,
}

/// What the reader gathers before the bodies are known.
#[derive(Default)]
struct Gathered {
    title: Option<String>,
    /// (part id, title, section id, material id, line).
    parts: Vec<(u64, String, u64, u64, usize)>,
    sections: Vec<u64>,
    /// (material id, density, E, nu).
    materials: Vec<ElasticMaterial>,
    rigid_materials: Vec<RigidMaterial>,
    /// (node set, components, line).
    spcs: Vec<(String, Vec<&'static str>, usize)>,
    /// (part id, velocity, spin, line).
    part_velocities: Vec<(u64, [f64; 3], Option<Spin>, usize)>,
    /// (node set, velocity, line).
    set_velocities: Vec<(String, [f64; 3], usize)>,
    /// (secondary segment set, primary segment set, friction, line).
    contacts: Vec<(String, String, f64, usize)>,
    walls: Vec<Wall>,
    end_time: Option<f64>,
    implicit_step: Option<f64>,
    passed: Vec<(String, usize)>,
}

struct Reader<'a> {
    src: DeckFile<'a>,
}

impl Reader<'_> {
    /// Field `i` of a card as a number ([`crate::mesh::lsdyna::real`]).
    fn real(&self, f: &[String], i: usize, line: usize, what: &str) -> Result<f64> {
        crate::mesh::lsdyna::real(f, i, line, what).map_err(|e| self.src.err(line, e.message))
    }

    fn id(&self, f: &[String], i: usize, line: usize, what: &str) -> Result<u64> {
        let x = self.real(f, i, line, what)?;
        if x < 0.0 || x.fract() != 0.0 {
            return Err(self.src.err(line, format!("{what}: `{x}` is not an id")));
        }
        Ok(x as u64)
    }

    /// Card `k` of `b` in 10-column fields, refused when missing.
    fn card(&self, b: &Block, k: usize) -> Result<(Vec<String>, usize)> {
        let (text, line) = b.cards.get(k).ok_or_else(|| {
            self.src.err(
                b.line,
                format!("*{} needs card {} of its data", b.name, k + 1),
            )
        })?;
        Ok((card(text, &[10]), *line))
    }

    fn take(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let name = b.name.as_str();
        match name {
            n if MESH.contains(&n) || n == "END" => {}
            "TITLE" => g.title = b.cards.first().map(|(t, _)| t.trim().to_string()),
            "PART" => {
                for pair in b.repeated().chunks(2) {
                    let title = pair[0].0.trim().to_string();
                    let (text, l) = pair.get(1).ok_or_else(|| {
                        self.src.err(b.line, "*PART: a title card, then pid, secid, mid")
                    })?;
                    let f = card(text, &[10]);
                    let ids = [0, 1, 2].map(|i| self.id(&f, i, *l, "*PART id"));
                    let [pid, sec, mid] = ids;
                    g.parts.push((pid?, title, sec?, mid?, *l));
                }
            }
            "SECTION_SOLID" => {
                let (f, l) = self.card(b, 0)?;
                g.sections.push(self.id(&f, 0, l, "*SECTION_SOLID secid")?);
                g.passed.push(("SECTION_SOLID ELFORM (impact's hex8 and tet4)".into(), l));
            }
            "MAT_ELASTIC" | "MAT_001" => {
                let (f, l) = self.card(b, 0)?;
                let v = [1, 2, 3].map(|i| self.real(&f, i, l, "*MAT_ELASTIC"));
                let [ro, e, pr] = v;
                let elastic = Elastic::Isotropic { e: e?, nu: pr? };
                g.materials.push(ElasticMaterial {
                    mid: self.id(&f, 0, l, "*MAT_ELASTIC mid")?,
                    ro: ro?,
                    elastic,
                    axes: None,
                    line: l,
                });
            }
            "MAT_ORTHOTROPIC_ELASTIC" | "MAT_002" => self.orthotropic(b, g)?,
            "MAT_RIGID" | "MAT_020" => {
                let (f, l) = self.card(b, 0)?;
                // without its second card a rigid part is unconstrained (CMO = 0)
                let (c, l2) = match b.repeated().len() {
                    1 => (Vec::new(), l),
                    _ => self.card(b, 1)?,
                };
                let k = [0, 1, 2].map(|i| self.real(&c, i, l2, "*MAT_RIGID constraint"));
                let [cmo, con1, con2] = k;
                g.rigid_materials.push(RigidMaterial {
                    mid: self.id(&f, 0, l, "*MAT_RIGID mid")?,
                    ro: self.real(&f, 1, l, "*MAT_RIGID ro")?,
                    constraints: [cmo?, con1?, con2?],
                    line: l2,
                    id_line: l,
                });
            }
            "BOUNDARY_SPC_SET" => self.spc(b, g)?,
            "INITIAL_VELOCITY_GENERATION" => self.velocity_generation(b, g)?,
            "INITIAL_VELOCITY" => self.initial_velocity(b, g)?,
            n if CONTACTS.contains(&n) => self.contact(b, g)?,
            "RIGIDWALL_PLANAR" => self.wall(b, g)?,
            "CONTROL_TERMINATION" => {
                let (f, l) = self.card(b, 0)?;
                g.end_time = Some(self.real(&f, 0, l, "*CONTROL_TERMINATION endtim")?);
            }
            "CONTROL_IMPLICIT_GENERAL" => {
                let (f, l) = self.card(b, 0)?;
                match self.real(&f, 0, l, "imflag")? {
                    0.0 => {}
                    1.0 => {
                        let dt0 = self.real(&f, 1, l, "*CONTROL_IMPLICIT_GENERAL dt0")?;
                        g.implicit_step = Some(dt0);
                    }
                    x => return Err(self.src.err(l, format!("*CONTROL_IMPLICIT_GENERAL IMFLAG {x}: impact reads 0 (explicit) and 1 (implicit); an explicit run followed by an implicit step, or a switching curve, is not one method"))),
                }
            }
            n if n.starts_with("DATABASE_") || n.starts_with("CONTROL_") || n == "HOURGLASS" => {
                g.passed.push((n.to_string(), b.line))
            }
            n => {
                return Err(self.src.err(
                    b.line,
                    format!("*{n}: impact cannot honour this keyword (it reads elastic solid parts, their supports, initial velocities, node-to-surface contacts with friction, planar rigid walls and the run's end; docs/decks.md lists them)"),
                ))
            }
        }
        Ok(())
    }

    /// Ids given twice (a part, a material) and elements of parts no `*PART` defines.
    fn check_blocks(&self, blocks: &[Block], g: &Gathered) -> Result<()> {
        for (k, (pid, _, _, _, line)) in g.parts.iter().enumerate() {
            if let Some(first) = g.parts[..k].iter().find(|p| p.0 == *pid) {
                let first = self.src.line(first.4);
                return Err(self.src.err(
                    *line,
                    format!("*PART {pid} is defined twice (first on line {first})"),
                ));
            }
        }
        let mids = (g.materials.iter().map(|m| (m.mid, m.line)))
            .chain(g.rigid_materials.iter().map(|m| (m.mid, m.id_line)));
        let mut seen: Vec<(u64, usize)> = Vec::new();
        for (mid, line) in mids {
            if let Some((_, first)) = seen.iter().find(|(m, _)| *m == mid) {
                let first = self.src.line(*first);
                return Err(self.src.err(
                    line,
                    format!("material {mid} is defined twice (first on line {first}): a material id names one *MAT card"),
                ));
            }
            seen.push((mid, line));
        }
        let solids = blocks.iter().filter(|b| b.name == "ELEMENT_SOLID");
        for (text, line) in solids.flat_map(|b| b.cards.iter()) {
            let f = card(text, &[8]);
            let part = self.id(&f, 1, *line, "*ELEMENT_SOLID pid")?;
            if text.trim().is_empty() || g.parts.iter().any(|p| p.0 == part) {
                continue;
            }
            let eid = f.first().map_or("", String::as_str);
            return Err(self.src.err(
                *line,
                format!("element {eid}: no *PART {part} defines its part"),
            ));
        }
        Ok(())
    }

    fn spc(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        for k in 0..b.repeated().len() {
            let (f, l) = self.card(b, k)?;
            if self.id(&f, 1, l, "*BOUNDARY_SPC_SET cid")? != 0 {
                return Err(self.src.err(l, "*BOUNDARY_SPC_SET with a coordinate system (cid): impact holds global components"));
            }
            let mut components = Vec::new();
            for (a, c) in ["x", "y", "z"].into_iter().enumerate() {
                if self.real(&f, 2 + a, l, "*BOUNDARY_SPC_SET dof")? != 0.0 {
                    components.push(c);
                }
            }
            let set = self.id(&f, 0, l, "*BOUNDARY_SPC_SET nsid")?.to_string();
            g.spcs.push((set, components, l));
        }
        Ok(())
    }

    fn velocity_generation(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let (f, l) = self.card(b, 0)?;
        let styp = self.id(&f, 1, l, "styp")?;
        if styp != 2 {
            return Err(self.src.err(
                l,
                "*INITIAL_VELOCITY_GENERATION: impact reads STYP = 2 (a part)",
            ));
        }
        if self.id(&f, 7, l, "icid")? != 0 {
            return Err(self.src.err(l, "*INITIAL_VELOCITY_GENERATION with a coordinate system (icid): impact reads global components"));
        }
        let omega = self.real(&f, 2, l, "omega")?;
        let spin = match omega {
            0.0 => None,
            _ => Some(self.spin(b, omega)?),
        };
        let v = [3, 4, 5].map(|i| self.real(&f, i, l, "velocity"));
        let [x, y, z] = v;
        let pid = self.id(&f, 0, l, "part id")?;
        if let Some((.., first)) = g.part_velocities.iter().find(|p| p.0 == pid) {
            let first = self.src.line(*first);
            return Err(self.src.err(
                l,
                format!(
                    "the initial velocity of part {pid} is given twice (first on line {first})"
                ),
            ));
        }
        g.part_velocities.push((pid, [x?, y?, z?], spin, l));
        Ok(())
    }

    /// The turning of an `*INITIAL_VELOCITY_GENERATION` of rate `omega`: its second card's
    /// axis (XC, YC, ZC through NX, NY, NZ, normalised).
    fn spin(&self, b: &Block, omega: f64) -> Result<Spin> {
        let (c, l) = self.card(b, 1)?;
        let x = [0, 1, 2, 3, 4, 5].map(|i| self.real(&c, i, l, "rotation axis"));
        let [xc, yc, zc, nx, ny, nz] = x;
        let n = [nx?, ny?, nz?];
        let Some(n) = crate::material::rotation::unit(n) else {
            return Err(self.src.err(
                l,
                "*INITIAL_VELOCITY_GENERATION: the rotation axis (NX, NY, NZ) is zero",
            ));
        };
        Ok(Spin {
            omega: n.map(|a| omega * a),
            centre: [xc?, yc?, zc?],
        })
    }

    fn initial_velocity(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let (f, l) = self.card(b, 0)?;
        if self.id(&f, 1, l, "nsidex")? != 0 || self.id(&f, 2, l, "boxid")? != 0 {
            return Err(self.src.err(l, "*INITIAL_VELOCITY with an excluded set or a box: impact gives a body one initial velocity"));
        }
        let set = self.id(&f, 0, l, "nsid")?.to_string();
        let (v, l2) = self.card(b, 1)?;
        if (3..6).any(|i| self.real(&v, i, l2, "rotation").map_or(true, |x| x != 0.0)) {
            return Err(self.src.err(
                l2,
                "*INITIAL_VELOCITY with rotational velocities: impact's solids have none",
            ));
        }
        let w = [0, 1, 2].map(|i| self.real(&v, i, l2, "velocity"));
        let [x, y, z] = w;
        if let Some((.., first)) = g.set_velocities.iter().find(|s| s.0 == set) {
            let first = self.src.line(*first);
            return Err(self.src.err(
                l2,
                format!(
                    "the initial velocity of node set {set} is given twice (first on line {first})"
                ),
            ));
        }
        g.set_velocities.push((set, [x?, y?, z?], l2));
        Ok(())
    }

    fn contact(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let (f, l) = self.card(b, 0)?;
        let (sstyp, mstyp) = (self.id(&f, 2, l, "sstyp")?, self.id(&f, 3, l, "mstyp")?);
        if sstyp != 0 || mstyp != 0 {
            return Err(self.src.err(
                l,
                format!(
                    "*{}: impact reads segment sets on both sides (SSTYP = MSTYP = 0)",
                    b.name
                ),
            ));
        }
        let (c, l2) = self.card(b, 1)?;
        let (fs, fd) = (self.real(&c, 0, l2, "fs")?, self.real(&c, 1, l2, "fd")?);
        if fd != 0.0 && fd != fs {
            g.passed
                .push(("CONTACT FD (Coulomb friction at FS)".into(), l2));
        }
        if b.repeated().len() > 2 {
            g.passed
                .push((format!("{} card 3 (penalty scales)", b.name), b.cards[2].1));
        }
        let ids = [0, 1].map(|i| self.id(&f, i, l, "segment set id"));
        let [s, m] = ids;
        let (s, m) = (s?.to_string(), m?.to_string());
        if let Some((.., first)) = g.contacts.iter().find(|c| c.0 == s && c.1 == m) {
            let first = self.src.line(*first);
            return Err(self.src.err(
                l,
                format!(
                    "a contact of segment sets {s} and {m} is given twice (first on line {first})"
                ),
            ));
        }
        g.contacts.push((s, m, fs, l));
        Ok(())
    }

    fn wall(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let (f, l) = self.card(b, 0)?;
        if self.id(&f, 1, l, "nsidex")? != 0 || self.id(&f, 2, l, "boxid")? != 0 {
            return Err(self.src.err(l, "*RIGIDWALL_PLANAR with an excluded set or a box: impact's rigid plane stops whole bodies"));
        }
        let (c, l2) = self.card(b, 1)?;
        let v: Vec<f64> = (0..7)
            .map(|i| self.real(&c, i, l2, "*RIGIDWALL_PLANAR"))
            .collect::<Result<_>>()?;
        let (tail, head) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        let normal = std::array::from_fn(|a| head[a] - tail[a]);
        g.walls.push(Wall {
            nsid: self.id(&f, 0, l, "nsid")?,
            point: tail,
            normal,
            friction: v[6],
            line: l,
        });
        Ok(())
    }
}

/// A rigid body's name and the segment set its contacts name.
type RigidSurface = (String, String);

/// The rigid material of part `pid`, if its material is one.
fn rigid_part(g: &Gathered, pid: u64) -> Option<&RigidMaterial> {
    let (_, _, _, mid, _) = g.parts.iter().find(|p| p.0 == pid)?;
    g.rigid_materials.iter().find(|m| m.mid == *mid)
}

/// A part's body name: its title where that is a name (letters, digits, `_`, `-`) that no
/// earlier part took, else `part<id>`.
fn body_name(g: &Gathered, pid: u64) -> String {
    let mut taken: Vec<String> = Vec::new();
    for (p, title, ..) in &g.parts {
        let ok = !title.is_empty()
            && (title.chars()).all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            && !taken.iter().any(|t| t.eq_ignore_ascii_case(title));
        let base = if ok {
            title.clone()
        } else {
            format!("part{p}")
        };
        let name = super::fresh(base, &taken);
        if *p == pid {
            return name;
        }
        taken.push(name);
    }
    format!("part{pid}")
}

/// The keyword file at `path` as a scene, and the notice of what it passed over.
pub(super) fn read_scene(path: &Path) -> Result<(DeckScene, Option<String>)> {
    let r = Reader {
        src: DeckFile::read(path, Dialect::Keyword)?,
    };
    let mut g = Gathered::default();
    let blocks = blocks(&r.src.deck.text).map_err(|(line, e)| r.src.err(line, e))?;
    // every keyword's refusal at once, each at its line
    let refusals = (blocks.iter())
        .filter_map(|b| r.take(b, &mut g).err())
        .collect();
    if let Some(e) = super::together(refusals) {
        return Err(e);
    }
    r.check_blocks(&blocks, &g)?;
    let end_time = g.end_time.ok_or_else(|| {
        r.src
            .whole("no *CONTROL_TERMINATION: impact runs to its ENDTIM")
    })?;
    if g.parts.is_empty() {
        return Err(r
            .src
            .whole("no *PART: each part of solid elements is a body"));
    }
    let bodies = r.bodies(&g)?;
    let rigid = r.rigid_parts(&g)?;
    let (contacts, surfaces) = r.contacts(&g, &bodies, &rigid)?;
    let (moving, velocities) = r.velocities(&g, &bodies)?;
    let mut scene = DeckScene {
        title: g.title.clone(),
        mesh: path
            .file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned()),
        files: r.src.deck.files().to_vec(),
        gravity: None,
        materials: r.materials(&g),
        fixes: r.fixes(&g, &bodies)?,
        loads: Vec::new(),
        velocities,
        contacts,
        ties: Vec::new(),
        rigid: (rigid.iter())
            .filter_map(|(d, _)| {
                // a rigid part that no contact names has no surface to act through
                let surface = surfaces.iter().find(|(n, _)| *n == d.name)?.1.clone();
                Some(DeckRigid {
                    surface,
                    ..d.clone()
                })
            })
            .collect(),
        planes: r.walls(&g, &bodies)?,
        bodies: moving,
        probes: Vec::new(),
        equations: Vec::new(),
        later_steps: Vec::new(),
        step: DeckStep {
            explicit: g.implicit_step.is_none(),
            end_time,
            time_step: g.implicit_step,
            minimum_step: None,
        },
        origins: Vec::new(),
    };
    scene.materials_complete(&r.src)?;
    scene.origins = r.origins(&g, &scene);
    let untouched: Vec<String> = (rigid.iter())
        .filter(|(d, _)| !scene.rigid.iter().any(|r| r.name == d.name))
        .map(|(d, _)| d.name.clone())
        .collect();
    let mut notice = notice(&r, &g);
    if !untouched.is_empty() {
        let line = format!(
            "rigid parts that no contact names, left out: {}",
            untouched.join(", ")
        );
        notice = Some(match notice {
            Some(n) => format!("{n}; {line}"),
            None => format!("{}: {line}", path.display()),
        });
    }
    Ok((scene, notice))
}

impl Reader<'_> {
    /// The deck's lines of the scene's materials, bodies, contacts, planes and rigid bodies.
    fn origins(&self, g: &Gathered, scene: &DeckScene) -> Vec<Origin> {
        let mut out = scene.material_origins(&self.src);
        let part = |pid: u64| g.parts.iter().find(|p| p.0 == pid);
        for (i, b) in scene.bodies.iter().enumerate() {
            if let Select::Part(pid) = b.select {
                if let Some(p) = part(pid) {
                    out.push(
                        self.src
                            .origin(format!("body[{i}]"), p.4, format!("*PART {pid}")),
                    );
                }
            }
        }
        for (i, c) in g.contacts.iter().enumerate() {
            let what = format!("the contact of segment sets {} and {}", c.0, c.1);
            out.push(self.src.origin(format!("contact[{i}]"), c.3, what));
        }
        for (i, w) in g.walls.iter().enumerate() {
            let what = "*RIGIDWALL_PLANAR".to_string();
            out.push(self.src.origin(format!("rigid_plane[{i}]"), w.line, what));
        }
        for (i, r) in scene.rigid.iter().enumerate() {
            if let Some(p) = g.parts.iter().find(|p| body_name(g, p.0) == r.name) {
                let what = format!("*PART {} (rigid)", p.0);
                out.push(self.src.origin(format!("rigid_body[{i}]"), p.4, what));
            }
        }
        out
    }
}

fn notice(r: &Reader, g: &Gathered) -> Option<String> {
    let path = r.src.path;
    let mut parts: Vec<String> = g
        .passed
        .iter()
        .map(|(k, l)| format!("*{k} (line {})", r.src.line(*l)))
        .collect();
    if !g.contacts.is_empty() || !g.walls.is_empty() {
        parts.push("the contacts' penalty (the augmented Lagrange iteration on the gap rate enforces the contact)".into());
    }
    (!parts.is_empty()).then(|| format!("{}: passed over: {}", path.display(), parts.join("; ")))
}

impl Reader<'_> {
    fn materials(&self, g: &Gathered) -> Vec<DeckMaterial> {
        (g.materials.iter())
            .map(|m| DeckMaterial {
                name: format!("mat{}", m.mid),
                density: Some(m.ro),
                elastic: Some(m.elastic.clone()),
                line: m.line,
                what: format!("*MAT {}", m.mid),
            })
            .collect()
    }

    /// `*MAT_ORTHOTROPIC_ELASTIC` (002): EA, EB, EC, the minor Poisson's ratios and the
    /// shear moduli, with its axes given globally (AOPT 2: the vectors a and d).
    fn orthotropic(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let what = "*MAT_ORTHOTROPIC_ELASTIC";
        let (f, l) = self.card(b, 0)?;
        let mut c = [0.0; 7];
        for (i, x) in c.iter_mut().enumerate() {
            *x = self.real(&f, i + 1, l, what)?;
        }
        let [ro, ea, eb, ec, prba, prca, prcb] = c;
        let (f2, l2) = self.card(b, 1)?;
        let mut s = [0.0; 6];
        for (i, x) in s.iter_mut().enumerate() {
            *x = self.real(&f2, i, l2, what)?;
        }
        let [gab, gbc, gca, aopt, gdamp, sigf] = s;
        if aopt != 2.0 {
            return Err(self.src.err(l2, format!("{what} AOPT {aopt}: impact reads AOPT = 2, axes given by the vectors a and d (axes from the elements' nodes, a point or a coordinate system are not read)")));
        }
        if gdamp != 0.0 || sigf != 0.0 {
            return Err(self.src.err(l2, format!("{what}: G and SIGF (frequency-independent damping) are not read; impact's materials are elastic")));
        }
        let (f3, l3) = self.card(b, 2)?;
        let macf = self.real(&f3, 6, l3, what)?;
        if macf > 1.0 {
            return Err(self.src.err(
                l3,
                format!("{what} MACF {macf}: the axes are read as given (MACF 1)"),
            ));
        }
        let (f4, l4) = self.card(b, 3)?;
        let (mut a, mut d) = ([0.0; 3], [0.0; 3]);
        for k in 0..3 {
            a[k] = self.real(&f3, 3 + k, l3, what)?;
            d[k] = self.real(&f4, 3 + k, l4, what)?;
        }
        use crate::geometry::vector::{cross, norm};
        if norm(cross(a, d)) <= 1e-12 * norm(a) * norm(d) {
            return Err(self.src.err(
                l3,
                format!("{what}: the vectors a {a:?} and d {d:?} must not be parallel (or zero)"),
            ));
        }
        let elastic = Elastic::from_lsdyna([ea, eb, ec], [prba, prca, prcb], [gab, gbc, gca]);
        let mid = self.id(&f, 0, l, what)?;
        g.materials.push(ElasticMaterial {
            mid,
            ro,
            elastic,
            axes: Some([a, d]),
            line: l,
        });
        Ok(())
    }

    fn bodies(&self, g: &Gathered) -> Result<Vec<(DeckBody, BodyParts)>> {
        let mut out = Vec::new();
        for (pid, _, sec, mid, line) in &g.parts {
            if !g.sections.contains(sec) {
                return Err(self
                    .src
                    .err(*line, format!("part {pid}: no *SECTION_SOLID {sec}")));
            }
            if g.rigid_materials.iter().any(|m| m.mid == *mid) {
                continue;
            }
            if !g.materials.iter().any(|m| m.mid == *mid) {
                return Err(self.src.err(
                    *line,
                    format!("part {pid}: no *MAT_ELASTIC or *MAT_RIGID {mid} (impact reads elastic and rigid materials)"),
                ));
            }
            let part = pid.to_string();
            let (parts, _) = crate::mesh::import(self.src.path, 1.0, [0.0; 3], Some(&part))?;
            let axes = (g.materials.iter())
                .find(|m| m.mid == *mid)
                .and_then(|m| m.axes);
            let body = DeckBody {
                name: body_name(g, *pid),
                material: format!("mat{mid}"),
                velocity: [0.0; 3],
                select: Select::Part(*pid),
                piece: None,
                axes,
            };
            out.push((body, parts));
        }
        Ok(out)
    }

    fn held<'b>(
        &self,
        bodies: &'b [(DeckBody, BodyParts)],
        set: &str,
        line: usize,
    ) -> Result<Vec<Holder<'b>>> {
        let found = holders(bodies, set);
        match found.is_empty() {
            true => Err(self.src.err(
                line,
                format!("no part's elements hold the nodes of node set {set}"),
            )),
            false => Ok(found),
        }
    }

    fn fixes(&self, g: &Gathered, bodies: &[(DeckBody, BodyParts)]) -> Result<Vec<DeckFix>> {
        let mut out = Vec::new();
        for (set, components, line) in g.spcs.iter().filter(|s| !s.1.is_empty()) {
            out.extend(fixes_of(self.held(bodies, set, *line)?, components));
        }
        Ok(out)
    }

    /// The bodies with their initial velocities, and those of node sets that hold part of a
    /// body (and, after one, of its whole sets: the file's order holds), by component.
    fn velocities(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
    ) -> Result<(Vec<DeckBody>, Vec<DeckVelocity>)> {
        let mut out: Vec<DeckBody> = bodies.iter().map(|(b, _)| b.clone()).collect();
        let mut parts: Vec<DeckVelocity> = Vec::new();
        for (pid, v, spin, line) in &g.part_velocities {
            if rigid_part(g, *pid).is_some() {
                continue;
            }
            let b = (out.iter_mut())
                .find(|b| b.select == Select::Part(*pid))
                .ok_or_else(|| self.src.err(*line, format!("no *PART {pid}")))?;
            if spin.is_some() {
                return Err(self.src.err(*line, format!("*INITIAL_VELOCITY_GENERATION: part {pid} is not rigid; impact gives a deformable body one initial velocity, without a rotation")));
            }
            b.velocity = *v;
        }
        for (set, v, line) in &g.set_velocities {
            for h in &self.held(bodies, set, *line)? {
                for (a, &value) in v.iter().enumerate() {
                    give_velocity((&mut out, &mut parts), h, a, value);
                }
            }
        }
        Ok((out, parts))
    }

    /// The constraints of a `*MAT_RIGID` (CMO, CON1, CON2): whether the part turns, and the
    /// translations held. CMO = 0 leaves it free; CMO = 1 holds CON1's translations (0
    /// none, 1 x, 2 y, 3 z, 4 x and y, 5 y and z, 6 z and x, 7 all) and CON2's rotations (0
    /// none, 7 all).
    fn rigid_constraints(&self, m: &RigidMaterial) -> Result<(bool, Vec<&'static str>)> {
        const HELD: [&[&str]; 8] = [
            &[],
            &["x"],
            &["y"],
            &["z"],
            &["x", "y"],
            &["y", "z"],
            &["x", "z"],
            &["x", "y", "z"],
        ];
        let [cmo, con1, con2] = m.constraints;
        let code = |c: f64| (c.fract() == 0.0 && (0.0..=7.0).contains(&c)).then_some(c as usize);
        match (cmo, code(con1), code(con2)) {
            (0.0, _, _) => Ok((true, Vec::new())),
            (1.0, Some(t), Some(r @ (0 | 7))) => Ok((r == 0, HELD[t].to_vec())),
            _ => Err(self.src.err(m.line, "*MAT_RIGID: impact reads CMO = 0 (free), or CMO = 1 with CON1 = 0..7 (global translations held) and CON2 = 0 (free to turn) or 7 (rotations held)")),
        }
    }

    /// The rigid parts as rigid bodies (their surfaces still to come from the contacts),
    /// each with its mesh.
    fn rigid_parts(&self, g: &Gathered) -> Result<Vec<(DeckRigid, BodyParts)>> {
        let mut out = Vec::new();
        for (pid, _, _, _, line) in &g.parts {
            let Some(m) = rigid_part(g, *pid) else {
                continue;
            };
            let (turns, held) = self.rigid_constraints(m)?;
            let part = pid.to_string();
            let (parts, _) = crate::mesh::import(self.src.path, 1.0, [0.0; 3], Some(&part))?;
            let mut rigid = DeckRigid::of_elements(body_name(g, *pid), &parts, m.ro, turns)
                .map_err(|e| self.src.err(*line, format!("rigid part {pid}: {e}")))?;
            match held.len() {
                3 if !turns => rigid.motion = "fixed",
                _ => rigid.held = held,
            }
            if let Some((_, v, spin, l)) = g.part_velocities.iter().find(|v| v.0 == *pid) {
                if rigid.motion == "fixed" && (*v != [0.0; 3] || spin.is_some()) {
                    return Err(self.src.err(*l, format!("rigid part {pid} is held (CON1 = CON2 = 7): it takes no initial velocity")));
                }
                rigid.start(*v, *spin).map_err(|e| self.src.err(*l, e))?;
                let mut axes = ["x", "y", "z"].into_iter().zip(rigid.velocity);
                if let Some((c, _)) = axes.find(|(c, v)| *v != 0.0 && rigid.held.contains(c)) {
                    return Err(self.src.err(*l, format!("rigid part {pid}: its initial velocity moves its centre along {c}, which its *MAT_RIGID CON1 holds")));
                }
            }
            out.push((rigid, parts));
        }
        Ok(out)
    }

    /// The contacts, and the surface (segment set) each rigid body acts through.
    fn contacts(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        rigid: &[(DeckRigid, BodyParts)],
    ) -> Result<(Vec<DeckContact>, Vec<RigidSurface>)> {
        let on_rigid = |set: &str| {
            (rigid.iter())
                .find(|(_, p)| p.surfaces.iter().any(|s| s.name == set))
                .map(|(r, _)| r.name.clone())
        };
        let owner = |set: &str, line: usize| -> Result<(String, String)> {
            let mut found = (bodies.iter()).filter_map(|(b, p)| {
                (p.surfaces.iter())
                    .find(|s| s.name == set)
                    .map(|s| (b.name.clone(), s.name.clone()))
            });
            let first = found.next().ok_or_else(|| {
                self.src.err(line, format!("no one part's elements hold all of segment set {set} (a contact surface is one part's: are its segments defined, and all on one part?)"))
            })?;
            if found.next().is_some() {
                return Err(self.src.err(
                    line,
                    format!("segment set {set} lies on two parts: a contact surface is one body's"),
                ));
            }
            Ok(first)
        };
        let mut out = Vec::new();
        let mut surfaces: Vec<RigidSurface> = Vec::new();
        for (k, (s, m, fs, line)) in g.contacts.iter().enumerate() {
            if on_rigid(s).is_some() {
                return Err(self.src.err(*line, format!("segment set {s} lies on a rigid part: a rigid part is a contact's master side")));
            }
            let on_body =
                |set: &str| (bodies.iter()).any(|(_, p)| p.surfaces.iter().any(|s| s.name == set));
            if on_rigid(m).is_some() && on_body(m) {
                return Err(self.src.err(*line, format!("segment set {m} lies on a rigid part and on a deformable one: a contact surface is one part's")));
            }
            let primary = match on_rigid(m) {
                Some(name) => {
                    match surfaces.iter().find(|(n, _)| *n == name) {
                        Some((_, other)) if other != m => {
                            return Err(self.src.err(*line, format!("rigid part `{name}` meets its contacts through segment sets {other} and {m}: impact's rigid body has one surface")));
                        }
                        Some(_) => {}
                        None => surfaces.push((name.clone(), m.clone())),
                    }
                    PrimarySide::Rigid(name)
                }
                None => {
                    let (body, surface) = owner(m, *line)?;
                    PrimarySide::Surface(body, surface)
                }
            };
            out.push(DeckContact {
                name: format!("contact{}", k + 1),
                secondary: owner(s, *line)?,
                secondary_nodes: false,
                adjust: None,
                pressure_law: None,
                stick_slope: None,
                primary,
                friction: *fs,
            });
        }
        Ok((out, surfaces))
    }

    fn walls(&self, g: &Gathered, bodies: &[(DeckBody, BodyParts)]) -> Result<Vec<DeckPlane>> {
        let mut out = Vec::new();
        for (k, w) in g.walls.iter().enumerate() {
            let line = &w.line;
            let stops = match w.nsid {
                0 => None,
                s => {
                    let mut names = Vec::new();
                    for h in self.held(bodies, &s.to_string(), *line)? {
                        if h.count != h.total {
                            return Err(self.src.err(*line, format!("node set {s} holds {} of body `{}`'s {} nodes: impact's rigid plane stops whole bodies", h.count, h.body.name, h.total)));
                        }
                        names.push(h.body.name.clone());
                    }
                    Some(names)
                }
            };
            out.push(DeckPlane {
                name: format!("wall{}", k + 1),
                point: w.point,
                normal: w.normal,
                friction: w.friction,
                bodies: stops,
            });
        }
        Ok(out)
    }
}
