//! CPU twin of `shaders/hex8_damage.wgsl`: the damage pass of a hex8 block
//! ([`super::damage_data`]), each damageable element's step by
//! [`crate::element::damage::hex_damage`] (no modes).

use super::damage_data::{damage_pass, BlockPass, DamageData};
use super::ElementData;
use crate::element::damage::{hex_damage, Modes};
use crate::element::ElementKind;

/// The pass over the hex8 block's damageable elements (`out` holds the block's part of the
/// corner forces).
pub(crate) fn hex8_damage(
    data: &ElementData,
    damage: &DamageData,
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    out: BlockPass,
    (dt, advance): (f64, bool),
) {
    let kind = ElementKind::Hex8;
    let block = damage.block(kind);
    let laws = damage.laws();
    damage_pass(
        block,
        data.elements.block(kind).corners::<8>(),
        (&data.reference, u, v, dt),
        out,
        advance,
        &|i, x, corners, old, new| {
            let plies = (block.plies_of(i), block.axis[i] as usize);
            hex_damage(
                x,
                corners,
                plies,
                &laws,
                (old, new),
                Modes::None,
                (dt, advance),
            )
        },
    );
}
