//! Abaqus/CalculiX input deck reader (flat decks, no parts or instances).
//!
//! Keywords read (case-insensitive): `*NODE` (`NSET=`), `*ELEMENT` with `TYPE=C3D8`,
//! `TYPE=C3D8I` (the hex8 with incompatible modes) or `TYPE=C3D4` (`ELSET=`; data lines may continue after a trailing comma), `*NSET` and
//! `*ELSET` (`GENERATE`, or lists of numbers and names of earlier sets), `*SURFACE`
//! (`TYPE=ELEMENT`, the default: lines `element-or-elset, Sn`; `TYPE=NODE`: a node set),
//! `*ORIENTATION` (`SYSTEM=RECTANGULAR`, `DEFINITION=COORDINATES`) and the `ORIENTATION=` of
//! `*SOLID SECTION` (its elements' material axes; [`super::orientation`]).
//! Other keywords (materials, steps, ...) are skipped with their data lines, and listed
//! with their lines in [`FileMesh::skipped`]; `**` starts a comment. `*INCLUDE` is expanded
//! before the deck is read ([`super::deck`]). Every element set is also offered as a node set (its elements' nodes) unless a
//! node set has the same name. Names compare without regard to case, as in Abaqus.

use std::collections::{HashMap, HashSet};

use super::file_mesh::{FileMesh, FileSurface};
use super::orientation::{AbaqusOrientation, ElementAxes};
use super::parse_error::ParseError;
use super::NodeSet;
use crate::element::ElementKind;

type Res<T> = std::result::Result<T, ParseError>;

/// Abaqus face numbering (1-based corner lists) of C3D8 and C3D4 sides S1, S2, ...
const C3D8_SIDES: [&[usize]; 6] = [
    &[1, 2, 3, 4],
    &[5, 8, 7, 6],
    &[1, 5, 6, 2],
    &[2, 6, 7, 3],
    &[3, 7, 8, 4],
    &[4, 8, 5, 1],
];
const C3D4_SIDES: [&[usize]; 4] = [&[1, 2, 3], &[1, 4, 2], &[2, 4, 3], &[3, 4, 1]];

/// The element types read: each type's name, kind and side numbering.
const TYPES: [(&str, ElementKind, &[&[usize]]); 3] = [
    ("C3D8", ElementKind::Hex8, &C3D8_SIDES),
    ("C3D4", ElementKind::Tet4, &C3D4_SIDES),
    ("C3D8I", ElementKind::Hex8i, &C3D8_SIDES),
];

/// The type name and side numbering of a kind.
fn type_of(kind: ElementKind) -> (&'static str, &'static [&'static [usize]]) {
    let (name, _, sides) = TYPES
        .iter()
        .find(|t| t.1 == kind)
        .expect("every kind read has a type");
    (name, sides)
}

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Skip,
    Node,
    Element {
        kind: ElementKind,
    },
    NSet {
        generate: bool,
    },
    ElSet {
        generate: bool,
    },
    SurfaceElement,
    SurfaceNode,
    Orientation,
    /// A keyword whose lines may name a node by its number where a node set may stand
    /// (`*BOUNDARY`, `*INITIAL CONDITIONS`, `*CLOAD`): passed over, its node numbers kept.
    NodeNumbers,
    /// `*EQUATION` data: the node numbers of its terms.
    EquationNodes,
    /// `*DLOAD`: each pressure line's element sides kept as a surface
    /// ([`pressure_surface`]).
    PressureSides,
}

struct Element {
    id: u64,
    kind: ElementKind,
    nodes: Vec<u64>,
    line: usize,
}

/// A set as written: numbers, or names of earlier sets; each number kept once, in the
/// order first named.
#[derive(Default)]
struct Set {
    name: String,
    ids: Vec<u64>,
    seen: HashSet<u64>,
}

impl Set {
    fn add(&mut self, id: u64) {
        if self.seen.insert(id) {
            self.ids.push(id);
        }
    }
}

/// A `*SURFACE, TYPE=ELEMENT` as written: its name, its (element-or-elset, side, line)
/// entries, and the line of its keyword.
type SideSurface = (String, Vec<(String, usize, usize)>, usize);

struct Reader {
    node_ids: HashMap<u64, u32>,
    nodes: Vec<[f64; 3]>,
    elements: Vec<Element>,
    /// Element number -> index in `elements`.
    element_ids: HashMap<u64, usize>,
    nsets: Vec<Set>,
    elsets: Vec<Set>,
    surfaces: Vec<SideSurface>,
    node_surfaces: Vec<(String, Vec<String>, usize)>,
    orientations: Vec<AbaqusOrientation>,
    /// `*SOLID SECTION`s with an orientation: (elset, orientation name, line).
    sections: Vec<(String, String, usize)>,
    /// Every `*SOLID SECTION`'s element set and line.
    section_sets: Vec<(String, usize)>,
    /// Keywords passed over, with their lines.
    skipped: Vec<(String, usize)>,
    /// The node numbers that `*BOUNDARY` and `*INITIAL CONDITIONS` lines give in place of a
    /// node set: each becomes a set of that one node, named by the number.
    numbered: Vec<u64>,
    /// At most this many nodes and elements are defined (see [`defined_bounds`]).
    max_nodes: usize,
    max_elements: usize,
}

/// The keywords of more than one word that the readers know, as they name them. CalculiX
/// reads a keyword with its blanks dropped (`*SOLIDSECTION` is `*SOLID SECTION`), and so
/// do the readers.
const SPACED: [&str; 22] = [
    "SOLID SECTION",
    "END STEP",
    "CONTACT PAIR",
    "INITIAL CONDITIONS",
    "NODE PRINT",
    "NODE OUTPUT",
    "NODE FILE",
    "EL PRINT",
    "EL FILE",
    "CONTACT PRINT",
    "CONTACT FILE",
    "CONTACT OUTPUT",
    "ELEMENT OUTPUT",
    "ENERGY PRINT",
    "SURFACE INTERACTION",
    "SURFACE BEHAVIOR",
    "RIGID BODY",
    "TIME POINTS",
    "CHANGE FRICTION",
    "SHELL SECTION",
    "BEAM SECTION",
    "MEMBRANE SECTION",
];

/// `s` upper case with its blanks dropped, as CalculiX compares keywords, parameters and
/// their words (`TYPE=SURFACE TO SURFACE` is `SURFACETOSURFACE`).
/// The name of the set of node `id`, where a deck gives a node number in place of a node set
/// (a blank in it: a deck's own set names have none, as CalculiX drops them).
pub(crate) fn numbered_set(id: u64) -> String {
    format!("node {id}")
}

/// The side n of a `*DLOAD` pressure label `Pn` (n from 1).
pub(crate) fn pressure_side(label: &str) -> Option<usize> {
    let l = label.to_ascii_uppercase();
    l.strip_prefix('P')?
        .parse::<usize>()
        .ok()
        .filter(|&n| n >= 1)
}

/// The name of the surface of side n of an element or element set that a `*DLOAD` line
/// presses (a blank in it, so that no deck's surface can take the name).
pub(crate) fn pressure_surface(target: &str, side: usize) -> String {
    format!("{} P{side}", target.to_ascii_uppercase())
}

pub(crate) fn word(s: &str) -> String {
    s.chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| c.to_ascii_uppercase())
        .collect()
}

/// A number as a deck writes it, Fortran's `D` exponent too (`2.1D5`); `None` where it is
/// not one or not finite.
pub(crate) fn real(s: &str) -> Option<f64> {
    let parsed = s.parse::<f64>().ok().or_else(|| {
        let at = s.find(['d', 'D'])?;
        format!("{}e{}", &s[..at], &s[at + 1..]).parse::<f64>().ok()
    });
    parsed.filter(|x| x.is_finite())
}

/// A keyword line's keyword (upper case, in the readers' spelling where it is one they
/// know, however its blanks fall) and its parameters (keys as [`word`] gives them).
pub(crate) fn params(line: &str) -> (String, HashMap<String, String>) {
    let mut parts = line[1..].split(',');
    let given = parts.next().unwrap_or("").trim();
    let squeezed = word(given);
    let keyword = match SPACED.iter().find(|k| word(k) == squeezed) {
        Some(k) => k.to_string(),
        None => given
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .to_ascii_uppercase(),
    };
    let mut map = HashMap::new();
    for p in parts {
        let (k, v) = match p.split_once('=') {
            Some((k, v)) => (k.trim(), v.trim()),
            None => (p.trim(), ""),
        };
        if !k.is_empty() {
            map.insert(word(k), v.to_string());
        }
    }
    (keyword, map)
}

fn find_set<'a>(sets: &'a [Set], name: &str) -> Option<&'a Set> {
    sets.iter().find(|s| s.name.eq_ignore_ascii_case(name))
}

fn set_mut<'a>(sets: &'a mut Vec<Set>, name: &str) -> &'a mut Set {
    match sets.iter().position(|s| s.name.eq_ignore_ascii_case(name)) {
        Some(i) => &mut sets[i],
        None => {
            sets.push(Set {
                name: name.to_string(),
                ..Set::default()
            });
            sets.last_mut().expect("just pushed")
        }
    }
}

fn integer(token: &str, line: usize, what: &str) -> Res<u64> {
    token
        .parse::<u64>()
        .map_err(|_| ParseError::at(line, format!("expected {what}, found `{token}`")))
}

/// Upper bounds of the number of nodes and of elements a deck defines: its data lines under
/// `*NODE` (each defines one node) and under `*ELEMENT` (each element starts one).
fn defined_bounds(text: &str) -> (usize, usize) {
    let (mut nodes, mut elements) = (0, 0);
    let mut keyword = String::new();
    for raw in text.lines() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if line.starts_with('*') {
            keyword = params(line).0;
        } else if keyword == "NODE" {
            nodes += 1;
        } else if keyword == "ELEMENT" {
            elements += 1;
        }
    }
    (nodes, elements)
}

/// Reads a deck's text: every element, or (`elset`) the elements of one `*ELSET` only, a
/// body of a deck that holds several. Restricted, a surface keeps its faces on the set's
/// elements, and one with none is left out.
pub fn read(text: &str, elset: Option<&str>) -> Res<FileMesh> {
    let mut p = Parser::new(text);
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if line.starts_with('*') {
            p.no_pending()?;
            p.keyword(line, line_no)?;
        } else {
            p.data(line, line_no)?;
        }
    }
    p.no_pending()?;
    let kept = match elset {
        None => None,
        Some(name) => Some(p.r.kept_elements(name)?),
    };
    p.r.finish(kept.as_ref())
}

/// A keyword line: its keyword (upper case), its parameters (keys upper case) and its line.
struct Keyword {
    name: String,
    params: HashMap<String, String>,
    line: usize,
}

impl Keyword {
    /// The value of the parameter `key`, refused when it is missing or empty.
    fn need(&self, key: &str) -> Res<String> {
        self.params
            .get(&word(key))
            .filter(|v| !v.is_empty())
            .cloned()
            .ok_or_else(|| ParseError::at(self.line, format!("*{} needs {key}=", self.name)))
    }

    /// The value of the parameter `key`, empty when it is missing.
    fn get(&self, key: &str) -> String {
        self.params.get(&word(key)).cloned().unwrap_or_default()
    }
}

/// The reader's place in a deck: what it has read ([`Reader`]), the keyword block that data
/// lines belong to, and an element whose data line continues on the next line.
struct Parser {
    r: Reader,
    mode: Mode,
    /// The set or surface the block's data lines add to; empty for none.
    set_name: String,
    /// An element being read: its number, then its nodes so far.
    pending: Vec<u64>,
    /// The line where the element in `pending` starts.
    pending_line: usize,
}

impl Parser {
    /// A parser at the start of the deck `text`.
    fn new(text: &str) -> Parser {
        let (max_nodes, max_elements) = defined_bounds(text);
        Parser {
            r: Reader {
                node_ids: HashMap::new(),
                nodes: Vec::new(),
                elements: Vec::new(),
                element_ids: HashMap::new(),
                nsets: Vec::new(),
                elsets: Vec::new(),
                surfaces: Vec::new(),
                node_surfaces: Vec::new(),
                orientations: Vec::new(),
                sections: Vec::new(),
                section_sets: Vec::new(),
                skipped: Vec::new(),
                numbered: Vec::new(),
                max_nodes,
                max_elements,
            },
            mode: Mode::Skip,
            set_name: String::new(),
            pending: Vec::new(),
            pending_line: 0,
        }
    }

    /// Refuses an element whose node list was left unfinished.
    fn no_pending(&self) -> Res<()> {
        if self.pending.is_empty() {
            return Ok(());
        }
        Err(ParseError::at(
            self.pending_line,
            format!("element {} lists too few nodes", self.pending[0]),
        ))
    }

    /// Opens the block of the keyword line `line`.
    fn keyword(&mut self, line: &str, line_no: usize) -> Res<()> {
        let (name, params) = params(line);
        let k = Keyword {
            name,
            params,
            line: line_no,
        };
        let generate = k.params.contains_key("GENERATE");
        self.mode = match k.name.as_str() {
            "NODE" => {
                self.set_name = k.get("NSET");
                Mode::Node
            }
            "ELEMENT" => self.element_keyword(&k)?,
            "NSET" => {
                self.set_name = k.need("NSET")?;
                set_mut(&mut self.r.nsets, &self.set_name);
                Mode::NSet { generate }
            }
            "ELSET" => {
                self.set_name = k.need("ELSET")?;
                set_mut(&mut self.r.elsets, &self.set_name);
                Mode::ElSet { generate }
            }
            "SURFACE" => self.surface_keyword(&k)?,
            "ORIENTATION" => self.orientation_keyword(&k)?,
            "SOLID SECTION" => {
                if let Some(m) = k.params.get("MATERIAL").filter(|m| !m.is_empty()) {
                    // the body's `material` is used, not the deck's
                    self.r.skipped.push((format!("SOLID SECTION MATERIAL={m}"), line_no));
                }
                if let Some(elset) = k.params.get("ELSET").filter(|e| !e.is_empty()) {
                    self.r.section_sets.push((elset.clone(), k.line));
                }
                if let Some(o) = k.params.get("ORIENTATION").filter(|o| !o.is_empty()) {
                    let elset = k.need("ELSET")?;
                    self.r.sections.push((elset, o.clone(), k.line));
                }
                Mode::Skip
            }
            "PART" | "INSTANCE" => {
                return Err(ParseError::at(
                    line_no,
                    format!("*{}: decks with parts and instances are not supported; write a flat deck (nodes and elements at the top level)", k.name),
                ))
            }
            "BOUNDARY" | "INITIAL CONDITIONS" | "CLOAD" => {
                self.r.skipped.push((k.name.clone(), line_no));
                Mode::NodeNumbers
            }
            "EQUATION" => {
                self.r.skipped.push((k.name.clone(), line_no));
                // a later step's `*EQUATION, REMOVE` lists (node, dof) lines
                match k.params.contains_key("REMOVE") {
                    true => Mode::NodeNumbers,
                    false => Mode::EquationNodes,
                }
            }
            "DLOAD" => {
                self.r.skipped.push((k.name.clone(), line_no));
                Mode::PressureSides
            }
            "INCLUDE" => {
                return Err(ParseError::at(
                    line_no,
                    "*INCLUDE is read only in a deck read from a file",
                ))
            }
            _ => {
                self.r.skipped.push((k.name.clone(), line_no));
                Mode::Skip
            }
        };
        Ok(())
    }

    /// Opens an `*ELEMENT` block: its type (C3D8, C3D8I or C3D4) and its `ELSET=`.
    fn element_keyword(&mut self, k: &Keyword) -> Res<Mode> {
        let ty = k.need("TYPE")?.to_ascii_uppercase();
        self.set_name = k.get("ELSET");
        match TYPES.iter().find(|t| t.0 == ty) {
            Some(&(_, kind, _)) => Ok(Mode::Element { kind }),
            None => Err(ParseError::at(
                k.line,
                format!("element type {ty} is not supported: only C3D8 (hex8), C3D8I (hex8i) and C3D4 (tet4) are"),
            )),
        }
    }

    /// Opens an `*ORIENTATION` block: rectangular axes given by coordinates.
    fn orientation_keyword(&mut self, k: &Keyword) -> Res<Mode> {
        let name = k.need("NAME")?;
        let upper = |key: &str, default: &str| {
            k.params
                .get(key)
                .map(|v| v.to_ascii_uppercase())
                .unwrap_or_else(|| default.into())
        };
        let system = upper("SYSTEM", "RECTANGULAR");
        if system != "RECTANGULAR" && system != "R" {
            return Err(ParseError::at(
                k.line,
                format!("*ORIENTATION {name}: SYSTEM={system} is not supported (RECTANGULAR only)"),
            ));
        }
        let definition = upper("DEFINITION", "COORDINATES");
        if definition != "COORDINATES" {
            return Err(ParseError::at(
                k.line,
                format!("*ORIENTATION {name}: DEFINITION={definition} is not supported (COORDINATES only)"),
            ));
        }
        self.r.orientations.push(AbaqusOrientation {
            name,
            lines: Vec::new(),
            line: k.line,
        });
        Ok(Mode::Orientation)
    }

    /// Opens a `*SURFACE` block: `TYPE=ELEMENT` (the default) or `TYPE=NODE`.
    fn surface_keyword(&mut self, k: &Keyword) -> Res<Mode> {
        self.set_name = k.need("NAME")?;
        let ty = k
            .params
            .get("TYPE")
            .map(|t| t.to_ascii_uppercase())
            .unwrap_or_else(|| "ELEMENT".into());
        match ty.as_str() {
            "ELEMENT" => {
                let surface = (self.set_name.clone(), Vec::new(), k.line);
                self.r.surfaces.push(surface);
                Ok(Mode::SurfaceElement)
            }
            "NODE" => {
                let surface = (self.set_name.clone(), Vec::new(), k.line);
                self.r.node_surfaces.push(surface);
                Ok(Mode::SurfaceNode)
            }
            other => Err(ParseError::at(
                k.line,
                format!("*SURFACE TYPE={other} is not supported (ELEMENT or NODE)"),
            )),
        }
    }

    /// Reads a data line of the open block.
    fn data(&mut self, line: &str, line_no: usize) -> Res<()> {
        let fields: Vec<&str> = line
            .split(',')
            .map(|f| f.trim())
            .filter(|f| !f.is_empty())
            .collect();
        match self.mode {
            Mode::Skip => Ok(()),
            Mode::PressureSides => {
                self.pressure_line(&fields, line_no);
                Ok(())
            }
            Mode::NodeNumbers => {
                if let Some(id) = fields.first().and_then(|f| f.parse::<u64>().ok()) {
                    self.r.numbered.push(id);
                }
                Ok(())
            }
            // a term count alone, or (node, dof, coefficient) triples
            Mode::EquationNodes => {
                let given: Vec<&str> = fields
                    .iter()
                    .map(|f| f.trim())
                    .filter(|f| !f.is_empty())
                    .collect();
                if given.len() >= 3 {
                    let ids = given
                        .iter()
                        .step_by(3)
                        .filter_map(|f| f.parse::<u64>().ok());
                    self.r.numbered.extend(ids);
                }
                Ok(())
            }
            Mode::Node => self.node_line(&fields, line, line_no),
            Mode::Element { kind } => self.element_line(kind, &fields, line, line_no),
            Mode::NSet { generate } => set_line(
                &mut self.r,
                &self.set_name,
                &fields,
                generate,
                true,
                line_no,
            ),
            Mode::ElSet { generate } => set_line(
                &mut self.r,
                &self.set_name,
                &fields,
                generate,
                false,
                line_no,
            ),
            Mode::SurfaceElement => self.side_line(&fields, line, line_no),
            Mode::Orientation => {
                let numbers = fields
                    .iter()
                    .map(|f| real(f))
                    .collect::<Option<Vec<f64>>>()
                    .ok_or_else(|| {
                        ParseError::at(
                            line_no,
                            format!("an *ORIENTATION line needs numbers, found `{line}`"),
                        )
                    })?;
                let o = self
                    .r
                    .orientations
                    .last_mut()
                    .expect("an orientation is open");
                o.lines.push(numbers);
                Ok(())
            }
            Mode::SurfaceNode => {
                let Some(first) = fields.first() else {
                    return Err(ParseError::at(
                        line_no,
                        format!(
                            "a *SURFACE, TYPE=NODE line needs a node set name or a node number, found `{line}`"
                        ),
                    ));
                };
                self.r
                    .node_surfaces
                    .last_mut()
                    .expect("a surface is open")
                    .1
                    .push(first.to_string());
                Ok(())
            }
        }
    }

    /// Reads a `*NODE` data line, `id, x, y, z`.
    fn node_line(&mut self, fields: &[&str], line: &str, line_no: usize) -> Res<()> {
        if fields.len() < 4 {
            return Err(ParseError::at(
                line_no,
                format!("a *NODE line needs `id, x, y, z`, found `{line}`"),
            ));
        }
        let id = integer(fields[0], line_no, "a node number")?;
        if id == 0 {
            return Err(ParseError::at(line_no, "node 0: node numbers start at 1"));
        }
        let mut p = [0.0; 3];
        for a in 0..3 {
            p[a] = real(fields[1 + a]).ok_or_else(|| {
                ParseError::at(
                    line_no,
                    format!("expected a coordinate, found `{}`", fields[1 + a]),
                )
            })?;
        }
        let r = &mut self.r;
        if r.node_ids.insert(id, r.nodes.len() as u32).is_some() {
            return Err(ParseError::at(
                line_no,
                format!("node {id} is defined twice"),
            ));
        }
        r.nodes.push(p);
        if !self.set_name.is_empty() {
            set_mut(&mut r.nsets, &self.set_name).add(id);
        }
        Ok(())
    }

    /// Reads an `*ELEMENT` data line (or its continuation) of an element of a kind.
    fn element_line(
        &mut self,
        kind: ElementKind,
        fields: &[&str],
        line: &str,
        line_no: usize,
    ) -> Res<()> {
        if self.pending.is_empty() {
            self.pending_line = line_no;
        }
        for f in fields {
            self.pending
                .push(integer(f, line_no, "an element or node number")?);
        }
        let (ty, corners) = (type_of(kind).0, kind.corners());
        if self.pending.len() > corners + 1 {
            return Err(ParseError::at(
                self.pending_line,
                format!(
                    "element {} lists {} nodes; a {ty} element has {corners}",
                    self.pending[0],
                    self.pending.len() - 1,
                ),
            ));
        }
        if self.pending.len() == corners + 1 {
            self.add_pending(kind)
        } else if !line.ends_with(',') {
            Err(ParseError::at(
                self.pending_line,
                format!(
                    "element {} lists {} nodes; a {ty} element has {corners} (continue a long line with a trailing comma)",
                    self.pending[0],
                    self.pending.len() - 1,
                ),
            ))
        } else {
            Ok(())
        }
    }

    /// Adds the complete element in `pending` (and to the block's `ELSET=`), and clears it.
    fn add_pending(&mut self, kind: ElementKind) -> Res<()> {
        let r = &mut self.r;
        let id = self.pending[0];
        if r.element_ids.insert(id, r.elements.len()).is_some() {
            return Err(ParseError::at(
                self.pending_line,
                format!("element {id} is defined twice"),
            ));
        }
        r.elements.push(Element {
            id,
            kind,
            nodes: self.pending[1..].to_vec(),
            line: self.pending_line,
        });
        if !self.set_name.is_empty() {
            set_mut(&mut r.elsets, &self.set_name).add(id);
        }
        self.pending.clear();
        Ok(())
    }

    /// Keeps the sides of a `*DLOAD` line `element-or-elset, Pn, value` as the surface
    /// [`pressure_surface`] (once, however many lines name it); other lines (`GRAV`, ...)
    /// are the scene reader's.
    fn pressure_line(&mut self, fields: &[&str], line_no: usize) {
        let (Some(target), Some(label)) = (fields.first(), fields.get(1)) else {
            return;
        };
        let Some(side) = pressure_side(label) else {
            return;
        };
        let name = pressure_surface(target, side);
        if !self.r.surfaces.iter().any(|s| s.0 == name) {
            let entry = (target.to_string(), side, line_no);
            self.r.surfaces.push((name, vec![entry], line_no));
        }
    }

    /// Reads a `*SURFACE, TYPE=ELEMENT` data line, `element-or-elset, Sn`.
    fn side_line(&mut self, fields: &[&str], line: &str, line_no: usize) -> Res<()> {
        if fields.len() != 2 {
            return Err(ParseError::at(
                line_no,
                format!("a *SURFACE line needs `element-or-elset, Sn`, found `{line}`"),
            ));
        }
        let side = fields[1]
            .to_ascii_uppercase()
            .strip_prefix('S')
            .and_then(|s| s.parse::<usize>().ok())
            .filter(|&s| s >= 1)
            .ok_or_else(|| {
                ParseError::at(
                    line_no,
                    format!("expected a side S1, S2, ..., found `{}`", fields[1]),
                )
            })?;
        self.r
            .surfaces
            .last_mut()
            .expect("a surface is open")
            .1
            .push((fields[0].to_string(), side, line_no));
        Ok(())
    }
}

/// Adds a set's data line to the set `name`: plain numbers, a `GENERATE` triple, or names
/// of earlier sets.
///
/// A set may not name more distinct numbers than the deck can define. Every node is defined
/// by a `*NODE` data line of its own and every element starts a data line under `*ELEMENT`
/// ([`defined_bounds`]), so a set of more numbers than those lines names one that no line
/// defines, which [`Reader::finish`] refuses anyway: the bound is exact (it refuses no deck
/// that would otherwise be read). A `GENERATE` range is counted before it is expanded, so
/// `1, 9223372036854775807` is refused without allocating, and the set is checked after every
/// field, so names of earlier sets cannot make it grow without bound. (An element set hidden
/// by a node set of the same name is not resolved by `finish`; it may not name undefined
/// elements either.)
fn set_line(
    r: &mut Reader,
    name: &str,
    fields: &[&str],
    generate: bool,
    node: bool,
    line: usize,
) -> Res<()> {
    let (what, limit, keyword, sets) = if node {
        ("node", r.max_nodes, "*NODE", &mut r.nsets)
    } else {
        ("element", r.max_elements, "*ELEMENT", &mut r.elsets)
    };
    set_mut(sets, name);
    let t = sets
        .iter()
        .position(|s| s.name.eq_ignore_ascii_case(name))
        .expect("just made");
    let defines = format!(
        "the file defines at most {limit} {what}s (one per {keyword} data line), so the set would name {what}s that do not exist"
    );
    let set_keyword = if node { "*NSET" } else { "*ELSET" };
    if generate {
        generate_line(&mut sets[t], fields, line, what, limit, &defines)?;
    } else {
        list_line(sets, t, fields, line, limit, set_keyword)?;
    }
    let n = sets[t].ids.len();
    if n > limit {
        return Err(ParseError::at(
            line,
            format!("{set_keyword} {name} names {n} distinct {what} numbers here, but {defines}"),
        ));
    }
    Ok(())
}

/// Adds a `GENERATE` line `first, last[, step]` to `set`, refusing a range of more than
/// `limit` numbers before expanding it.
fn generate_line(
    set: &mut Set,
    fields: &[&str],
    line: usize,
    what: &str,
    limit: usize,
    defines: &str,
) -> Res<()> {
    if !(2..=3).contains(&fields.len()) {
        return Err(ParseError::at(
            line,
            "a GENERATE line needs `first, last[, step]`",
        ));
    }
    let a = integer(fields[0], line, "a first number")?;
    let b = integer(fields[1], line, "a last number")?;
    let s = match fields.get(2) {
        Some(f) => integer(f, line, "a step")?,
        None => 1,
    };
    if s == 0 || b < a {
        return Err(ParseError::at(
            line,
            format!("GENERATE {a}, {b}, {s}: need first <= last and step >= 1"),
        ));
    }
    let count = u128::from(b - a) / u128::from(s) + 1;
    if count > limit as u128 {
        return Err(ParseError::at(
            line,
            format!("GENERATE {a}, {b}, {s} makes {count} {what} numbers, but {defines}"),
        ));
    }
    let mut id = a;
    loop {
        set.add(id);
        match id.checked_add(s) {
            Some(next) if next <= b => id = next,
            _ => break,
        }
    }
    Ok(())
}

/// Adds a line of numbers and names of earlier sets to `sets[t]`, stopping once it holds
/// more than `limit` numbers (`set_keyword` names the kind of set, for messages).
fn list_line(
    sets: &mut [Set],
    t: usize,
    fields: &[&str],
    line: usize,
    limit: usize,
    set_keyword: &str,
) -> Res<()> {
    for f in fields {
        match f.parse::<u64>() {
            Ok(id) => sets[t].add(id),
            Err(_) => {
                let from = sets
                    .iter()
                    .position(|s| s.name.eq_ignore_ascii_case(f))
                    .ok_or_else(|| {
                        ParseError::at(
                            line,
                            format!(
                                "`{f}` is neither a number nor the name of an earlier {set_keyword}"
                            ),
                        )
                    })?;
                if from == t {
                    return Err(ParseError::at(
                        line,
                        format!("{set_keyword} {f} names itself"),
                    ));
                }
                for k in 0..sets[from].ids.len() {
                    let id = sets[from].ids[k];
                    sets[t].add(id);
                }
            }
        }
        if sets[t].ids.len() > limit {
            break;
        }
    }
    Ok(())
}

impl Reader {
    fn node(&self, id: u64, line: usize, whose: &str) -> Res<u32> {
        self.node_ids.get(&id).copied().ok_or_else(|| {
            ParseError::at(
                line,
                format!("{whose} uses node {id}, which no *NODE defines"),
            )
        })
    }

    fn element(&self, id: u64, line: usize) -> Res<usize> {
        self.element_ids
            .get(&id)
            .copied()
            .ok_or_else(|| ParseError::at(line, format!("element {id} is not defined")))
    }

    /// The indices of the elements of the `*ELSET` named `name`.
    fn kept_elements(&self, name: &str) -> Res<HashSet<usize>> {
        let set = find_set(&self.elsets, name).ok_or_else(|| {
            let known: Vec<&str> = self.elsets.iter().map(|s| s.name.as_str()).collect();
            ParseError::whole(format!(
                "no *ELSET named `{name}`; the deck's element sets are {known:?}"
            ))
        })?;
        set.ids.iter().map(|&id| self.element(id, 0)).collect()
    }

    /// The mesh of every element, or of the `kept` ones.
    fn finish(self, kept: Option<&HashSet<usize>>) -> Res<FileMesh> {
        let mut mesh = FileMesh {
            nodes: self.nodes.clone(),
            ..Default::default()
        };
        self.one_section_each()?;
        let keeps = |k: usize| kept.is_none_or(|s| s.contains(&k));
        let corners = self.add_elements(&mut mesh, &keeps)?;
        for surface in &self.surfaces {
            let s = self.side_surface(surface, &corners, &keeps)?;
            if kept.is_none() || !s.faces.is_empty() {
                mesh.surfaces.push(s);
            }
        }
        let mut node_sets = Vec::new();
        for s in &self.nsets {
            node_sets.push(self.nset(s)?);
        }
        for surface in &self.node_surfaces {
            node_sets.push(self.node_surface(surface)?);
        }
        // a node number where a set may stand: the set of that node, named so that no deck's
        // set can take the name (a number no *NODE gives is left to the scene, which names
        // its line)
        let mut seen = HashSet::new();
        for &id in &self.numbered {
            if let (Some(&n), true) = (self.node_ids.get(&id), seen.insert(id)) {
                node_sets.push(NodeSet {
                    name: numbered_set(id),
                    nodes: vec![n],
                });
            }
        }
        for s in &self.elsets {
            if node_sets
                .iter()
                .any(|n| n.name.eq_ignore_ascii_case(&s.name))
            {
                continue;
            }
            node_sets.push(self.elset_nodes(s, &corners)?);
        }
        mesh.node_sets = node_sets;
        mesh.axes = self.element_axes(&keeps)?;
        mesh.skipped = self.skipped.clone();
        Ok(mesh)
    }

    /// Refuses an element that two `*SOLID SECTION`s name (it would be two overlapping
    /// bodies' element).
    fn one_section_each(&self) -> Res<()> {
        let mut section: HashMap<u64, usize> = HashMap::new();
        for (k, (elset, line)) in self.section_sets.iter().enumerate() {
            let Some(set) = find_set(&self.elsets, elset) else {
                continue;
            };
            for &id in &set.ids {
                if let Some(first) = section.insert(id, k).filter(|&f| f != k) {
                    let other = &self.section_sets[first].0;
                    return Err(ParseError::at(
                        *line,
                        format!("element {id} is in two *SOLID SECTIONs (ELSET={other}, and ELSET={elset} here): an element is one section's"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The axes of each element in a `*SOLID SECTION` with an orientation, by block as
    /// [`Self::add_elements`] places the elements.
    fn element_axes(&self, keeps: &dyn Fn(usize) -> bool) -> Res<ElementAxes> {
        if self.sections.is_empty() {
            return Ok(ElementAxes::default());
        }
        let mut per_element: Vec<Option<crate::material::Rotation>> =
            vec![None; self.elements.len()];
        for (elset, name, line) in &self.sections {
            let o = (self.orientations.iter())
                .find(|o| o.name.eq_ignore_ascii_case(name))
                .ok_or_else(|| {
                    ParseError::at(
                        *line,
                        format!("*SOLID SECTION: no *ORIENTATION named `{name}`"),
                    )
                })?;
            let axes = o.axes()?;
            for id in self.elements_named(elset, *line)? {
                let e = *self.element_ids.get(&id).ok_or_else(|| {
                    ParseError::at(
                        *line,
                        format!("*SOLID SECTION ELSET={elset}: element {id} is not defined"),
                    )
                })?;
                if per_element[e].replace(axes).is_some() {
                    return Err(ParseError::at(
                        *line,
                        format!("element {id} is in two *SOLID SECTIONs with an orientation"),
                    ));
                }
            }
        }
        let mut axes = ElementAxes::default();
        for (k, (e, a)) in self.elements.iter().zip(per_element).enumerate() {
            if keeps(k) {
                axes.push(e.kind, a);
            }
        }
        Ok(axes)
    }

    /// Adds the elements `keeps` takes to `mesh`'s blocks; returns every element's node
    /// indices.
    fn add_elements(
        &self,
        mesh: &mut FileMesh,
        keeps: &dyn Fn(usize) -> bool,
    ) -> Res<Vec<Vec<u32>>> {
        let mut corners: Vec<Vec<u32>> = Vec::with_capacity(self.elements.len());
        for (k, e) in self.elements.iter().enumerate() {
            let whose = format!("element {}", e.id);
            let c: Vec<u32> = e
                .nodes
                .iter()
                .map(|&n| self.node(n, e.line, &whose))
                .collect::<Res<_>>()?;
            if keeps(k) {
                mesh.elements.push(e.kind, &c, 0);
            }
            corners.push(c);
        }
        Ok(corners)
    }

    /// The faces of a `*SURFACE, TYPE=ELEMENT` on the elements `keeps` takes (`corners`:
    /// each element's node indices).
    fn side_surface(
        &self,
        (name, entries, surface_line): &SideSurface,
        corners: &[Vec<u32>],
        keeps: &dyn Fn(usize) -> bool,
    ) -> Res<FileSurface> {
        let mut faces = Vec::new();
        // each (element, side) once, however many lines name it: the faces are at most
        // six per element, not lines times elements
        let mut done = HashSet::new();
        for (target, side, line) in entries {
            for id in self.elements_named(target, *line)? {
                let k = self.element(id, *line)?;
                if !keeps(k) || !done.insert((k, *side)) {
                    continue;
                }
                let c = &corners[k];
                let sides = type_of(self.elements[k].kind).1;
                let s = sides.get(side - 1).ok_or_else(|| {
                    ParseError::at(
                        *line,
                        format!("element {id} has sides S1 to S{}, not S{side}", sides.len()),
                    )
                })?;
                faces.push(s.iter().map(|&k| c[k - 1]).collect());
            }
        }
        Ok(FileSurface {
            name: name.clone(),
            faces,
            line: *surface_line,
        })
    }

    /// The element numbers an entry names (a surface line's or a section's `ELSET=`): an
    /// element number or an `*ELSET`'s name.
    fn elements_named(&self, target: &str, line: usize) -> Res<Vec<u64>> {
        Ok(match target.parse::<u64>() {
            Ok(id) => vec![id],
            Err(_) => find_set(&self.elsets, target)
                .ok_or_else(|| ParseError::at(line, format!("no *ELSET named `{target}`")))?
                .ids
                .clone(),
        })
    }

    /// The node set of an `*NSET` (an undefined node is refused without a line).
    fn nset(&self, s: &Set) -> Res<NodeSet> {
        let nodes = s
            .ids
            .iter()
            .map(|&n| self.node(n, 0, &format!("*NSET {}", s.name)))
            .collect::<Res<Vec<u32>>>()
            .map_err(|mut e| {
                e.line = None;
                e
            })?;
        Ok(NodeSet {
            name: s.name.clone(),
            nodes,
        })
    }

    /// The node set of a `*SURFACE, TYPE=NODE`: its node numbers and `*NSET`s, each node once.
    fn node_surface(&self, (name, entries, line): &(String, Vec<String>, usize)) -> Res<NodeSet> {
        let mut nodes = Vec::new();
        // each node once, however many entries name it
        let mut seen = HashSet::new();
        let mut add = |n: u32| {
            if seen.insert(n) {
                nodes.push(n);
            }
        };
        for t in entries {
            match t.parse::<u64>() {
                Ok(id) => add(self.node(id, *line, &format!("surface {name}"))?),
                Err(_) => {
                    let set = find_set(&self.nsets, t)
                        .ok_or_else(|| ParseError::at(*line, format!("no *NSET named `{t}`")))?;
                    for &id in &set.ids {
                        add(self.node(id, *line, &format!("surface {name}"))?);
                    }
                }
            }
        }
        Ok(NodeSet {
            name: name.clone(),
            nodes,
        })
    }

    /// The node set of an `*ELSET`: its elements' nodes (`corners`), in element order.
    fn elset_nodes(&self, s: &Set, corners: &[Vec<u32>]) -> Res<NodeSet> {
        let mut nodes = Vec::new();
        for &id in &s.ids {
            let k = self.element(id, 0).map_err(|mut e| {
                e.line = None;
                e.message = format!("*ELSET {}: {}", s.name, e.message);
                e
            })?;
            nodes.extend_from_slice(&corners[k]);
        }
        Ok(NodeSet {
            name: s.name.clone(),
            nodes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "\
** a unit cube as one C3D8, bottom face as a surface
*HEADING
unit cube
*NODE, NSET=ALL
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
*ELEMENT, TYPE=C3D8, ELSET=CUBE
10, 1, 2, 3, 4,
    5, 6, 7, 8
*NSET, NSET=TOP, GENERATE
5, 8
*SURFACE, NAME=Bottom, TYPE=ELEMENT
CUBE, S1
*MATERIAL, NAME=STEEL
*ELASTIC
2.1e5, 0.3
";

    #[test]
    fn reads_nodes_elements_sets_and_surfaces() {
        let m = read(CUBE, None).unwrap();
        assert_eq!(m.nodes.len(), 8);
        assert_eq!(
            m.elements.block(ElementKind::Hex8).nodes,
            (0..8).collect::<Vec<u32>>()
        );
        assert_eq!(m.surfaces[0].name, "Bottom");
        assert_eq!(m.surfaces[0].faces, vec![vec![0, 1, 2, 3]]);
        let top = m.node_sets.iter().find(|s| s.name == "TOP").unwrap();
        assert_eq!(top.nodes, vec![4, 5, 6, 7]);
        assert!(m.node_sets.iter().any(|s| s.name == "CUBE"));
    }

    #[test]
    fn an_unsupported_element_type_names_the_type_and_line() {
        let t = CUBE.replace("TYPE=C3D8,", "TYPE=C3D20R,");
        let e = read(&t, None).unwrap_err();
        assert_eq!(e.line, Some(13));
        assert!(e.message.contains("C3D20R"), "{}", e.message);
    }

    #[test]
    fn a_missing_node_names_the_element_line() {
        let t = CUBE.replace("5, 6, 7, 8", "5, 6, 7, 99");
        let e = read(&t, None).unwrap_err();
        assert_eq!(e.line, Some(14));
        assert!(e.message.contains("node 99"), "{}", e.message);
    }

    /// A `*SURFACE, TYPE=NODE` data line with no field is an error naming its line, not a
    /// panic.
    #[test]
    fn an_empty_node_surface_line_names_the_line() {
        let t = CUBE.replace(
            "*MATERIAL, NAME=STEEL",
            "*SURFACE, NAME=TopNodes, TYPE=NODE\n,\n*MATERIAL, NAME=STEEL",
        );
        let e = read(&t, None).unwrap_err();
        assert_eq!(e.line, Some(21));
        assert!(e.message.contains("TYPE=NODE"), "{}", e.message);
    }

    /// Writes `text` as `<name>.inp` in a fresh temporary folder and imports it; returns the
    /// path and the error's message (which must name the file).
    fn import_error(name: &str, text: &str) -> (std::path::PathBuf, String) {
        let dir = std::env::temp_dir().join(format!("impact_abaqus_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("{name}.inp"));
        std::fs::write(&path, text).unwrap();
        let e = crate::mesh::import(&path, 1.0, [0.0; 3], None).expect_err("must be refused");
        (path, e.to_string())
    }

    /// `CUBE` with a set keyword and its data line appended; returns the text and the data
    /// line's number.
    fn with_set(keyword: &str, data: &str) -> (String, usize) {
        let line = CUBE.lines().count() + 2;
        (format!("{CUBE}{keyword}\n{data}\n"), line)
    }

    #[test]
    fn generate_to_i64_max_is_refused_before_it_is_expanded() {
        let (t, line) = with_set(
            "*ELSET, ELSET=ALL_EL, GENERATE",
            "1, 9223372036854775807, 1",
        );
        let (path, msg) = import_error("generate_i64_max", &t);
        assert!(
            msg.starts_with(&format!("{}:{line}: ", path.display())),
            "names the file and line: {msg}"
        );
        assert!(
            msg.contains(
                "GENERATE 1, 9223372036854775807, 1 makes 9223372036854775807 element numbers"
            ),
            "{msg}"
        );
        // the element's data line and its continuation
        assert!(msg.contains("at most 2 elements"), "{msg}");
    }

    #[test]
    fn generate_of_a_billion_nodes_is_refused_before_it_is_expanded() {
        let (t, line) = with_set("*NSET, NSET=MANY, GENERATE", "1, 1000000000, 1");
        let (path, msg) = import_error("generate_billion", &t);
        assert!(
            msg.starts_with(&format!("{}:{line}: ", path.display())),
            "names the file and line: {msg}"
        );
        assert!(
            msg.contains("makes 1000000000 node numbers, but the file defines at most 8 nodes"),
            "{msg}"
        );
    }

    #[test]
    fn generate_near_u64_max_neither_overflows_nor_panics() {
        let (t, line) = with_set(
            "*NSET, NSET=TOP_END, GENERATE",
            "18446744073709551610, 18446744073709551615, 3",
        );
        // two numbers, within the bound; neither is a node, which `finish` refuses
        let e = read(&t, None).unwrap_err();
        assert!(e.message.contains("node 18446744073709551610"), "{e:?}");
        let (t, _) = with_set("*NSET, NSET=ALL_U64, GENERATE", "0, 18446744073709551615");
        let e = read(&t, None).unwrap_err();
        assert_eq!(e.line, Some(line));
        assert!(
            e.message
                .contains("makes 18446744073709551616 node numbers"),
            "{e:?}"
        );
    }

    #[test]
    fn a_set_naming_itself_is_refused_at_its_line() {
        // once kept, each such line would have tripled the set
        let lines = "TWICE, TWICE, TWICE\n".repeat(64);
        let t = format!("{CUBE}*NSET, NSET=TWICE\n1, 2\n{lines}");
        let e = read(&t, None).unwrap_err();
        assert_eq!(e.line, Some(CUBE.lines().count() + 3));
        assert!(e.message.contains("*NSET TWICE names itself"), "{e:?}");
    }

    #[test]
    fn a_set_of_more_numbers_than_nodes_names_the_line() {
        let (t, line) = with_set("*NSET, NSET=LISTED", "1, 2, 3, 4, 5, 6, 7, 8, 9");
        let e = read(&t, None).unwrap_err();
        assert_eq!(e.line, Some(line));
        assert!(
            e.message
                .contains("*NSET LISTED names 9 distinct node numbers"),
            "{e:?}"
        );
    }
}
