//! LS-DYNA keyword file (`.k`) mesh reader: `*NODE`, `*ELEMENT_SOLID` (8 nodes; a hexahedron
//! whose last five nodes are one node is a tetrahedron), `*SET_NODE_LIST` (node sets named
//! by their id) and `*SET_SEGMENT` (surfaces named by their id), each with its `_TITLE`
//! variant. Cards are fixed width (`*NODE`: 8 + 3 x 16 columns; elements: 8-column fields;
//! sets: 10-column fields) or free format (comma-separated). `$` starts a comment line; a
//! blank line is a card of defaults where a set's title or header is due (elsewhere it
//! holds nothing to read); `*END` ends the file. An element or set id given twice is
//! refused. Other keywords are the scene's ([`crate::scene::from_deck`]) and are listed as
//! skipped.

use std::collections::HashMap;

use super::file_mesh::{FileMesh, FileSurface};
use super::parse_error::ParseError;
use super::NodeSet;
use crate::element::ElementKind;

type Res<T> = Result<T, ParseError>;

/// A card's fields: comma-separated where the line holds a comma, else the columns of
/// `widths` (the last repeated), each trimmed.
pub(crate) fn card(line: &str, widths: &[usize]) -> Vec<String> {
    if line.contains(',') {
        return line.split(',').map(|f| f.trim().to_string()).collect();
    }
    let mut out = Vec::new();
    let (mut at, mut k) = (0, 0);
    let chars: Vec<char> = line.chars().collect();
    while at < chars.len() {
        let w = widths[k.min(widths.len() - 1)];
        let end = (at + w).min(chars.len());
        out.push(chars[at..end].iter().collect::<String>().trim().to_string());
        at = end;
        k += 1;
    }
    out
}

/// The keyword of a line starting with `*`, upper case: its first word (`*KEYWORD
/// 100000000` gives the memory after it).
pub(crate) fn keyword(line: &str) -> String {
    let word = line[1..].split_whitespace().next().unwrap_or("");
    word.to_ascii_uppercase()
}

/// The refusal of a keyword that does not start in column 1.
pub(crate) fn misplaced_keyword(line: &str) -> String {
    format!(
        "`{}`: a keyword starts in column 1 (this line has blanks before its `*`)",
        line.trim()
    )
}

/// What a block's data cards are.
enum Block {
    Node,
    Solid,
    /// A set's cards: its header still to come (after the title where `titled`), then ids.
    NodeSet {
        titled: bool,
        header: bool,
    },
    Segments {
        titled: bool,
        header: bool,
    },
    Skip,
}

impl Block {
    /// Whether the block's next card is a set's title or header, which a blank line fills.
    fn due(&self) -> bool {
        match self {
            Block::NodeSet { titled, header } | Block::Segments { titled, header } => {
                *titled || *header
            }
            _ => false,
        }
    }
}

struct Reader {
    nodes: Vec<[f64; 3]>,
    node_ids: HashMap<u64, u32>,
    /// (element id, part id, node ids, line).
    elements: Vec<(u64, u64, Vec<u64>, usize)>,
    /// Each element id's line.
    element_ids: HashMap<u64, usize>,
    node_sets: Vec<(String, Vec<u64>, usize)>,
    segments: Vec<(String, Vec<Vec<u64>>, usize)>,
    skipped: Vec<(String, usize)>,
}

fn integer(f: &[String], i: usize, line: usize, what: &str) -> Res<u64> {
    let s = f.get(i).map(String::as_str).unwrap_or("");
    s.parse::<u64>()
        .map_err(|_| ParseError::at(line, format!("{what}: `{s}` is not a positive integer")))
}

/// Field `i` of a card as a number (an empty field is 0, as LS-DYNA reads it).
pub(crate) fn real(f: &[String], i: usize, line: usize, what: &str) -> Res<f64> {
    let s = f.get(i).map(String::as_str).unwrap_or("");
    if s.is_empty() {
        return Ok(0.0);
    }
    s.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| ParseError::at(line, format!("{what}: `{s}` is not a finite number")))
}

impl Reader {
    fn data(&mut self, block: &mut Block, line: &str, n: usize) -> Res<()> {
        match block {
            Block::Node => {
                let f = card(line, &[8, 16, 16, 16, 8, 8]);
                let id = integer(&f, 0, n, "node id")?;
                if id == 0 {
                    return Err(ParseError::at(n, "node 0: node ids start at 1"));
                }
                let x = [1, 2, 3].map(|i| real(&f, i, n, "node coordinate"));
                let [a, b, c] = x;
                let index = self.nodes.len() as u32;
                if self.node_ids.insert(id, index).is_some() {
                    return Err(ParseError::at(n, format!("node {id} is defined twice")));
                }
                self.nodes.push([a?, b?, c?]);
            }
            Block::Solid => {
                let f = card(line, &[8]);
                let id = integer(&f, 0, n, "element id")?;
                if id == 0 {
                    return Err(ParseError::at(n, "element 0: element ids start at 1"));
                }
                let part = integer(&f, 1, n, "part id")?;
                let nodes = (2..10)
                    .map(|i| integer(&f, i, n, "element node"))
                    .collect::<Res<Vec<u64>>>()?;
                if let Some(first) = self.element_ids.insert(id, n) {
                    return Err(ParseError::at(
                        n,
                        format!("element {id} is defined twice (first on line {first})"),
                    ));
                }
                self.elements.push((id, part, nodes, n));
            }
            Block::NodeSet { titled, header } | Block::Segments { titled, header } => {
                if *titled {
                    *titled = false;
                    return Ok(());
                }
                let f = card(line, &[10]);
                if *header {
                    *header = false;
                    let sid = integer(&f, 0, n, "set id")?.to_string();
                    let first = match block {
                        Block::NodeSet { .. } => self
                            .node_sets
                            .iter()
                            .find(|s| s.0 == sid)
                            .map(|s| ("*SET_NODE_LIST", s.2)),
                        _ => self
                            .segments
                            .iter()
                            .find(|s| s.0 == sid)
                            .map(|s| ("*SET_SEGMENT", s.2)),
                    };
                    if let Some((kind, first)) = first {
                        return Err(ParseError::at(
                            n,
                            format!("{kind} {sid} is defined twice (first on line {first})"),
                        ));
                    }
                    match block {
                        Block::NodeSet { .. } => self.node_sets.push((sid, Vec::new(), n)),
                        _ => self.segments.push((sid, Vec::new(), n)),
                    }
                    return Ok(());
                }
                if let Block::NodeSet { .. } = block {
                    let set = self.node_sets.last_mut().expect("a header first");
                    for (i, _) in f.iter().enumerate().filter(|(_, s)| !s.is_empty()) {
                        let id = integer(&f, i, n, "set node")?;
                        // a zero ends the card's ids
                        if id == 0 {
                            break;
                        }
                        set.1.push(id);
                    }
                } else {
                    let ids = (0..4)
                        .map(|i| integer(&f, i, n, "segment node"))
                        .collect::<Res<Vec<u64>>>()?;
                    let set = self.segments.last_mut().expect("a header first");
                    set.1.push(ids);
                }
            }
            Block::Skip => {}
        }
        Ok(())
    }

    fn node(&self, id: u64, line: usize, whose: &str) -> Res<u32> {
        self.node_ids
            .get(&id)
            .copied()
            .ok_or_else(|| ParseError::at(line, format!("{whose}: node {id} is not defined")))
    }

    /// The mesh of every element, or of part `part` alone.
    fn finish(self, part: Option<u64>) -> Res<FileMesh> {
        let mut mesh = FileMesh {
            nodes: self.nodes.clone(),
            ..Default::default()
        };
        if let Some(p) = part {
            if !self.elements.iter().any(|e| e.1 == p) {
                return Err(ParseError::whole(format!("no *ELEMENT_SOLID of part {p}")));
            }
        }
        for (id, pid, nodes, line) in &self.elements {
            if part.is_some_and(|p| p != *pid) {
                continue;
            }
            let whose = format!("element {id}");
            let c = (nodes.iter())
                .map(|&n| self.node(n, *line, &whose))
                .collect::<Res<Vec<u32>>>()?;
            // a tetrahedron is written as a hexahedron whose nodes 4 to 8 are one node
            match c[3..].iter().all(|&n| n == c[3]) {
                true => mesh.elements.push(ElementKind::Tet4, &c[..4], 0),
                false => mesh.elements.push(ElementKind::Hex8, &c, 0),
            }
        }
        for (name, ids, line) in &self.node_sets {
            let nodes = (ids.iter())
                .map(|&n| self.node(n, *line, &format!("*SET_NODE_LIST {name}")))
                .collect::<Res<Vec<u32>>>()?;
            mesh.node_sets.push(NodeSet {
                name: name.clone(),
                nodes,
            });
        }
        self.add_surfaces(&mut mesh, part.is_some())?;
        mesh.skipped = self.skipped;
        Ok(mesh)
    }

    /// The segment sets as surfaces (a segment whose last two nodes are one is a triangle);
    /// restricted to a part, a set is kept where its nodes are all the part's.
    fn add_surfaces(&self, mesh: &mut FileMesh, restricted: bool) -> Res<()> {
        let mut used = vec![false; self.nodes.len()];
        for n in mesh.elements.corner_nodes() {
            used[n as usize] = true;
        }
        for (name, segments, line) in &self.segments {
            if segments.is_empty() {
                return Err(ParseError::at(
                    *line,
                    format!("*SET_SEGMENT {name} has no segments"),
                ));
            }
            let mut faces = Vec::new();
            for s in segments {
                let mut f = (s.iter())
                    .map(|&n| self.node(n, *line, &format!("*SET_SEGMENT {name}")))
                    .collect::<Res<Vec<u32>>>()?;
                if f[2] == f[3] {
                    f.pop();
                }
                faces.push(f);
            }
            let on_part = faces.iter().flatten().all(|&n| used[n as usize]);
            if restricted && !on_part {
                continue;
            }
            mesh.surfaces.push(FileSurface {
                name: name.clone(),
                faces,
                line: *line,
            });
        }
        Ok(())
    }
}

/// Reads a keyword file's text: every solid element, or (`part`) those of one part.
pub fn read(text: &str, part: Option<&str>) -> Res<FileMesh> {
    let part = match part {
        None => None,
        Some(p) => Some(p.trim().parse::<u64>().map_err(|_| {
            ParseError::whole(format!("part `{p}`: an LS-DYNA part is named by its id"))
        })?),
    };
    let mut r = Reader {
        nodes: Vec::new(),
        node_ids: HashMap::new(),
        elements: Vec::new(),
        element_ids: HashMap::new(),
        node_sets: Vec::new(),
        segments: Vec::new(),
        skipped: Vec::new(),
    };
    let mut block = Block::Skip;
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        if raw.starts_with('$') || (raw.trim().is_empty() && !block.due()) {
            continue;
        }
        if !raw.starts_with('*') && raw.trim_start().starts_with('*') {
            return Err(ParseError::at(n, misplaced_keyword(raw)));
        }
        if raw.starts_with('*') {
            let k = keyword(raw);
            if k == "END" {
                break;
            }
            block = match k.as_str() {
                "NODE" => Block::Node,
                "ELEMENT_SOLID" => Block::Solid,
                "SET_NODE_LIST" | "SET_NODE_LIST_TITLE" => Block::NodeSet {
                    titled: k.ends_with("_TITLE"),
                    header: true,
                },
                "SET_SEGMENT" | "SET_SEGMENT_TITLE" => Block::Segments {
                    titled: k.ends_with("_TITLE"),
                    header: true,
                },
                "INCLUDE" => {
                    return Err(ParseError::at(
                        n,
                        "*INCLUDE in a keyword file is not read: give the model in one file",
                    ))
                }
                "KEYWORD" => Block::Skip,
                _ => {
                    r.skipped.push((k, n));
                    Block::Skip
                }
            };
            continue;
        }
        r.data(&mut block, raw, n)?;
    }
    r.finish(part)
}
