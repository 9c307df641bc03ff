//! Element blocks: the elements of a mesh, one [`ElementBlock`] per [`ElementKind`], each
//! holding its elements' corner nodes (flat, [`ElementKind::corners`] per element) and
//! materials. [`Elements`] numbers them globally: the blocks in [`ElementKind::ALL`]
//! order, each block's elements in its own order.

use std::ops::Range;

use super::kind::ElementKind;

/// The elements of one kind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElementBlock {
    pub kind: ElementKind,
    /// Corner nodes, [`ElementKind::corners`] per element.
    pub nodes: Vec<u32>,
    /// Material index of each element.
    pub material: Vec<u32>,
}

impl ElementBlock {
    pub fn new(kind: ElementKind) -> Self {
        ElementBlock {
            kind,
            nodes: Vec::new(),
            material: Vec::new(),
        }
    }

    pub fn len(&self) -> usize {
        self.material.len()
    }

    pub fn is_empty(&self) -> bool {
        self.material.is_empty()
    }

    /// Corner nodes of element `e`.
    pub fn element(&self, e: usize) -> &[u32] {
        let n = self.kind.corners();
        &self.nodes[n * e..n * (e + 1)]
    }

    /// The corner nodes of every element, as fixed arrays of `N` (the kind's corner count).
    pub fn corners<const N: usize>(&self) -> &[[u32; N]] {
        assert_eq!(N, self.kind.corners(), "{} corners", self.kind);
        bytemuck::cast_slice(&self.nodes)
    }

    /// Each element's corner nodes and material.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (&[u32], u32)> + '_ {
        (self.nodes.chunks_exact(self.kind.corners())).zip(self.material.iter().copied())
    }

    /// Appends an element.
    pub fn push(&mut self, nodes: &[u32], material: u32) {
        assert_eq!(nodes.len(), self.kind.corners(), "{} corners", self.kind);
        self.nodes.extend_from_slice(nodes);
        self.material.push(material);
    }
}

/// One element of a mesh: its kind, corner nodes and material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementRef<'a> {
    pub kind: ElementKind,
    pub nodes: &'a [u32],
    pub material: u32,
}

/// Every element of a mesh (or of one body before it joins one), a block per kind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Elements {
    /// One block per kind, in [`ElementKind::ALL`] order (empty where there are none).
    pub blocks: Vec<ElementBlock>,
}

impl Default for Elements {
    fn default() -> Self {
        Elements {
            blocks: ElementKind::ALL.map(ElementBlock::new).to_vec(),
        }
    }
}

impl Elements {
    pub fn block(&self, kind: ElementKind) -> &ElementBlock {
        &self.blocks[kind.index()]
    }

    pub fn block_mut(&mut self, kind: ElementKind) -> &mut ElementBlock {
        &mut self.blocks[kind.index()]
    }

    /// Elements of every kind.
    pub fn count(&self) -> usize {
        self.blocks.iter().map(ElementBlock::len).sum()
    }

    /// Elements of one kind.
    pub fn count_of(&self, kind: ElementKind) -> usize {
        self.block(kind).len()
    }

    /// Corners of every element (the corner-force slots, see [`super::corners`]).
    pub fn corner_count(&self) -> usize {
        self.blocks.iter().map(|b| b.nodes.len()).sum()
    }

    /// The global number of the first element of a kind's block.
    pub fn offset(&self, kind: ElementKind) -> usize {
        self.blocks[..kind.index()]
            .iter()
            .map(ElementBlock::len)
            .sum()
    }

    /// Global numbers of a block's elements `local`.
    pub fn global(&self, kind: ElementKind, local: Range<usize>) -> Range<usize> {
        let o = self.offset(kind);
        o + local.start..o + local.end
    }

    /// Every element in global order.
    pub fn iter(&self) -> impl Iterator<Item = ElementRef<'_>> + '_ {
        self.blocks.iter().flat_map(|b| {
            b.iter().map(move |(nodes, material)| ElementRef {
                kind: b.kind,
                nodes,
                material,
            })
        })
    }

    /// The kind and the number within its block of global element `e`.
    pub fn locate(&self, mut e: usize) -> (ElementKind, usize) {
        for b in &self.blocks {
            if e < b.len() {
                return (b.kind, e);
            }
            e -= b.len();
        }
        panic!("element number past the mesh's {} elements", self.count())
    }

    /// Element `e` in global order.
    pub fn element(&self, e: usize) -> ElementRef<'_> {
        let (kind, e) = self.locate(e);
        let b = self.block(kind);
        ElementRef {
            kind,
            nodes: b.element(e),
            material: b.material[e],
        }
    }

    /// Every corner's node in corner order (each block's in turn).
    pub fn corner_nodes(&self) -> impl Iterator<Item = u32> + '_ {
        self.blocks.iter().flat_map(|b| b.nodes.iter().copied())
    }

    /// Appends an element of its kind's block.
    pub fn push(&mut self, kind: ElementKind, nodes: &[u32], material: u32) {
        self.block_mut(kind).push(nodes, material);
    }

    /// Appends every element of `other`, its nodes shifted by `shift`, with `material`
    /// (where given) in place of its own; returns each block's new local range.
    pub fn append(
        &mut self,
        other: &Elements,
        shift: u32,
        material: Option<u32>,
    ) -> Vec<Range<usize>> {
        (self.blocks.iter_mut().zip(&other.blocks))
            .map(|(b, o)| {
                let start = b.len();
                b.nodes.extend(o.nodes.iter().map(|n| n + shift));
                match material {
                    Some(m) => b.material.extend(std::iter::repeat_n(m, o.len())),
                    None => b.material.extend_from_slice(&o.material),
                }
                start..b.len()
            })
            .collect()
    }

    /// The elements for which `keep(global number)` holds, in order, with their global
    /// numbers, their nodes renumbered by `node`.
    pub fn select(
        &self,
        keep: impl Fn(usize) -> bool,
        node: impl Fn(u32) -> u32,
    ) -> (Elements, Vec<usize>) {
        let mut out = Elements::default();
        let mut kept = Vec::new();
        for (e, el) in self.iter().enumerate() {
            if keep(e) {
                let nodes: Vec<u32> = el.nodes.iter().map(|&n| node(n)).collect();
                out.push(el.kind, &nodes, el.material);
                kept.push(e);
            }
        }
        (out, kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn global_numbers_run_through_the_blocks_in_kind_order() {
        let mut els = Elements::default();
        els.push(ElementKind::Tet4, &[0, 1, 2, 3], 5);
        els.push(ElementKind::Hex8, &[0, 1, 2, 3, 4, 5, 6, 7], 1);
        els.push(ElementKind::Hex8, &[8, 9, 10, 11, 12, 13, 14, 15], 2);
        assert_eq!((els.count(), els.corner_count()), (3, 20));
        assert_eq!(els.offset(ElementKind::Tet4), 2);
        let kinds: Vec<_> = els.iter().map(|e| (e.kind, e.material)).collect();
        use ElementKind::*;
        assert_eq!(kinds, vec![(Hex8, 1), (Hex8, 2), (Tet4, 5)]);
        assert_eq!(els.element(2).nodes, &[0, 1, 2, 3]);
        assert_eq!(els.element(1).nodes[0], 8);
        assert_eq!(els.corner_nodes().nth(16), Some(0));
        let (part, kept) = els.select(|e| e != 1, |n| n + 100);
        assert_eq!(kept, vec![0, 2]);
        assert_eq!(part.element(1).nodes, &[100, 101, 102, 103]);
        let mut all = Elements::default();
        let ranges = all.append(&els, 10, Some(7));
        assert_eq!(ranges, vec![0..2, 0..1, 0..0]);
        assert_eq!(all.element(2).nodes, &[10, 11, 12, 13]);
        assert!(all.iter().all(|e| e.material == 7));
    }
}
