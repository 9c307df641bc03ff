//! CPU twin of `shaders/hex8i_damage.wgsl`: the damage pass of a hex8i block
//! ([`super::damage_pass`]), each damageable element's step through its shape's point
//! operators ([`crate::element::damage::hex_damage_operated`]), or from its corners by
//! [`crate::element::damage::hex_damage`], its modes condensed elastically.

use super::damage_data::{DamageBlock, DamageData};
use super::damage_pass::{damage_pass, BlockPass, ElementDamage};
use super::ElementData;
use crate::element::damage::{
    hex_damage, hex_damage_operated, hex_reach, hex_reach_operated, DamageLaws, DamageStep, Modes,
};
use crate::element::ElementKind;

/// The pass over the hex8i block's damageable elements (`out` holds the block's part of the
/// corner forces).
pub(crate) fn hex8i_damage(
    data: &ElementData,
    damage: &DamageData,
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    out: BlockPass,
    (dt, advance): (f64, bool),
) {
    hex_pass(ElementKind::Hex8i, data, damage, (u, v), out, (dt, advance));
}

/// A hex block's pass (hex8 or hex8i).
pub(crate) fn hex_pass(
    kind: ElementKind,
    data: &ElementData,
    damage: &DamageData,
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    out: BlockPass,
    (dt, advance): (f64, bool),
) {
    let kernel = HexDamage {
        block: damage.block(kind),
        laws: damage.laws(),
        incompatible: kind == ElementKind::Hex8i,
        step: (dt, advance),
    };
    let corners = data.elements.block(kind).corners::<8>();
    damage_pass(
        kernel.block,
        corners,
        (&data.reference, u, v, dt),
        out,
        advance,
        &kernel,
    );
}

/// A hex block's damageable elements.
struct HexDamage<'a> {
    block: &'a DamageBlock,
    laws: DamageLaws<'a>,
    /// Whether they have incompatible modes (hex8i).
    incompatible: bool,
    step: (f64, bool),
}

impl HexDamage<'_> {
    fn modes(&self, i: usize) -> Modes<'_> {
        match self.incompatible {
            true => Modes::Elastic(&self.block.condensation[216 * i..216 * (i + 1)]),
            false => Modes::None,
        }
    }
}

impl ElementDamage<8> for HexDamage<'_> {
    fn step(
        &self,
        i: usize,
        x: &[[f64; 3]; 8],
        u: (&[[f64; 3]; 8], &[[f64; 3]; 8]),
        state: &mut [f64],
    ) -> DamageStep<8> {
        let (block, laws) = (self.block, &self.laws);
        match block.operators_of(i) {
            Some(ops) => hex_damage_operated(ops, u, block.plies_of(i), laws, state, self.step),
            None => {
                let plies = (block.plies_of(i), block.axis[i] as usize);
                hex_damage(x, u, plies, laws, state, self.modes(i), self.step)
            }
        }
    }

    fn reach(&self, i: usize, x: &[[f64; 3]; 8], u: &[[f64; 3]; 8]) -> f64 {
        let (block, laws) = (self.block, &self.laws);
        match block.operators_of(i) {
            Some(ops) => hex_reach_operated(ops, u, block.plies_of(i), laws),
            None => {
                let plies = (block.plies_of(i), block.axis[i] as usize);
                hex_reach(x, u, plies, laws, self.modes(i))
            }
        }
    }
}
