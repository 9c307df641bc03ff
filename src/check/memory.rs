//! The memory a model needs, from the scene's counts alone (before anything is allocated),
//! against what this process may use.
//!
//! The estimates are lower bounds: they count the arrays whose size the element and node
//! counts fix exactly (coordinates, connectivity, the state vectors, the implicit path's
//! assembly triplets, the resident path's device buffers) and leave out what depends on the
//! run (contact candidate lists, the sparse factor's fill). A model refused by a lower bound
//! could never have run.

use serde::Serialize;

use crate::element::ElementKind;
use crate::error::{bytes, ImpactError, Result};
use crate::scene::{BodyShape, MassKind, Method, Scene};

/// Element and node counts of a scene, from box divisions and imported meshes.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub(crate) struct Counts {
    /// Elements of each kind ([`ElementKind::ALL`] order).
    pub elements: [u64; ElementKind::ALL.len()],
    pub nodes: u64,
}

impl Counts {
    pub fn of(scene: &Scene) -> Counts {
        let mut c = Counts::default();
        for b in &scene.bodies {
            match &b.shape {
                BodyShape::Box(s) => {
                    let [x, y, z] = s.cells().map(|d| d as u64);
                    // validated: the products fit (box.divisions is checked against u32 nodes)
                    let cells = x.saturating_mul(y).saturating_mul(z);
                    let (kind, per_cell) = s.element.per_cell();
                    let n = &mut c.elements[kind.index()];
                    *n = n.saturating_add(cells.saturating_mul(per_cell));
                    c.nodes = c
                        .nodes
                        .saturating_add((x + 1).saturating_mul(y + 1).saturating_mul(z + 1));
                }
                BodyShape::Imported { parts, .. } => {
                    for kind in ElementKind::ALL {
                        c.elements[kind.index()] += parts.elements.count_of(kind) as u64;
                    }
                    c.nodes += parts.nodes.len() as u64;
                }
            }
        }
        c
    }

    /// Elements of every kind.
    pub fn element_count(&self) -> u64 {
        self.elements.iter().sum()
    }

    /// The sum over the elements of `per(kind)`, saturating.
    fn sum(&self, per: impl Fn(ElementKind) -> u64) -> u64 {
        (ElementKind::ALL.iter()).fold(0u64, |acc, &k| {
            acc.saturating_add(self.elements[k.index()].saturating_mul(per(k)))
        })
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
/// Host bytes per element of n corners: connectivity twice, material ids twice, and what its
/// force kernel keeps (f64).
fn host_per_element(kind: ElementKind) -> u64 {
    2 * 4 * kind.corners() as u64 + 2 * 4 + 8 * kind.kept_per_element() as u64
}
/// Device bytes of the resident explicit step: per element its connectivity, its corner
/// forces (f32 x 3 per corner) and what its force kernel keeps (f32); per node ten f32 3-vectors (reference, u, v, a, forces, ...).
fn device_per_element(kind: ElementKind) -> u64 {
    (4 + 12) * kind.corners() as u64 + 4 * kind.kept_per_element() as u64
}
const DEVICE_PER_NODE: u64 = 10 * 12;
/// Implicit assembly: a (row, column, value) triplet is 16 bytes; an element of n corners
/// gives (3 n)^2 stiffness triplets and 3 n^2 consistent-mass triplets.
const TRIPLET: u64 = 16;

/// The lower-bound estimate for a scene run by `method` (the explicit path with `gpu`: the
/// resident engine).
pub(crate) fn estimate(scene: &Scene, method: Method, gpu: bool) -> Estimate {
    let c = Counts::of(scene);
    let base = (c.nodes.saturating_mul(HOST_PER_NODE)).saturating_add(c.sum(host_per_element));
    let (host, what) = match method {
        Method::Implicit | Method::Static => {
            let mass = u64::from(scene.implicit.mass == MassKind::Consistent);
            let triplets = c.sum(|k| {
                let n = k.corners() as u64;
                9 * n * n + mass * 3 * n * n
            });
            (
                base.saturating_add(triplets.saturating_mul(TRIPLET)),
                format!(
                    "{} elements, {} nodes: model, state and the implicit assembly's {} triplets; the sparse factor comes on top",
                    c.element_count(),
                    c.nodes,
                    triplets
                ),
            )
        }
        Method::Explicit | Method::Auto => (
            base,
            format!(
                "{} elements, {} nodes: model and explicit state",
                c.element_count(),
                c.nodes
            ),
        ),
    };
    let device = if gpu {
        (c.sum(device_per_element)).saturating_add(c.nodes.saturating_mul(DEVICE_PER_NODE))
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
