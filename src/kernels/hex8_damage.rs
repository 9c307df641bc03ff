//! CPU twin of `shaders/hex8_damage.wgsl`: the damage pass of a hex8 block, as
//! [`super::hex8i_damage`]'s without modes.

use super::damage_data::DamageData;
use super::damage_pass::BlockPass;
use super::hex8i_damage::hex_pass;
use super::ElementData;
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
    hex_pass(ElementKind::Hex8, data, damage, (u, v), out, (dt, advance));
}
