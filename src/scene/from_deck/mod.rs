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
use std::path::{Path, PathBuf};

use crate::error::{ImpactError, Result};
use crate::mesh::deck::{Deck, Dialect};

/// A material as the deck gives it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckMaterial {
    pub name: String,
    pub density: Option<f64>,
    pub elastic: Option<Elastic>,
    /// The deck's line that defines it, and what the deck calls it (`*MATERIAL, NAME=STEEL`).
    pub line: usize,
    pub what: String,
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

impl Elastic {
    /// The engineering constants of an orthotropic stiffness given as Abaqus orders it:
    /// D1111, D1122, D2222, D1133, D2233, D3333, D1212, D1313, D2323 (D1212 = G12 with the
    /// engineering shear strain). The normal block's inverse is the compliance S: E_i =
    /// 1 / S_ii, nu_ij = -S_ij E_i. Refused unless the stiffness is positive definite.
    pub(crate) fn from_stiffness(d: [f64; 9]) -> std::result::Result<Elastic, String> {
        let [d11, d12, d22, d13, d23, d33, g12, g13, g23] = d;
        let c = nalgebra::Matrix3::new(d11, d12, d13, d12, d22, d23, d13, d23, d33);
        let minors = [d11, d11 * d22 - d12 * d12, c.determinant()];
        // NaN is not positive either
        let positive = |x: &f64| *x > 0.0;
        if !minors.iter().chain(&[g12, g13, g23]).all(positive) {
            return Err(format!(
                "the stiffness (D1111 {d11}, D1122 {d12}, D2222 {d22}, D1133 {d13}, D2233 {d23}, D3333 {d33}, D1212 {g12}, D1313 {g13}, D2323 {g23}) is not positive definite"
            ));
        }
        let s = c
            .try_inverse()
            .ok_or("the stiffness's normal block is singular")?;
        let e = [1.0 / s[(0, 0)], 1.0 / s[(1, 1)], 1.0 / s[(2, 2)]];
        let nu12 = -s[(0, 1)] * e[0];
        let nu13 = -s[(0, 2)] * e[0];
        let nu23 = -s[(1, 2)] * e[1];
        Ok(Elastic::Orthotropic([
            e[0], e[1], e[2], nu12, nu13, nu23, g12, g13, g23,
        ]))
    }

    /// The engineering constants of LS-DYNA's `*MAT_ORTHOTROPIC_ELASTIC`: EA, EB, EC, its
    /// minor Poisson's ratios PRBA, PRCA, PRCB (nu_ba, the strain along a under a stress
    /// along b) and GAB, GBC, GCA; nu_ab = PRBA EA / EB.
    pub(crate) fn from_lsdyna(e: [f64; 3], pr: [f64; 3], g: [f64; 3]) -> Elastic {
        let [ea, eb, ec] = e;
        let [prba, prca, prcb] = pr;
        let [gab, gbc, gca] = g;
        Elastic::Orthotropic([
            ea,
            eb,
            ec,
            prba * ea / eb,
            prca * ea / ec,
            prcb * eb / ec,
            gab,
            gca,
            gbc,
        ])
    }
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
    /// The connected piece of the selected elements (1-based), where they make several.
    pub piece: Option<usize>,
    /// The material axes: axis 1 along the first vector, axis 2 the second's part normal
    /// to it (the scene's `orientation = { axes = [...] }`); the global axes where `None`.
    pub axes: Option<[[f64; 3]; 2]>,
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

/// Held components of a node set of a body (of a rigid body as a whole where `set` is
/// empty). A node number where a deck allows a set is the mesh's set of that one node.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckFix {
    pub body: String,
    pub set: String,
    pub components: Vec<&'static str>,
    /// The displacement the components are moved to, and its amplitude table (empty: a
    /// ramp over the run); `None` for a fix that holds them still.
    pub displacement: Option<crate::scene::Displacement>,
}

/// One component of the initial velocity of a node set that is part of a body (or of a whole
/// body's set after such a part's, so that the deck's order holds).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckVelocity {
    pub body: String,
    pub set: String,
    /// 0, 1 or 2.
    pub component: usize,
    pub value: f64,
}

/// What a deck's load acts on: a node set of a body (a force on each node), or a surface
/// (a pressure).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum LoadOn {
    Set(String),
    Surface(String),
}

/// A load of a deck on one body: a force on each node of a set or a pressure on a surface,
/// with its amplitude table (none: constant), and the line that gives it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckLoad {
    pub body: String,
    pub on: LoadOn,
    pub force: Option<[f64; 3]>,
    pub pressure: Option<f64>,
    pub amplitude: Vec<[f64; 2]>,
    pub line: usize,
}

/// A contact's primary side: a body's surface, or a rigid body.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PrimarySide {
    Surface(String, String),
    Rigid(String),
}

/// A rigid body made of a deck's rigid part: its mass and centre of mass (its `position`)
/// from its elements, its motion (`"free"` or `"fixed"`), the translations held where it is
/// free, its inertia about its centre where it turns, its velocity and angular velocity, its
/// surface a set of the deck, in the deck's coordinates.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckRigid {
    pub name: String,
    pub mass: f64,
    pub position: [f64; 3],
    pub velocity: [f64; 3],
    pub motion: &'static str,
    pub held: Vec<&'static str>,
    pub inertia: Option<[[f64; 3]; 3]>,
    pub angular_velocity: [f64; 3],
    pub surface: String,
}

/// A rigid part's initial turning: its angular velocity, about an axis through `centre`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Spin {
    pub omega: [f64; 3],
    pub centre: [f64; 3],
}

impl DeckRigid {
    /// The rigid body of the elements of `parts`, of density `density`, free (turning where
    /// `turns`): its mass, centre of mass and inertia from the elements. The error says why
    /// its mass is not positive.
    pub(crate) fn of_elements(
        name: String,
        parts: &crate::mesh::BodyParts,
        density: f64,
        turns: bool,
    ) -> std::result::Result<DeckRigid, String> {
        // the moments about the nodes' mean, where the inertia's S - m c c^T cancels little
        let count = parts.nodes.len().max(1) as f64;
        let o: [f64; 3] =
            std::array::from_fn(|a| parts.nodes.iter().map(|x| x[a]).sum::<f64>() / count);
        let m = (parts.elements.iter())
            .map(|e| {
                let x: Vec<[f64; 3]> = (e.nodes.iter())
                    .map(|&n| std::array::from_fn(|a| parts.nodes[n as usize][a] - o[a]))
                    .collect();
                crate::element::MassMoments::of_element(e.kind, &x, 1.0)
            })
            .fold(crate::element::MassMoments::default(), |a, b| a.plus(b));
        // the moments at unit density: the volume, and the density scales the rest
        let mass = density * m.mass;
        if mass.is_nan() || mass <= 0.0 {
            return Err(format!(
                "its mass, density x volume = {density} x {}, must be positive",
                m.mass
            ));
        }
        Ok(DeckRigid {
            name,
            mass,
            position: std::array::from_fn(|a| o[a] + m.centre()[a]),
            velocity: [0.0; 3],
            motion: "free",
            held: Vec::new(),
            inertia: turns.then(|| m.inertia().map(|row| row.map(|i| density * i))),
            angular_velocity: [0.0; 3],
            surface: String::new(),
        })
    }

    /// Sets its initial motion: `v` at the point `at` and the `spin` (or none), as its
    /// centre's velocity $v + \omega \times (c - a)$ and its angular velocity. The error
    /// says why it cannot take the spin.
    pub(crate) fn start(
        &mut self,
        v: [f64; 3],
        spin: Option<Spin>,
    ) -> std::result::Result<(), String> {
        self.velocity = v;
        let Some(Spin { omega, centre }) = spin.filter(|s| s.omega != [0.0; 3]) else {
            return Ok(());
        };
        if self.inertia.is_none() {
            return Err(format!(
                "rigid body `{}` has its rotations held: it cannot start turning",
                self.name
            ));
        }
        let r: [f64; 3] = std::array::from_fn(|a| self.position[a] - centre[a]);
        let turn = crate::geometry::vector::cross(omega, r);
        self.velocity = std::array::from_fn(|a| v[a] + turn[a]);
        self.angular_velocity = omega;
        Ok(())
    }
}

/// A contact pair: the secondary (slave) and primary (master) surfaces and their bodies.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckContact {
    pub name: String,
    pub secondary: (String, String),
    /// The secondary side is a node-based surface: the body's node set of that name.
    pub secondary_nodes: bool,
    pub primary: PrimarySide,
    pub friction: f64,
    /// Abaqus's `ADJUST=`: the slave nodes within it (in front, or behind) are moved onto
    /// the master surface before t = 0.
    pub adjust: Option<f64>,
    /// A linear or exponential pressure-overclosure (static steps).
    pub pressure_law: Option<crate::scene::PressureLaw>,
    /// A static step's friction stick slope (`*FRICTION`'s second value).
    pub stick_slope: Option<f64>,
}

/// A tie: the secondary (slave) side, a body's surface or node set, bonded to the primary
/// (master) body's surface.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckTie {
    pub name: String,
    pub secondary: (String, String),
    /// The secondary side is a node-based surface: the body's node set of that name.
    pub secondary_nodes: bool,
    pub primary: (String, String),
    /// `POSITION TOLERANCE=` (`None`: the scene's default).
    pub tolerance: Option<f64>,
    pub adjust: bool,
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
    /// A static step's smallest increment (`None`: a dynamic step).
    pub minimum_step: Option<f64>,
}

/// A step after the first: where it starts, and `None` (no equation removed), all of
/// them (an empty list), or the dependent dofs (body, node set, dof 0-2) whose end.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckLaterStep {
    pub start: f64,
    /// The step's method where its procedure is not the first step's, and its increment
    /// (an explicit step's none: the stable step).
    pub method: Option<&'static str>,
    pub time_step: Option<f64>,
    /// Its end: its start and period.
    pub end: f64,
    pub remove: Option<Vec<(String, String, usize)>>,
    /// `*BOUNDARY, OP=NEW`: the fixes before the step end at its start.
    pub release_fixes: bool,
    /// The step's `*BOUNDARY` lines, each ramped over the step.
    pub fixes: Vec<DeckFix>,
    /// `*CHANGE FRICTION`: (contact, coefficient, stick slope).
    pub friction: Vec<(String, f64, Option<f64>)>,
}

/// One term of an `*EQUATION`: body, node set, dof 0-2, coefficient.
pub(crate) type DeckTerm = (String, String, usize, f64);

/// Everything a scene file would say, read from a deck.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DeckScene {
    pub title: Option<String>,
    /// The deck's file name, as the bodies' `mesh` (the scene sits beside it).
    pub mesh: String,
    /// The deck's own file and every file it includes.
    pub files: Vec<PathBuf>,
    pub gravity: Option<[f64; 3]>,
    pub materials: Vec<DeckMaterial>,
    pub bodies: Vec<DeckBody>,
    pub fixes: Vec<DeckFix>,
    /// Initial velocities of parts of bodies, after the bodies' own.
    pub velocities: Vec<DeckVelocity>,
    pub loads: Vec<DeckLoad>,
    pub contacts: Vec<DeckContact>,
    pub ties: Vec<DeckTie>,
    pub probes: Vec<DeckProbe>,
    pub planes: Vec<DeckPlane>,
    pub rigid: Vec<DeckRigid>,
    /// `*EQUATION`s: each term's body, node set (`node N` for a node number), dof 0-2 and
    /// coefficient.
    pub equations: Vec<Vec<DeckTerm>>,
    pub step: DeckStep,
    /// The steps after the first: each one's start and the equations it removes.
    pub later_steps: Vec<DeckLaterStep>,
    /// Where each piece came from, for the scene checker's messages.
    pub origins: Vec<Origin>,
}

/// Where a piece of a deck's scene comes from: its scene key (`material[0]`), the file and
/// line that give it, and what the deck calls it (`*MAT_ELASTIC 1`).
#[derive(Debug, Clone, PartialEq)]
pub struct Origin {
    pub key: String,
    pub path: PathBuf,
    pub line: usize,
    pub what: String,
}

/// `base`, or `base_2`, `base_3`, ... where `base` is taken: a name the reader makes never
/// takes one the deck gives.
pub(crate) fn fresh(base: String, taken: &[String]) -> String {
    let free = |n: &String| !taken.iter().any(|t| t.eq_ignore_ascii_case(n));
    if free(&base) {
        return base;
    }
    (2..)
        .map(|k| format!("{base}_{k}"))
        .find(free)
        .expect("a free name")
}

impl DeckScene {
    /// The names the reader made (contacts, planes, probes) renamed where they take a body's,
    /// a rigid body's or an earlier one's.
    fn distinct_names(&mut self) {
        let mut taken: Vec<String> = (self.bodies.iter().map(|b| b.name.clone()))
            .chain(self.rigid.iter().map(|r| r.name.clone()))
            .collect();
        let made = (self.contacts.iter_mut().map(|c| &mut c.name))
            .chain(self.planes.iter_mut().map(|p| &mut p.name))
            .chain(self.probes.iter_mut().map(|p| &mut p.name));
        for name in made {
            *name = fresh(std::mem::take(name), &taken);
            taken.push(name.clone());
        }
    }

    /// The materials the scene writes: those a body uses (a material no body uses is the
    /// deck's business: it may lack what a body's needs).
    fn used_materials(&self) -> impl Iterator<Item = &DeckMaterial> + '_ {
        (self.materials.iter()).filter(|m| self.bodies.iter().any(|b| b.material == m.name))
    }

    /// The deck's line of each material the scene writes, by its scene key.
    fn material_origins(&self, src: &DeckFile) -> Vec<Origin> {
        (self.used_materials().enumerate())
            .map(|(i, m)| src.origin(format!("material[{i}]"), m.line, m.what.clone()))
            .collect()
    }

    /// Refuses a body's material without a density or elastic constants, at the deck's line.
    fn materials_complete(&self, src: &DeckFile) -> Result<()> {
        let statics = self.step.minimum_step.is_some();
        for m in self.used_materials() {
            if m.density.is_none() && !statics {
                return Err(src.err(
                    m.line,
                    format!(
                        "{}: no *DENSITY (a body's material needs its density)",
                        m.what
                    ),
                ));
            }
            if m.elastic.is_none() {
                return Err(src.err(
                    m.line,
                    format!(
                        "{}: no *ELASTIC (a body's material needs its elastic constants)",
                        m.what
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A deck's scene as TOML text, and the notice of what it passed over.
#[derive(Debug, Clone)]
pub struct Converted {
    pub toml: String,
    pub notice: Option<String>,
    /// The deck's own file and every file it includes (a scene must not be written onto
    /// any of them).
    pub files: Vec<PathBuf>,
    /// Where each piece of the scene came from.
    pub origins: Vec<Origin>,
}

impl Converted {
    /// The scene checker's error on a key of this scene, told at the deck's line that gave
    /// the key's piece (`material[0].density` at the `*MATERIAL`).
    pub fn locate(&self, e: ImpactError) -> ImpactError {
        let (ImpactError::SceneValue { key, message, .. }
        | ImpactError::Unsupported { key, message, .. }) = &e
        else {
            return e;
        };
        let piece = |o: &&Origin| {
            key.strip_prefix(o.key.as_str())
                .is_some_and(|rest| rest.is_empty() || rest.starts_with('.'))
        };
        let Some(o) = self.origins.iter().find(piece) else {
            return e;
        };
        let field = key[o.key.len()..].trim_start_matches('.');
        let message = match field {
            "" => format!("{}: {message}", o.what),
            f => format!("{}, its {f}: {message}", o.what),
        };
        ImpactError::Mesh {
            path: o.path.clone(),
            line: Some(o.line),
            message,
        }
    }
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
    let (mut scene, notice) = match LSDYNA.contains(&extension(path).as_str()) {
        true => lsdyna::read_scene(path)?,
        false => abaqus::read_scene(path)?,
    };
    scene.distinct_names();
    Ok(Converted {
        toml: scene.to_toml(),
        notice,
        files: scene.files,
        origins: scene.origins,
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
        displacement: None,
    })
}

/// Gives component `a` of the initial velocity `value` to the nodes of holder `h`: a set that
/// holds the whole body sets the body's own, unless the body already has a part's (then, as
/// one that holds part of it, an entry of its own after the others, so the deck's order holds).
pub(crate) fn give_velocity(
    (bodies, parts): (&mut [DeckBody], &mut Vec<DeckVelocity>),
    h: &Holder,
    a: usize,
    value: f64,
) {
    let parted = parts.iter().any(|p| p.body == h.body.name);
    if h.count == h.total && !parted {
        if let Some(b) = bodies.iter_mut().find(|b| b.name == h.body.name) {
            b.velocity[a] = value;
        }
        return;
    }
    parts.push(DeckVelocity {
        body: h.body.name.clone(),
        set: h.set.clone(),
        component: a,
        value,
    });
}

/// A deck's refusals as one error: the first, with each of the others on a line of its own
/// (its file and line first, as the first's); `None` where there is none.
pub(crate) fn together(refusals: Vec<ImpactError>) -> Option<ImpactError> {
    let mut all = refusals.into_iter();
    let first = all.next()?;
    // an explanation in parentheses that an earlier line gave is not given again
    let mut given = vec![parenthesis(&first.to_string()).to_string()];
    let rest: Vec<String> = (all.map(|e| e.to_string()))
        .map(|m| {
            let p = parenthesis(&m).to_string();
            if !p.is_empty() && given.contains(&p) {
                return m[..m.len() - p.len()].trim_end().to_string();
            }
            given.push(p);
            m
        })
        .collect();
    if rest.is_empty() {
        return Some(first);
    }
    let count = rest.len() + 1;
    Some(match first {
        ImpactError::Mesh {
            path,
            line,
            message,
        } => ImpactError::Mesh {
            path,
            line,
            message: format!("{message}\n{}\n({count} refusals in all)", rest.join("\n")),
        },
        // a keyword's refusal is its deck line's (`DeckFile::err`): none is of another kind
        other => other,
    })
}

/// The parenthesis that ends `message` (with its opening blank), or nothing.
fn parenthesis(message: &str) -> &str {
    match (message.ends_with(')'), message.rfind(" (")) {
        (true, Some(at)) if !message[at + 2..].contains('(') => &message[at..],
        _ => "",
    }
}

/// A TOML string (quoted, escaped).
fn quoted(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// A TOML float.
fn float(x: f64) -> String {
    format!("{x:?}")
}

/// A fix as the table `[[table]]` (`fix`, or a step's `step.fix`).
fn write_fix(t: &mut String, table: &str, f: &DeckFix) {
    let components: Vec<String> = f.components.iter().map(|c| quoted(c)).collect();
    let _ = writeln!(t, "\n[[{table}]]\nbody = {}", quoted(&f.body));
    if !f.set.is_empty() {
        let _ = writeln!(t, "set = {}", quoted(&f.set));
    }
    let _ = writeln!(t, "components = [{}]", components.join(", "));
    if let Some((d, amplitude)) = &f.displacement {
        let _ = writeln!(t, "displacement = {}", vector(*d));
        write_amplitude(t, amplitude);
    }
}

/// `amplitude = [[t, a], ...]`, where the table has points.
fn write_amplitude(t: &mut String, amplitude: &[[f64; 2]]) {
    if !amplitude.is_empty() {
        let points: Vec<String> = (amplitude.iter())
            .map(|[a, b]| format!("[{}, {}]", float(*a), float(*b)))
            .collect();
        let _ = writeln!(t, "amplitude = [{}]", points.join(", "));
    }
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
        for m in self.used_materials() {
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
            if let Some(k) = b.piece {
                let _ = writeln!(t, "piece = {k}");
            }
            if b.velocity != [0.0; 3] {
                let _ = writeln!(t, "velocity = {}", vector(b.velocity));
            }
            if let Some([a, d]) = b.axes {
                let _ = writeln!(
                    t,
                    "orientation = {{ axes = [{}, {}] }}",
                    vector(a),
                    vector(d)
                );
            }
        }
        self.write_pieces(&mut t);
        t
    }

    fn write_run(&self, t: &mut String) {
        let s = &self.step;
        let method = match (s.explicit, s.minimum_step) {
            (true, _) => "explicit",
            (false, None) => "implicit",
            (false, Some(_)) => "static",
        };
        let _ = writeln!(
            t,
            "\n[run]\nend_time = {}\nmethod = \"{method}\"",
            float(s.end_time)
        );
        if let Some(dt) = s.time_step {
            let _ = writeln!(t, "time_step = {}", float(dt));
        }
        if let Some(m) = s.minimum_step {
            let _ = writeln!(t, "\n[static]\nminimum_step = {}", float(m));
        }
        for l in &self.later_steps {
            let _ = writeln!(
                t,
                "\n[[step]]\nstart = {}\nend = {}",
                float(l.start),
                float(l.end)
            );
            if let Some(m) = l.method {
                let _ = writeln!(t, "method = \"{m}\"");
            }
            if let Some(dt) = l.time_step {
                let _ = writeln!(t, "time_step = {}", float(dt));
            }
            match &l.remove {
                None => {}
                Some(dofs) if dofs.is_empty() => {
                    let _ = writeln!(t, "remove_equations = \"all\"");
                }
                Some(dofs) => {
                    let each: Vec<String> = (dofs.iter())
                        .map(|(b, set, c)| {
                            format!(
                                "{{ body = {}, set = {}, component = \"{}\" }}",
                                quoted(b),
                                quoted(set),
                                ["x", "y", "z"][*c]
                            )
                        })
                        .collect();
                    let _ = writeln!(t, "remove_equations = [{}]", each.join(", "));
                }
            }
            if l.release_fixes {
                let _ = writeln!(t, "release_fixes = \"all\"");
            }
            for f in &l.fixes {
                write_fix(t, "step.fix", f);
            }
            for (name, mu, slope) in &l.friction {
                let _ = writeln!(
                    t,
                    "\n[[step.contact]]\nname = {}\nfriction = {}",
                    quoted(name),
                    float(*mu)
                );
                if let Some(k) = slope {
                    let _ = writeln!(t, "stick_slope = {}", float(*k));
                }
            }
        }
    }

    /// The contacts, the fixes and the probes.
    fn write_equations(&self, t: &mut String) {
        for e in &self.equations {
            let terms: Vec<String> = (e.iter())
                .map(|(body, set, dof, c)| {
                    format!(
                        "{{ body = {}, set = {}, component = \"{}\", coefficient = {} }}",
                        quoted(body),
                        quoted(set),
                        ["x", "y", "z"][*dof],
                        float(*c)
                    )
                })
                .collect();
            let _ = writeln!(t, "\n[[equation]]\nterms = [{}]", terms.join(", "));
        }
    }

    fn write_pieces(&self, t: &mut String) {
        self.write_equations(t);
        for r in &self.rigid {
            let _ = writeln!(
                t,
                "\n[[rigid_body]]\nname = {}\nmass = {}\nposition = {}\nvelocity = {}\nmotion = \"{}\"\nshape = {{ mesh = {}, surface = {}, origin = {} }}",
                quoted(&r.name),
                float(r.mass),
                vector(r.position),
                vector(r.velocity),
                r.motion,
                quoted(&self.mesh),
                quoted(&r.surface),
                vector(r.position),
            );
            if let Some(i) = r.inertia {
                let _ = writeln!(
                    t,
                    "inertia = [{}, {}, {}]",
                    vector(i[0]),
                    vector(i[1]),
                    vector(i[2])
                );
            }
            if r.angular_velocity != [0.0; 3] {
                let _ = writeln!(t, "angular_velocity = {}", vector(r.angular_velocity));
            }
        }
        for c in &self.contacts {
            let primary = match &c.primary {
                PrimarySide::Surface(b, s) => {
                    format!("{{ body = {}, surface = {} }}", quoted(b), quoted(s))
                }
                PrimarySide::Rigid(r) => format!("{{ rigid_body = {} }}", quoted(r)),
            };
            let kind = if c.secondary_nodes { "set" } else { "surface" };
            let _ = writeln!(
                t,
                "\n[[contact]]\nname = {}\nsecondary = {{ body = {}, {kind} = {} }}\nprimary = {primary}\nfriction = {}",
                quoted(&c.name),
                quoted(&c.secondary.0),
                quoted(&c.secondary.1),
                float(c.friction)
            );
            match c.adjust {
                Some(d) => {
                    let _ = writeln!(t, "adjust = {}\ninitial_penetration = \"adjust\"", float(d));
                }
                // CalculiX's static step pushes an overclosure apart in its first increment
                None if self.step.minimum_step.is_some() => {
                    let _ = writeln!(t, "initial_penetration = \"resolve\"");
                }
                None => {}
            }
            match c.pressure_law {
                Some(crate::scene::PressureLaw::Linear { stiffness }) => {
                    let _ = writeln!(t, "stiffness = {}", float(stiffness));
                }
                Some(crate::scene::PressureLaw::Exponential {
                    clearance,
                    pressure,
                }) => {
                    let _ = writeln!(
                        t,
                        "exponential = {{ clearance = {}, pressure = {} }}",
                        float(clearance),
                        float(pressure)
                    );
                }
                None => {}
            }
            if let Some(k) = c.stick_slope {
                let _ = writeln!(t, "stick_slope = {}", float(k));
            }
        }
        for c in &self.ties {
            let kind = if c.secondary_nodes { "set" } else { "surface" };
            let _ = writeln!(
                t,
                "\n[[tie]]\nname = {}\nsecondary = {{ body = {}, {kind} = {} }}\nprimary = {{ body = {}, surface = {} }}",
                quoted(&c.name),
                quoted(&c.secondary.0),
                quoted(&c.secondary.1),
                quoted(&c.primary.0),
                quoted(&c.primary.1),
            );
            if let Some(d) = c.tolerance {
                let _ = writeln!(t, "tolerance = {}", float(d));
            }
            if !c.adjust {
                let _ = writeln!(t, "adjust = false");
            }
        }
        let held = (self.rigid.iter())
            .filter(|r| !r.held.is_empty())
            .map(|r| DeckFix {
                body: r.name.clone(),
                set: String::new(),
                components: r.held.clone(),
                displacement: None,
            });
        for f in self.fixes.iter().cloned().chain(held) {
            write_fix(t, "fix", &f);
        }
        for v in &self.velocities {
            let _ = writeln!(t, "\n[[initial_velocity]]\nbody = {}", quoted(&v.body));
            let mut velocity = [0.0; 3];
            velocity[v.component] = v.value;
            let _ = writeln!(
                t,
                "set = {}\nvelocity = {}\ncomponents = [\"{}\"]",
                quoted(&v.set),
                vector(velocity),
                ["x", "y", "z"][v.component]
            );
        }
        for l in &self.loads {
            let _ = writeln!(t, "\n[[load]]\nbody = {}", quoted(&l.body));
            let _ = match &l.on {
                LoadOn::Set(s) => writeln!(t, "set = {}", quoted(s)),
                LoadOn::Surface(s) => writeln!(t, "surface = {}", quoted(s)),
            };
            if let Some(f) = l.force {
                let _ = writeln!(t, "force = {}", vector(f));
            }
            if let Some(p) = l.pressure {
                let _ = writeln!(t, "pressure = {}", float(p));
            }
            write_amplitude(t, &l.amplitude);
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

/// A deck file read with its includes expanded: where its errors and notices point.
struct DeckFile<'a> {
    path: &'a Path,
    deck: Deck,
}

impl<'a> DeckFile<'a> {
    /// The deck at `path`, in `dialect`, with its includes expanded.
    fn read(path: &'a Path, dialect: Dialect) -> Result<Self> {
        let text = crate::limits::read_input_text(path).map_err(|e| ImpactError::Mesh {
            path: path.to_path_buf(),
            line: None,
            message: format!("cannot read: {e}"),
        })?;
        let deck = Deck::expand_as(dialect, &text, Some(path)).map_err(|e| ImpactError::Mesh {
            path: e.file.clone().unwrap_or_else(|| path.to_path_buf()),
            line: e.line,
            message: e.message,
        })?;
        Ok(DeckFile { path, deck })
    }

    /// Where the piece at scene key `key` comes from: expanded line `line`, which the deck
    /// calls `what`.
    fn origin(&self, key: String, line: usize, what: String) -> Origin {
        let (file, line) = self.deck.origin(line);
        Origin {
            key,
            path: file.unwrap_or(self.path).to_path_buf(),
            line,
            what,
        }
    }

    /// An error about the whole deck.
    fn whole(&self, message: impl Into<String>) -> ImpactError {
        ImpactError::Mesh {
            path: self.path.to_path_buf(),
            line: None,
            message: message.into(),
        }
    }

    /// An error at expanded line `line`, in the file and at the line it came from.
    fn err(&self, line: usize, message: impl Into<String>) -> ImpactError {
        let (file, l) = self.deck.origin(line);
        ImpactError::Mesh {
            path: file.unwrap_or(self.path).to_path_buf(),
            line: Some(l),
            message: message.into(),
        }
    }

    /// Expanded line `line` as a notice names it: the line, or the included file and its
    /// line.
    fn line(&self, line: usize) -> String {
        match self.deck.origin(line) {
            (None, l) => format!("{l}"),
            (Some(f), l) => format!("{}:{l}", f.display()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stiffness of engineering constants, in Abaqus's order.
    fn stiffness(c: [f64; 9]) -> [f64; 9] {
        let m = crate::material::Orthotropic {
            e: [c[0], c[1], c[2]],
            nu: [c[3], c[4], c[5]],
            g: [c[6], c[7], c[8]],
        };
        let d = m.stiffness();
        let g = m.g;
        [
            d[0][0], d[0][1], d[1][1], d[0][2], d[1][2], d[2][2], g[0], g[1], g[2],
        ]
    }

    #[test]
    fn an_orthotropic_stiffness_gives_back_its_engineering_constants() {
        let c = [
            161e3, 11.38e3, 9.0e3, 0.32, 0.3, 0.45, 5.17e3, 5.2e3, 3.98e3,
        ];
        let Elastic::Orthotropic(back) = Elastic::from_stiffness(stiffness(c)).unwrap() else {
            panic!("orthotropic");
        };
        for (a, b) in back.iter().zip(c) {
            assert!((a - b).abs() <= 1e-12 * b.abs(), "{back:?} against {c:?}");
        }
        // not positive definite: a Poisson's ratio past its bound, a shear modulus of zero
        let mut d = stiffness(c);
        d[1] = 2.0 * (d[0] * d[2]).sqrt();
        assert!(Elastic::from_stiffness(d).is_err());
        let mut d = stiffness(c);
        d[8] = 0.0;
        assert!(Elastic::from_stiffness(d).is_err());
    }

    #[test]
    fn lsdyna_minor_ratios_become_the_major_ones() {
        let e = Elastic::from_lsdyna([200.0, 100.0, 50.0], [0.15, 0.06, 0.1], [40.0, 30.0, 20.0]);
        let want = [200.0, 100.0, 50.0, 0.3, 0.24, 0.2, 40.0, 20.0, 30.0];
        let Elastic::Orthotropic(c) = e else {
            panic!("orthotropic");
        };
        for (a, b) in c.iter().zip(want) {
            assert!((a - b).abs() <= 1e-12, "{c:?}");
        }
    }
}
