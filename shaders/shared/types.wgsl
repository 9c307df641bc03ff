// Buffer element types shared by the kernels. Must be kept in sync with `src/gpu/types.rs`
// (a test compares the Rust sizes and offsets with naga's layout of these structs).

// Launch parameters of a kernel: `count` items, dispatched over a 2D grid of workgroups whose
// row is `row` items long (so that more than 65535 workgroups fit).
// `aux` and `aux2` are kernel-specific (an offset, a count).
struct Params {
    count: u32,
    row: u32,
    aux: u32,
    aux2: u32,
}

// A 3-vector packed in 12 bytes (a vec3<f32> takes 16 in a buffer) and a 2-vector, as
// named fields rather than arrays: a struct that holds an array and is loaded whole, passed
// to a function or indexed by a variable ends up in per-thread local memory on GPU hardware
// (`tests/shader_rules.rs`).
struct Float3 {
    x: f32,
    y: f32,
    z: f32,
}

struct Float2 {
    x: f32,
    y: f32,
}

fn vec3_of(p: Float3) -> vec3<f32> {
    return vec3<f32>(p.x, p.y, p.z);
}

fn float3(v: vec3<f32>) -> Float3 {
    return Float3(v.x, v.y, v.z);
}

// A nodal 3-vector (reference coordinates, displacements) split into an f32 pair, hi + lo =
// the f64 value to ~1e-14, so that differences of nearby nodes keep f32's relative precision
// (a rigid translation does not eat the digits of a strain or a gap).
struct Split3 {
    hi: Float3,
    lo: Float3,
}

// Lame parameters and density; for an anisotropic material (anisotropic = 1) the
// stiffness's upper triangle in Voigt order (xx, yy, zz, yz, xz, xy), global axes, in place
// of lambda and mu (twin: `material::Elastic`).
struct Material {
    lambda: f32,
    mu: f32,
    density: f32,
    anisotropic: u32,
    c11: f32,
    c12: f32,
    c13: f32,
    c14: f32,
    c15: f32,
    c16: f32,
    c22: f32,
    c23: f32,
    c24: f32,
    c25: f32,
    c26: f32,
    c33: f32,
    c34: f32,
    c35: f32,
    c36: f32,
    c44: f32,
    c45: f32,
    c46: f32,
    c55: f32,
    c56: f32,
    c66: f32,
}

// One contact query: a secondary node and its candidate faces candidates[first..end].
struct ContactQuery {
    secondary: u32,
    first: u32,
    end: u32,
}

// A primary face, outward oriented (global node numbers, corners 0-3 as x y z w; a triangle
// repeats its third corner).
struct Quad {
    nodes: vec4<u32>,
}

// A primary face's box at the current displacement, in absolute f32 coordinates (the
// narrow phase's first, conservative filter: `face_box`).
struct FaceBox {
    lo: Float3,
    hi: Float3,
}

// Contact kinematics of one query; face = 0xffffffff when it has no candidate.
struct ContactPoint {
    face: u32,
    xi: Float2,
    normal: Float3,
    gap: f32,
    gap_rate: f32,
}

const NO_FACE: u32 = 0xffffffffu;
const WORKGROUP: u32 = 64u;

// Constants shared with the host, checked against `src/gpu/types.rs`'s `shared_constants()`
// by `tests/gpu_kernels.rs`.
// The result slot of a (secondary node, plane) or (node, face) pair of `plane_contact` and
// `contact_report`: SLOT floats, the fields at these offsets (friction impulse and impulse:
// 3 floats).
const SLOT: u32 = 14u;
const SLOT_NORMAL_IMPULSE: u32 = 0u;
const SLOT_FRICTION_IMPULSE: u32 = 1u;
const SLOT_ACTIVE: u32 = 4u;
const SLOT_SLIDING: u32 = 5u;
const SLOT_GAP: u32 = 6u;
const SLOT_FRICTION_WORK: u32 = 7u;
const SLOT_SWEEPS: u32 = 8u;
const SLOT_IMPULSE: u32 = 9u;
const SLOT_DRIVER_WORK: u32 = 12u;
const SLOT_IMPACT_LOSS: u32 = 13u;
// The kinds of a rigid body's analytic surface (`RigidSurface.kind`).
const RIGID_SPHERE: u32 = 0u;
const RIGID_CAPSULE: u32 = 1u;
const RIGID_CYLINDER: u32 = 2u;
const RIGID_PLANE: u32 = 3u;
const RIGID_PLATE: u32 = 4u;
// Planes a node can have (the bit set and the kernel's local state).
const MAX_PLANES: u32 = 8u;
// Partial sums per workgroup of `explicit_correct`.
const FIELDS: u32 = 6u;
// The column operations of `history_reduce`.
const OP_PARTIALS: u32 = 0u;
const OP_SUM: u32 = 1u;
const OP_MAX: u32 = 2u;
const OP_DISPLACEMENT: u32 = 3u;
const OP_VELOCITY: u32 = 4u;
const OP_CORNERS: u32 = 5u;

// The item index of an invocation in a 2D dispatch (see Params.row).
fn item_index(gid: vec3<u32>, p: Params) -> u32 {
    return gid.x + gid.y * p.row;
}

// a - b of two split vectors: the hi parts of nearby values subtract exactly.
fn split_difference(a: Split3, b: Split3) -> vec3<f32> {
    return (vec3_of(a.hi) - vec3_of(b.hi)) + (vec3_of(a.lo) - vec3_of(b.lo));
}

// The value of a split vector in f32.
fn split_value(a: Split3) -> vec3<f32> {
    return vec3_of(a.hi) + vec3_of(a.lo);
}

// Lumped nodal data of the explicit step: the node's mass, the inverse mass of each dof (zero
// on prescribed dofs) and the body-force acceleration of each dof (f_ext / m, zero where
// prescribed).
struct Lumped {
    mass: f32,
    inv_mass: Float3,
    ext_acc: Float3,
}

// An analytic rigid plane: a point on it (split like the nodes), the unit normal pointing
// into the half-space the bodies stay in, and its contact law (`contact_law.wgsl`).
struct Plane {
    point: Split3,
    normal: Float3,
    law: u32,
    mu: f32,
}

// A secondary node of the rigid planes and the planes it is secondary to (bit p: plane p).
struct PlaneNode {
    node: u32,
    planes: u32,
}

// One history value: `op` over `count` entries `first + k * stride` of its source (see
// `history_reduce.wgsl`).
struct ReduceColumn {
    first: u32,
    count: u32,
    stride: u32,
    op: u32,
}

// Constants of the explicit step: the time step, the contact iteration's tolerance (a gap
// rate) and its sweep limit.
struct Step {
    dt: f32,
    tolerance: f32,
    max_iterations: u32,
    pad: u32,
}

// The uniform grid of the contact search: cubic cells of side `cell`, hashed into a table of
// mask + 1 buckets (a power of two), into which the faces were last sorted; `margin` grows
// each face's box for this step's candidate test. A grid kept across steps (`search_grid`)
// holds while every face within the margin of a node lies in the 27 cells around it; a step
// for which it no longer does tests every face of the query's interface (`all_faces` 1).
// `face_size` is the margin's base (the largest face size); `fill` the largest share of the
// cell that the kept steps since the last reset needed, and `stale_steps` counts the steps
// that tested every face.
struct SearchGrid {
    cell: f32,
    margin: f32,
    mask: u32,
    all_faces: u32,
    face_size: f32,
    fill: f32,
    stale_steps: u32,
    pad: u32,
}

// The bucket of cell c of the interface whose faces start at `salt` (twin:
// `kernels::face_cells::cell_key`).
fn cell_key(c: vec3<i32>, salt: u32, mask: u32) -> u32 {
    let h = (bitcast<u32>(c.x) * 73856093u) ^ (bitcast<u32>(c.y) * 19349663u)
        ^ (bitcast<u32>(c.z) * 83492791u) ^ (salt * 2654435761u);
    return h & mask;
}

// The grid cell of a point.
fn cell_of(x: vec3<f32>, cell: f32) -> vec3<i32> {
    return vec3<i32>(floor(x / cell));
}

// A split position as one f32 vector (cells need no more).
fn split_sum(a: Split3, b: Split3) -> vec3<f32> {
    return vec3_of(a.hi) + vec3_of(b.hi) + (vec3_of(a.lo) + vec3_of(b.lo));
}

// A pair of the explicit step's contact iteration: secondary node `node` of an interface
// against its surface query `query` (its contact point), against a rigid body's surface
// (`query` = NO_FACE, `body` its `RigidSurface`), or against a rigid plane (`query` = `body`
// = NO_FACE; the plane's point, split like the nodes, and its unit normal into the bodies'
// side), with the interface's contact law (`contact_law.wgsl`).
struct ContactPair {
    node: u32,
    query: u32,
    law: u32,
    mu: f32,
    point: Split3,
    normal: Float3,
    body: u32,
}

// The analytic surface of a rigid body on node `node` (`rigid_shape.wgsl`, twin:
// `geometry::rigid_shape`): its kind (RIGID_*), whether a driver moves it (prescribed: the
// report adds the driver's work), `radius` and `length` (sphere, cylinder, capsule), `axis`
// (the cylinder's axis, or the plane's and plate's normal), the in-plane axes `e1`, `e2`
// (the plate's; e1 is also the cylinder's radial direction on its axis), the plate's size
// and window.
struct RigidSurface {
    node: u32,
    kind: u32,
    driven: u32,
    radius: f32,
    length: f32,
    axis: Float3,
    e1: Float3,
    e2: Float3,
    size_a: f32,
    size_b: f32,
    opening_a: f32,
    opening_b: f32,
}

// One constraint of the step (see `contact_constraints.wgsl`): the primary face's nodes and
// shape function values (face[0] = NO_FACE for a plane), the unit normal, the gap at u_n, the
// split compliance, the impulses J_N and J_T, the slip at v_{n-1/2} (friction work) and
// whether the pair is in reach this step (0/1).
// face and weights are indexed by a corner through the buffer (`constraints[q].weights[k]`);
// a constraint loaded whole reads them with constant indices only.
struct Constraint {
    face: array<u32, 4>,
    weights: array<f32, 4>,
    normal: Float3,
    gap: f32,
    compliance: f32,
    jn: f32,
    jt: Float3,
    before: Float3,
    in_reach: u32,
}

// A node the contact iteration moves: the pairs it is the secondary node of,
// links[pair_first..pair_end], the primary face corners it is, links[face_first..face_end]
// (each 4 face + corner), and, where it carries a rigid body, the pair ranges of the body's
// interfaces, links[body_first..body_end] (each a first pair and an end pair).
struct ContactNode {
    node: u32,
    pair_first: u32,
    pair_end: u32,
    face_first: u32,
    face_end: u32,
    body_first: u32,
    body_end: u32,
}

// A ply failure evaluation point (`failure_survey.wgsl`): its cell's corner nodes (the first
// `corners`), its strength and its stress operator (6 rows of SURVEY_COLUMNS in `operators`).
struct SurveyPoint {
    nodes: array<u32, 8>,
    corners: u32,
    strength: u32,
    stress_operator: u32,
}

// A ply's strengths: tension and compression along the fibre and across it, in-plane and
// transverse shear.
struct PlyStrength {
    xt: f32,
    xc: f32,
    yt: f32,
    yc: f32,
    s12: f32,
    s23: f32,
}

// Values of a damage point's state (twin: `material::damage::POINT_STATE`), and words of a
// damageable element's record (flag, first step, first point, dissipation, its fibre
// share).
const POINT_STATE: u32 = 8u;
const DAMAGE_RECORD: u32 = 5u;

// A ply's damage law in its own axes (twin: `material::PlyDamage`): the undamaged
// stiffness's normal block and shear moduli, the compliance's normal block and shear
// compliances (23, 13, 12), the strengths (sl, st: in-plane and transverse shear), the
// fracture energies' snap-back widths 2 E G / X^2 of fibre tension and compression and matrix
// tension and compression, the Duvaut-Lions viscosity, and 1 where the ply damages by its
// in-plane stresses alone (11, 22, 12), softening only its in-plane stiffness.
struct DamageLaw {
    c11: f32,
    c12: f32,
    c13: f32,
    c22: f32,
    c23: f32,
    c33: f32,
    c44: f32,
    c55: f32,
    c66: f32,
    s11: f32,
    s12: f32,
    s13: f32,
    s22: f32,
    s23: f32,
    s33: f32,
    h23: f32,
    h13: f32,
    h12: f32,
    xt: f32,
    xc: f32,
    yt: f32,
    yc: f32,
    sl: f32,
    st: f32,
    viscosity: f32,
    snap_ft: f32,
    snap_fc: f32,
    snap_mt: f32,
    snap_mc: f32,
    in_plane: f32,
    lower_strength: f32,
}

// A damageable ply's material entry: its law and its axes 1, 2, 3 as rows.
struct DamageEntry {
    law: u32,
    a11: f32,
    a12: f32,
    a13: f32,
    a21: f32,
    a22: f32,
    a23: f32,
    a31: f32,
    a32: f32,
    a33: f32,
}

// A damageable element's ply: its entry, its range of the natural coordinate along the
// element's layup axis, and its bands across fibre and matrix cracks.
struct DamagePlyRecord {
    entry: u32,
    lo: f32,
    hi: f32,
    band_f: f32,
    band_m: f32,
}

// A damageable element: its number in its block, its plies, its first point, its layup axis
// and its sieve factor.
struct DamageElementRecord {
    element: u32,
    first_ply: u32,
    plies: u32,
    first_point: u32,
    axis: u32,
    sieve: f32,
}

// The damage kernels' step (one per block): the step dt, whether the state advances, the
// block's element count (E) and its first record's word.
struct DamageParams {
    dt: f32,
    advance: u32,
    elements: u32,
    records: u32,
}

// A cohesive interface's law (twin: `material::CohesiveLaw`): the penalty stiffness K, the
// onset tractions (normal N, shear S), the toughnesses G_Ic and G_IIc, the BK exponent and
// Coulomb's coefficient of the damaged share's faces (0: none).
struct CohesiveLaw {
    stiffness: f32,
    strength_n: f32,
    strength_s: f32,
    toughness_i: f32,
    toughness_ii: f32,
    bk: f32,
    friction: f32,
    pad: f32,
}

// A bonded pair (twin: `kernels::cohesive_pairs::PairRecord`): its upper and lower nodes,
// its law, its area and the unit normal its separation opens along.
struct CohesivePair {
    upper: u32,
    lower: u32,
    law: u32,
    area: f32,
    normal: Float3,
    pad: u32,
}

// A bonded pair's state between steps: its damage and its slip.
struct PairState {
    damage: f32,
    slip: Float3,
}

// What a pair's step gives (twin: `kernels::cohesive_pairs::PairOutput`): its force on the
// upper node, and its area times the step's dissipation and times its stored-energy offset.
struct PairOutput {
    force: Float3,
    dissipated: f32,
    offset: f32,
}

// A bonded node (twin: `kernels::cohesive_scatter::BondedNode`): the corner slot its pairs'
// forces are added to, and its links links[first..end].
struct BondedNode {
    node: u32,
    corner: u32,
    first: u32,
    end: u32,
}

// A link's flag: the node is its pair's lower node.
const LOWER: u32 = 0x80000000u;

// Values of each cohesive interface in a history row.
const COHESIVE_COLUMNS: u32 = 4u;

// Columns of a failure operator (three per corner of a hex8), and the values of a failure
// record: the five indices' maxima, the worst point's value, number and index.
const SURVEY_COLUMNS: u32 = 24u;
const FAILURE_FIELDS: u32 = 8u;

// The contact iteration's state words (`state` buffers): the sweep's largest violation (f32
// bits: non-negative floats order as their bits), the pairs in reach, the sweeps done, and
// the phase (0 not started, 1 sweeping, 2 converged, 3 stopped at the sweep limit),
// whether the last sweep dispatched ran (the apply after it applies it), and three words
// from STATE_RING on, sweep k's largest violation in word STATE_RING + k % 3
// (`contact_relax`). Eight words.
const STATE_VIOLATION: u32 = 0u;
const STATE_ACTIVE: u32 = 1u;
const STATE_SWEEPS: u32 = 2u;
const STATE_PHASE: u32 = 3u;
const STATE_SWEPT: u32 = 4u;
const STATE_RING: u32 = 5u;
