//! The input format: read a scene file, check every value, and hand out a validated [`Scene`].
//!
//! `docs/scene-format.md` documents each key (meaning, units, default).

pub mod from_deck;
mod raw;
pub mod suggest;
mod validate;

use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use crate::mesh::box_mesh::{BoxElement, BoxFace, BoxSpec, Refine};
use crate::mesh::BodyParts;
pub use rigid_body::{PrimarySide, RigidBodySpec, RigidMotion};

use crate::error::{ImpactError, Result};
use crate::material::{Elastic, Rotation};

/// Names each value of a scene option once: `CHOICES` (what the scene reader and the command
/// line accept, in the order error messages list them) and `name()` (what summaries print).
macro_rules! option_names {
    ($ty:ident { $($variant:ident = $name:literal),* $(,)? }) => {
        impl $ty {
            pub const CHOICES: &'static [(&'static str, $ty)] = &[$(($name, $ty::$variant)),*];

            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),*
                }
            }
        }
    };
}

pub mod rigid_body;

option_names!(Method { Implicit = "implicit", Explicit = "explicit", Auto = "auto", Static = "static" });
option_names!(DeviceChoice { Auto = "auto", Gpu = "gpu", Cpu = "cpu" });
option_names!(Kinematics { Linear = "linear", Corotational = "corotational" });
option_names!(ConstraintMeasure { GapRate = "gap_rate", Gap = "gap" });
option_names!(PenaltyLaw { Adaptive = "adaptive", Fixed = "fixed" });
option_names!(Acceleration { Anderson = "anderson", Newton = "newton", None = "none" });
option_names!(ContactSpace { Auto = "auto", Off = "off" });
option_names!(MassKind { Lumped = "lumped", Consistent = "consistent" });
option_names!(PenetrationPolicy { Error = "error", Adjust = "adjust", Ignore = "ignore", Resolve = "resolve" });
option_names!(Ordering { NestedDissection = "nested_dissection", Amd = "amd" });

/// Summaries name the ordering.
impl serde::Serialize for Ordering {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// Which integrator runs the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Implicit,
    Explicit,
    Auto,
    /// Equilibrium without inertia at each step's load level ([`StaticSettings`]).
    Static,
}

/// `[static]`: the increments of a static step (`method = "static"`) are `run.time_step`
/// long, halved where one does not converge down to `minimum_step`; `stabilisation` is the
/// spring on every dof, relative to its own stiffness, that holds a body nothing else holds
/// (`integrate::statics`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticSettings {
    pub minimum_step: f64,
    pub stabilisation: f64,
}

/// How the elements' strains follow their corners (`run.kinematics`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Kinematics {
    /// The linear strain of the displacement: small displacements and rotations.
    #[default]
    Linear,
    /// Each element's linear strain in a frame that turns with it
    /// ([`crate::element::corotation`]): large rotations, small strains (explicit, CPU).
    Corotational,
}

/// Where the element and contact kernels run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeviceChoice {
    Auto,
    Gpu,
    Cpu,
}

impl std::str::FromStr for DeviceChoice {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let found = DeviceChoice::CHOICES.iter().find(|(n, _)| *n == s);
        found.map(|&(_, d)| d).ok_or_else(|| {
            let names: Vec<String> = DeviceChoice::CHOICES
                .iter()
                .map(|(n, _)| format!("`{n}`"))
                .collect();
            format!("unknown device `{s}`, expected one of {}", names.join(", "))
        })
    }
}

/// Which kinematic quantity the augmented Lagrange multiplier update is driven by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConstraintMeasure {
    /// The paper's choice: the normal gap rate (velocity level).
    GapRate,
    /// The classical choice, for comparison: the normal gap (position level).
    Gap,
}

/// Whether the penalty of the multiplier update adapts (paper eqs. 18-20) or stays fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PenaltyLaw {
    Adaptive,
    Fixed,
}

/// How the multiplier iteration is driven: the plain augmented Lagrange update, that update
/// with Anderson acceleration (`contact::anderson`), or the semi-smooth Newton step on the
/// update's active set (`integrate::implicit::newton`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Acceleration {
    Anderson,
    Newton,
    None,
}

/// Where the implicit multiplier iteration solves: on the contact equations alone, through
/// the trailing block of a factor that numbers them last (`Auto`, where the kernels compute
/// in f64 and there are at most [`CONTACT_SPACE_MAX`] of them), or on the whole model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactSpace {
    Auto,
    Off,
}

/// The most contact equations the iteration solves on alone.
pub const CONTACT_SPACE_MAX: usize = 20_000;

/// Mass matrix of the implicit integrator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MassKind {
    Lumped,
    Consistent,
}

#[derive(Debug, Clone)]
pub struct RunSettings {
    pub end_time: f64,
    pub time_step: Option<f64>,
    pub method: Method,
    pub device: DeviceChoice,
    /// How the elements' strains follow their corners.
    pub kinematics: Kinematics,
    /// A rise of the total energy above its start by more than this fraction of the run's
    /// energy scale is a warning (elastic contact can only lose energy).
    pub energy_tolerance: f64,
}

/// The default of `run.energy_tolerance`.
pub(crate) const ENERGY_TOLERANCE: f64 = 0.05;

/// What a run does with secondary nodes found behind their primary surface at t = 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PenetrationPolicy {
    /// Refuse the scene, with the count, deepest node and depth.
    #[default]
    Error,
    /// Move the nodes onto the surface before t = 0 (a change of the reference shape, so
    /// strain free), and report what moved.
    Adjust,
    /// Run as given; the run ends with a warning.
    Ignore,
    /// A static step's first increment pushes the bodies apart (an interference fit), as
    /// CalculiX resolves a deck's overclosure; static steps only.
    Resolve,
}

/// Settings of the explicit central-difference path (`[explicit]`).
#[derive(Debug, Clone)]
pub struct ExplicitSettings {
    /// The default step is this fraction of the stable step.
    pub safety_factor: f64,
    /// Sweeps of the contact impulse iteration per step.
    pub max_iterations: usize,
    /// The contact iteration ends when no constraint is violated by more than this fraction
    /// of the scene's speed scale.
    pub tolerance: f64,
    /// Run a `time_step` above the stable bound instead of refusing it (stability studies).
    pub allow_unstable: bool,
}

impl Default for ExplicitSettings {
    fn default() -> Self {
        ExplicitSettings {
            safety_factor: 0.9,
            max_iterations: 200,
            tolerance: 1e-6,
            allow_unstable: false,
        }
    }
}

/// Which fill-reducing ordering the implicit factorisation uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ordering {
    /// METIS nested dissection on the supervariable graph (the default).
    #[default]
    NestedDissection,
    /// faer's approximate minimum degree.
    Amd,
}

#[derive(Debug, Clone)]
pub struct ImplicitSettings {
    pub beta: f64,
    pub gamma: f64,
    pub constraint: ConstraintMeasure,
    pub penalty: PenaltyLaw,
    /// Initial eps_N; `None` means "estimate from the scene" (see `integrate::implicit::interface::default_penalty`).
    pub penalty_normal: Option<f64>,
    /// Initial eps_T; `None` means "equal to eps_N".
    pub penalty_tangential: Option<f64>,
    pub max_iterations: usize,
    pub tolerance: f64,
    pub mass: MassKind,
    /// MAR of eq. 20a, the largest admissible gap rate; `None`: 1e-3 of the scene's speed scale.
    pub max_gap_rate: Option<f64>,
    /// T_MAX of eq. 20b, the largest relative force change allowed to alternate in sign (a
    /// smaller one that grows while the measured eps s exceeds 2 counts as well).
    pub max_force_change: f64,
    pub acceleration: Acceleration,
    /// Sub-steps of a step in which an interface's contact force changes abruptly (impact,
    /// release); 1 turns the refinement off. Gap-rate constraint only.
    pub event_substeps: usize,
    /// The relative change of an interface's normal force from one step to the next above
    /// which a step counts as a contact event.
    pub event_force_change: f64,
    /// The fill-reducing ordering of the factorisation.
    pub ordering: Ordering,
    /// Whether the multiplier iteration solves on the contact equations alone.
    pub contact_space: ContactSpace,
}

impl Default for ImplicitSettings {
    fn default() -> Self {
        ImplicitSettings {
            beta: 0.25,
            gamma: 0.5,
            constraint: ConstraintMeasure::GapRate,
            penalty: PenaltyLaw::Adaptive,
            penalty_normal: None,
            penalty_tangential: None,
            max_iterations: 100,
            tolerance: 1e-6,
            mass: MassKind::Consistent,
            max_gap_rate: None,
            max_force_change: 0.05,
            acceleration: Acceleration::Newton,
            event_substeps: 4,
            event_force_change: 0.2,
            ordering: Ordering::default(),
            contact_space: ContactSpace::Auto,
        }
    }
}

#[derive(Debug, Clone)]
pub struct Material {
    pub name: String,
    pub density: f64,
    /// The elastic law in the material's own axes.
    pub elastic: Elastic,
    /// Ply strengths, for the failure indices (`strength`).
    pub strength: Option<crate::material::Strength>,
    /// The plies' damage (`fracture_energy`, `damage_viscosity`), where given.
    pub damage: Option<DamageSpec>,
}

/// A material's damage: the fracture energies of fibre tension and compression and matrix
/// tension and compression (energy per unit crack area), and the Duvaut-Lions time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamageSpec {
    pub energy: [f64; 4],
    pub viscosity: f64,
    /// `damage_stresses = "in_plane"`: the plies damage by their in-plane stresses alone.
    pub in_plane: bool,
    /// `snap_back = "lower_strength"`: an element wider than a mode's snap-back width
    /// starts to damage at the strength its width dissipates G with.
    pub lower_strength: bool,
}

/// Where a body's mesh comes from.
#[derive(Debug, Clone)]
pub enum BodyShape {
    /// A structured hex8 box; its surfaces are the six faces in [`BoxFace::ALL`] order.
    Box(BoxSpec),
    /// A mesh file, read (and scaled, translated) while the scene is checked.
    Imported {
        path: PathBuf,
        parts: Arc<BodyParts>,
    },
}

#[derive(Debug, Clone)]
pub struct BodySpec {
    pub name: String,
    pub material: usize,
    pub shape: BodyShape,
    pub velocity: [f64; 3],
    /// The material axes of the body (of its plies' 0 degree direction with plies).
    pub orientation: Rotation,
    pub plies: Option<Plies>,
}

/// A laminate: plies stacked along a global axis from the body's lowest coordinate on it.
#[derive(Debug, Clone, PartialEq)]
pub struct Plies {
    /// The stacking axis: 0, 1, 2 for x, y, z.
    pub axis: usize,
    /// The body's lowest coordinate along the axis, where the first ply starts.
    pub start: f64,
    pub layers: Vec<Ply>,
}

/// One ply: its material axes are the body's turned by `angle` (radians) about the stacking
/// axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ply {
    pub angle: f64,
    pub thickness: f64,
}

impl Plies {
    /// The ply holding the coordinate `t` along the stacking axis (the first or the last
    /// beyond the ends).
    pub fn ply_at(&self, t: f64) -> usize {
        let mut top = self.start;
        for (k, p) in self.layers.iter().enumerate() {
            top += p.thickness;
            if t < top {
                return k;
            }
        }
        self.layers.len() - 1
    }

    /// The unit vector of the stacking axis.
    pub fn normal(&self) -> [f64; 3] {
        std::array::from_fn(|a| (a == self.axis) as u8 as f64)
    }
}

impl BodySpec {
    /// The body's mesh in its own node numbering.
    pub fn parts(&self) -> BodyParts {
        match &self.shape {
            BodyShape::Box(b) => crate::mesh::box_mesh(b),
            BodyShape::Imported { parts, .. } => (**parts).clone(),
        }
    }
}

/// A surface of a body: for a box, `surface` is a [`BoxFace`] as `usize`; for an imported
/// mesh, an index into its named surfaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SurfaceRef {
    pub body: usize,
    pub surface: usize,
}

/// The secondary side of a `[[contact]]`: a body's faces, or a node set of it (`set`, a
/// deck's node-based surface), whose nodes alone take part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SecondarySide {
    Faces(SurfaceRef),
    Nodes { body: usize, set: usize },
}

impl SecondarySide {
    pub fn body(&self) -> usize {
        match *self {
            Self::Faces(s) => s.body,
            Self::Nodes { body, .. } => body,
        }
    }
}

#[derive(Debug, Clone)]
pub struct ContactSpec {
    pub name: String,
    pub secondary: SecondarySide,
    pub primary: PrimarySide,
    pub friction: f64,
    pub initial_penetration: PenetrationPolicy,
    /// `region`: only the secondary faces with every node inside this box take part (of a
    /// node set, the nodes inside it).
    pub region: Option<([f64; 3], [f64; 3])>,
    /// `adjust`: secondary nodes in front of the primary surface by at most this at t = 0
    /// are moved onto it (0: none).
    pub adjust: f64,
    /// `stiffness` or `exponential`: a soft pressure-overclosure law; none for hard
    /// contact. Static steps honour it.
    pub pressure_law: Option<PressureLaw>,
    /// `stick_slope`: a static step's friction, the shear stress per unit slip while a node
    /// sticks (none: the hard contact's own penalty).
    pub stick_slope: Option<f64>,
}

/// A soft contact's pressure against the overclosure g (g > 0 a penetration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PressureLaw {
    /// `stiffness`: p = k g for g > 0 (CalculiX's linear pressure-overclosure).
    Linear { stiffness: f64 },
    /// `exponential = { clearance, pressure }`: p = p0 exp(beta g) for g > -c0, with
    /// beta = ln 100 / c0 (p is 1% of p0 at the clearance c0), 0 beyond (CalculiX's
    /// exponential pressure-overclosure).
    Exponential { clearance: f64, pressure: f64 },
}

impl PressureLaw {
    /// The pressure at overclosure `g`, and its slope dp/dg.
    pub fn at(&self, g: f64) -> (f64, f64) {
        match *self {
            PressureLaw::Linear { stiffness } if g > 0.0 => (stiffness * g, stiffness),
            PressureLaw::Linear { .. } => (0.0, 0.0),
            PressureLaw::Exponential {
                clearance,
                pressure,
            } if g > -clearance => {
                let beta = 100f64.ln() / clearance;
                let p = pressure * (beta * g).exp();
                (p, beta * p)
            }
            PressureLaw::Exponential { .. } => (0.0, 0.0),
        }
    }

    /// The energy the law holds at overclosure `g` per unit area: the integral of p from
    /// where it starts.
    pub fn energy(&self, g: f64) -> f64 {
        match *self {
            PressureLaw::Linear { stiffness } => 0.5 * stiffness * g.max(0.0).powi(2),
            PressureLaw::Exponential {
                clearance,
                pressure,
            } if g > -clearance => {
                let beta = 100f64.ln() / clearance;
                (self.at(g).0 - 0.01 * pressure) / beta
            }
            PressureLaw::Exponential { .. } => 0.0,
        }
    }
}

/// A `[[tie]]`: each secondary node within `tolerance` of the primary surface follows the
/// point of it nearest to the node (a linear constraint per component, as a deck's `*TIE`).
#[derive(Debug, Clone, PartialEq)]
pub struct TieSpec {
    pub name: String,
    pub secondary: SecondarySide,
    pub primary: SurfaceRef,
    /// The largest distance from the primary surface at which a secondary node is tied
    /// (`None`: 2.5% of the primary faces' mean size, CalculiX's default).
    pub tolerance: Option<f64>,
    /// Each tied node is moved onto its point of the primary surface before the run.
    pub adjust: bool,
}

/// A `[[cohesive]]` interface: between two bodies' faces (the second side's nodes pair with
/// the first's where they coincide), or inside a laminate body split at its ply changes.
#[derive(Debug, Clone)]
pub struct CohesiveSpec {
    pub name: String,
    pub sides: CohesiveSides,
    /// Only the nodes inside this box are bonded (the rest is a pre-crack).
    pub region: Option<([f64; 3], [f64; 3])>,
    pub law: crate::material::CohesiveLaw,
}

/// Where a cohesive interface lies.
#[derive(Debug, Clone)]
pub enum CohesiveSides {
    /// Between two bodies' surfaces.
    Between([SurfaceRef; 2]),
    /// Inside box body `body`, at the element layer boundaries (coordinates along
    /// `axis`, its plies' stacking axis) where the plies on either side differ in angle.
    Laminate {
        body: usize,
        axis: usize,
        planes: Vec<f64>,
    },
}

#[derive(Debug, Clone)]
pub struct PlaneSpec {
    pub name: String,
    pub point: [f64; 3],
    /// Unit normal into the free side.
    pub normal: [f64; 3],
    pub friction: f64,
    pub bodies: Vec<usize>,
    pub initial_penetration: PenetrationPolicy,
}

#[derive(Debug, Clone)]
pub enum NodeSelection {
    /// The nodes of a surface (a box face or a named surface of a mesh file).
    Surface(usize),
    /// A named node set of a mesh file.
    Set(usize),
    Region {
        min: [f64; 3],
        max: [f64; 3],
    },
    /// A rigid body's node: `body` then indexes [`Scene::rigid_bodies`].
    RigidBody,
}

/// A prescribed displacement at full amplitude, and the amplitude table that scales it over
/// time (empty: a ramp over the run).
pub type Displacement = ([f64; 3], Vec<[f64; 2]>);

/// An `[[equation]]`: sum of coefficient x the component of one node = 0; the first term's
/// dof is the one the others set (a static step's constraint).
#[derive(Debug, Clone)]
pub struct EquationSpec {
    pub terms: Vec<TermSpec>,
}

/// A `[[step]]` after the first (the `[run]`'s): at `start` the run goes on from the last
/// step's state without the equations it removes.
#[derive(Debug, Clone)]
pub struct StepSpec {
    pub start: f64,
    /// The step's method where it is not the run's: static, explicit or implicit (a
    /// preload, then an impact). The state carries over; a dynamic step after static ones
    /// starts at rest, but for the run's initial velocities where no dynamic step came
    /// before.
    pub method: Option<Method>,
    /// The step's own time step (`None`: the run's where the method is the run's; the stable
    /// step's for an explicit step after another method).
    pub time_step: Option<f64>,
    /// Where the step's fixes' ramps end (`None`: at the next step's start, or at
    /// `run.end_time`).
    pub end: Option<f64>,
    pub remove_equations: Removal,
    /// The fixes before this step that end at its start: none, every one, or these
    /// `[[fix]]`es (their indices).
    pub release_fixes: Release,
    /// The step's own fixes, from its start on. Where one holds a dof an earlier fix holds,
    /// it takes the dof over. A `displacement` without an `amplitude` is reached at the
    /// step's end, straight from where the nodes are at its start.
    pub fixes: Vec<FixSpec>,
    /// The contacts whose friction changes from the step on.
    pub contacts: Vec<FrictionChange>,
}

/// The fixes a step ends.
#[derive(Debug, Clone, PartialEq)]
pub enum Release {
    None,
    All,
    Fixes(Vec<usize>),
}

/// A step's `[[step.contact]]`: contact `contact`'s friction coefficient and (static steps)
/// stick slope from the step on, each kept as it was where `None`.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionChange {
    pub contact: usize,
    pub friction: Option<f64>,
    pub stick_slope: Option<f64>,
}

/// The `[[equation]]`s a step removes: none, all, or those whose dependent dof (their first
/// term's) is one of these components (body, nodes, component 0-2).
#[derive(Debug, Clone)]
pub enum Removal {
    None,
    All,
    Dofs(Vec<(usize, NodeSelection, usize)>),
}

/// One term of an equation: the one node `nodes` selects on `body`, its component (0-2)
/// and its coefficient.
#[derive(Debug, Clone)]
pub struct TermSpec {
    pub body: usize,
    pub nodes: NodeSelection,
    pub component: usize,
    pub coefficient: f64,
}

#[derive(Debug, Clone)]
pub struct FixSpec {
    /// A meshed body, or a rigid body where `nodes` is [`NodeSelection::RigidBody`].
    pub body: usize,
    pub nodes: NodeSelection,
    pub components: [bool; 3],
    /// The velocity of the held components from t = 0 (zero where not held).
    pub velocity: [f64; 3],
    /// The displacement the held components are moved to, and the amplitude that scales it
    /// over time (empty: a ramp from 0 at t = 0 to 1 at the run's end); `None` for a fix
    /// that holds its nodes still or moves them at `velocity`.
    pub displacement: Option<Displacement>,
    /// With a name, the history gives the fix's reaction (`<name>.fx`, `.fy`, `.fz`).
    pub name: Option<String>,
}

/// `[[initial_velocity]]`: the velocity at t = 0 of some of a meshed body's nodes, in place of
/// the body's own `velocity` there.
#[derive(Debug, Clone)]
pub struct InitialVelocitySpec {
    pub body: usize,
    /// A face, a node set or a region (never [`NodeSelection::RigidBody`]).
    pub nodes: NodeSelection,
    pub velocity: [f64; 3],
    /// The components it sets (`components`; every one by default).
    pub components: [bool; 3],
}

/// What a `[[load]]` applies at full amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoadKind {
    /// `force`: the same force on each selected node.
    Force([f64; 3]),
    /// `pressure`: a pressure on a face, against its outward normal.
    Pressure(f64),
}

/// `[[load]]`: a force on each node of a meshed body's face, node set or region, or a
/// pressure on its face, scaled by a piecewise linear amplitude of time (1 without one).
#[derive(Debug, Clone)]
pub struct LoadSpec {
    pub body: usize,
    pub nodes: NodeSelection,
    pub kind: LoadKind,
    /// (time, value) points, times increasing; empty: the constant 1.
    pub amplitude: Vec<[f64; 2]>,
}

/// A known solution of one history column, drawn beside the computed curve: a piecewise
/// linear curve through (time, value) points.
#[derive(Debug, Clone)]
pub struct ExactCurve {
    pub column: String,
    pub points: Vec<[f64; 2]>,
    pub label: String,
}

#[derive(Debug, Clone)]
pub struct ProbeSpec {
    pub name: String,
    pub body: usize,
    pub point: [f64; 3],
}

/// A checked scene: every name resolved to an index, every number in range.
#[derive(Debug, Clone)]
pub struct Scene {
    pub path: PathBuf,
    pub title: String,
    pub gravity: [f64; 3],
    pub run: RunSettings,
    pub implicit: ImplicitSettings,
    pub explicit: ExplicitSettings,
    pub statics: StaticSettings,
    pub materials: Vec<Material>,
    pub bodies: Vec<BodySpec>,
    pub contacts: Vec<ContactSpec>,
    pub planes: Vec<PlaneSpec>,
    pub rigid_bodies: Vec<RigidBodySpec>,
    pub fixes: Vec<FixSpec>,
    pub equations: Vec<EquationSpec>,
    pub ties: Vec<TieSpec>,
    /// The steps after the first, in time order.
    pub steps: Vec<StepSpec>,
    /// In the scene's order: where two select a node, the later one's velocity is its.
    pub initial_velocities: Vec<InitialVelocitySpec>,
    /// The `[[load]]`s, in the scene's order.
    pub loads: Vec<LoadSpec>,
    pub probes: Vec<ProbeSpec>,
    pub cohesive: Vec<CohesiveSpec>,
    pub output_dir: PathBuf,
    /// Write a VTU frame every this many steps (and at t = 0); `None`: no frames.
    pub vtu_every: Option<usize>,
    /// Write a checkpoint every this many steps; `None`: only when interrupted.
    pub checkpoint_every: Option<usize>,
    pub exact: Vec<ExactCurve>,
    /// What the mesh files hold that the scene does not read (a deck's materials and steps),
    /// one line each, shown before a run or a check.
    pub notices: Vec<String>,
}

impl Scene {
    /// Whether a `[[step]]` changes the method or the time step: its steps then run each at
    /// its own (a preload, then an impact).
    pub fn mixed_steps(&self) -> bool {
        (self.steps.iter())
            .any(|s| s.method.is_some_and(|m| m != self.run.method) || s.time_step.is_some())
    }

    /// Reads and checks a scene file, or an Abaqus/CalculiX deck (`.inp`) as the scene it
    /// converts to ([`from_deck`]).
    pub fn load(path: impl AsRef<Path>) -> Result<Scene> {
        let path = path.as_ref();
        if from_deck::is_deck(path) {
            return Self::from_deck(path);
        }
        let text =
            crate::limits::read_input_text(path).map_err(|source| ImpactError::ReadScene {
                path: path.to_path_buf(),
                source,
            })?;
        Self::parse(&text, path)
    }

    /// The scene of the deck at `path`: its converted text, checked, with the deck's notice
    /// in place of the mesh reader's (which lists the keywords the conversion read).
    fn from_deck(path: &Path) -> Result<Scene> {
        let converted = from_deck::convert(path)?;
        let mut scene = Self::parse(&converted.toml, path).map_err(|e| converted.locate(e))?;
        let mesh_notice = format!("{}: keywords not read", path.display());
        scene.notices.retain(|n| !n.starts_with(&mesh_notice));
        scene.notices.extend(converted.notice);
        Ok(scene)
    }

    /// Checks scene text; `path` is used in messages and for the default output folder.
    pub fn parse(text: &str, path: &Path) -> Result<Scene> {
        let raw: raw::RawScene = toml::from_str(text).map_err(|e| ImpactError::SceneSyntax {
            path: path.to_path_buf(),
            message: suggest::with_suggestion(&e.to_string()),
        })?;
        // the reader takes an array's first components and passes over the rest
        let file: Option<toml::Value> = toml::from_str(text).ok();
        let read = toml::Value::try_from(&raw).ok();
        if let Some((key, given, taken)) = file
            .zip(read)
            .and_then(|(f, r)| raw::extra_components(&f, &r, ""))
        {
            return Err(ImpactError::SceneValue {
                path: path.to_path_buf(),
                key,
                message: format!("has {given} components; it takes {taken}"),
            });
        }
        validate::validate(raw, path)
    }

    /// The initial-penetration policy of each interface, in the model's order (contacts,
    /// then rigid planes).
    pub fn penetration_policies(&self) -> Vec<PenetrationPolicy> {
        self.contacts
            .iter()
            .map(|c| c.initial_penetration)
            .chain(self.planes.iter().map(|p| p.initial_penetration))
            .collect()
    }

    /// Each interface's `adjust` distance, in the model's order (contacts, then rigid planes,
    /// which have none).
    pub fn adjust_distances(&self) -> Vec<f64> {
        (self.contacts.iter().map(|c| c.adjust))
            .chain(self.planes.iter().map(|_| 0.0))
            .collect()
    }

    /// The scene key of interface `k` (model order: contacts, then rigid planes).
    pub fn interface_key(&self, k: usize) -> String {
        if k < self.contacts.len() {
            format!("contact[{k}] (contact `{}`)", self.contacts[k].name)
        } else {
            let i = k - self.contacts.len();
            format!("rigid_plane[{i}] (plane `{}`)", self.planes[i].name)
        }
    }

    /// Speed scale of the scene: the largest initial speed, or the speed gravity gives over the
    /// run, whichever is larger (used for default tolerances).
    pub fn speed_scale(&self) -> f64 {
        let v0 = (self.bodies.iter().map(|b| norm3(b.velocity)))
            .chain(self.initial_velocities.iter().map(|v| norm3(v.velocity)))
            .chain(self.rigid_bodies.iter().map(|b| norm3(b.velocity)))
            .fold(0.0, f64::max);
        let vg = norm3(self.gravity) * self.run.end_time;
        v0.max(vg)
    }
}

pub(crate) fn norm3(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
