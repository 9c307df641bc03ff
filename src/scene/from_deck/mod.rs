//! A scene from a solver's input deck (Abaqus/CalculiX `.inp`, LS-DYNA `.k`): the deck is read into a [`DeckScene`] (what a scene
//! file would say, the mesh kept in the deck) and written out as scene TOML, which the scene
//! reader then checks as any other. `impact run model.inp` runs that text; `impact convert`
//! writes it to a file, so that a deck and its scene give the same history.
//!
//! What the deck asks that `impact` cannot honour is refused, naming the keyword, the file
//! and the line; what it may safely pass over (output requests, solver controls, the deck's
//! contact penalty) is listed once in [`Converted::notice`].

mod abaqus;
mod lsdyna;

use std::fmt::Write;
use std::path::Path;

use crate::error::Result;

/// A material as the deck gives it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckMaterial {
    pub name: String,
    pub density: Option<f64>,
    pub elastic: Option<Elastic>,
}

/// A material's elastic constants.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Elastic {
    Isotropic {
        e: f64,
        nu: f64,
    },
    /// E1, E2, E3, nu12, nu13, nu23, G12, G13, G23.
    Orthotropic([f64; 9]),
}

/// Which of the deck's elements make a body.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Select {
    /// An Abaqus/CalculiX element set (a section's).
    Elset(String),
    /// An LS-DYNA part id.
    Part(u64),
}

/// A body: a section's element set, or a part, of the deck.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckBody {
    pub name: String,
    pub material: String,
    pub velocity: [f64; 3],
    pub select: Select,
}

/// A rigid plane (an LS-DYNA planar rigid wall).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckPlane {
    pub name: String,
    pub point: [f64; 3],
    pub normal: [f64; 3],
    pub friction: f64,
    /// The bodies it stops (every body where `None`).
    pub bodies: Option<Vec<String>>,
}

/// Held components of a node set of a body.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckFix {
    pub body: String,
    pub set: String,
    pub components: Vec<&'static str>,
}

/// A contact's primary side: a body's surface, or a rigid body.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PrimarySide {
    Surface(String, String),
    Rigid(String),
}

/// A rigid body made of a deck's rigid part: its mass, velocity and motion (`"free"` or
/// `"fixed"`, translating), its surface a set of the deck, in the deck's coordinates.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckRigid {
    pub name: String,
    pub mass: f64,
    pub velocity: [f64; 3],
    pub motion: &'static str,
    pub surface: String,
}

/// A contact pair: the secondary (slave) and primary (master) surfaces and their bodies.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckContact {
    pub name: String,
    pub secondary: (String, String),
    pub primary: PrimarySide,
    pub friction: f64,
}

/// A probe: a node of a printed node set, at its position.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckProbe {
    pub name: String,
    pub body: String,
    pub point: [f64; 3],
}

/// The step: its method, period and (implicit) time step.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckStep {
    pub explicit: bool,
    pub end_time: f64,
    pub time_step: Option<f64>,
}

/// Everything a scene file would say, read from a deck.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckScene {
    pub title: Option<String>,
    /// The deck's file name, as the bodies' `mesh` (the scene sits beside it).
    pub mesh: String,
    pub gravity: Option<[f64; 3]>,
    pub materials: Vec<DeckMaterial>,
    pub bodies: Vec<DeckBody>,
    pub fixes: Vec<DeckFix>,
    pub contacts: Vec<DeckContact>,
    pub probes: Vec<DeckProbe>,
    pub planes: Vec<DeckPlane>,
    pub rigid: Vec<DeckRigid>,
    pub step: DeckStep,
}

/// A deck's scene as TOML text, and the notice of what it passed over.
#[derive(Debug, Clone)]
pub struct Converted {
    pub toml: String,
    pub notice: Option<String>,
}

/// The deck formats by file extension: Abaqus/CalculiX, then LS-DYNA.
const ABAQUS: [&str; 1] = ["inp"];
const LSDYNA: [&str; 3] = ["k", "key", "dyn"];

fn extension(path: &Path) -> String {
    (path.extension())
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// Whether `path` is a deck (`.inp`, `.k`) rather than a scene file.
pub fn is_deck(path: &Path) -> bool {
    let e = extension(path);
    ABAQUS.contains(&e.as_str()) || LSDYNA.contains(&e.as_str())
}

/// Reads the deck at `path` as a scene.
pub fn convert(path: &Path) -> Result<Converted> {
    let (scene, notice) = match LSDYNA.contains(&extension(path).as_str()) {
        true => lsdyna::read_scene(path)?,
        false => abaqus::read_scene(path)?,
    };
    Ok(Converted {
        toml: scene.to_toml(),
        notice,
    })
}

/// A body holding nodes of a node set: the set's name as the mesh has it, how many of the
/// body's nodes it holds, and the body's count.
pub(crate) struct Holder<'b> {
    pub body: &'b DeckBody,
    pub set: String,
    pub count: usize,
    pub total: usize,
}

/// The bodies holding nodes of the node set named `set` (in any case).
pub(crate) fn holders<'b>(
    bodies: &'b [(DeckBody, crate::mesh::BodyParts)],
    set: &str,
) -> Vec<Holder<'b>> {
    (bodies.iter())
        .filter_map(|(b, p)| {
            let s = (p.node_sets.iter()).find(|s| s.name.eq_ignore_ascii_case(set))?;
            (!s.nodes.is_empty()).then_some(Holder {
                body: b,
                set: s.name.clone(),
                count: s.nodes.len(),
                total: p.nodes.len(),
            })
        })
        .collect()
}

/// A fix of `components` on the node set of each body that `holders` names.
pub(crate) fn fixes_of<'a>(
    holders: Vec<Holder<'a>>,
    components: &'a [&'static str],
) -> impl Iterator<Item = DeckFix> + 'a {
    holders.into_iter().map(move |h| DeckFix {
        body: h.body.name.clone(),
        set: h.set,
        components: components.to_vec(),
    })
}

/// A TOML string (quoted, escaped).
fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// A TOML float.
fn float(x: f64) -> String {
    format!("{x:?}")
}

fn vector(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", float(v[0]), float(v[1]), float(v[2]))
}

impl DeckScene {
    /// The scene file's text.
    pub fn to_toml(&self) -> String {
        let mut t = String::new();
        let title = self.title.as_deref().unwrap_or("a deck's model");
        let _ = writeln!(
            t,
            "# read from the deck {}\ntitle = {}",
            self.mesh,
            quoted(title)
        );
        if let Some(g) = self.gravity {
            let _ = writeln!(t, "gravity = {}", vector(g));
        }
        self.write_run(&mut t);
        for m in &self.materials {
            let _ = writeln!(t, "\n[[material]]\nname = {}", quoted(&m.name));
            if let Some(rho) = m.density {
                let _ = writeln!(t, "density = {}", float(rho));
            }
            match &m.elastic {
                Some(Elastic::Isotropic { e, nu }) => {
                    let _ = writeln!(
                        t,
                        "youngs_modulus = {}\npoissons_ratio = {}",
                        float(*e),
                        float(*nu)
                    );
                }
                Some(Elastic::Orthotropic(c)) => {
                    let keys = [
                        "e1", "e2", "e3", "nu12", "nu13", "nu23", "g12", "g13", "g23",
                    ];
                    let pairs: Vec<String> = (keys.iter().zip(c))
                        .map(|(k, v)| format!("{k} = {}", float(*v)))
                        .collect();
                    let _ = writeln!(t, "orthotropic = {{ {} }}", pairs.join(", "));
                }
                None => {}
            }
        }
        for b in &self.bodies {
            let select = match &b.select {
                Select::Elset(e) => format!("elset = {}", quoted(e)),
                Select::Part(p) => format!("part = {p}"),
            };
            let _ = writeln!(
                t,
                "\n[[body]]\nname = {}\nmaterial = {}\nmesh = {}\n{select}",
                quoted(&b.name),
                quoted(&b.material),
                quoted(&self.mesh),
            );
            if b.velocity != [0.0; 3] {
                let _ = writeln!(t, "velocity = {}", vector(b.velocity));
            }
        }
        self.write_pieces(&mut t);
        t
    }

    fn write_run(&self, t: &mut String) {
        let s = &self.step;
        let method = if s.explicit { "explicit" } else { "implicit" };
        let _ = writeln!(
            t,
            "\n[run]\nend_time = {}\nmethod = \"{method}\"",
            float(s.end_time)
        );
        if let Some(dt) = s.time_step {
            let _ = writeln!(t, "time_step = {}", float(dt));
        }
    }

    /// The contacts, the fixes and the probes.
    fn write_pieces(&self, t: &mut String) {
        for r in &self.rigid {
            let _ = writeln!(
                t,
                "\n[[rigid_body]]\nname = {}\nmass = {}\nposition = [0.0, 0.0, 0.0]\nvelocity = {}\nmotion = \"{}\"\nshape = {{ mesh = {}, surface = {} }}",
                quoted(&r.name),
                float(r.mass),
                vector(r.velocity),
                r.motion,
                quoted(&self.mesh),
                quoted(&r.surface)
            );
        }
        for c in &self.contacts {
            let primary = match &c.primary {
                PrimarySide::Surface(b, s) => {
                    format!("{{ body = {}, surface = {} }}", quoted(b), quoted(s))
                }
                PrimarySide::Rigid(r) => format!("{{ rigid_body = {} }}", quoted(r)),
            };
            let _ = writeln!(
                t,
                "\n[[contact]]\nname = {}\nsecondary = {{ body = {}, surface = {} }}\nprimary = {primary}\nfriction = {}",
                quoted(&c.name),
                quoted(&c.secondary.0),
                quoted(&c.secondary.1),
                float(c.friction)
            );
        }
        for f in &self.fixes {
            let components: Vec<String> = f.components.iter().map(|c| quoted(c)).collect();
            let _ = writeln!(
                t,
                "\n[[fix]]\nbody = {}\nset = {}\ncomponents = [{}]",
                quoted(&f.body),
                quoted(&f.set),
                components.join(", ")
            );
        }
        for p in &self.planes {
            let _ = writeln!(
                t,
                "\n[[rigid_plane]]\nname = {}\npoint = {}\nnormal = {}\nfriction = {}",
                quoted(&p.name),
                vector(p.point),
                vector(p.normal),
                float(p.friction)
            );
            if let Some(bodies) = &p.bodies {
                let names: Vec<String> = bodies.iter().map(|b| quoted(b)).collect();
                let _ = writeln!(t, "bodies = [{}]", names.join(", "));
            }
        }
        for p in &self.probes {
            let _ = writeln!(
                t,
                "\n[[probe]]\nname = {}\nbody = {}\npoint = {}",
                quoted(&p.name),
                quoted(&p.body),
                vector(p.point)
            );
        }
    }
}

/// Expanded line `line` of a deck as its notice names it: the line, or the included file
/// and its line.
fn deck_line(deck: &crate::mesh::deck::Deck, line: usize) -> String {
    match deck.origin(line) {
        (None, l) => format!("{l}"),
        (Some(f), l) => format!("{}:{l}", f.display()),
    }
}
