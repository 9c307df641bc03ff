//! Fixed, printed seeds and the random distorted meshes the kernel twins are compared on.

/// A fresh seed for randomised tests (or `IMPACT_TEST_SEED`), printed so a failure can be
/// replayed.
pub fn seed(test: &str) -> u64 {
    let s = std::env::var("IMPACT_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            // a fixed seed per test (FNV-1a of its name): every run draws the same inputs
            test.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
                (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
            })
        });
    eprintln!("{test}: seed {s} (replay with IMPACT_TEST_SEED={s})");
    s
}

/// Element size and origin of [`jittered_box`]: far from the origin, so that the f32 kernels
/// must keep the precision of the element scale.
pub const JITTER_H: f64 = 0.5;

pub const JITTER_ORIGIN: [f64; 3] = [120.0, -64.0, 30.0];

/// A box of `divisions` cells of size [`JITTER_H`] from [`JITTER_ORIGIN`], every node moved by
/// up to 0.2 of the cell size along each axis (a distorted mesh).
pub fn jittered_box(rng: &mut impl rand::Rng, divisions: [usize; 3]) -> impact::mesh::BodyParts {
    let (h, origin) = (JITTER_H, JITTER_ORIGIN);
    let spec = impact::scene::BoxSpec {
        min: origin,
        max: std::array::from_fn(|a| origin[a] + h * divisions[a] as f64),
        divisions,
        element: impact::scene::BoxElement::Hex8,
        refine: None,
    };
    let mut parts = impact::mesh::box_mesh::box_mesh(&spec);
    for x in &mut parts.nodes {
        for c in x.iter_mut() {
            *c += rng.random_range(-0.2..0.2) * h;
        }
    }
    parts
}
