//! Gmsh MSH 4.1 reader, ASCII and binary (little-endian, 8-byte `size_t`).
//!
//! Sections read: `$MeshFormat`, `$PhysicalNames`, `$Entities` (which physical groups each
//! entity belongs to), `$Nodes`, `$Elements`; others are skipped. Hexahedra (type 5) and
//! tetrahedra (type 4) make the body; triangles (2) and quadrangles (3) make the surfaces:
//! each physical group of dimension 2 is a surface named by its `$PhysicalNames` entry (or
//! by its number), and every physical group, of any dimension, is also a node set of the
//! nodes of its elements. Higher-order and other volume elements are refused.

use std::collections::HashMap;

use super::file_mesh::{FileMesh, FileSurface};
use super::parse_error::ParseError;
use super::NodeSet;
use crate::element::ElementKind;

type Res<T> = std::result::Result<T, ParseError>;

/// Nodes per element of the Gmsh element types a mesh may hold, and a name for messages.
fn element_kind(t: i64) -> Option<(usize, &'static str)> {
    Some(match t {
        1 => (2, "2-node line"),
        2 => (3, "3-node triangle"),
        3 => (4, "4-node quadrangle"),
        4 => (4, "4-node tetrahedron"),
        5 => (8, "8-node hexahedron"),
        6 => (6, "6-node prism"),
        7 => (5, "5-node pyramid"),
        8 => (3, "3-node line"),
        9 => (6, "6-node triangle"),
        10 => (9, "9-node quadrangle"),
        11 => (10, "10-node tetrahedron"),
        12 => (27, "27-node hexahedron"),
        13 => (18, "18-node prism"),
        14 => (14, "14-node pyramid"),
        15 => (1, "point"),
        16 => (8, "8-node quadrangle"),
        17 => (20, "20-node hexahedron"),
        18 => (15, "15-node prism"),
        19 => (13, "13-node pyramid"),
        _ => return None,
    })
}

/// Dimension of the Gmsh element types above.
fn element_dim(t: i64) -> usize {
    match t {
        15 => 0,
        1 | 8 => 1,
        2 | 3 | 9 | 10 | 16 => 2,
        _ => 3,
    }
}

struct Cursor<'a> {
    b: &'a [u8],
    pos: usize,
    binary: bool,
    /// Offsets of the file's `\n` bytes, so that a line number costs a binary search.
    newlines: &'a [usize],
}

impl<'a> Cursor<'a> {
    fn line_at(&self, pos: usize) -> usize {
        1 + self.newlines.partition_point(|&n| n < pos)
    }

    fn err(&self, message: impl Into<String>) -> ParseError {
        ParseError::at(self.line_at(self.pos), message)
    }

    fn skip_space(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn at_end(&mut self) -> bool {
        self.skip_space();
        self.pos >= self.b.len()
    }

    /// The next line (without its end), after skipping blank space.
    fn line(&mut self) -> Res<&'a str> {
        self.skip_space();
        let start = self.pos;
        while self.pos < self.b.len() && self.b[self.pos] != b'\n' {
            self.pos += 1;
        }
        let raw = &self.b[start..self.pos];
        if self.pos < self.b.len() {
            self.pos += 1;
        }
        std::str::from_utf8(raw)
            .map(|s| s.trim_end_matches('\r'))
            .map_err(|_| ParseError::at(self.line_at(start), "expected a line of text"))
    }

    fn token(&mut self, what: &str) -> Res<&'a str> {
        self.skip_space();
        let start = self.pos;
        while self.pos < self.b.len() && !self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.err(format!("the file ends where {what} was expected")));
        }
        std::str::from_utf8(&self.b[start..self.pos])
            .map_err(|_| ParseError::at(self.line_at(start), format!("expected {what}")))
    }

    fn number<T: std::str::FromStr>(&mut self, what: &str) -> Res<T> {
        let start = self.pos;
        let t = self.token(what)?;
        t.parse().map_err(|_| {
            let mut c = Cursor {
                pos: start,
                ..*self
            };
            c.skip_space();
            c.err(format!("expected {what}, found `{t}`"))
        })
    }

    fn bytes(&mut self, n: usize, what: &str) -> Res<&'a [u8]> {
        if self.pos + n > self.b.len() {
            return Err(self.err(format!("the file ends inside {what}")));
        }
        let s = &self.b[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// An integer: a text token, or in binary sections an `int` (4 bytes).
    fn int(&mut self, what: &str) -> Res<i64> {
        if self.binary {
            let b = self.bytes(4, what)?;
            Ok(i32::from_le_bytes(b.try_into().expect("4 bytes")) as i64)
        } else {
            self.number(what)
        }
    }

    /// A count or a tag of type `size_t`: a text token, or 8 bytes in binary sections.
    fn size(&mut self, what: &str) -> Res<u64> {
        if self.binary {
            let b = self.bytes(8, what)?;
            Ok(u64::from_le_bytes(b.try_into().expect("8 bytes")))
        } else {
            self.number(what)
        }
    }

    fn real(&mut self, what: &str) -> Res<f64> {
        if self.binary {
            let b = self.bytes(8, what)?;
            Ok(f64::from_le_bytes(b.try_into().expect("8 bytes")))
        } else {
            self.number(what)
        }
    }

    /// Expects the line `$End<name>`.
    fn end(&mut self, name: &str) -> Res<()> {
        let l = self.line()?;
        if l.trim() == format!("$End{name}") {
            Ok(())
        } else {
            Err(self.err_prev(format!("expected `$End{name}`, found `{}`", l.trim())))
        }
    }

    /// An error about the line just read.
    fn err_prev(&self, message: impl Into<String>) -> ParseError {
        ParseError::at(self.line_at(self.pos.saturating_sub(1)), message)
    }

    /// A count of entries that follow, each at least `tokens` text tokens or, in binary
    /// sections, `bytes` bytes: refused when the rest of the file is too short to hold them,
    /// so no count from a corrupt file can drive an allocation or a loop past the file's own
    /// size. A text token takes at least 2 bytes, itself and the space after it (every
    /// section ends with a `$End` line, so even its last token is followed by one).
    fn count(&mut self, what: &str, tokens: usize, bytes: usize) -> Res<usize> {
        let n = self.size(what)?;
        let each = if self.binary { bytes } else { 2 * tokens }.max(1);
        let left = self.b.len().saturating_sub(self.pos);
        if n > (left / each) as u64 {
            return Err(self.err(format!(
                "{what} = {n} is more than the rest of the file can hold ({left} bytes left, each entry takes at least {each})"
            )));
        }
        Ok(n as usize)
    }

    /// Skips the rest of the `$MeshFormat` line of a binary file and checks the `int` 1
    /// after it: the file must be little-endian.
    fn endianness(&mut self) -> Res<()> {
        // the rest of the line, then the binary one
        while self.pos < self.b.len() && self.b[self.pos] != b'\n' {
            self.pos += 1;
        }
        self.pos += 1;
        let one = self.bytes(4, "the endianness check")?;
        if i32::from_le_bytes(one.try_into().expect("4 bytes")) != 1 {
            return Err(self.err("a big-endian binary file is not supported"));
        }
        Ok(())
    }

    /// An entity dimension, 0 to 3.
    fn dim(&mut self) -> Res<usize> {
        let d = self.int("an entity dimension")?;
        if !(0..=3).contains(&d) {
            return Err(self.err(format!("entity dimension {d} (expected 0 to 3)")));
        }
        Ok(d as usize)
    }
}

struct Block {
    dim: usize,
    tag: i64,
    kind: i64,
    elements: Vec<Vec<u64>>,
    line: usize,
}

/// Reads a whole `.msh` file.
pub fn read(bytes: &[u8]) -> Res<FileMesh> {
    let newlines: Vec<usize> = (0..bytes.len()).filter(|&i| bytes[i] == b'\n').collect();
    let mut c = Cursor {
        b: bytes,
        pos: 0,
        binary: false,
        newlines: &newlines,
    };
    let mut m = Msh::default();
    while !c.at_end() {
        m.section(&mut c)?;
    }
    if !m.seen_format {
        return Err(ParseError::whole("empty file: not a Gmsh mesh"));
    }
    assemble(m.nodes, &m.node_tags, &m.blocks, &m.physicals, &m.names)
}

/// What the sections of a `.msh` file read so far have given.
#[derive(Default)]
struct Msh {
    /// Whether `$MeshFormat` has been read.
    seen_format: bool,
    /// Whether `$MeshFormat` declared a binary file.
    binary: bool,
    /// `$PhysicalNames`: (dimension, physical tag) -> name.
    names: HashMap<(usize, i64), String>,
    /// `$Entities`: (dimension, entity tag) -> the entity's physical tags.
    physicals: HashMap<(usize, i64), Vec<i64>>,
    /// `$Nodes`: node tag -> index in `nodes`.
    node_tags: HashMap<u64, u32>,
    nodes: Vec<[f64; 3]>,
    blocks: Vec<Block>,
}

impl Msh {
    /// Reads one section, from its `$Name` line to its `$EndName` line.
    fn section(&mut self, c: &mut Cursor) -> Res<()> {
        let header = c.line()?.trim();
        let Some(section) = header.strip_prefix('$') else {
            return Err(c.err_prev(format!(
                "expected a section such as `$Nodes`, found `{header}`"
            )));
        };
        if section != "MeshFormat" && !self.seen_format {
            return Err(c.err_prev("the file does not start with `$MeshFormat`: not a Gmsh mesh"));
        }
        c.binary = false;
        match section {
            "MeshFormat" => self.mesh_format(c),
            "PhysicalNames" => self.physical_names(c),
            "Entities" => self.entities(c),
            "Nodes" => self.read_nodes(c),
            "Elements" => {
                if !self.binary {
                    read_ascii_elements(c, &mut self.blocks)?;
                } else {
                    read_binary_elements(c, &mut self.blocks)?;
                }
                c.end("Elements")
            }
            other => skip_section(c, other),
        }
    }

    /// Reads `$MeshFormat`: version 4.1, ASCII or little-endian binary, 8-byte `size_t`.
    fn mesh_format(&mut self, c: &mut Cursor) -> Res<()> {
        let version: String = c.token("the format version")?.to_string();
        let file_type: i64 = c.number("the file type (0 ASCII, 1 binary)")?;
        let data_size: i64 = c.number("the data size")?;
        if version != "4.1" {
            return Err(c.err(format!(
                "MSH format version {version} is not supported: save the mesh as version 4.1 (`-format msh41`, or Mesh.MshFileVersion = 4.1)"
            )));
        }
        if data_size != 8 {
            return Err(c.err(format!(
                "data size {data_size} is not supported (expected 8)"
            )));
        }
        match file_type {
            0 => {}
            1 => {
                self.binary = true;
                c.endianness()?;
            }
            t => return Err(c.err(format!("unknown file type {t} (expected 0 or 1)"))),
        }
        self.seen_format = true;
        c.end("MeshFormat")
    }

    /// Reads `$PhysicalNames`: lines `dim tag "name"`.
    fn physical_names(&mut self, c: &mut Cursor) -> Res<()> {
        let n = c.count("the number of physical names", 3, 0)?;
        for _ in 0..n {
            let dim: usize = c.number("a physical dimension")?;
            let tag: i64 = c.number("a physical tag")?;
            let name = c.line()?.trim().trim_matches('"').to_string();
            self.names.insert((dim, tag), name);
        }
        c.end("PhysicalNames")
    }

    /// Reads `$Entities`: the physical tags of every point, curve, surface and volume.
    fn entities(&mut self, c: &mut Cursor) -> Res<()> {
        c.binary = self.binary;
        // a point: tag, 3 coordinates, a count of physical tags; a curve, surface or
        // volume: tag, 6 coordinates and two counts
        let counts = [
            c.count("the number of points", 5, 4 + 3 * 8 + 8)?,
            c.count("the number of curves", 9, 4 + 6 * 8 + 2 * 8)?,
            c.count("the number of surfaces", 9, 4 + 6 * 8 + 2 * 8)?,
            c.count("the number of volumes", 9, 4 + 6 * 8 + 2 * 8)?,
        ];
        for (dim, &n) in counts.iter().enumerate() {
            for _ in 0..n {
                self.entity(c, dim)?;
            }
        }
        c.binary = false;
        c.end("Entities")
    }

    /// Reads one entity of dimension `dim` and keeps its physical tags.
    fn entity(&mut self, c: &mut Cursor, dim: usize) -> Res<()> {
        let tag = c.int("an entity tag")?;
        let coords = if dim == 0 { 3 } else { 6 };
        for _ in 0..coords {
            c.real("an entity coordinate")?;
        }
        let np = c.count("the number of physical tags", 1, 4)?;
        let mut tags = Vec::with_capacity(np);
        for _ in 0..np {
            tags.push(c.int("a physical tag")?);
        }
        self.physicals.insert((dim, tag), tags);
        if dim > 0 {
            let nb = c.count("the number of bounding entities", 1, 4)?;
            for _ in 0..nb {
                c.int("a bounding entity tag")?;
            }
        }
        Ok(())
    }

    /// Reads `$Nodes`: its header, then its blocks of nodes.
    fn read_nodes(&mut self, c: &mut Cursor) -> Res<()> {
        c.binary = self.binary;
        // a block header: dimension, tag, parametric flag, count; a node: its tag and
        // 3 coordinates
        let nblocks = c.count("the number of node blocks", 4, 3 * 4 + 8)?;
        let total = c.count("the number of nodes", 4, 8 + 3 * 8)?;
        c.size("the smallest node tag")?;
        c.size("the largest node tag")?;
        self.nodes.reserve(total);
        for _ in 0..nblocks {
            self.node_block(c)?;
        }
        c.binary = false;
        c.end("Nodes")
    }

    /// Reads one block of `$Nodes`: its header, its node tags, then their coordinates.
    fn node_block(&mut self, c: &mut Cursor) -> Res<()> {
        let dim = c.dim()?;
        c.int("an entity tag")?;
        let parametric = c.int("the parametric flag")?;
        let n = c.count("the number of nodes in the block", 4, 8 + 3 * 8)?;
        let mut tags = Vec::with_capacity(n);
        for _ in 0..n {
            tags.push(c.size("a node tag")?);
        }
        let extra = if parametric != 0 { dim } else { 0 };
        for tag in tags {
            let p = [
                c.real("a node coordinate")?,
                c.real("a node coordinate")?,
                c.real("a node coordinate")?,
            ];
            for _ in 0..extra {
                c.real("a parametric coordinate")?;
            }
            if !p.iter().all(|v| v.is_finite()) {
                return Err(c.err(format!("node {tag} has a coordinate that is not finite")));
            }
            if self
                .node_tags
                .insert(tag, self.nodes.len() as u32)
                .is_some()
            {
                return Err(c.err(format!("node tag {tag} is defined twice")));
            }
            self.nodes.push(p);
        }
        Ok(())
    }
}

/// Skips a section we do not use, `$<name>`, to its end marker.
fn skip_section(c: &mut Cursor, name: &str) -> Res<()> {
    let end = format!("$End{name}");
    let start = c.pos;
    let rest = &c.b[start..];
    let Some(at) = rest.windows(end.len()).position(|w| w == end.as_bytes()) else {
        return Err(c.err_prev(format!("section `${name}` has no `{end}`")));
    };
    c.pos = start + at + end.len();
    Ok(())
}

/// Reads the blocks of a binary `$Elements` section, up to its `$EndElements` line.
fn read_binary_elements(c: &mut Cursor, blocks: &mut Vec<Block>) -> Res<()> {
    c.binary = true;
    // a block header: dimension, tag, type, count; an element: its tag and at least one
    // node tag
    let nblocks = c.count("the number of element blocks", 4, 3 * 4 + 8)?;
    c.count("the number of elements", 2, 2 * 8)?;
    c.size("the smallest element tag")?;
    c.size("the largest element tag")?;
    for _ in 0..nblocks {
        blocks.push(binary_element_block(c)?);
    }
    c.binary = false;
    Ok(())
}

/// Reads one block of a binary `$Elements` section.
fn binary_element_block(c: &mut Cursor) -> Res<Block> {
    let line = c.line_at(c.pos);
    let dim = c.dim()?;
    let tag = c.int("an entity tag")?;
    let kind = c.int("an element type")?;
    let Some((per, _)) = element_kind(kind) else {
        return Err(c.err(format!("unknown element type {kind}")));
    };
    let n = c.count("the number of elements in the block", 1 + per, 8 + 8 * per)?;
    let mut elements = Vec::with_capacity(n);
    for _ in 0..n {
        c.size("an element tag")?;
        let mut e = Vec::with_capacity(per);
        for _ in 0..per {
            e.push(c.size("a node tag")?);
        }
        elements.push(e);
    }
    Ok(Block {
        dim,
        tag,
        kind,
        elements,
        line,
    })
}

/// Reads the blocks of an ASCII `$Elements` section, up to its `$EndElements` line.
fn read_ascii_elements(c: &mut Cursor, blocks: &mut Vec<Block>) -> Res<()> {
    // as in the binary reader, [`read_binary_elements`]
    let nblocks = c.count("the number of element blocks", 4, 0)?;
    c.count("the number of elements", 2, 0)?;
    c.size("the smallest element tag")?;
    c.size("the largest element tag")?;
    for _ in 0..nblocks {
        c.skip_space();
        let line = c.line_at(c.pos);
        let dim = c.dim()?;
        let tag: i64 = c.number("an entity tag")?;
        let kind: i64 = c.number("an element type")?;
        let Some((per, _)) = element_kind(kind) else {
            return Err(ParseError::at(line, format!("unknown element type {kind}")));
        };
        let n = c.count("the number of elements in the block", 1 + per, 0)?;
        let mut elements = Vec::with_capacity(n);
        for _ in 0..n {
            if c.at_end() {
                return Err(c.err("the file ends inside an element block"));
            }
            let text = c.line()?;
            let mut fields = text.split_whitespace();
            fields.next(); // element tag
            let e: Vec<u64> = fields
                .map(|f| f.parse::<u64>())
                .collect::<Result<_, _>>()
                .map_err(|_| {
                    c.err_prev(format!(
                        "expected an element tag and its node tags, found `{text}`"
                    ))
                })?;
            if e.len() != per {
                return Err(c.err_prev(format!(
                    "an element of type {kind} has {per} nodes, this line gives {}",
                    e.len()
                )));
            }
            elements.push(e);
        }
        blocks.push(Block {
            dim,
            tag,
            kind,
            elements,
            line,
        });
    }
    Ok(())
}

/// A physical group as collected: (dimension, tag), its faces (2D groups), its nodes, and
/// the line of its first block.
type Group = ((usize, i64), Vec<Vec<u32>>, Vec<u32>, usize);

fn assemble(
    nodes: Vec<[f64; 3]>,
    node_tags: &HashMap<u64, u32>,
    blocks: &[Block],
    physicals: &HashMap<(usize, i64), Vec<i64>>,
    names: &HashMap<(usize, i64), String>,
) -> Res<FileMesh> {
    let mut mesh = FileMesh {
        nodes,
        ..Default::default()
    };
    let mut groups: Vec<Group> = Vec::new();
    for b in blocks {
        let block_nodes = resolve_block(b, node_tags)?;
        add_body_elements(&mut mesh, b, &block_nodes)?;
        add_to_groups(&mut groups, b, &block_nodes, physicals);
    }
    add_groups(&mut mesh, groups, names);
    Ok(mesh)
}

/// The node indices of each element of block `b`, refusing a node tag `$Nodes` lacks.
fn resolve_block(b: &Block, node_tags: &HashMap<u64, u32>) -> Res<Vec<Vec<u32>>> {
    let resolve = |e: &[u64]| -> Res<Vec<u32>> {
        e.iter()
            .map(|t| {
                node_tags.get(t).copied().ok_or_else(|| {
                    ParseError::at(
                        b.line,
                        format!("an element of this block uses node {t}, which `$Nodes` does not define"),
                    )
                })
            })
            .collect()
    };
    let mut block_nodes: Vec<Vec<u32>> = Vec::with_capacity(b.elements.len());
    for e in &b.elements {
        block_nodes.push(resolve(e)?);
    }
    Ok(block_nodes)
}

/// Adds block `b`'s hexahedra and tetrahedra to the body; refuses other volume and
/// higher-order surface elements.
fn add_body_elements(mesh: &mut FileMesh, b: &Block, block_nodes: &[Vec<u32>]) -> Res<()> {
    let (_, kind_name) = element_kind(b.kind).expect("checked while reading");
    let dim = element_dim(b.kind);
    match b.kind {
        5 => (block_nodes.iter()).for_each(|e| mesh.elements.push(ElementKind::Hex8, e, 0)),
        4 => (block_nodes.iter()).for_each(|e| mesh.elements.push(ElementKind::Tet4, e, 0)),
        1 | 2 | 3 | 15 => {}
        _ if dim == 3 || dim == 2 => {
            return Err(ParseError::at(
                b.line,
                format!(
                    "element type {} ({kind_name}) is not supported: mesh with linear tetrahedra (type 4) or hexahedra (type 5), `-order 1`",
                    b.kind
                ),
            ))
        }
        _ => {}
    }
    Ok(())
}

/// Adds block `b`'s elements to the physical groups of its entity: their nodes, and as
/// faces its triangles and quadrangles.
fn add_to_groups(
    groups: &mut Vec<Group>,
    b: &Block,
    block_nodes: &[Vec<u32>],
    physicals: &HashMap<(usize, i64), Vec<i64>>,
) {
    for &p in physicals
        .get(&(b.dim, b.tag))
        .map(|v| v.as_slice())
        .unwrap_or(&[])
    {
        let key = (b.dim, p);
        let g = match groups.iter().position(|g| g.0 == key) {
            Some(i) => i,
            None => {
                groups.push((key, Vec::new(), Vec::new(), b.line));
                groups.len() - 1
            }
        };
        for e in block_nodes {
            groups[g].2.extend_from_slice(e);
            if matches!(b.kind, 2 | 3) {
                groups[g].1.push(e.clone());
            }
        }
    }
}

/// Adds every physical group to `mesh` as a node set, and each of dimension 2 as a surface,
/// named by its `$PhysicalNames` entry or by its number.
fn add_groups(mesh: &mut FileMesh, groups: Vec<Group>, names: &HashMap<(usize, i64), String>) {
    for ((dim, tag), faces, mut set, line) in groups {
        let name = names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| tag.to_string());
        if dim == 2 {
            mesh.surfaces.push(FileSurface {
                name: name.clone(),
                faces,
                line,
            });
        }
        set.sort_unstable();
        set.dedup();
        mesh.node_sets.push(NodeSet { name, nodes: set });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube as one hex, its bottom face a physical surface and its volume a physical
    /// group, laid out as Gmsh 4.1 writes it.
    pub(crate) const CUBE: &str = r#"$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "bottom"
3 2 "cube"
$EndPhysicalNames
$Entities
0 0 1 1
1 0 0 0 1 1 0 1 1 0
1 0 0 0 1 1 1 1 2 1 1
$EndEntities
$Nodes
2 8 1 8
2 1 0 4
1
2
3
4
0 0 0
1 0 0
1 1 0
0 1 0
3 1 0 4
5
6
7
8
0 0 1
1 0 1
1 1 1
0 1 1
$EndNodes
$Elements
2 2 1 2
2 1 3 1
1 1 4 3 2
3 1 5 1
2 1 2 3 4 5 6 7 8
$EndElements
"#;

    #[test]
    fn reads_a_hex_with_a_named_surface() {
        let m = read(CUBE.as_bytes()).unwrap();
        assert_eq!(m.nodes.len(), 8);
        assert_eq!(
            m.elements.block(ElementKind::Hex8).nodes,
            (0..8).collect::<Vec<u32>>()
        );
        assert_eq!(m.surfaces.len(), 1);
        assert_eq!(m.surfaces[0].name, "bottom");
        assert_eq!(m.surfaces[0].faces, vec![vec![0, 3, 2, 1]]);
        let cube = m.node_sets.iter().find(|s| s.name == "cube").unwrap();
        assert_eq!(cube.nodes, (0..8).collect::<Vec<u32>>());
    }

    #[test]
    fn a_bad_node_coordinate_names_its_line() {
        let bad = CUBE.replace("1 1 0\n0 1 0\n3 1", "1 1 0\n0 x 0\n3 1");
        let e = read(bad.as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(24), "{e:?}");
        assert!(e.message.contains("`x`"), "{}", e.message);
    }

    #[test]
    fn an_old_format_is_refused_with_the_fix() {
        let old = CUBE.replace("4.1 0 8", "2.2 0 8");
        let e = read(old.as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(2));
        assert!(e.message.contains("version 4.1"), "{}", e.message);
    }

    #[test]
    fn second_order_elements_are_refused() {
        let t = CUBE.replace(
            "3 1 5 1\n2 1 2 3 4 5 6 7 8",
            "3 1 11 1\n2 1 2 3 4 5 6 7 8 1 2",
        );
        let e = read(t.as_bytes()).unwrap_err();
        assert!(e.message.contains("10-node tetrahedron"), "{}", e.message);
    }

    /// Writes `bytes` as `<name>.msh` in a fresh temporary folder and imports it; returns the
    /// path and the error's message (which must name the file).
    fn import_error(name: &str, bytes: &[u8]) -> (std::path::PathBuf, String) {
        let dir = std::env::temp_dir().join(format!("impact_gmsh_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("{name}.msh"));
        std::fs::write(&path, bytes).unwrap();
        let e = crate::mesh::import(&path, 1.0, [0.0; 3], None).expect_err("must be refused");
        (path, e.to_string())
    }

    #[test]
    fn a_huge_node_count_in_the_header_is_refused_before_allocating() {
        let t = CUBE.replace("$Nodes\n2 8 1 8", "$Nodes\n2 9223372036854775807 1 8");
        let (path, msg) = import_error("huge_nodes", t.as_bytes());
        assert!(
            msg.starts_with(&format!("{}:15: ", path.display())),
            "names the file and line: {msg}"
        );
        assert!(
            msg.contains("the number of nodes = 9223372036854775807 is more than the rest of the file can hold"),
            "{msg}"
        );
    }

    #[test]
    fn huge_counts_anywhere_are_refused_with_their_line() {
        for (from, to, line, what) in [
            (
                "$PhysicalNames\n2",
                "$PhysicalNames\n18446744073709551615",
                5,
                "physical names",
            ),
            ("0 0 1 1", "0 0 1 4294967296", 10, "the number of volumes"),
            ("1 1 0 1 1 0", "1 1 0 2147483648 1 0", 11, "physical tags"),
            ("$Nodes\n2 8", "$Nodes\n1000000 8", 15, "node blocks"),
            ("2 1 0 4\n1", "2 1 0 400000\n1", 16, "nodes in the block"),
            (
                "$Elements\n2 2",
                "$Elements\n2 2000000000",
                36,
                "the number of elements",
            ),
            (
                "3 1 5 1\n",
                "3 1 5 9223372036854775807\n",
                39,
                "elements in the block",
            ),
        ] {
            let t = CUBE.replace(from, to);
            assert_ne!(t, CUBE, "{from:?}");
            let e = read(t.as_bytes()).unwrap_err();
            assert_eq!(e.line, Some(line), "{to:?}: {e:?}");
            assert!(
                e.message.contains(what) && e.message.contains("more than the rest of the file"),
                "{to:?}: {e:?}"
            );
        }
    }

    #[test]
    fn an_empty_block_of_an_unknown_type_is_refused() {
        // it used to be accepted while reading and then panic while the body was assembled
        let t = CUBE.replace("2 1 3 1\n1 1 4 3 2", "2 1 99 0");
        let e = read(t.as_bytes()).unwrap_err();
        assert_eq!(e.line, Some(37), "{e:?}");
        assert!(e.message.contains("unknown element type 99"), "{e:?}");
    }

    #[test]
    fn an_entity_dimension_out_of_range_is_refused() {
        let t = CUBE.replace("2 1 0 4\n1", "2147483647 1 1 4\n1");
        let e = read(t.as_bytes()).unwrap_err();
        assert!(e.message.contains("entity dimension 2147483647"), "{e:?}");
    }

    #[test]
    fn a_huge_count_in_a_binary_file_is_refused() {
        let good: &[u8] = include_bytes!("../../scenes/meshes/block_tet_binary.msh");
        assert!(read(good).is_ok());
        let at = good.windows(7).position(|w| w == b"$Nodes\n").unwrap() + 7;
        for (k, what) in [(0, "node blocks"), (8, "the number of nodes")] {
            let mut bad = good.to_vec();
            bad[at + k..at + k + 8].copy_from_slice(&u64::MAX.to_le_bytes());
            let e = read(&bad).unwrap_err();
            assert!(
                e.message.contains(what) && e.message.contains("18446744073709551615"),
                "{e:?}"
            );
        }
    }
}
