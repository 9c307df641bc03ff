//! An Abaqus/CalculiX deck read as a scene. The mesh keywords (`*NODE`, `*ELEMENT`, `*NSET`,
//! `*ELSET`, `*SURFACE`, `*ORIENTATION`) stay the mesh reader's ([`crate::mesh::abaqus`]);
//! this reader takes the rest: `*HEADING`, `*MATERIAL` with `*ELASTIC` (isotropic or
//! engineering constants) and `*DENSITY`, `*SOLID SECTION` (each section's element set is a
//! body), `*RIGID BODY` (a section's element set moving as one, [`rigid`]), `*BOUNDARY`
//! (zero values on node sets), `*INITIAL CONDITIONS, TYPE=VELOCITY` (a velocity per body),
//! `*SURFACE INTERACTION` with `*FRICTION`, `*CONTACT PAIR`, `*DLOAD` gravity, the loads
//! ([`loads`]: `*CLOAD`, pressure `*DLOAD`, `*AMPLITUDE`) and one `*STEP` with `*DYNAMIC`
//! (implicit) or `*DYNAMIC, EXPLICIT`.

mod loads;
mod rigid;

use std::collections::HashMap;
use std::path::Path;

use super::{
    fixes_of, give_velocity, holders, DeckBody, DeckContact, DeckFile, DeckFix, DeckMaterial,
    DeckProbe, DeckRigid, DeckScene, DeckStep, DeckTie, DeckVelocity, Elastic, Holder, Origin,
    PrimarySide, Select,
};
use crate::error::Result;
use crate::mesh::abaqus::{params, word};
use crate::mesh::deck::Dialect;
use crate::mesh::BodyParts;
use rigid::{DeckNodes, RigidDecl, Rigids};

/// The probes of the printed node sets, and the (set, line) of those too large for probes.
type Probes = (Vec<DeckProbe>, Vec<(String, usize)>);

/// Keywords the mesh reader takes.
const MESH: [&str; 6] = ["NODE", "ELEMENT", "NSET", "ELSET", "SURFACE", "ORIENTATION"];

/// Keywords passed over with a notice: output requests and solver controls, and the deck's
/// contact penalty (the augmented Lagrange iteration replaces it).
const PASSED_OVER: [&str; 15] = [
    "TIME POINTS",
    "RESTART",
    "NODE PRINT",
    "NODE OUTPUT",
    "EL PRINT",
    "NODE FILE",
    "EL FILE",
    "CONTACT PRINT",
    "CONTACT FILE",
    "OUTPUT",
    "ELEMENT OUTPUT",
    "CONTACT OUTPUT",
    "ENERGY PRINT",
    "CONTROLS",
    "PREPRINT",
];

/// A keyword line and its data lines (fields trimmed), each with its expanded line number.
struct Block {
    name: String,
    params: HashMap<String, String>,
    line: usize,
    data: Vec<(Vec<String>, usize)>,
}

impl Block {
    /// The value of parameter `key` (its blanks as the deck has them or not: CalculiX
    /// drops them), `None` where it is missing or empty.
    fn get(&self, key: &str) -> Option<&str> {
        self.params
            .get(&word(key))
            .map(String::as_str)
            .filter(|v| !v.is_empty())
    }
}

/// The deck's blocks in order (comments and blank lines left out), or the line of a data
/// line before the first keyword.
fn blocks(text: &str) -> std::result::Result<Vec<Block>, usize> {
    let mut out: Vec<Block> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if line.starts_with('*') {
            let (name, params) = params(line);
            out.push(Block {
                name,
                params,
                line: i + 1,
                data: Vec::new(),
            });
        } else if let Some(b) = out.last_mut() {
            let fields = line.split(',').map(|f| f.trim().to_string()).collect();
            b.data.push((fields, i + 1));
        } else {
            return Err(i + 1);
        }
    }
    Ok(out)
}

/// What the reader gathers before the bodies are known.
#[derive(Default)]
struct Gathered {
    title: Option<String>,
    /// (element set, g times direction, line) of each `*DLOAD` GRAV line.
    gravity: Vec<(String, [f64; 3], usize)>,
    materials: Vec<DeckMaterial>,
    /// (element set, material, line) of each section.
    sections: Vec<(String, String, usize)>,
    boundaries: Vec<Boundary>,
    rigid: Vec<RigidDecl>,
    /// (node set, dof, value, line).
    velocities: Vec<(String, usize, f64, usize)>,
    /// Each interaction's friction coefficient, and the interaction last opened.
    friction: HashMap<String, f64>,
    /// Each interaction's stick slope (`*FRICTION`'s second value), with its line.
    stick: HashMap<String, (f64, usize)>,
    interaction: Option<String>,
    /// Each `*EQUATION`'s terms (node or node set, dof 0-2, coefficient) and line.
    equations: Vec<(Vec<EquationTerm>, usize)>,
    /// Each interaction's linear pressure-overclosure slope (`*SURFACE BEHAVIOR,
    /// PRESSURE-OVERCLOSURE=LINEAR`), with its line.
    stiffness: HashMap<String, (crate::scene::PressureLaw, usize)>,
    /// (secondary surface, primary surface, interaction, line).
    pairs: Vec<(String, String, String, usize)>,
    /// The `ADJUST=` distance of the pairs on each line that gives one.
    adjust: HashMap<usize, f64>,
    step: Option<DeckStep>,
    /// The line of the first step's procedure.
    step_line: usize,
    steps: usize,
    /// (node set, line) of each `*NODE PRINT` or `*NODE OUTPUT` with `NSET=`.
    printed: Vec<(String, usize)>,
    /// Keywords passed over, with their lines.
    passed: Vec<(String, usize)>,
    /// The `*AMPLITUDE` tables by name (upper case), the `*CLOAD` and pressure `*DLOAD`
    /// lines, and whether `*STEP, AMPLITUDE=RAMP` ramps the loads without one.
    amplitudes: HashMap<String, Vec<[f64; 2]>>,
    cloads: Vec<loads::NodalLoad>,
    pressures: Vec<loads::PressureLoad>,
    ramp: bool,
    /// Whether the first step ramps a value without an amplitude.
    first_ramp: bool,
    /// The names of the node-based surfaces (`*SURFACE, TYPE=NODE`).
    node_surfaces: Vec<String>,
    /// The steps after the first.
    later: Vec<LaterStep>,
    /// Each `*TIE`: (name, slave surface, master surface, tolerance, adjust, line).
    ties: Vec<(String, String, String, Option<f64>, bool, usize)>,
}

/// Parameters impact reads past, each listed in the notice with its line: `*STEP, NLGEOM`
/// (impact's strain is small), `*DYNAMIC, ALPHA=` (impact's implicit step is the
/// trapezoidal rule, alpha = 0) and `*CONTACT PAIR, SMALL SLIDING` (impact's contact
/// follows finite sliding).
fn noted_parameters(b: &Block, g: &mut Gathered) {
    let given = |k: &str| b.get(k).map(str::to_ascii_uppercase);
    let note = match b.name.as_str() {
        "STEP" if b.params.contains_key("NLGEOM") && given("NLGEOM").as_deref() != Some("NO") => {
            "STEP NLGEOM (impact's strain is small: the strain and the material are linear)"
        }
        "DYNAMIC" if given("ALPHA").is_some_and(|a| crate::mesh::abaqus::real(&a) != Some(0.0)) => {
            "DYNAMIC ALPHA= (impact's implicit step is the trapezoidal rule, alpha = 0)"
        }
        "CONTACT PAIR" if b.params.contains_key("SMALLSLIDING") => {
            "CONTACT PAIR SMALL SLIDING (impact's contact follows finite sliding)"
        }
        _ => return,
    };
    g.passed.push((note.to_string(), b.line));
}

impl Gathered {
    /// Keeps whether the step read so far ramps its values without an amplitude.
    fn close_step(&mut self) {
        match (self.steps, self.later.last_mut()) {
            (1, _) => self.first_ramp = self.ramp,
            (_, Some(l)) => l.ramp = self.ramp,
            _ => {}
        }
    }
}

/// A `*STEP` after the first: its line (its procedure's, once read), its period and
/// increments, the equations it removes, its `*BOUNDARY` lines (and whether one of them,
/// `OP=NEW`, ends those before) and its `*CHANGE FRICTION`s (interaction, coefficient,
/// stick slope).
#[derive(Default)]
struct LaterStep {
    line: usize,
    period: Option<f64>,
    /// The step's procedure where it is not the first step's: "static", "implicit" or
    /// "explicit" (a preload, then an impact).
    method: Option<&'static str>,
    increment: Option<f64>,
    minimum: Option<f64>,
    remove: Option<DeckRemoval>,
    boundaries: Vec<Boundary>,
    renew: bool,
    /// Whether the step ramps a value without an amplitude (a static step, or
    /// `*STEP, AMPLITUDE=RAMP`).
    ramp: bool,
    friction: Vec<(String, f64, Option<f64>)>,
    /// The interaction `*CHANGE FRICTION` opened, whose `*FRICTION` follows.
    changing: Option<String>,
}

/// The method a step's procedure becomes.
fn method_of(s: &DeckStep) -> &'static str {
    match (s.explicit, s.minimum_step) {
        (true, _) => "explicit",
        (false, None) => "implicit",
        (false, Some(_)) => "static",
    }
}

/// `*EQUATION, REMOVE ALL`, or `*EQUATION, REMOVE` with (node or node set, dof 0-2, line)
/// lines: the equations whose dependent term is that dof end.
enum DeckRemoval {
    All,
    Dofs(Vec<(String, usize, usize)>),
}

/// An `*EQUATION` term as written: node (or node set), dof 0-2, coefficient.
type EquationTerm = (String, usize, f64);

/// A `*BOUNDARY` line: its node set, the dofs it holds (1-3 translations, 4-6 a rigid
/// body's reference node's rotations), whether a named condition (`ENCASTRE`, ...) gave
/// them, and its line.
struct Boundary {
    set: String,
    dofs: Vec<usize>,
    named: bool,
    /// The displacement the dofs are moved to (0: held still) and the `AMPLITUDE=` it
    /// follows.
    value: f64,
    amplitude: Option<String>,
    line: usize,
}

/// The reader: the deck and the error it locates.
struct Reader<'a> {
    src: DeckFile<'a>,
}

impl Reader<'_> {
    fn number(&self, fields: &[String], i: usize, line: usize, what: &str) -> Result<f64> {
        let f = fields.get(i).map(String::as_str).unwrap_or("");
        crate::mesh::abaqus::real(f).ok_or_else(|| {
            self.src
                .err(line, format!("{what}: `{f}` is not a finite number"))
        })
    }

    fn dof(&self, fields: &[String], i: usize, line: usize) -> Result<usize> {
        let f = fields.get(i).map(String::as_str).unwrap_or("");
        match f.parse::<usize>() {
            Ok(d @ 1..=6) => Ok(d),
            _ => Err(self.src.err(
                line,
                format!("degree of freedom `{f}`: a solid's are 1, 2 and 3 (x, y, z), a rigid body's reference node's also 4, 5 and 6 (its rotations)"),
            )),
        }
    }

    /// The first data line of `b`, refused when there is none.
    fn first<'b>(&self, b: &'b Block) -> Result<&'b (Vec<String>, usize)> {
        b.data.first().ok_or_else(|| {
            self.src
                .err(b.line, format!("*{} needs a data line", b.name))
        })
    }

    /// Takes one block into `g`.
    fn take(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        // a static step's loads and displacements ramp over it (refused below, but its
        // displacements are not told they jump)
        g.ramp |= b.name == "STATIC";
        noted_parameters(b, g);
        if g.steps > 1 && b.name != "STEP" {
            return self.later_step(b, g);
        }
        match b.name.as_str() {
            n if MESH.contains(&n) || n == "END STEP" => {}
            // the heading's line as written (its fields are split at the commas)
            "HEADING" => {
                let text = &self.src.deck.text;
                g.title = (b.data.first())
                    .and_then(|(_, l)| text.lines().nth(l - 1))
                    .map(|t| t.trim().to_string());
            }
            "MATERIAL" => {
                let name = b.get("NAME").ok_or_else(|| self.src.err(b.line, "*MATERIAL needs NAME="))?;
                g.materials.push(DeckMaterial {
                    name: name.to_string(),
                    density: None,
                    elastic: None,
                    line: b.line,
                    what: format!("*MATERIAL, NAME={name}"),
                });
            }
            "ELASTIC" => {
                let e = self.elastic(b)?;
                self.material(g, b)?.elastic = Some(e);
            }
            "DENSITY" => {
                let (f, l) = self.first(b)?;
                if b.data.len() > 1 || f.iter().skip(1).any(|x| !x.is_empty()) {
                    return Err(self.src.err(*l, "*DENSITY over temperatures: impact's materials take one density"));
                }
                let rho = self.number(f, 0, *l, "*DENSITY")?;
                self.material(g, b)?.density = Some(rho);
            }
            "SOLID SECTION" => {
                let need = |k: &str| {
                    b.get(k)
                        .map(str::to_string)
                        .ok_or_else(|| self.src.err(b.line, format!("*SOLID SECTION needs {k}=")))
                };
                g.sections.push((need("ELSET")?, need("MATERIAL")?, b.line));
            }
            "BOUNDARY" => {
                let lines = self.boundary(b)?;
                g.boundaries.extend(lines);
            }
            "RIGID BODY" => self.rigid_body_keyword(b, g)?,
            "INITIAL CONDITIONS" => self.initial_velocity(b, g)?,
            "SURFACE INTERACTION" => {
                let name = (b.get("NAME"))
                    .ok_or_else(|| self.src.err(b.line, "*SURFACE INTERACTION needs NAME="))?;
                g.friction.insert(name.to_ascii_uppercase(), 0.0);
                g.interaction = Some(name.to_ascii_uppercase());
            }
            "FRICTION" => self.friction(b, g)?,
            "SURFACE BEHAVIOR" => self.surface_behavior(b, g)?,
            "STATIC" => {
                g.step = Some(self.statics(b)?);
                g.step_line = b.line;
            }
            "EQUATION" => self.equation(b, g)?,
            "CONTACT PAIR" => self.contact_pair(b, g)?,
            "TIE" => self.tie(b, g)?,
            "STEP" => {
                g.close_step();
                g.ramp = b.get("AMPLITUDE").is_some_and(|a| a.eq_ignore_ascii_case("RAMP"));
                g.steps += 1;
                if g.steps > 1 {
                    g.later.push(LaterStep {
                        line: b.line,
                        ..Default::default()
                    });
                }
            }
            "DYNAMIC" => {
                g.step = Some(self.dynamic(b)?);
                g.step_line = b.line;
            }
            "DLOAD" => self.dload(b, g)?,
            "CLOAD" => self.cload(b, g)?,
            "AMPLITUDE" => self.amplitude(b, g)?,
            "NODE PRINT" | "NODE OUTPUT" if b.get("NSET").is_some() => {
                let set = b.get("NSET").unwrap_or_default().to_string();
                g.printed.push((set, b.line));
            }
            n if PASSED_OVER.contains(&n) => g.passed.push((n.to_string(), b.line)),
            n => {
                return Err(self.src.err(
                    b.line,
                    format!("*{n}: impact cannot honour this keyword (it reads elastic solids, rigid bodies of solid elements, their supports, initial velocities, contact pairs with friction, gravity, loads (*CLOAD, pressure *DLOAD, *AMPLITUDE), equations, ties, and *STATIC and *DYNAMIC steps in sequence; docs/decks.md lists them)"),
                ))
            }
        }
        Ok(())
    }

    /// A block of a step after the first: its procedure (the first step's kind, with an
    /// increment and a period of its own), `*EQUATION, REMOVE`, `*BOUNDARY` (`OP=MOD` or
    /// `NEW`), `*CHANGE FRICTION` with its `*FRICTION`, and output requests.
    fn later_step(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let refuse = |why: &str| {
            Err(self
                .src
                .err(b.line, format!("*{} in a later *STEP: {why}", b.name)))
        };
        let Some(later) = g.later.last_mut() else {
            return Ok(());
        };
        if b.name != "FRICTION" {
            later.changing = None;
        }
        match b.name.as_str() {
            "END STEP" => {}
            "DYNAMIC" | "STATIC" => {
                let step = match b.name.as_str() {
                    "DYNAMIC" => self.dynamic(b)?,
                    _ => self.statics(b)?,
                };
                let first = g.step.as_ref();
                let same = first.is_some_and(|f| method_of(f) == method_of(&step));
                // a step of another procedure keeps its own increment (an explicit one
                // steps at the stable step)
                later.method = (!same).then(|| method_of(&step));
                // the step's line from here on is its procedure's, which gives the increment
                later.line = b.line;
                later.period = Some(step.end_time);
                later.increment = step.time_step;
                later.minimum = step.minimum_step;
            }
            "EQUATION" => {
                let remove = match (b.params.contains_key("REMOVEALL"), b.params.contains_key("REMOVE")) {
                    (true, _) => DeckRemoval::All,
                    (false, true) => {
                        let mut dofs = Vec::with_capacity(b.data.len());
                        for (f, l) in &b.data {
                            let set = f.first().cloned().unwrap_or_default();
                            let dof = self.dof(f, 1, *l)?;
                            if dof > 3 {
                                return Err(self.src.err(*l, "*EQUATION, REMOVE: impact's constraints act on translations (dofs 1 to 3)"));
                            }
                            dofs.push((set, dof - 1, *l));
                        }
                        DeckRemoval::Dofs(dofs)
                    }
                    _ => return refuse("a later step removes equations (`REMOVE`, `REMOVE ALL`); new ones are the first step's"),
                };
                later.remove = Some(remove);
            }
            "BOUNDARY" => {
                match b.get("OP").map(str::to_ascii_uppercase).as_deref() {
                    None | Some("MOD") => {}
                    Some("NEW") => {
                        later.renew = true;
                        later.boundaries.clear();
                    }
                    Some(op) => return refuse(&format!("OP={op}: a *BOUNDARY is OP=MOD (changes and adds) or OP=NEW (ends those before)")),
                }
                let lines = self.boundary(b)?;
                later.boundaries.extend(lines);
            }
            "CHANGE FRICTION" => {
                let Some(name) = b.get("INTERACTION") else {
                    return refuse("*CHANGE FRICTION needs INTERACTION=");
                };
                let name = name.to_ascii_uppercase();
                if !g.friction.contains_key(&name) {
                    return refuse(&format!("INTERACTION={name}: no *SURFACE INTERACTION of that name"));
                }
                later.changing = Some(name);
            }
            "FRICTION" => {
                let Some(interaction) = later.changing.clone() else {
                    return refuse("a later step's *FRICTION follows *CHANGE FRICTION, INTERACTION=");
                };
                let (mu, slope, _) = self.friction_values(b)?;
                later.friction.push((interaction, mu, slope));
            }
            "NODE PRINT" | "NODE OUTPUT" if b.get("NSET").is_some() => {
                let set = b.get("NSET").unwrap_or_default().to_string();
                if !g.printed.iter().any(|(s, _)| s.eq_ignore_ascii_case(&set)) {
                    g.printed.push((set, b.line));
                }
            }
            n if PASSED_OVER.contains(&n) => g.passed.push((n.to_string(), b.line)),
            _ => return refuse("between steps impact changes the equations (`*EQUATION, REMOVE`), the supports (`*BOUNDARY`) and the friction (`*CHANGE FRICTION`); the loads and the contact go on as the first step set them"),
        }
        Ok(())
    }

    /// The material the last `*MATERIAL` opened.
    fn material<'g>(&self, g: &'g mut Gathered, b: &Block) -> Result<&'g mut DeckMaterial> {
        g.materials.last_mut().ok_or_else(|| {
            self.src
                .err(b.line, format!("*{} outside a *MATERIAL", b.name))
        })
    }

    fn elastic(&self, b: &Block) -> Result<Elastic> {
        // CalculiX's own spellings (ISO, ORTHO), blanks or none
        let given = b.get("TYPE").unwrap_or("ISOTROPIC").to_ascii_uppercase();
        let ty = match word(&given).as_str() {
            "ISO" | "ISOTROPIC" => "ISOTROPIC".to_string(),
            "ORTHO" | "ORTHOTROPIC" => "ORTHOTROPIC".to_string(),
            "ENGINEERINGCONSTANTS" => "ENGINEERING CONSTANTS".to_string(),
            _ => given,
        };
        let values: Vec<(String, usize)> = (b.data.iter())
            .flat_map(|(f, l)| f.iter().filter(|x| !x.is_empty()).map(|x| (x.clone(), *l)))
            .collect();
        let at = |i: usize| -> Result<f64> {
            let (v, l) = values
                .get(i)
                .cloned()
                .unwrap_or_else(|| (String::new(), b.line));
            self.number(&[v], 0, l, &format!("*ELASTIC, TYPE={ty}, value {}", i + 1))
        };
        let count = match ty.as_str() {
            "ISOTROPIC" => 2,
            _ => 9,
        };
        if values.len() > count {
            let (_, l) = &values[count];
            return Err(self.src.err(*l, format!("*ELASTIC, TYPE={ty}: more than its {count} constants (a temperature, or a table over temperatures): impact's materials take one set of constants")));
        }
        match ty.as_str() {
            "ISOTROPIC" => Ok(Elastic::Isotropic {
                e: at(0)?,
                nu: at(1)?,
            }),
            "ENGINEERING CONSTANTS" | "ORTHOTROPIC" => {
                let mut c = [0.0; 9];
                for (i, x) in c.iter_mut().enumerate() {
                    *x = at(i)?;
                }
                if ty == "ENGINEERING CONSTANTS" {
                    return Ok(Elastic::Orthotropic(c));
                }
                Elastic::from_stiffness(c)
                    .map_err(|e| self.src.err(b.line, format!("*ELASTIC, TYPE=ORTHOTROPIC: {e}")))
            }
            _ => Err(self.src.err(
                b.line,
                format!("*ELASTIC, TYPE={ty}: impact reads TYPE=ISOTROPIC, ENGINEERING CONSTANTS and ORTHOTROPIC"),
            )),
        }
    }

    /// A `*BOUNDARY`'s lines.
    fn boundary(&self, b: &Block) -> Result<Vec<Boundary>> {
        let mut out = Vec::with_capacity(b.data.len());
        for (f, l) in &b.data {
            let set = f[0].clone();
            // Abaqus's named conditions, as they hold a solid's translations
            let named: Option<&[usize]> = match f.get(1).map(|x| x.to_ascii_uppercase()).as_deref()
            {
                Some("ENCASTRE") => Some(&[1, 2, 3, 4, 5, 6]),
                Some("PINNED") => Some(&[1, 2, 3]),
                Some("XSYMM") => Some(&[1, 5, 6]),
                Some("YSYMM") => Some(&[2, 4, 6]),
                Some("ZSYMM") => Some(&[3, 4, 5]),
                _ => None,
            };
            if let Some(dofs) = named {
                out.push(Boundary {
                    set,
                    dofs: dofs.to_vec(),
                    named: true,
                    value: 0.0,
                    amplitude: None,
                    line: *l,
                });
                continue;
            }
            let first = self.dof(f, 1, *l)?;
            let last = match f.get(2).filter(|x| !x.is_empty()) {
                Some(_) => self.dof(f, 2, *l)?,
                None => first,
            };
            if last < first {
                return Err(self.src.err(*l, format!("*BOUNDARY {set}, {first}, {last}: the last dof comes before the first (a line holds dofs first to last)")));
            }
            let value = match f.get(3).filter(|x| !x.is_empty()) {
                Some(_) => self.number(f, 3, *l, "*BOUNDARY value")?,
                None => 0.0,
            };
            out.push(Boundary {
                set,
                dofs: (first..=last.max(first)).collect(),
                named: false,
                value,
                amplitude: b.get("AMPLITUDE").map(str::to_ascii_uppercase),
                line: *l,
            });
        }
        Ok(out)
    }

    fn initial_velocity(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let ty = b.get("TYPE").unwrap_or("").to_ascii_uppercase();
        if word(&ty) != "VELOCITY" {
            return Err(self.src.err(
                b.line,
                format!("*INITIAL CONDITIONS, TYPE={ty}: impact reads TYPE=VELOCITY"),
            ));
        }
        for (f, l) in &b.data {
            let dof = self.dof(f, 1, *l)?;
            let value = self.number(f, 2, *l, "*INITIAL CONDITIONS velocity")?;
            let same =
                |v: &&(String, usize, f64, usize)| v.0.eq_ignore_ascii_case(&f[0]) && v.1 == dof;
            if let Some((.., first)) = g.velocities.iter().find(same) {
                let first = self.src.line(*first);
                return Err(self.src.err(
                    *l,
                    format!(
                        "the velocity of {}, dof {dof}, is given twice (first on line {first})",
                        f[0]
                    ),
                ));
            }
            g.velocities.push((f[0].clone(), dof, value, *l));
        }
        Ok(())
    }

    fn friction(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let (mu, slope, l) = self.friction_values(b)?;
        let last = (g.interaction.clone()).ok_or_else(|| {
            self.src
                .err(b.line, "*FRICTION outside a *SURFACE INTERACTION")
        })?;
        if let Some(slope) = slope {
            g.stick.insert(last.clone(), (slope, l));
        }
        g.friction.insert(last, mu);
        Ok(())
    }

    /// A `*FRICTION`'s coefficient, its stick slope where given (positive), and its line.
    fn friction_values(&self, b: &Block) -> Result<(f64, Option<f64>, usize)> {
        let (f, l) = self.first(b)?;
        let mu = self.number(f, 0, *l, "*FRICTION coefficient")?;
        if f.get(1).is_none_or(|x| x.is_empty()) {
            return Ok((mu, None, *l));
        }
        let slope = self.number(f, 1, *l, "*FRICTION stick slope")?;
        if slope <= 0.0 {
            return Err(self.src.err(
                *l,
                format!("*FRICTION: the stick slope {slope} must be positive"),
            ));
        }
        Ok((mu, Some(slope), *l))
    }

    fn contact_pair(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let interaction = (b.get("INTERACTION"))
            .ok_or_else(|| self.src.err(b.line, "*CONTACT PAIR needs INTERACTION="))?;
        if let Some(ty) = b.get("TYPE") {
            let ty = ty.to_ascii_uppercase();
            if !["NODETOSURFACE", "SURFACETOSURFACE"].contains(&word(&ty).as_str()) {
                return Err(self.src.err(b.line, format!("*CONTACT PAIR, TYPE={ty}: impact reads NODE TO SURFACE and SURFACE TO SURFACE (both become its node-to-surface contact)")));
            }
        }
        if b.data.is_empty() {
            return Err(self.src.err(
                b.line,
                "*CONTACT PAIR needs a data line naming the slave, then the master surface",
            ));
        }
        let adjust = match b.get("ADJUST") {
            None => None,
            Some(d) => match crate::mesh::abaqus::real(d).filter(|d| d.is_finite() && *d >= 0.0) {
                Some(d) => Some(d),
                None => return Err(self.src.err(b.line, format!("*CONTACT PAIR, ADJUST={d}: impact reads a distance >= 0 (the slave nodes within it are moved onto the master surface), not a node set"))),
            },
        };
        for (f, l) in &b.data {
            if f.len() < 2 || f[1].is_empty() || f.iter().skip(2).any(|x| !x.is_empty()) {
                return Err(self.src.err(
                    *l,
                    "a contact pair line names the slave, then the master surface (two surfaces)",
                ));
            }
            let same = |(s, m, _, _): &&(String, String, String, usize)| {
                s.eq_ignore_ascii_case(&f[0]) && m.eq_ignore_ascii_case(&f[1])
            };
            if let Some((.., first)) = g.pairs.iter().find(same) {
                let first = self.src.line(*first);
                return Err(self.src.err(
                    *l,
                    format!(
                        "the contact pair {}, {} is given twice (first on line {first})",
                        f[0], f[1]
                    ),
                ));
            }
            g.pairs.push((
                f[0].clone(),
                f[1].clone(),
                interaction.to_ascii_uppercase(),
                *l,
            ));
            if let Some(d) = adjust {
                g.adjust.insert(*l, d);
            }
        }
        Ok(())
    }

    /// `*TIE`: one line, the slave surface then the master one; `POSITION TOLERANCE=` and
    /// `ADJUST=NO` read. The cyclic, multistage and fluid ties are refused.
    fn tie(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let kinds = [
            "CYCLIC SYMMETRY",
            "MULTISTAGE",
            "FLUID PERIODIC",
            "FLUID CYCLIC",
        ];
        if let Some(k) = kinds.iter().find(|k| b.params.contains_key(&word(k))) {
            return Err(self.src.err(b.line, format!("*TIE, {k}: impact cannot honour this tie (it ties two adjacent surfaces, a tied contact, and has no sector or fluid models)")));
        }
        let tolerance = match b.get("POSITION TOLERANCE") {
            None => None,
            Some(d) => match crate::mesh::abaqus::real(d).filter(|d| d.is_finite() && *d > 0.0) {
                Some(d) => Some(d),
                None => {
                    return Err(self.src.err(
                        b.line,
                        format!("*TIE, POSITION TOLERANCE={d}: a distance > 0"),
                    ))
                }
            },
        };
        let adjust = match b.get("ADJUST").map(str::to_ascii_uppercase).as_deref() {
            None | Some("YES") => true,
            Some("NO") => false,
            Some(a) => return Err(self.src.err(b.line, format!("*TIE, ADJUST={a}: YES or NO"))),
        };
        let [(f, l)] = &b.data[..] else {
            return Err(self.src.err(
                b.line,
                "*TIE takes one data line: the slave surface, then the master surface",
            ));
        };
        if f.len() < 2 || f[1].is_empty() || f.iter().skip(2).any(|x| !x.is_empty()) {
            return Err(self.src.err(
                *l,
                "a *TIE line names the slave, then the master surface (two surfaces)",
            ));
        }
        let name = b
            .get("NAME")
            .map_or_else(|| format!("tie{}", g.ties.len() + 1), str::to_string);
        g.ties
            .push((name, f[0].clone(), f[1].clone(), tolerance, adjust, *l));
        Ok(())
    }

    /// `*SURFACE BEHAVIOR`: a linear pressure-overclosure's slope is the contact's
    /// penalty stiffness (a static step honours it); the other laws are passed over.
    fn surface_behavior(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        use crate::scene::PressureLaw;
        let law = b
            .get("PRESSURE-OVERCLOSURE")
            .unwrap_or("HARD")
            .to_ascii_uppercase();
        if law != "LINEAR" && law != "EXPONENTIAL" {
            if law != "HARD" {
                g.passed.push((
                    format!("SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE={law}"),
                    b.line,
                ));
            }
            return Ok(());
        }
        let (f, l) = self.first(b)?;
        let what = format!("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE={law}");
        let positive = |i: usize, name: &str| -> Result<f64> {
            let v = self.number(f, i, *l, &format!("{what} {name}"))?;
            match v > 0.0 {
                true => Ok(v),
                false => Err(self
                    .src
                    .err(*l, format!("{what}: the {name} {v} must be positive"))),
            }
        };
        let pressure_law = match law.as_str() {
            "LINEAR" => PressureLaw::Linear {
                stiffness: positive(0, "slope")?,
            },
            _ => PressureLaw::Exponential {
                clearance: positive(0, "clearance c0")?,
                pressure: positive(1, "pressure p0")?,
            },
        };
        let last = (g.interaction.clone()).ok_or_else(|| {
            self.src
                .err(b.line, "*SURFACE BEHAVIOR outside a *SURFACE INTERACTION")
        })?;
        g.stiffness.insert(last, (pressure_law, b.line));
        Ok(())
    }

    /// `*EQUATION`: blocks of a term count, then that many (node, dof, coefficient)
    /// triples over one or more lines.
    fn equation(&self, b: &Block, g: &mut Gathered) -> Result<()> {
        let fields: Vec<(String, usize)> = (b.data.iter())
            .flat_map(|(f, l)| {
                f.iter()
                    .filter(|x| !x.is_empty())
                    .map(move |x| (x.clone(), *l))
            })
            .collect();
        let mut k = 0;
        while k < fields.len() {
            let (count, l) = &fields[k];
            let n = match count.parse::<usize>() {
                Ok(n) if n >= 1 => n,
                _ => {
                    return Err(self
                        .src
                        .err(*l, format!("*EQUATION: `{count}` is not a count of terms")))
                }
            };
            let terms = fields.get(k + 1..k + 1 + 3 * n).ok_or_else(|| {
                self.src.err(
                    *l,
                    format!(
                        "*EQUATION: {n} terms need {} numbers after the count",
                        3 * n
                    ),
                )
            })?;
            let mut out = Vec::with_capacity(n);
            for t in terms.chunks(3) {
                let line = t[0].1;
                let values: Vec<String> = t.iter().map(|x| x.0.clone()).collect();
                let dof = self.dof(&values, 1, line)?;
                if dof > 3 {
                    return Err(self.src.err(
                        line,
                        "*EQUATION: impact's constraints act on translations (dofs 1 to 3)",
                    ));
                }
                let c = self.number(&values, 2, line, "*EQUATION coefficient")?;
                out.push((values[0].clone(), dof - 1, c));
            }
            g.equations.push((out, *l));
            k += 1 + 3 * n;
        }
        Ok(())
    }

    /// `*STATIC`: initial increment, period, minimum (and maximum) increment; CalculiX's
    /// defaults 1, 1 and 1e-5 of the period.
    fn statics(&self, b: &Block) -> Result<DeckStep> {
        let field = |i: usize| -> Result<Option<f64>> {
            match b.data.first() {
                Some((f, l)) if f.get(i).is_some_and(|x| !x.is_empty()) => {
                    self.number(f, i, *l, "*STATIC increment control").map(Some)
                }
                _ => Ok(None),
            }
        };
        let period = field(1)?.unwrap_or(1.0);
        let initial = field(0)?.unwrap_or(period).min(period);
        let minimum = field(2)?.unwrap_or(1e-5 * period).min(initial);
        if period <= 0.0 || initial <= 0.0 || minimum <= 0.0 {
            return Err(self.src.err(
                b.line,
                "*STATIC: the increments and the period must be positive",
            ));
        }
        Ok(DeckStep {
            explicit: false,
            end_time: period,
            time_step: Some(initial),
            minimum_step: Some(minimum),
        })
    }

    fn dynamic(&self, b: &Block) -> Result<DeckStep> {
        let explicit = b.params.contains_key("EXPLICIT");
        let (f, l) = self.first(b)?;
        let end_time = self.number(f, 1, *l, "*DYNAMIC time period")?;
        let time_step = match explicit {
            // the explicit path takes the mesh's stable step (the notice says so)
            true => None,
            false => Some(self.number(f, 0, *l, "*DYNAMIC time increment")?),
        };
        Ok(DeckStep {
            explicit,
            end_time,
            time_step,
            minimum_step: None,
        })
    }

    /// A `*DLOAD` GRAV line: (element set, g times direction, line).
    fn gravity_line(&self, f: &[String], l: usize) -> Result<(String, [f64; 3], usize)> {
        let m = self.number(f, 2, l, "*DLOAD GRAV magnitude")?;
        let d = [3, 4, 5].map(|i| self.number(f, i, l, "*DLOAD GRAV direction"));
        let [x, y, z] = d;
        let direction = [x?, y?, z?];
        if m != 0.0 && direction == [0.0; 3] {
            return Err(self.src.err(
                l,
                "*DLOAD GRAV: the direction is zero (give the unit vector gravity acts along)",
            ));
        }
        Ok((f[0].clone(), direction.map(|c| m * c), l))
    }

    /// The model's gravity: the GRAV lines must give one vector to every section's elements
    /// (impact's gravity acts on the whole model).
    fn whole_gravity(&self, g: &Gathered) -> Result<Option<[f64; 3]>> {
        let Some((_, first, _)) = g.gravity.first() else {
            return Ok(None);
        };
        for (set, v, l) in &g.gravity {
            if v != first {
                return Err(self.src.err(*l, "*DLOAD GRAV: a second gravity vector; impact's gravity is one vector on the whole model"));
            }
            if !g
                .sections
                .iter()
                .any(|(e, _, _)| e.eq_ignore_ascii_case(set))
            {
                return Err(self.src.err(*l, format!("*DLOAD GRAV on `{set}`: name the *SOLID SECTION element sets (impact's gravity acts on every body)")));
            }
        }
        for (e, _, l) in &g.sections {
            if !g
                .gravity
                .iter()
                .any(|(set, _, _)| e.eq_ignore_ascii_case(set))
            {
                return Err(self.src.err(
                    *l,
                    format!("*DLOAD GRAV leaves out `{e}`: impact's gravity acts on every body"),
                ));
            }
        }
        Ok(Some(*first))
    }
}

/// The deck at `path` as a scene, and the notice of the keywords it passed over.
pub(super) fn read_scene(path: &Path) -> Result<(DeckScene, Option<String>)> {
    let r = Reader {
        src: DeckFile::read(path, Dialect::Abaqus)?,
    };
    let mut g = Gathered::default();
    let all = blocks(&r.src.deck.text)
        .map_err(|l| r.src.err(l, "a data line before the first keyword"))?;
    // every keyword's refusal at once, each at its line
    let mut refusals = Vec::new();
    for b in &all {
        if let Err(e) = r.take(b, &mut g) {
            refusals.push(e);
        }
        let node_based = b
            .get("TYPE")
            .is_some_and(|t| t.eq_ignore_ascii_case("NODE"));
        if let Some(name) = b.get("NAME").filter(|_| b.name == "SURFACE" && node_based) {
            g.node_surfaces.push(name.to_string());
        }
    }
    g.close_step();
    if let Some(e) = super::together(refusals) {
        return Err(e);
    }
    let mut step = g.step.clone().ok_or_else(|| {
        r.src.whole("no *STEP with *DYNAMIC or *STATIC: impact runs one step, implicit (*DYNAMIC), explicit (*DYNAMIC, EXPLICIT) or static (*STATIC)")
    })?;
    // the run goes on to the last step's end, in the smallest of the steps' increments
    step.end_time += g.later.iter().filter_map(|l| l.period).sum::<f64>();
    let notes = r.common_increment(&g, &mut step)?;
    // a dynamic step's contact is the augmented Lagrange iteration's: a linear law's slope
    // is passed over
    if step.minimum_step.is_none() {
        let mut lines: Vec<usize> = g.stiffness.values().map(|s| s.1).collect();
        lines.sort_unstable();
        g.passed.extend(
            lines
                .into_iter()
                .map(|l| ("SURFACE BEHAVIOR".to_string(), l)),
        );
        let mut lines: Vec<usize> = g.stick.values().map(|s| s.1).collect();
        lines.sort_unstable();
        g.passed.extend(
            lines
                .into_iter()
                .map(|l| ("FRICTION stick slope".to_string(), l)),
        );
    }
    if g.sections.is_empty() {
        return Err(r
            .src
            .whole("no *SOLID SECTION: each section's element set is a body, with its material"));
    }
    let deck = DeckNodes { blocks: &all };
    let rigid = r.rigid_bodies(&g, &deck)?;
    let on = On {
        deck: &deck,
        rigid: &rigid,
    };
    let bodies = r.bodies(&g)?;
    let (probes, unprobed) = r.probes(&g, &bodies, &on)?;
    let (contacts, rigid_bodies) = r.contacts(&g, &bodies, &rigid)?;
    let ties = r.ties(&g, &bodies, &rigid)?;
    let (moving, velocities) = r.velocities(&g, &bodies, &on)?;
    let mut scene = DeckScene {
        title: g.title.clone(),
        mesh: path
            .file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned()),
        files: r.src.deck.files().to_vec(),
        gravity: r.whole_gravity(&g)?,
        materials: g.materials.clone(),
        fixes: r.fixes((&g, &g.boundaries, None), &bodies, &on)?,
        loads: r.loads(&g, &bodies, &on)?,
        velocities,
        contacts,
        ties,
        probes,
        planes: Vec::new(),
        rigid: rigid_bodies,
        equations: r.equations(&g, &bodies, &on)?,
        later_steps: r.later_steps(&g, &bodies, &on)?,
        bodies: moving,
        step,
        origins: Vec::new(),
    };
    let mut unprobed = unprobed;
    unprobed.extend(notes);
    for (d, (r, _)) in g.rigid.iter().zip(&rigid.bodies) {
        if !scene.rigid.iter().any(|s| s.name == r.name) {
            let what = format!(
                "RIGID BODY ELSET={}: no contact pair names its surface, left out",
                d.elset
            );
            unprobed.push((what, d.line));
        }
    }
    scene.materials_complete(&r.src)?;
    scene.origins = r.origins(&g, &scene);
    let notice = notice(&r, &g, &unprobed);
    Ok((scene, notice))
}

impl Reader<'_> {
    /// The deck's lines of the scene's materials, bodies, contacts and rigid bodies.
    fn origins(&self, g: &Gathered, scene: &DeckScene) -> Vec<Origin> {
        let mut out = scene.material_origins(&self.src);
        for (i, b) in scene.bodies.iter().enumerate() {
            let section = (g.sections.iter()).find(|s| Select::Elset(s.0.clone()) == b.select);
            if let Some((elset, _, line)) = section {
                let what = format!("*SOLID SECTION, ELSET={elset}");
                out.push(self.src.origin(format!("body[{i}]"), *line, what));
            }
        }
        for (i, (slave, master, _, line)) in g.pairs.iter().enumerate() {
            let what = format!("*CONTACT PAIR {slave}, {master}");
            out.push(self.src.origin(format!("contact[{i}]"), *line, what));
        }
        for (i, (name, slave, master, .., line)) in g.ties.iter().enumerate() {
            let what = format!("*TIE, NAME={name} {slave}, {master}");
            out.push(self.src.origin(format!("tie[{i}]"), *line, what));
        }
        for (i, l) in scene.loads.iter().enumerate() {
            let what = match l.on {
                super::LoadOn::Set(_) => "*CLOAD",
                super::LoadOn::Surface(_) => "*DLOAD",
            };
            out.push(self.src.origin(format!("load[{i}]"), l.line, what.into()));
        }
        for (i, r) in scene.rigid.iter().enumerate() {
            if let Some(d) = g.rigid.iter().find(|d| d.elset == r.name) {
                let what = format!("*RIGID BODY, ELSET={}", d.elset);
                out.push(self.src.origin(format!("rigid_body[{i}]"), d.line, what));
            }
        }
        out
    }
}

/// The names the bodies take so far and the sections' element sets (a piece's body takes
/// neither).
fn taken(sections: &[(String, String, usize)], bodies: &[(DeckBody, BodyParts)]) -> Vec<String> {
    (sections.iter().map(|s| s.0.clone()))
        .chain(bodies.iter().map(|(b, _)| b.name.clone()))
        .collect()
}

/// What names a rigid body's nodes: the deck's nodes and its rigid bodies.
struct On<'a, 'b> {
    deck: &'a DeckNodes<'b>,
    rigid: &'a Rigids,
}

impl On<'_, '_> {
    /// Whether `set` names a rigid body's reference or rotation node.
    fn rigid(&self, set: &str) -> bool {
        self.rigid.names_a_node(self.deck, set)
    }
}

/// One line naming the keywords passed over, with their files' lines.
/// `unprobed`: what else was passed over (printed sets without probes, rigid bodies
/// without contacts), with its line.
fn notice(r: &Reader, g: &Gathered, unprobed: &[(String, usize)]) -> Option<String> {
    let mut listed: Vec<(String, Vec<String>)> = Vec::new();
    for (name, line) in &g.passed {
        let at = r.src.line(*line);
        match listed.iter_mut().find(|(k, _)| k == name) {
            Some((_, lines)) => lines.push(at),
            None => listed.push((name.clone(), vec![at])),
        }
    }
    for (what, line) in unprobed {
        let (_, l) = r.src.deck.origin(*line);
        listed.push((what.clone(), vec![l.to_string()]));
    }
    let mut parts: Vec<String> = listed
        .iter()
        .map(|(k, l)| format!("*{k} (line {})", l.join(", ")))
        .collect();
    if g.step.as_ref().is_some_and(|s| s.explicit) {
        parts.push("the *DYNAMIC, EXPLICIT time increment (the explicit path takes the mesh's stable step)".into());
    }
    let static_step = g.step.as_ref().is_some_and(|s| s.minimum_step.is_some());
    if !g.pairs.is_empty() && !static_step {
        parts.push("the contact pairs' penalty (the augmented Lagrange iteration on the gap rate enforces the contact)".into());
    }
    (!parts.is_empty()).then(|| {
        format!(
            "{}: passed over: {}",
            r.src.path.display(),
            parts.join("; ")
        )
    })
}

impl Reader<'_> {
    /// Each section's body, its mesh read from the deck.
    fn bodies(&self, g: &Gathered) -> Result<Vec<(DeckBody, BodyParts)>> {
        let mut out = Vec::new();
        for (elset, material, line) in &g.sections {
            if (g.rigid.iter()).any(|d| d.elset.eq_ignore_ascii_case(elset)) {
                continue;
            }
            if !(g.materials.iter()).any(|m| m.name.eq_ignore_ascii_case(material)) {
                return Err(self.src.err(
                    *line,
                    format!("*SOLID SECTION: no *MATERIAL named `{material}`"),
                ));
            }
            let m = (g.materials.iter())
                .find(|m| m.name.eq_ignore_ascii_case(material))
                .map(|m| m.name.clone())
                .unwrap_or_default();
            let (parts, _) = crate::mesh::import(self.src.path, 1.0, [0.0; 3], Some(elset))?;
            let (_, count) = crate::mesh::pieces::pieces(&parts.elements, parts.nodes.len());
            // a section of separate parts is a body per part (CalculiX's contact decks)
            let pieces: Vec<(Option<usize>, BodyParts)> = match count {
                1 => vec![(None, parts)],
                n => (1..=n)
                    .map(|k| {
                        let at = (self.src.path, 1.0, [0.0; 3]);
                        let (p, _) = crate::mesh::import::import_piece(
                            at.0,
                            at.1,
                            at.2,
                            Some(elset),
                            Some(k),
                        )?;
                        Ok((Some(k), p))
                    })
                    .collect::<Result<_>>()?,
            };
            for (piece, parts) in pieces {
                let name = match piece {
                    Some(k) => super::fresh(format!("{elset}_{k}"), &taken(&g.sections, &out)),
                    None => elset.clone(),
                };
                let body = DeckBody {
                    name,
                    material: m.clone(),
                    velocity: [0.0; 3],
                    select: Select::Elset(elset.clone()),
                    piece,
                    // a section's ORIENTATION reaches the elements through the mesh
                    axes: None,
                };
                out.push((body, parts));
            }
        }
        Ok(out)
    }

    /// The bodies holding nodes of node set `set` (by name), with how many of their nodes.
    fn holders<'b>(
        &self,
        bodies: &'b [(DeckBody, BodyParts)],
        set: &str,
        line: usize,
    ) -> Result<Vec<Holder<'b>>> {
        let found = holders(bodies, set);
        if let (true, Some(id)) = (found.is_empty(), set.strip_prefix("node ")) {
            return Err(self.src.err(
                line,
                format!("node {id}: no *NODE line gives it, or no body's elements hold it"),
            ));
        }
        if found.is_empty() {
            return Err(self.src.err(
                line,
                format!("no body's elements hold the nodes of node set `{set}`"),
            ));
        }
        Ok(found)
    }

    /// A probe at each node of each printed node set (once, however often it is printed):
    /// `SET` for a set of one node, `SET_1`, `SET_2`, ... for more.
    fn probes(&self, g: &Gathered, bodies: &[(DeckBody, BodyParts)], on: &On) -> Result<Probes> {
        let mut out: Vec<DeckProbe> = Vec::new();
        let mut unprobed = Vec::new();
        for (k, (set, line)) in g.printed.iter().enumerate() {
            // a set printed again (its displacements, then its velocities) has its probes
            if g.printed[..k]
                .iter()
                .any(|(s, _)| s.eq_ignore_ascii_case(set))
            {
                continue;
            }
            let mut points = Vec::new();
            for (b, p) in bodies {
                let Some(s) = p
                    .node_sets
                    .iter()
                    .find(|s| s.name.eq_ignore_ascii_case(set))
                else {
                    continue;
                };
                points.extend(
                    s.nodes
                        .iter()
                        .map(|&n| (b.name.clone(), p.nodes[n as usize])),
                );
            }
            if points.is_empty() && on.rigid(set) {
                let what = format!("NODE PRINT NSET={set}, a rigid body's reference node (the body's own history columns record it)");
                unprobed.push((what, *line));
                continue;
            }
            if points.is_empty() {
                return Err(self.src.err(
                    *line,
                    format!("no body's elements hold the nodes of node set `{set}`"),
                ));
            }
            let one = points.len() == 1;
            for (i, (body, point)) in points.into_iter().enumerate() {
                let name = if one {
                    set.clone()
                } else {
                    format!("{set}_{}", i + 1)
                };
                out.push(DeckProbe { name, body, point });
            }
        }
        Ok((out, unprobed))
    }

    /// The solids' fixes: each `*BOUNDARY` line's translations on the bodies holding its
    /// set's nodes (a line on a rigid body's reference node is the rigid body's).
    fn fixes(
        &self,
        (g, boundaries, later): (&Gathered, &[Boundary], Option<&LaterStep>),
        bodies: &[(DeckBody, BodyParts)],
        on: &On,
    ) -> Result<Vec<DeckFix>> {
        let mut out = Vec::new();
        for b in boundaries {
            let Some(found) = self.solids(bodies, &b.set, b.line, on)? else {
                if later.is_some() {
                    return Err(self.src.err(b.line, format!("*BOUNDARY on `{}`, a rigid body's reference node, in a later step: a rigid body keeps the motion the first step gives it", b.set)));
                }
                continue;
            };
            if !b.named && b.dofs.iter().any(|&d| d > 3) {
                return Err(self.src.err(b.line, format!("*BOUNDARY on `{}`: dofs 4-6 are rotations, which a solid's nodes do not have (a rigid body's reference node does)", b.set)));
            }
            let components: Vec<&'static str> = (b.dofs.iter())
                .filter(|&&d| d <= 3)
                .map(|&d| ["x", "y", "z"][d - 1])
                .collect();
            let displacement = self.displacement(g, b, later)?;
            out.extend(fixes_of(found, &components).map(|f| DeckFix {
                displacement: displacement.clone(),
                ..f
            }));
        }
        Ok(out)
    }

    /// A `*BOUNDARY` line's displacement: its value on each of its dofs, along its
    /// `AMPLITUDE=` or the step's ramp (none for a value of 0 in the first step, or in a
    /// later dynamic one without a ramp: held still). A dynamic step's value without either would be a jump, which no time step
    /// follows: refused. A `later` step's line ramps from where its nodes are to its value
    /// over the step, 0 too, and takes no amplitude (whose times would be the step's).
    fn displacement(
        &self,
        g: &Gathered,
        b: &Boundary,
        later: Option<&LaterStep>,
    ) -> Result<Option<crate::scene::Displacement>> {
        let ramp = later.map_or(g.first_ramp, |l| l.ramp);
        let later = later.is_some();
        if later && b.amplitude.is_some() {
            return Err(self.src.err(b.line, format!("*BOUNDARY {}, AMPLITUDE= in a later step: impact ramps a later step's displacement over the step; leave the amplitude out", b.set)));
        }
        // a 0 in the first step, or in a later dynamic one without a ramp: held where the
        // nodes are (CalculiX would move them back to 0 at once, a jump no step follows)
        if b.value == 0.0 && (!later || (b.amplitude.is_none() && !ramp)) {
            return Ok(None);
        }
        if b.amplitude.is_none() && !ramp {
            let at = if later {
                "at the step's start"
            } else {
                "at t = 0"
            };
            return Err(self.src.err(b.line, format!("*BOUNDARY {}: a displacement of {} without an amplitude, which a dynamic step applies at once: a jump {at} that no time step follows; give the *STEP AMPLITUDE=RAMP{}", b.set, b.value, if later { "" } else { " or the *BOUNDARY an AMPLITUDE=" })));
        }
        let mut d = [0.0; 3];
        for &k in b.dofs.iter().filter(|&&k| k <= 3) {
            d[k - 1] = b.value;
        }
        let table = match &b.amplitude {
            Some(name) => self.named_amplitude(g, name, b.line)?,
            None => Vec::new(),
        };
        Ok(Some((d, table)))
    }

    /// The solids holding nodes of `set`; `None` where it names only a rigid body's node.
    fn solids<'b>(
        &self,
        bodies: &'b [(DeckBody, BodyParts)],
        set: &str,
        line: usize,
        on: &On,
    ) -> Result<Option<Vec<Holder<'b>>>> {
        if on.rigid(set) && (set.parse::<u64>().is_ok() || holders(bodies, set).is_empty()) {
            return Ok(None);
        }
        // a node number: the mesh's set of that one node
        let named = match set.parse::<u64>() {
            Ok(id) => crate::mesh::abaqus::numbered_set(id),
            Err(_) => set.to_string(),
        };
        self.holders(bodies, &named, line).map(Some)
    }

    /// The bodies with the initial velocities of the deck, line by line in its order: a node
    /// set that holds a whole body's nodes gives the body's velocity, one that holds part of
    /// them (or a node number) the component of its line over the body's; once a body has
    /// such a part, its whole-body lines that follow are components of their own too.
    fn velocities(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        on: &On,
    ) -> Result<(Vec<DeckBody>, Vec<DeckVelocity>)> {
        let mut out: Vec<DeckBody> = bodies.iter().map(|(b, _)| b.clone()).collect();
        let mut parts: Vec<DeckVelocity> = Vec::new();
        for (set, dof, value, line) in &g.velocities {
            let Some(found) = self.solids(bodies, set, *line, on)? else {
                continue;
            };
            if *dof > 3 {
                return Err(self.src.err(*line, format!("*INITIAL CONDITIONS on `{set}`: dofs 4-6 are rotations, which a solid's nodes do not have (a rigid body's reference node does)")));
            }
            for h in &found {
                give_velocity((&mut out, &mut parts), h, dof - 1, *value);
            }
        }
        Ok((out, parts))
    }

    /// Each later step's start (the steps before it end to end) and the dependent dofs
    /// whose equations it removes; a later step without a procedure is refused.
    fn later_steps(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        on: &On,
    ) -> Result<Vec<super::DeckLaterStep>> {
        let mut start = g.step.as_ref().map_or(0.0, |s| s.end_time);
        let mut out = Vec::with_capacity(g.later.len());
        for l in &g.later {
            let period = l.period.ok_or_else(|| {
                self.src.err(
                    l.line,
                    "a later *STEP without *DYNAMIC or *STATIC: give it its procedure",
                )
            })?;
            let remove = match &l.remove {
                None => None,
                Some(DeckRemoval::All) => Some(Vec::new()),
                Some(DeckRemoval::Dofs(dofs)) => {
                    let mut each = Vec::with_capacity(dofs.len());
                    for (set, dof, line) in dofs {
                        let Some(found) = self.solids(bodies, set, *line, on)? else {
                            return Err(self.src.err(*line, format!("*EQUATION, REMOVE on `{set}`, a rigid body's node: impact's constraints act on solids")));
                        };
                        each.extend(
                            found
                                .iter()
                                .map(|h| (h.body.name.clone(), h.set.clone(), *dof)),
                        );
                    }
                    Some(each)
                }
            };
            let fixes = self.fixes((g, &l.boundaries, Some(l)), bodies, on)?;
            out.push(super::DeckLaterStep {
                start,
                method: l.method,
                time_step: l.method.and(l.increment),
                end: start + period,
                remove,
                release_fixes: l.renew,
                fixes,
                friction: self.friction_changes(g, l),
            });
            start += period;
        }
        Ok(out)
    }

    /// The increment every step runs at: the smallest of theirs, of which each step's
    /// period must be a whole number (a step's start lands on an increment); the smallest
    /// minimum increment. Returns a note for each step whose increment changes.
    fn common_increment(&self, g: &Gathered, step: &mut DeckStep) -> Result<Vec<(String, usize)>> {
        let Some(first) = g.step.as_ref() else {
            return Ok(Vec::new());
        };
        // the steps of the first step's procedure run at one increment
        let alike = || g.later.iter().filter(|l| l.method.is_none());
        let Some(dt) = (alike().filter_map(|l| l.increment))
            .chain(first.time_step)
            .min_by(f64::total_cmp)
        else {
            return Ok(Vec::new());
        };
        step.time_step = Some(dt);
        step.minimum_step = (alike().filter_map(|l| l.minimum))
            .chain(first.minimum_step)
            .min_by(f64::total_cmp);
        let steps = std::iter::once((first.end_time, first.time_step, g.step_line))
            .chain(alike().map(|l| (l.period.unwrap_or(0.0), l.increment, l.line)));
        let mut notes = Vec::new();
        for (period, increment, line) in steps {
            let whole = period / dt;
            if (whole - whole.round()).abs() > 1e-9 * whole.max(1.0) {
                return Err(self.src.err(line, format!("a step of {period} is not a whole number of increments of {dt}, the smallest of the steps': its end would fall between two of them")));
            }
            if let Some(h) = increment.filter(|&h| h != dt) {
                notes.push((
                    format!("STEP increment {h} (run at {dt}, the smallest of the deck's steps')"),
                    line,
                ));
            }
        }
        Ok(notes)
    }

    /// A later step's `*CHANGE FRICTION`s as (contact, coefficient, stick slope): every
    /// pair of the interaction changes.
    fn friction_changes(&self, g: &Gathered, l: &LaterStep) -> Vec<(String, f64, Option<f64>)> {
        let static_step = g.step.as_ref().is_some_and(|s| s.minimum_step.is_some());
        let mut out = Vec::new();
        for (interaction, mu, slope) in &l.friction {
            for (slave, master, _, _) in g.pairs.iter().filter(|p| &p.2 == interaction) {
                out.push((
                    format!("{slave}-{master}"),
                    *mu,
                    slope.filter(|_| static_step),
                ));
            }
        }
        out
    }

    /// The contact pairs, and the rigid bodies whose surfaces they name as masters (each
    /// with that surface).
    /// Each `*EQUATION`'s terms on the bodies: a node number as the body's `node N` set.
    fn equations(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        on: &On,
    ) -> Result<Vec<Vec<super::DeckTerm>>> {
        let mut out = Vec::with_capacity(g.equations.len());
        for (terms, line) in &g.equations {
            let mut e = Vec::with_capacity(terms.len());
            for (set, dof, c) in terms {
                let Some(found) = self.solids(bodies, set, *line, on)? else {
                    return Err(self.src.err(*line, format!("*EQUATION on `{set}`, a rigid body's node: impact's constraints act on solids")));
                };
                let [h] = &found[..] else {
                    return Err(self.src.err(
                        *line,
                        format!(
                            "*EQUATION: `{set}` lies on {} bodies; a term is one node's",
                            found.len()
                        ),
                    ));
                };
                e.push((h.body.name.clone(), h.set.clone(), *dof, *c));
            }
            out.push(e);
        }
        Ok(out)
    }

    fn contacts(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        rigid: &Rigids,
    ) -> Result<(Vec<DeckContact>, Vec<DeckRigid>)> {
        let owner = |surface: &str, line: usize| self.surface_owner(g, bodies, surface, line);
        let mut out = Vec::new();
        let mut used: Vec<DeckRigid> = Vec::new();
        for (slave, master, interaction, line) in &g.pairs {
            let friction = *g.friction.get(interaction).ok_or_else(|| {
                self.src.err(
                    *line,
                    format!("no *SURFACE INTERACTION named `{interaction}`"),
                )
            })?;
            let on_both = rigid.with_surface(master).is_some()
                && (bodies.iter())
                    .any(|(_, p)| (p.surfaces.iter()).any(|s| s.name.eq_ignore_ascii_case(master)));
            if on_both {
                return Err(self.src.err(*line, format!("surface `{master}` lies on a rigid body and on a deformable one: a contact surface is one body's")));
            }
            if rigid.with_surface(slave).is_some() {
                return Err(self.src.err(*line, format!("surface `{slave}` lies on a rigid body: a rigid body is a contact pair's master side")));
            }
            let primary = match rigid.with_surface(master) {
                Some((i, surface)) => {
                    self.rigid_master(&rigid.bodies[i].0, surface, &mut used, *line)?
                }
                None => {
                    let (body, surface) = owner(master, *line)?;
                    PrimarySide::Surface(body, surface)
                }
            };
            let static_step = g.step.as_ref().is_some_and(|s| s.minimum_step.is_some());
            let stiffness = g.stiffness.get(interaction).filter(|_| static_step);
            let secondary_nodes = (g.node_surfaces.iter()).any(|s| s.eq_ignore_ascii_case(slave));
            out.push(DeckContact {
                pressure_law: stiffness.map(|s| s.0),
                stick_slope: g
                    .stick
                    .get(interaction)
                    .filter(|_| static_step)
                    .map(|s| s.0),
                name: format!("{slave}-{master}"),
                secondary: match secondary_nodes {
                    true => self.node_surface_owner(bodies, slave, *line)?,
                    false => owner(slave, *line)?,
                },
                secondary_nodes,
                adjust: g.adjust.get(line).copied(),
                primary,
                friction,
            });
        }
        Ok((out, used))
    }

    /// The deformable body whose elements hold element surface `surface`.
    fn surface_owner(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        surface: &str,
        line: usize,
    ) -> Result<(String, String)> {
        let mut found = (bodies.iter()).filter_map(|(b, p)| {
            p.surfaces
                .iter()
                .find(|s| s.name.eq_ignore_ascii_case(surface))
                .map(|s| (b.name.clone(), s.name.clone()))
        });
        let first = found.next().ok_or_else(|| {
            let message = match g.node_surfaces.iter().any(|s| s.eq_ignore_ascii_case(surface)) {
                true => format!("surface `{surface}` is a node-based surface (*SURFACE, TYPE=NODE): a master side is element faces"),
                false => format!("no body's elements hold surface `{surface}`"),
            };
            self.src.err(line, message)
        })?;
        if found.next().is_some() {
            return Err(self.src.err(
                line,
                format!("surface `{surface}` lies on two bodies: a contact or tie surface is one body's"),
            ));
        }
        Ok(first)
    }

    /// The `*TIE`s: the slave side a body's element or node-based surface, the master side
    /// a deformable body's element surface.
    fn ties(
        &self,
        g: &Gathered,
        bodies: &[(DeckBody, BodyParts)],
        rigid: &Rigids,
    ) -> Result<Vec<DeckTie>> {
        let mut out = Vec::with_capacity(g.ties.len());
        for (name, slave, master, tolerance, adjust, line) in &g.ties {
            for side in [slave, master] {
                if rigid.with_surface(side).is_some() {
                    return Err(self.src.err(*line, format!("surface `{side}` lies on a rigid body: impact ties two deformable bodies' surfaces")));
                }
            }
            let secondary_nodes = (g.node_surfaces.iter()).any(|s| s.eq_ignore_ascii_case(slave));
            out.push(DeckTie {
                name: name.clone(),
                secondary: match secondary_nodes {
                    true => self.node_surface_owner(bodies, slave, *line)?,
                    false => self.surface_owner(g, bodies, slave, *line)?,
                },
                secondary_nodes,
                primary: self.surface_owner(g, bodies, master, *line)?,
                tolerance: *tolerance,
                adjust: *adjust,
            });
        }
        Ok(out)
    }

    /// The body whose nodes a node-based surface's set holds: one body's (its nodes on
    /// several bodies are refused).
    fn node_surface_owner(
        &self,
        bodies: &[(DeckBody, BodyParts)],
        surface: &str,
        line: usize,
    ) -> Result<(String, String)> {
        let mut found = (bodies.iter()).filter_map(|(b, p)| {
            (p.node_sets.iter())
                .find(|s| s.name.eq_ignore_ascii_case(surface) && !s.nodes.is_empty())
                .map(|s| (b.name.clone(), s.name.clone()))
        });
        let first = found.next().ok_or_else(|| {
            self.src.err(
                line,
                format!("node-based surface `{surface}` holds no node of a deformable body"),
            )
        })?;
        match found.next() {
            Some((other, _)) => Err(self.src.err(line, format!("node-based surface `{surface}` holds nodes of bodies `{}` and `{other}`: a contact's slave side is one body's", first.0))),
            None => Ok(first),
        }
    }

    /// A rigid body as a contact's master through `surface`, added to `used` the first
    /// time; a rigid body acts through one surface.
    fn rigid_master(
        &self,
        body: &DeckRigid,
        surface: String,
        used: &mut Vec<DeckRigid>,
        line: usize,
    ) -> Result<PrimarySide> {
        match used.iter().find(|r| r.name == body.name) {
            Some(r) if !r.surface.eq_ignore_ascii_case(&surface) => {
                return Err(self.src.err(line, format!("rigid body `{}` meets its contacts through surfaces {} and {surface}: impact's rigid body has one surface", body.name, r.surface)));
            }
            Some(_) => {}
            None => used.push(DeckRigid {
                surface,
                ..body.clone()
            }),
        }
        Ok(PrimarySide::Rigid(body.name.clone()))
    }
}
