//! Buffer element types. Must be kept in sync with `shaders/shared/types.wgsl`: the test
//! `gpu_types_match_wgsl` compares these sizes and offsets with naga's layout of the WGSL
//! structs.

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

use crate::kernels;
use crate::kernels::contact_gap::{ContactPoint as CpuContactPoint, NO_FACE};

/// Invocations per workgroup (`WORKGROUP` in `shaders/shared/types.wgsl`).
pub(crate) const WORKGROUP: u32 = 64;

/// Declares a buffer element type (`#[repr(C)]`) with its layout, by WGSL name, from the
/// declaration itself: `Name::layout()` gives its size and its fields' offsets in order, for
/// the test that compares them with naga's layout of `shaders/shared/types.wgsl`.
macro_rules! device_struct {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $($(#[$field_meta:meta])* pub $field:ident: $ty:ty),* $(,)?
        }
    ) => {
        device_struct! {
            $(#[$meta])*
            pub struct $name as $name {
                $($(#[$field_meta])* pub $field: $ty),*
            }
        }
    };
    (
        $(#[$meta:meta])*
        pub struct $name:ident as $wgsl:ident {
            $($(#[$field_meta:meta])* pub $field:ident: $ty:ty),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[repr(C)]
        pub struct $name {
            $($(#[$field_meta])* pub $field: $ty),*
        }

        impl $name {
            /// Size and field offsets, by WGSL name.
            pub fn layout() -> StructLayout {
                (
                    stringify!($wgsl),
                    std::mem::size_of::<$name>(),
                    vec![$((stringify!($field), std::mem::offset_of!($name, $field))),*],
                )
            }
        }
    };
}

/// Host values (f64) as the device's type (f32), each by its `From`, on all threads.
pub(crate) fn to_device<'a, H: Sync + 'a, D: From<&'a H> + Send>(host: &'a [H]) -> Vec<D> {
    host.par_iter().map(D::from).collect()
}

device_struct! {
    /// Launch parameters: `count` items over a 2D grid whose rows are `row` items long.
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct Params {
        pub count: u32,
        pub row: u32,
        pub aux: u32,
        pub aux2: u32,
    }
}

device_struct! {
    /// A nodal 3-vector (reference coordinates, displacements) split into an f32 pair, `hi + lo`
    /// equal to the f64 value to about 1e-14 relative, so that differences of nearby nodes keep
    /// f32's relative precision: a rigid translation does not eat the digits of a strain or a gap.
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct Split3 {
        pub hi: [f32; 3],
        pub lo: [f32; 3],
    }
}

impl Split3 {
    pub fn split(x: [f64; 3]) -> Self {
        let hi = x.map(|c| c as f32);
        let lo = [0, 1, 2].map(|a| (x[a] - hi[a] as f64) as f32);
        Split3 { hi, lo }
    }
}

device_struct! {
    /// Lamé parameters and density; for an anisotropic material (`anisotropic` = 1) the
    /// stiffness's upper triangle in Voigt order (xx, yy, zz, yz, xz, xy), global axes, row by
    /// row, in place of lambda and mu.
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct GpuMaterial as Material {
        pub lambda: f32,
        pub mu: f32,
        pub density: f32,
        pub anisotropic: u32,
        pub c11: f32,
        pub c12: f32,
        pub c13: f32,
        pub c14: f32,
        pub c15: f32,
        pub c16: f32,
        pub c22: f32,
        pub c23: f32,
        pub c24: f32,
        pub c25: f32,
        pub c26: f32,
        pub c33: f32,
        pub c34: f32,
        pub c35: f32,
        pub c36: f32,
        pub c44: f32,
        pub c45: f32,
        pub c46: f32,
        pub c55: f32,
        pub c56: f32,
        pub c66: f32,
    }
}

impl GpuMaterial {
    /// The device form of a material.
    pub fn of(m: &crate::material::Elastic) -> GpuMaterial {
        let mut d = GpuMaterial {
            lambda: m.lambda as f32,
            mu: m.mu as f32,
            density: m.density as f32,
            ..Default::default()
        };
        if let Some(c) = &m.c {
            d.anisotropic = 1;
            let upper: Vec<f32> = (0..6)
                .flat_map(|i| (i..6).map(move |j| c[i][j] as f32))
                .collect();
            let words: &mut [f32] = bytemuck::cast_slice_mut(std::slice::from_mut(&mut d));
            words[4..].copy_from_slice(&upper);
        }
        d
    }
}

device_struct! {
    /// A secondary node and its candidate faces `candidates[first..end]`.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct ContactQuery {
        pub secondary: u32,
        pub first: u32,
        pub end: u32,
    }
}

/// A query as `(secondary node, first face, end face)`.
impl From<&(u32, u32, u32)> for ContactQuery {
    fn from(&(secondary, first, end): &(u32, u32, u32)) -> Self {
        ContactQuery {
            secondary,
            first,
            end,
        }
    }
}

device_struct! {
    /// A primary face's four slots, outward oriented ([`crate::geometry::face::Face::slots`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct Quad {
        pub nodes: [u32; 4],
    }
}

device_struct! {
    /// A primary face's box in absolute f32 coordinates (twin: `kernels::face_cells::face_box`).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct FaceBox {
        pub lo: [f32; 3],
        pub hi: [f32; 3],
    }
}

impl From<&[u32; 4]> for Quad {
    fn from(&nodes: &[u32; 4]) -> Self {
        Quad { nodes }
    }
}

device_struct! {
    /// Contact kinematics of one query (`face = 0xffffffff`: no candidate).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct GpuContactPoint as ContactPoint {
        pub face: u32,
        pub xi: [f32; 2],
        pub normal: [f32; 3],
        pub gap: f32,
        pub gap_rate: f32,
    }
}

impl From<GpuContactPoint> for CpuContactPoint {
    fn from(p: GpuContactPoint) -> Self {
        CpuContactPoint {
            face: p.face,
            xi: p.xi.map(f64::from),
            normal: p.normal.map(f64::from),
            gap: p.gap as f64,
            gap_rate: p.gap_rate as f64,
        }
    }
}

impl From<&CpuContactPoint> for GpuContactPoint {
    fn from(p: &CpuContactPoint) -> Self {
        if p.face == NO_FACE {
            return GpuContactPoint {
                face: NO_FACE,
                ..Default::default()
            };
        }
        GpuContactPoint {
            face: p.face,
            xi: p.xi.map(|x| x as f32),
            normal: p.normal.map(|x| x as f32),
            gap: p.gap as f32,
            gap_rate: p.gap_rate as f32,
        }
    }
}

device_struct! {
    /// Lumped nodal data of the explicit step (twin: [`crate::kernels::explicit_correct::LumpedNode`]).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct Lumped {
        pub mass: f32,
        pub inv_mass: [f32; 3],
        pub ext_acc: [f32; 3],
    }
}

impl From<&kernels::LumpedNode> for Lumped {
    fn from(l: &kernels::LumpedNode) -> Self {
        Lumped {
            mass: l.mass as f32,
            inv_mass: l.inv_mass.map(|x| x as f32),
            ext_acc: l.ext_acc.map(|x| x as f32),
        }
    }
}

device_struct! {
    /// An analytic rigid plane (twin: [`crate::kernels::plane_contact::PlaneData`]).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct Plane {
        pub point: Split3,
        pub normal: [f32; 3],
        pub law: u32,
        pub mu: f32,
    }
}

impl From<&kernels::PlaneData> for Plane {
    fn from(p: &kernels::PlaneData) -> Self {
        Plane {
            point: Split3::split(p.point),
            normal: p.normal.map(|x| x as f32),
            law: p.law.code(),
            mu: p.law.coefficient() as f32,
        }
    }
}

device_struct! {
    /// A secondary node of the rigid planes and its planes as a bit set.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct GpuPlaneNode as PlaneNode {
        pub node: u32,
        pub planes: u32,
    }
}

impl From<&kernels::PlaneNode> for GpuPlaneNode {
    fn from(p: &kernels::PlaneNode) -> Self {
        GpuPlaneNode {
            node: p.node,
            planes: p.planes,
        }
    }
}

device_struct! {
    /// One history value (twin: [`crate::kernels::history_reduce::ReduceColumn`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct GpuReduceColumn as ReduceColumn {
        pub first: u32,
        pub count: u32,
        pub stride: u32,
        pub op: u32,
    }
}

impl From<&kernels::ReduceColumn> for GpuReduceColumn {
    fn from(c: &kernels::ReduceColumn) -> Self {
        GpuReduceColumn {
            first: c.first,
            count: c.count,
            stride: c.stride,
            op: c.op,
        }
    }
}

device_struct! {
    /// Constants of the explicit step.
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct Step {
        pub dt: f32,
        pub tolerance: f32,
        pub max_iterations: u32,
        pub pad: u32,
    }
}

device_struct! {
    /// The contact search grid (twin: [`crate::kernels::SearchGrid`]).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct GpuSearchGrid as SearchGrid {
        pub cell: f32,
        pub margin: f32,
        pub mask: u32,
        pub all_faces: u32,
        pub face_size: f32,
        pub fill: f32,
        pub stale_steps: u32,
        pub pad: u32,
    }
}

impl GpuSearchGrid {
    /// The device form of a grid the host computed for one step (its faces sorted at it).
    pub fn of(grid: &crate::kernels::SearchGrid) -> Self {
        GpuSearchGrid {
            cell: grid.cell as f32,
            margin: grid.margin as f32,
            mask: grid.mask,
            all_faces: grid.all_faces as u32,
            face_size: grid.face_size as f32,
            fill: grid.fill as f32,
            stale_steps: grid.stale_steps,
            pad: 0,
        }
    }
}

device_struct! {
    /// A pair of the device contact iteration (twin: [`crate::kernels::ContactPair`]).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct GpuContactPair as ContactPair {
        pub node: u32,
        pub query: u32,
        pub law: u32,
        pub mu: f32,
        pub point: Split3,
        pub normal: [f32; 3],
        pub body: u32,
    }
}

impl From<&kernels::ContactPair> for GpuContactPair {
    fn from(p: &kernels::ContactPair) -> Self {
        GpuContactPair {
            node: p.node,
            query: p.query,
            law: p.law.code(),
            mu: p.law.coefficient() as f32,
            point: Split3::split(p.point),
            normal: p.normal.map(|x| x as f32),
            body: p.body,
        }
    }
}

/// The kinds of a rigid body's analytic surface on the device (`RIGID_*` in
/// `shaders/shared/types.wgsl`).
pub mod rigid_kind {
    pub const SPHERE: u32 = 0;
    pub const CAPSULE: u32 = 1;
    pub const CYLINDER: u32 = 2;
    pub const PLANE: u32 = 3;
    pub const PLATE: u32 = 4;
}

device_struct! {
    /// A rigid body's analytic surface (twin: [`crate::kernels::RigidSurface`], whose
    /// shape's distance is `shaders/shared/rigid_shape.wgsl`'s `rigid_distance`).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct GpuRigidSurface as RigidSurface {
        pub node: u32,
        pub kind: u32,
        pub driven: u32,
        pub radius: f32,
        pub length: f32,
        pub axis: [f32; 3],
        pub e1: [f32; 3],
        pub e2: [f32; 3],
        pub size_a: f32,
        pub size_b: f32,
        pub opening_a: f32,
        pub opening_b: f32,
    }
}

impl GpuRigidSurface {
    /// The device form of an analytic surface; `None` for a meshed one.
    pub fn of(s: &kernels::RigidSurface) -> Option<Self> {
        use crate::geometry::rigid_shape::RigidShape;
        let f = |v: [f64; 3]| v.map(|x| x as f32);
        let mut d = GpuRigidSurface {
            node: s.node,
            driven: u32::from(s.driven),
            ..Default::default()
        };
        match s.shape {
            RigidShape::Sphere { radius } => {
                (d.kind, d.radius) = (rigid_kind::SPHERE, radius as f32);
            }
            RigidShape::Cylinder {
                radius,
                axis,
                length,
                round,
            } => {
                d.kind = if round {
                    rigid_kind::CAPSULE
                } else {
                    rigid_kind::CYLINDER
                };
                (d.radius, d.length, d.axis) = (radius as f32, length as f32, f(axis));
                d.e1 = f(RigidShape::plate_axes(axis)[0]);
            }
            RigidShape::Plane { normal } => (d.kind, d.axis) = (rigid_kind::PLANE, f(normal)),
            RigidShape::Plate {
                normal,
                axes,
                size,
                opening,
            } => {
                (d.kind, d.axis, d.e1, d.e2) =
                    (rigid_kind::PLATE, f(normal), f(axes[0]), f(axes[1]));
                (d.size_a, d.size_b) = (size[0] as f32, size[1] as f32);
                (d.opening_a, d.opening_b) = (opening[0] as f32, opening[1] as f32);
            }
            RigidShape::Mesh(_) => return None,
        }
        Some(d)
    }
}

device_struct! {
    /// One constraint of the device contact iteration (twin: [`crate::kernels::Constraint`]).
    #[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
    pub struct GpuConstraint as Constraint {
        pub face: [u32; 4],
        pub weights: [f32; 4],
        pub normal: [f32; 3],
        pub gap: f32,
        pub compliance: f32,
        pub jn: f32,
        pub jt: [f32; 3],
        pub before: [f32; 3],
        pub in_reach: u32,
    }
}

impl From<GpuConstraint> for kernels::Constraint {
    fn from(c: GpuConstraint) -> Self {
        kernels::Constraint {
            face: c.face,
            weights: c.weights.map(f64::from),
            normal: c.normal.map(f64::from),
            gap: c.gap as f64,
            compliance: c.compliance as f64,
            jn: c.jn as f64,
            jt: c.jt.map(f64::from),
            before: c.before.map(f64::from),
            in_reach: c.in_reach != 0,
        }
    }
}

impl From<&kernels::Constraint> for GpuConstraint {
    fn from(c: &kernels::Constraint) -> Self {
        GpuConstraint {
            face: c.face,
            weights: c.weights.map(|x| x as f32),
            normal: c.normal.map(|x| x as f32),
            gap: c.gap as f32,
            compliance: c.compliance as f32,
            jn: c.jn as f32,
            jt: c.jt.map(|x| x as f32),
            before: c.before.map(|x| x as f32),
            in_reach: c.in_reach as u32,
        }
    }
}

device_struct! {
    /// A node of the device contact iteration (twin: [`crate::kernels::ContactNode`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct GpuContactNode as ContactNode {
        pub node: u32,
        pub pair_first: u32,
        pub pair_end: u32,
        pub face_first: u32,
        pub face_end: u32,
        pub body_first: u32,
        pub body_end: u32,
    }
}

impl From<&kernels::ContactNode> for GpuContactNode {
    fn from(c: &kernels::ContactNode) -> Self {
        GpuContactNode {
            node: c.node,
            pair_first: c.pair_first,
            pair_end: c.pair_end,
            face_first: c.face_first,
            face_end: c.face_end,
            body_first: c.body_first,
            body_end: c.body_end,
        }
    }
}

device_struct! {
    /// A ply failure evaluation point (twin: [`crate::kernels::SurveyPoint`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct GpuSurveyPoint as SurveyPoint {
        pub nodes: [u32; 8],
        pub corners: u32,
        pub strength: u32,
        pub stress_operator: u32,
    }
}

impl From<&kernels::SurveyPoint> for GpuSurveyPoint {
    fn from(p: &kernels::SurveyPoint) -> Self {
        GpuSurveyPoint {
            nodes: p.nodes,
            corners: p.corners,
            strength: p.strength,
            stress_operator: p.stress_operator,
        }
    }
}

device_struct! {
    /// A ply's strengths (twin: [`crate::material::Strength`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct PlyStrength {
        pub xt: f32,
        pub xc: f32,
        pub yt: f32,
        pub yc: f32,
        pub s12: f32,
        pub s23: f32,
    }
}

impl From<&crate::material::Strength> for PlyStrength {
    fn from(k: &crate::material::Strength) -> Self {
        PlyStrength {
            xt: k.xt as f32,
            xc: k.xc as f32,
            yt: k.yt as f32,
            yc: k.yc as f32,
            s12: k.s12 as f32,
            s23: k.s23 as f32,
        }
    }
}

device_struct! {
    /// A ply's damage law in its own axes (twin: [`crate::material::PlyDamage`]): the
    /// undamaged stiffness's normal block and shear moduli, the compliance's normal block
    /// and shear compliances (23, 13, 12), the strengths, the fracture energies (fibre
    /// tension, compression, matrix tension, compression), the viscosity, each mode's
    /// snap-back width $2 E G / X^2$, whether it damages by its in-plane stresses alone, and
    /// whether a band wider than a snap-back width lowers the mode's strength.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct DamageLaw {
        pub c11: f32,
        pub c12: f32,
        pub c13: f32,
        pub c22: f32,
        pub c23: f32,
        pub c33: f32,
        pub c44: f32,
        pub c55: f32,
        pub c66: f32,
        pub s11: f32,
        pub s12: f32,
        pub s13: f32,
        pub s22: f32,
        pub s23: f32,
        pub s33: f32,
        pub h23: f32,
        pub h13: f32,
        pub h12: f32,
        pub xt: f32,
        pub xc: f32,
        pub yt: f32,
        pub yc: f32,
        pub sl: f32,
        pub st: f32,
        pub viscosity: f32,
        pub snap_ft: f32,
        pub snap_fc: f32,
        pub snap_mt: f32,
        pub snap_mc: f32,
        /// 1 where the ply damages by its in-plane stresses alone, else 0.
        pub in_plane: f32,
        /// 1 where a band wider than a mode's snap-back width lowers its strength, else 0.
        pub lower_strength: f32,
    }
}

impl From<&crate::material::PlyDamage> for DamageLaw {
    fn from(l: &crate::material::PlyDamage) -> Self {
        let (c, n, k) = (&l.c0, &l.normal, &l.strength);
        let f = |x: f64| x as f32;
        DamageLaw {
            c11: f(c[0][0]),
            c12: f(c[0][1]),
            c13: f(c[0][2]),
            c22: f(c[1][1]),
            c23: f(c[1][2]),
            c33: f(c[2][2]),
            c44: f(c[3][3]),
            c55: f(c[4][4]),
            c66: f(c[5][5]),
            s11: f(n[0][0]),
            s12: f(n[0][1]),
            s13: f(n[0][2]),
            s22: f(n[1][1]),
            s23: f(n[1][2]),
            s33: f(n[2][2]),
            h23: f(l.shear[0]),
            h13: f(l.shear[1]),
            h12: f(l.shear[2]),
            xt: f(k.xt),
            xc: f(k.xc),
            yt: f(k.yt),
            yc: f(k.yc),
            sl: f(k.s12),
            st: f(k.s23),
            viscosity: f(l.viscosity),
            snap_ft: f(l.snap_back_width(0)),
            snap_fc: f(l.snap_back_width(1)),
            snap_mt: f(l.snap_back_width(2)),
            snap_mc: f(l.snap_back_width(3)),
            in_plane: if l.in_plane { 1.0 } else { 0.0 },
            lower_strength: if l.lower_strength { 1.0 } else { 0.0 },
        }
    }
}

device_struct! {
    /// A material entry of a damageable element's ply: its law (an index, `u32::MAX` for
    /// none) and its axes 1, 2, 3 as rows in the global axes.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct DamageEntry {
        pub law: u32,
        pub a11: f32,
        pub a12: f32,
        pub a13: f32,
        pub a21: f32,
        pub a22: f32,
        pub a23: f32,
        pub a31: f32,
        pub a32: f32,
        pub a33: f32,
    }
}

device_struct! {
    /// A damageable element's ply (twin: [`crate::element::damage::DamagePly`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct DamagePlyRecord {
        pub entry: u32,
        pub lo: f32,
        pub hi: f32,
        pub band_f: f32,
        pub band_m: f32,
    }
}

impl From<&crate::element::damage::DamagePly> for DamagePlyRecord {
    fn from(p: &crate::element::damage::DamagePly) -> Self {
        DamagePlyRecord {
            entry: p.entry,
            lo: p.lo as f32,
            hi: p.hi as f32,
            band_f: p.bands[0] as f32,
            band_m: p.bands[1] as f32,
        }
    }
}

device_struct! {
    /// A damageable element of a block (twin: [`crate::kernels::damage_data::DamageBlock`]'s
    /// entries): its number in the block, its first ply and ply count, its first point, its
    /// layup axis and its sieve factor.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct DamageElementRecord {
        pub element: u32,
        pub first_ply: u32,
        pub plies: u32,
        pub first_point: u32,
        pub axis: u32,
        pub sieve: f32,
    }
}

device_struct! {
    /// The damage kernels' step (a uniform, one per block): the step, whether the state
    /// advances, and the block's element count (E) and its first record's word.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct DamageParams {
        pub dt: f32,
        pub advance: u32,
        pub elements: u32,
        pub records: u32,
    }
}

device_struct! {
    /// A cohesive interface's law (twin: [`crate::material::CohesiveLaw`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct CohesiveLaw {
        pub stiffness: f32,
        pub strength_n: f32,
        pub strength_s: f32,
        pub toughness_i: f32,
        pub toughness_ii: f32,
        pub bk: f32,
        pub friction: f32,
        pub pad: f32,
    }
}

impl From<&crate::material::CohesiveLaw> for CohesiveLaw {
    fn from(l: &crate::material::CohesiveLaw) -> Self {
        CohesiveLaw {
            stiffness: l.stiffness as f32,
            strength_n: l.strength[0] as f32,
            strength_s: l.strength[1] as f32,
            toughness_i: l.toughness[0] as f32,
            toughness_ii: l.toughness[1] as f32,
            bk: l.bk as f32,
            friction: l.friction as f32,
            pad: 0.0,
        }
    }
}

device_struct! {
    /// A bonded pair (twin: [`kernels::cohesive_pairs::PairRecord`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct CohesivePair {
        pub upper: u32,
        pub lower: u32,
        pub law: u32,
        pub area: f32,
        pub normal: [f32; 3],
        pub pad: u32,
    }
}

impl From<&kernels::cohesive_pairs::PairRecord> for CohesivePair {
    fn from(p: &kernels::cohesive_pairs::PairRecord) -> Self {
        CohesivePair {
            upper: p.upper,
            lower: p.lower,
            law: p.law,
            area: p.area as f32,
            normal: p.normal.map(|x| x as f32),
            pad: 0,
        }
    }
}

device_struct! {
    /// A bonded pair's state (twin: [`kernels::cohesive_pairs::PairState`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct PairState {
        pub damage: f32,
        pub slip: [f32; 3],
    }
}

impl From<&kernels::cohesive_pairs::PairState> for PairState {
    fn from(s: &kernels::cohesive_pairs::PairState) -> Self {
        PairState {
            damage: s.damage as f32,
            slip: s.slip.map(|x| x as f32),
        }
    }
}

device_struct! {
    /// A pair's step (twin: [`kernels::cohesive_pairs::PairOutput`]).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
    pub struct PairOutput {
        pub force: [f32; 3],
        pub dissipated: f32,
        pub offset: f32,
    }
}

device_struct! {
    /// A bonded node (twin: [`kernels::cohesive_scatter::BondedNode`]), its corner a
    /// device's slot.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct BondedNode {
        pub node: u32,
        pub corner: u32,
        pub first: u32,
        pub end: u32,
    }
}

/// A struct's WGSL name, Rust size, and (field name, Rust offset) in declaration order.
pub(crate) type StructLayout = (&'static str, usize, Vec<(&'static str, usize)>);

/// The constants `shaders/shared/types.wgsl` shares with the host, by WGSL name, with the
/// host's values (the layout test compares them with naga's reading of the WGSL).
pub fn shared_constants() -> Vec<(&'static str, u32)> {
    use crate::kernels::explicit_correct::FIELDS;
    use crate::kernels::history_reduce::*;
    use crate::kernels::plane_contact::{slot, MAX_PLANES, SLOT};
    use crate::kernels::sweep_control::word;
    let u = |v: usize| v as u32;
    vec![
        ("POINT_STATE", u(crate::material::damage::POINT_STATE)),
        (
            "DAMAGE_RECORD",
            u(crate::kernels::damage_data::DAMAGE_RECORD),
        ),
        ("NO_FACE", crate::geometry::point::NO_FACE),
        ("WORKGROUP", WORKGROUP),
        ("SLOT", u(SLOT)),
        ("SLOT_NORMAL_IMPULSE", u(slot::NORMAL_IMPULSE)),
        ("SLOT_FRICTION_IMPULSE", u(slot::FRICTION_IMPULSE)),
        ("SLOT_ACTIVE", u(slot::ACTIVE)),
        ("SLOT_SLIDING", u(slot::SLIDING)),
        ("SLOT_GAP", u(slot::GAP)),
        ("SLOT_FRICTION_WORK", u(slot::FRICTION_WORK)),
        ("SLOT_SWEEPS", u(slot::SWEEPS)),
        ("SLOT_IMPULSE", u(slot::IMPULSE)),
        ("SLOT_DRIVER_WORK", u(slot::DRIVER_WORK)),
        ("SLOT_IMPACT_LOSS", u(slot::IMPACT_LOSS)),
        (
            "SURVEY_COLUMNS",
            u(crate::kernels::failure_survey::SURVEY_COLUMNS),
        ),
        ("FAILURE_FIELDS", u(crate::kernels::FAILURE_FIELDS)),
        ("RIGID_SPHERE", rigid_kind::SPHERE),
        ("RIGID_CAPSULE", rigid_kind::CAPSULE),
        ("RIGID_CYLINDER", rigid_kind::CYLINDER),
        ("RIGID_PLANE", rigid_kind::PLANE),
        ("RIGID_PLATE", rigid_kind::PLATE),
        ("MAX_PLANES", u(MAX_PLANES)),
        ("FIELDS", u(FIELDS)),
        ("OP_PARTIALS", OP_PARTIALS),
        ("OP_SUM", OP_SUM),
        ("OP_MAX", OP_MAX),
        ("OP_DISPLACEMENT", OP_DISPLACEMENT),
        ("OP_VELOCITY", OP_VELOCITY),
        ("OP_CORNERS", OP_CORNERS),
        ("LOWER", crate::kernels::cohesive_scatter::LOWER),
        (
            "COHESIVE_COLUMNS",
            u(crate::kernels::cohesive_reduce::COHESIVE_COLUMNS),
        ),
        ("STATE_VIOLATION", u(word::VIOLATION)),
        ("STATE_ACTIVE", u(word::ACTIVE)),
        ("STATE_SWEEPS", u(word::SWEEPS)),
        ("STATE_PHASE", u(word::PHASE)),
        ("STATE_SWEPT", u(word::SWEPT)),
        ("STATE_RING", u(word::RING)),
    ]
}

/// Sizes and field offsets of every struct, by WGSL name, for the layout test (each from
/// its declaration, [`device_struct`]).
pub fn layouts() -> Vec<StructLayout> {
    vec![
        Params::layout(),
        Split3::layout(),
        GpuMaterial::layout(),
        ContactQuery::layout(),
        Quad::layout(),
        FaceBox::layout(),
        GpuContactPoint::layout(),
        Lumped::layout(),
        Plane::layout(),
        GpuPlaneNode::layout(),
        GpuReduceColumn::layout(),
        Step::layout(),
        GpuSearchGrid::layout(),
        GpuContactPair::layout(),
        GpuConstraint::layout(),
        GpuContactNode::layout(),
        GpuRigidSurface::layout(),
        GpuSurveyPoint::layout(),
        PlyStrength::layout(),
        DamageLaw::layout(),
        DamageEntry::layout(),
        DamagePlyRecord::layout(),
        DamageElementRecord::layout(),
        DamageParams::layout(),
        CohesiveLaw::layout(),
        CohesivePair::layout(),
        PairState::layout(),
        PairOutput::layout(),
        BondedNode::layout(),
    ]
}
