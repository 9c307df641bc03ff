//! CPU twin of `shaders/tet4_damage.wgsl`: the damage pass of a tet4 block
//! ([`super::damage_data`]), each damageable element's step by
//! [`crate::element::damage::tet_damage`].

use super::damage_data::{damage_pass, BlockPass, DamageData};
use super::ElementData;
use crate::element::damage::tet_damage;
use crate::element::ElementKind;

/// The pass over the tet4 block's damageable elements (`out` holds the block's part of the
/// corner forces).
pub(crate) fn tet4_damage(
    data: &ElementData,
    damage: &DamageData,
    (u, v): (&[[f64; 3]], &[[f64; 3]]),
    out: BlockPass,
    (dt, advance): (f64, bool),
) {
    let kind = ElementKind::Tet4;
    let block = damage.block(kind);
    let laws = damage.laws();
    damage_pass(
        block,
        data.elements.block(kind).corners::<4>(),
        (&data.reference, u, v, dt),
        out,
        advance,
        &|i, x, corners, old, new| {
            tet_damage(
                x,
                corners,
                &block.plies_of(i)[0],
                &laws,
                (old, new),
                (dt, advance),
            )
        },
    );
}
