//! The memory a model needs, from the scene's counts alone (before anything is allocated),
//! against what this process may use.
//!
//! The estimates are lower bounds: they count the arrays whose size the element and node
//! counts fix exactly (coordinates, connectivity, the state vectors, the implicit path's
//! assembly triplets, the resident path's device buffers) and leave out what depends on the
//! run (contact candidate lists, the sparse factor's fill). A model refused by a lower bound
//! could never have run.

use serde::Serialize;

use crate::error::{bytes, ImpactError, Result};
use crate::scene::{BodyShape, BoxElement, MassKind, Method, Scene};

/// Element and node counts of a scene, from box divisions and imported meshes.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Counts {
    pub hexes: u64,
    pub tets: u64,
    pub nodes: u64,
}

impl Counts {
    pub fn of(scene: &Scene) -> Counts {
        let mut c = Counts::default();
        for b in &scene.bodies {
            match &b.shape {
                BodyShape::Box(s) => {
                    let [x, y, z] = s.divisions.map(|d| d as u64);
                    // validated: the products fit (box.divisions is checked against u32 nodes)
                    let cells = x.saturating_mul(y).saturating_mul(z);
                    match s.element {
                        BoxElement::Hex8 => c.hexes = c.hexes.saturating_add(cells),
                        BoxElement::Tet4 => c.tets = c.tets.saturating_add(cells.saturating_mul(6)),
                    }
                    c.nodes = c
                        .nodes
                        .saturating_add((x + 1).saturating_mul(y + 1).saturating_mul(z + 1));
                }
                BodyShape::Imported { parts, .. } => {
                    c.hexes += parts.hexes.len() as u64;
                    c.tets += parts.tets.len() as u64;
                    c.nodes += parts.nodes.len() as u64;
                }
            }
        }
        c
    }
}

/// Bytes the run needs at least, on the host and on the GPU.
#[derive(Debug, Clone, Serialize)]
pub struct Estimate {
    pub host: u64,
    pub device: u64,
    /// What the host figure counts.
    pub what: String,
}

/// Host bytes per node of the model and any explicit state: coordinates (twice: the model and
/// the kernels' copy), initial velocity, fixed flags, and eight f64 state vectors.
const HOST_PER_NODE: u64 = 24 + 24 + 24 + 3 + 8 * 24 + 8;
/// Host bytes per element: connectivity twice, material ids twice.
const HOST_PER_HEX: u64 = 2 * 32 + 2 * 4;
const HOST_PER_TET: u64 = 2 * 16 + 2 * 4;
/// Device bytes of the resident explicit step: per element its connectivity and its corner
/// forces (f32 x 3 per corner); per node ten f32 3-vectors (reference, u, v, a, forces, ...).
const DEVICE_PER_HEX: u64 = 32 + 8 * 12;
const DEVICE_PER_TET: u64 = 16 + 4 * 12;
const DEVICE_PER_NODE: u64 = 10 * 12;
/// Implicit assembly: a (row, column, value) triplet is 16 bytes; a hex8 gives 24^2 stiffness
/// triplets and 3 x 8^2 consistent-mass triplets, a tet4 12^2 and 3 x 4^2.
const TRIPLET: u64 = 16;

/// The lower-bound estimate for a scene run by `method` (the explicit path with `gpu`: the
/// resident engine).
pub fn estimate(scene: &Scene, method: Method, gpu: bool) -> Estimate {
    let c = Counts::of(scene);
    let base = c
        .nodes
        .saturating_mul(HOST_PER_NODE)
        .saturating_add(c.hexes.saturating_mul(HOST_PER_HEX))
        .saturating_add(c.tets.saturating_mul(HOST_PER_TET));
    let (host, what) = match method {
        Method::Implicit => {
            let mass = u64::from(scene.implicit.mass == MassKind::Consistent);
            let triplets = c
                .hexes
                .saturating_mul(576 + mass * 192)
                .saturating_add(c.tets.saturating_mul(144 + mass * 48));
            (
                base.saturating_add(triplets.saturating_mul(TRIPLET)),
                format!(
                    "{} elements, {} nodes: model, state and the implicit assembly's {} triplets; the sparse factor comes on top",
                    c.hexes + c.tets,
                    c.nodes,
                    triplets
                ),
            )
        }
        Method::Explicit | Method::Auto => (
            base,
            format!(
                "{} elements, {} nodes: model and explicit state",
                c.hexes + c.tets,
                c.nodes
            ),
        ),
    };
    let device = if gpu {
        c.hexes
            .saturating_mul(DEVICE_PER_HEX)
            .saturating_add(c.tets.saturating_mul(DEVICE_PER_TET))
            .saturating_add(c.nodes.saturating_mul(DEVICE_PER_NODE))
    } else {
        0
    };
    Estimate { host, device, what }
}

pub use crate::limits::host_limit;

/// Refuses an estimate above the host limit; `held`: the bytes of the estimate the process
/// holds already (the built model).
pub fn check(scene: &Scene, e: &Estimate, held: u64) -> Result<()> {
    let Some((limit, source)) = host_limit(held) else {
        return Ok(());
    };
    if e.host > limit {
        return Err(ImpactError::TooLarge {
            path: scene.path.clone(),
            what: e.what.clone(),
            estimate: e.host,
            limit,
            limit_source: source,
        });
    }
    Ok(())
}

/// One line for `impact check` and the console.
pub fn describe(e: &Estimate) -> String {
    let limit = host_limit(0)
        .map(|(b, s)| format!("; this process may use {} ({s})", bytes(b)))
        .unwrap_or_default();
    let device = if e.device > 0 {
        format!(", GPU at least {}", bytes(e.device))
    } else {
        String::new()
    };
    format!(
        "host at least {}{device} ({}){limit}",
        bytes(e.host),
        e.what
    )
}
