//! The scene file as written: serde structs that mirror the TOML keys one to one.
//!
//! Every struct denies unknown keys, so a misspelt key is an error (with the line, from the
//! TOML reader) and [`super::suggest`] adds the closest known key to the message. Values are
//! checked afterwards in [`super::validate`]. The structs also serialise, so that an array
//! given more components than its key takes (which the TOML reader passes over) is found by
//! comparing the file with what was read ([`extra_components`]).

use serde::{Deserialize, Serialize};

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScene {
    pub title: Option<String>,
    pub gravity: Option<[f64; 3]>,
    pub run: Option<RawRun>,
    pub implicit: Option<RawImplicit>,
    pub explicit: Option<RawExplicit>,
    #[serde(rename = "static")]
    pub statics: Option<RawStatic>,
    #[serde(default)]
    pub material: Vec<RawMaterial>,
    #[serde(default)]
    pub body: Vec<RawBody>,
    #[serde(default)]
    pub contact: Vec<RawContact>,
    #[serde(default)]
    pub rigid_plane: Vec<RawPlane>,
    #[serde(default)]
    pub rigid_body: Vec<RawRigidBody>,
    #[serde(default)]
    pub fix: Vec<RawFix>,
    #[serde(default)]
    pub initial_velocity: Vec<RawInitialVelocity>,
    #[serde(default)]
    pub load: Vec<RawLoad>,
    #[serde(default)]
    pub probe: Vec<RawProbe>,
    #[serde(default)]
    pub cohesive: Vec<RawCohesive>,
    #[serde(default)]
    pub equation: Vec<RawEquation>,
    #[serde(default)]
    pub tie: Vec<RawTie>,
    #[serde(default)]
    pub step: Vec<RawStep>,
    pub output: Option<RawOutput>,
    #[serde(default)]
    pub exact: Vec<RawExact>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRun {
    pub end_time: Option<f64>,
    pub time_step: Option<f64>,
    pub method: Option<String>,
    pub device: Option<String>,
    pub energy_tolerance: Option<f64>,
    pub kinematics: Option<String>,
}

/// `[static]`: a static step's increment control and stabilisation.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawStatic {
    pub minimum_step: Option<f64>,
    pub stabilisation: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawImplicit {
    pub beta: Option<f64>,
    pub gamma: Option<f64>,
    pub constraint: Option<String>,
    pub penalty: Option<String>,
    pub penalty_normal: Option<f64>,
    pub penalty_tangential: Option<f64>,
    pub max_iterations: Option<i64>,
    pub tolerance: Option<f64>,
    pub mass: Option<String>,
    pub max_gap_rate: Option<f64>,
    pub max_force_change: Option<f64>,
    pub acceleration: Option<String>,
    pub event_substeps: Option<i64>,
    pub event_force_change: Option<f64>,
    pub ordering: Option<String>,
    pub contact_space: Option<String>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawExact {
    pub column: String,
    pub points: Vec<[f64; 2]>,
    pub label: Option<String>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawExplicit {
    pub safety_factor: Option<f64>,
    pub allow_unstable: Option<bool>,
    pub max_iterations: Option<i64>,
    pub tolerance: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMaterial {
    pub name: String,
    pub density: Option<f64>,
    pub youngs_modulus: Option<f64>,
    pub poissons_ratio: Option<f64>,
    pub orthotropic: Option<RawOrthotropic>,
    pub transversely_isotropic: Option<RawTransverselyIsotropic>,
    pub strength: Option<RawStrength>,
    pub fracture_energy: Option<RawFractureEnergy>,
    pub damage_viscosity: Option<f64>,
    pub damage_stresses: Option<String>,
    pub snap_back: Option<String>,
}

/// A ply's fracture energies (`fracture_energy = { ft, fc, mt, mc }`).
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFractureEnergy {
    pub ft: f64,
    pub fc: f64,
    pub mt: f64,
    pub mc: f64,
}

/// A ply's strengths (`strength = { xt, xc, yt, yc, s12, s23 }`).
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawStrength {
    pub xt: f64,
    pub xc: f64,
    pub yt: f64,
    pub yc: f64,
    pub s12: f64,
    pub s23: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOrthotropic {
    pub e1: f64,
    pub e2: f64,
    pub e3: f64,
    pub nu12: f64,
    pub nu13: f64,
    pub nu23: f64,
    pub g12: f64,
    pub g13: f64,
    pub g23: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTransverselyIsotropic {
    pub e1: f64,
    pub e2: f64,
    pub nu12: f64,
    pub nu23: f64,
    pub g12: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOrientation {
    pub axes: Option<[[f64; 3]; 2]>,
    pub axis: Option<[f64; 3]>,
    pub angle: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPlies {
    pub normal: String,
    pub layers: Vec<RawPly>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPly {
    pub angle: f64,
    pub thickness: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub divisions: [i64; 3],
    pub element: Option<String>,
    pub refine: Option<RawRefine>,
}

/// `box.refine = { min, max, size }`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRefine {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub size: [f64; 3],
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBody {
    pub name: String,
    pub material: String,
    #[serde(rename = "box")]
    pub box_: Option<RawBox>,
    pub mesh: Option<String>,
    pub elset: Option<String>,
    pub part: Option<i64>,
    pub piece: Option<i64>,
    pub scale: Option<f64>,
    pub translate: Option<[f64; 3]>,
    pub velocity: Option<[f64; 3]>,
    pub orientation: Option<RawOrientation>,
    pub plies: Option<RawPlies>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSurfaceRef {
    pub body: Option<String>,
    pub rigid_body: Option<String>,
    pub face: Option<String>,
    pub surface: Option<String>,
    /// A node set: a contact's secondary side of nodes alone.
    pub set: Option<String>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawContact {
    pub name: String,
    pub secondary: RawSurfaceRef,
    pub primary: RawSurfaceRef,
    pub friction: Option<f64>,
    pub initial_penetration: Option<String>,
    pub region: Option<RawRegion>,
    pub adjust: Option<f64>,
    pub stiffness: Option<f64>,
    pub exponential: Option<RawExponential>,
    pub stick_slope: Option<f64>,
}

/// `[[tie]]`: a secondary surface (or node set) bonded to a primary surface.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTie {
    pub name: String,
    pub secondary: RawSurfaceRef,
    pub primary: RawSurfaceRef,
    pub tolerance: Option<f64>,
    pub adjust: Option<bool>,
}

/// `exponential = { clearance, pressure }` of a `[[contact]]`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawExponential {
    pub clearance: f64,
    pub pressure: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPlane {
    pub name: String,
    pub point: [f64; 3],
    pub normal: [f64; 3],
    pub friction: Option<f64>,
    pub bodies: Option<Vec<String>>,
    pub initial_penetration: Option<String>,
}

/// A `[[rigid_body]]`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRigidBody {
    pub name: String,
    pub mass: Option<f64>,
    pub inertia: Option<[[f64; 3]; 3]>,
    pub position: [f64; 3],
    pub velocity: Option<[f64; 3]>,
    pub angular_velocity: Option<[f64; 3]>,
    pub shape: RawRigidShape,
    pub motion: Option<String>,
}

/// A rigid body's `shape`: exactly one of the analytic shapes, or `mesh` with `surface`.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRigidShape {
    pub sphere: Option<RawSphere>,
    pub cylinder: Option<RawCylinder>,
    pub plane: Option<RawRigidPlane>,
    pub plate: Option<RawRigidPlate>,
    pub mesh: Option<String>,
    pub surface: Option<String>,
    pub origin: Option<[f64; 3]>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSphere {
    pub radius: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCylinder {
    pub radius: f64,
    pub axis: [f64; 3],
    pub length: f64,
    pub ends: Option<String>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRigidPlane {
    pub normal: [f64; 3],
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRigidPlate {
    pub normal: [f64; 3],
    pub size: [f64; 2],
    pub opening: Option<[f64; 2]>,
}

/// A `[[cohesive]]` interface: between two bodies' faces (`between`), or inside a laminate
/// (`body` and `at`).
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCohesive {
    pub name: String,
    pub between: Option<Vec<RawSurfaceRef>>,
    pub body: Option<String>,
    pub at: Option<String>,
    pub region: Option<RawRegion>,
    pub stiffness: f64,
    pub strength: RawCohesiveStrength,
    pub toughness: RawToughness,
    pub friction: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCohesiveStrength {
    pub normal: f64,
    pub shear: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawToughness {
    pub normal: f64,
    pub shear: f64,
    pub bk: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRegion {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFix {
    pub body: String,
    pub face: Option<String>,
    pub set: Option<String>,
    pub region: Option<RawRegion>,
    pub components: Vec<String>,
    pub velocity: Option<[f64; 3]>,
    pub displacement: Option<[f64; 3]>,
    pub amplitude: Option<Vec<[f64; 2]>>,
    pub name: Option<String>,
}

/// `[[equation]]`: a linear constraint sum of coefficient x displacement = 0.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEquation {
    pub terms: Vec<RawTerm>,
}

/// A `[[step]]`: from `start` on, the run goes on with what it changes.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawStep {
    pub start: f64,
    pub end: Option<f64>,
    pub method: Option<String>,
    pub time_step: Option<f64>,
    pub remove_equations: Option<RawRemoval>,
    pub release_fixes: Option<RawRelease>,
    #[serde(default)]
    pub fix: Vec<RawFix>,
    #[serde(default)]
    pub contact: Vec<RawStepContact>,
}

/// `release_fixes`: `"all"`, or the names of the `[[fix]]`es that end.
#[derive(Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawRelease {
    All(String),
    Names(Vec<String>),
}

/// A step's `[[step.contact]]`: a contact's friction from the step on.
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawStepContact {
    pub name: String,
    pub friction: Option<f64>,
    pub stick_slope: Option<f64>,
}

/// `remove_equations`: `"all"`, or the dependent dofs whose equations end.
#[derive(Debug, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum RawRemoval {
    All(String),
    Dofs(Vec<RawDof>),
}

/// One node's component (or each node's of a set or region).
#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDof {
    pub body: String,
    pub set: Option<String>,
    pub region: Option<RawRegion>,
    pub component: String,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTerm {
    pub body: String,
    pub set: Option<String>,
    pub region: Option<RawRegion>,
    pub component: String,
    pub coefficient: f64,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawInitialVelocity {
    pub body: String,
    pub face: Option<String>,
    pub set: Option<String>,
    pub region: Option<RawRegion>,
    pub velocity: [f64; 3],
    pub components: Option<Vec<String>>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLoad {
    pub body: String,
    pub face: Option<String>,
    pub surface: Option<String>,
    pub set: Option<String>,
    pub region: Option<RawRegion>,
    pub force: Option<[f64; 3]>,
    pub pressure: Option<f64>,
    pub amplitude: Option<Vec<[f64; 2]>>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawProbe {
    pub name: String,
    pub body: String,
    pub point: [f64; 3],
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    pub dir: Option<String>,
    pub vtu_every: Option<i64>,
    pub checkpoint_every: Option<i64>,
}

/// The first array of the scene `file` that holds more entries than `read` (the scene as
/// deserialised, serialised back) kept: its key path (`rigid_body[0].shape.plate.size`),
/// and both lengths.
pub(crate) fn extra_components(
    file: &toml::Value,
    read: &toml::Value,
    path: &str,
) -> Option<(String, usize, usize)> {
    let key = |k: &str| match path {
        "" => k.to_string(),
        p => format!("{p}.{k}"),
    };
    match (file, read) {
        (toml::Value::Table(f), toml::Value::Table(r)) => (f.iter())
            .filter_map(|(k, v)| Some((k, v, r.get(k)?)))
            .find_map(|(k, v, w)| extra_components(v, w, &key(k))),
        (toml::Value::Array(f), toml::Value::Array(r)) => {
            if f.len() > r.len() {
                return Some((path.to_string(), f.len(), r.len()));
            }
            (f.iter().zip(r).enumerate())
                .find_map(|(i, (v, w))| extra_components(v, w, &format!("{path}[{i}]")))
        }
        _ => None,
    }
}
