//! [`CornerLayout`]: where each element corner's force lives in the corner-force array,
//! the one home of that arithmetic for the CPU twins, the GPU engine, the corner selection
//! and the subdomains.
//!
//! The blocks follow each other (in [`ElementKind::ALL`] order), each taking
//! `corners x elements` slots. Within a block the twins number corner k of element e
//! `n e + k` (element-major, n the kind's corner count) and a device `k E + e`
//! (corner-major, E the block's elements), so that neighbouring invocations write
//! neighbouring words. A "corner id" is the twins' slot.

use super::block::Elements;
use super::kind::ElementKind;

/// One block's place in the corner-force array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct BlockSlots {
    kind: ElementKind,
    /// Elements in the block.
    elements: usize,
    /// The block's first slot.
    offset: usize,
    /// The global number of the block's first element.
    first_element: usize,
}

impl BlockSlots {
    fn corners(&self) -> usize {
        self.kind.corners()
    }

    fn slots(&self) -> usize {
        self.corners() * self.elements
    }
}

/// The corner-force layout of a mesh's elements.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CornerLayout {
    blocks: Vec<BlockSlots>,
}

impl CornerLayout {
    pub fn of(elements: &Elements) -> Self {
        let (mut offset, mut first_element) = (0, 0);
        let blocks = (elements.blocks.iter())
            .map(|b| {
                let s = BlockSlots {
                    kind: b.kind,
                    elements: b.len(),
                    offset,
                    first_element,
                };
                offset += s.slots();
                first_element += s.elements;
                s
            })
            .collect();
        CornerLayout { blocks }
    }

    fn block(&self, kind: ElementKind) -> &BlockSlots {
        &self.blocks[kind.index()]
    }

    /// Slots in all.
    pub fn count(&self) -> usize {
        self.blocks.iter().map(BlockSlots::slots).sum()
    }

    /// The first slot of a kind's block (the same on the host and on a device).
    pub fn offset(&self, kind: ElementKind) -> usize {
        self.block(kind).offset
    }

    /// The twins' slot (corner id) of corner `k` of element `e` of a kind's block.
    pub fn twin(&self, kind: ElementKind, e: usize, k: usize) -> usize {
        let b = self.block(kind);
        b.offset + b.corners() * e + k
    }

    /// A device's slot of corner `k` of element `e` of a kind's block.
    pub fn device(&self, kind: ElementKind, e: usize, k: usize) -> usize {
        let b = self.block(kind);
        b.offset + k * b.elements + e
    }

    /// The block, the element within it and the corner of corner id `c`.
    fn locate(&self, c: usize) -> (&BlockSlots, usize, usize) {
        let b = (self.blocks.iter())
            .find(|b| c < b.offset + b.slots())
            .expect("a corner id within the layout");
        let i = c - b.offset;
        (b, i / b.corners(), i % b.corners())
    }

    /// A device's slot of corner id `c`.
    pub fn to_device(&self, c: usize) -> usize {
        let (b, e, k) = self.locate(c);
        self.device(b.kind, e, k)
    }

    /// The corner id of corner 0 of global element `e`.
    pub fn first_corner(&self, e: usize) -> usize {
        let b = (self.blocks.iter())
            .find(|b| e < b.first_element + b.elements)
            .expect("an element within the layout");
        b.offset + b.corners() * (e - b.first_element)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both numberings cover the slots once, and agree on the block of every corner.
    #[test]
    fn host_and_device_slots_are_permutations_of_each_other() {
        let mut els = Elements::default();
        for e in 0..3u32 {
            els.push(ElementKind::Hex8, &[e; 8], 0);
        }
        for e in 0..5u32 {
            els.push(ElementKind::Tet4, &[e; 4], 0);
        }
        let layout = CornerLayout::of(&els);
        assert_eq!(layout.count(), 8 * 3 + 4 * 5);
        assert_eq!(layout.offset(ElementKind::Tet4), 24);
        let mut seen = vec![false; layout.count()];
        for c in 0..layout.count() {
            let d = layout.to_device(c);
            assert!(!seen[d]);
            seen[d] = true;
        }
        assert_eq!(layout.twin(ElementKind::Tet4, 2, 3), 24 + 11);
        assert_eq!(layout.device(ElementKind::Tet4, 2, 3), 24 + 3 * 5 + 2);
        assert_eq!(layout.to_device(24 + 11), 24 + 17);
        assert_eq!(layout.first_corner(5), 32);
        assert_eq!(layout.first_corner(2), 16);
    }
}
