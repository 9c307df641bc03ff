//! CPU twin of `shaders/tet4_damage.wgsl`: the damage pass of a tet4 block
//! ([`super::damage_pass`]), each damageable element's step by
//! [`crate::element::damage::tet_damage`].

use super::damage_data::{DamageBlock, DamageData};
use super::damage_pass::{damage_pass, BlockPass, ElementDamage};
use super::ElementData;
use crate::element::damage::{tet_damage, tet_reach, DamageLaws, DamageStep};
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
    let kernel = TetDamage {
        block: damage.block(kind),
        laws: damage.laws(),
        step: (dt, advance),
    };
    let corners = data.elements.block(kind).corners::<4>();
    damage_pass(
        kernel.block,
        corners,
        (&data.reference, u, v, dt),
        out,
        advance,
        &kernel,
    );
}

/// A tet4 block's damageable elements.
struct TetDamage<'a> {
    block: &'a DamageBlock,
    laws: DamageLaws<'a>,
    step: (f64, bool),
}

impl ElementDamage<4> for TetDamage<'_> {
    fn step(
        &self,
        i: usize,
        x: &[[f64; 3]; 4],
        u: (&[[f64; 3]; 4], &[[f64; 3]; 4]),
        state: &mut [f64],
    ) -> DamageStep<4> {
        tet_damage(
            x,
            u,
            &self.block.plies_of(i)[0],
            &self.laws,
            state,
            self.step,
        )
    }

    fn reach(&self, i: usize, x: &[[f64; 3]; 4], u: &[[f64; 3]; 4]) -> f64 {
        tet_reach(x, u, &self.block.plies_of(i)[0], &self.laws)
    }
}
