// Ply damage (twin: `material::damage`): Hashin initiation on the effective stress, linear
// softening over the crack band, the stiffness degraded in the MLT form in 3D, Duvaut-Lions
// viscosity, and the step's dissipation. Written without arrays: a Voigt 6-vector is its
// normal part (11, 22, 33) and shear part (23, 13, 12, engineering), a point's state two
// vec4s (fibre tension, fibre compression, matrix tension, matrix compression).

// The largest damage (twin: `material::damage::D_MAX`).
const D_MAX: f32 = 0.9999;

struct Voigt6 {
    n: vec3<f32>,
    s: vec3<f32>,
}

// A point's damage: the four variables the softening gives, then the four that act.
struct PointState {
    inviscid: vec4<f32>,
    acting: vec4<f32>,
}

// An orthotropic stiffness in the ply axes: its normal block and shear moduli.
struct OrthoStiffness {
    normal: mat3x3<f32>,
    shear: vec3<f32>,
}

// A point's step: its state and stress, its dissipation per unit volume and the fibre
// modes' share of it.
struct PointStep {
    state: PointState,
    stress: Voigt6,
    dissipated: f32,
    fibre: f32,
}

fn ortho_apply(c: OrthoStiffness, e: Voigt6) -> Voigt6 {
    return Voigt6(c.normal * e.n, c.shear * e.s);
}

fn voigt_dot(a: Voigt6, b: Voigt6) -> f32 {
    return dot(a.n, b.n) + dot(a.s, b.s);
}

fn law_undamaged(l: DamageLaw) -> OrthoStiffness {
    let n = mat3x3<f32>(
        vec3<f32>(l.c11, l.c12, l.c13),
        vec3<f32>(l.c12, l.c22, l.c23),
        vec3<f32>(l.c13, l.c23, l.c33),
    );
    return OrthoStiffness(n, vec3<f32>(l.c44, l.c55, l.c66));
}

// The stiffness with the damage d = (df, dmt, ds, dmc) that acts: the compliance's fibre
// term over 1 - df, its transverse terms over 1 - dmt, plus the crushed matrix's deviatoric
// c v v^T (v = (0, 1, -1), c = s22 dmc / (1 - dmc)), inverted; the shear moduli times 1 - ds.
// In plane: s22 alone over 1 - dmt - dmc, and the 12 modulus alone times 1 - ds.
fn law_stiffness(l: DamageLaw, d: vec4<f32>) -> OrthoStiffness {
    let ip = l.in_plane > 0.5;
    let crush = select(l.s22 * d.w / (1.0 - d.w), 0.0, ip);
    let s22 = select(l.s22 / (1.0 - d.y) + crush, l.s22 / ((1.0 - d.y) * (1.0 - d.w)), ip);
    let s33 = select(l.s33 / (1.0 - d.y) + crush, l.s33, ip);
    let s = mat3x3<f32>(
        vec3<f32>(l.s11 / (1.0 - d.x), l.s12, l.s13),
        vec3<f32>(l.s12, s22, l.s23 - crush),
        vec3<f32>(l.s13, l.s23 - crush, s33),
    );
    let c = cofactor(s);
    let det = dot(s[0], c[0]);
    // symmetric: the inverse is the cofactor matrix over the determinant
    let keep = select(vec3<f32>(1.0 - d.z), vec3<f32>(1.0, 1.0, 1.0 - d.z), ip);
    let shear = keep / vec3<f32>(l.h23, l.h13, l.h12);
    return OrthoStiffness(c * (1.0 / det), shear);
}

// The damage that acts, by the signs of the effective fibre stress and of the transverse
// stresses' sum: fibre, matrix tension, shear, matrix compression; in 3D the crushed
// matrix's deviatoric compliance acts in tension too (twin: `PlyDamage::acting`).
fn damage_acting(l: DamageLaw, st: PointState, fibre: bool, matrix: bool) -> vec4<f32> {
    let v = st.acting;
    let df = select(v.y, v.x, fibre);
    let ds = 1.0 - (1.0 - v.x) * (1.0 - v.y) * (1.0 - v.z) * (1.0 - v.w);
    let crush = select(v.w, 0.0, matrix && l.in_plane > 0.5);
    return vec4<f32>(df, select(0.0, v.z, matrix), min(ds, D_MAX), crush);
}

// Each mode's r of the effective stress s: sqrt of the Hashin index (fibre tension without
// its shear term), matrix compression's the inverse of the load factor to the index 1.
fn index_ratios(l: DamageLaw, s_all: Voigt6) -> vec4<f32> {
    // in plane: 33, 23 and 13 left out
    let ip = l.in_plane > 0.5;
    let s = Voigt6(
        select(s_all.n, vec3<f32>(s_all.n.xy, 0.0), ip),
        select(s_all.s, vec3<f32>(0.0, 0.0, s_all.s.z), ip),
    );
    let s11 = s.n.x;
    let s22 = s.n.y;
    let s33 = s.n.z;
    let long = (s.s.z * s.s.z + s.s.y * s.s.y) / (l.sl * l.sl);
    let trans = (s.s.x * s.s.x - s22 * s33) / (l.st * l.st);
    let i1 = s22 + s33;
    let ft = select(0.0, s11 / l.xt, s11 >= 0.0);
    let fc = select(0.0, -s11 / l.xc, s11 < 0.0);
    let fmt = (i1 / l.yt) * (i1 / l.yt) + trans + long;
    let mt = select(0.0, sqrt(max(fmt, 0.0)), i1 >= 0.0);
    let q = l.yc / (2.0 * l.st);
    let a = (q * q - 1.0) * i1 / l.yc;
    let h = i1 / (2.0 * l.st);
    let b = h * h + trans + long;
    let mc_quadratic = 0.5 * (a + sqrt(a * a + 4.0 * b));
    let mc = select(0.0, select(max(a, 0.0), mc_quadratic, b > 0.0), i1 < 0.0);
    return vec4<f32>(ft, fc, mt, mc);
}

// One mode's damage at r in a band of width `band` (snap-back width `snap`), its strength
// lowered to the band's where `lower` and the band is wider than `snap` (twins:
// `material::PlyDamage::onset` and `softening_end`).
fn mode_damage(r: f32, snap: f32, band: f32, lower: bool) -> f32 {
    let onset2 = select(1.0, min(snap / band, 1.0), lower);
    let ro = r / sqrt(onset2);
    let rf = max(snap / (band * onset2), 1.0 + 1e-6);
    return select(0.0, min(rf * (ro - 1.0) / (ro * (rf - 1.0)), D_MAX), ro > 1.0);
}

// The effective stress: each component over one minus its damage (d as damage_acting's),
// the transverse ones the sign's own matrix mode's (matrix: in tension).
fn effective_stress(s: Voigt6, d: vec4<f32>, matrix: bool) -> Voigt6 {
    let dm = select(d.w, d.y, matrix);
    return Voigt6(s.n / vec3<f32>(1.0 - d.x, 1.0 - dm, 1.0 - dm), s.s / (1.0 - d.z));
}

// One point's step from strain e and the step before's prev (ply axes), its old state, its
// bands and dt (twin: `material::PlyDamage::step`).
fn law_step(l: DamageLaw, e: Voigt6, prev: Voigt6, old: PointState, bands: vec2<f32>, dt: f32) -> PointStep {
    let c0 = law_undamaged(l);
    let eff = ortho_apply(c0, e);
    let fibre = eff.n.x >= 0.0;
    let matrix = eff.n.y + eff.n.z >= 0.0;
    let d_old = damage_acting(l, old, fibre, matrix);
    let before = law_stiffness(l, d_old);
    let r = index_ratios(l, effective_stress(ortho_apply(before, e), d_old, matrix));
    let lower = l.lower_strength > 0.5;
    let trial = vec4<f32>(
        mode_damage(r.x, l.snap_ft, bands.x, lower),
        mode_damage(r.y, l.snap_fc, bands.x, lower),
        mode_damage(r.z, l.snap_mt, bands.y, lower),
        mode_damage(r.w, l.snap_mc, bands.y, lower),
    );
    var st: PointState;
    st.inviscid = max(old.inviscid, trial);
    if (l.viscosity > 0.0) {
        let a = dt / l.viscosity;
        st.acting = min((old.acting + a * st.inviscid) / (1.0 + a), vec4<f32>(D_MAX));
    } else {
        st.acting = st.inviscid;
    }
    let after = law_stiffness(l, damage_acting(l, st, fibre, matrix));
    let stress = ortho_apply(after, e);
    // the damage's growth alone, both stiffnesses at this step's signs
    let dissipated = released(before, after, e, prev);
    // the fibre modes' share: through the stiffness of the new fibre and old matrix damage
    // where both kinds grew
    var fibre_part = 0.0;
    if (any(st.acting.xy != old.acting.xy)) {
        fibre_part = dissipated;
        if (any(st.acting.zw != old.acting.zw)) {
            let mid = PointState(st.inviscid, vec4<f32>(st.acting.xy, old.acting.zw));
            fibre_part = released(before, law_stiffness(l, damage_acting(l, mid, fibre, matrix)), e, prev);
        }
    }
    return PointStep(st, stress, dissipated, fibre_part);
}

// What a stiffness falling from a to b at strain e releases from the step before's prev:
// (prev . (a - b) e) / 2.
fn released(a: OrthoStiffness, b: OrthoStiffness, e: Voigt6, prev: Voigt6) -> f32 {
    let change = Voigt6((a.normal - b.normal) * e.n, (a.shear - b.shear) * e.s);
    return 0.5 * voigt_dot(prev, change);
}

// The stress of strain e with a point's damage as it is (no step).
fn law_stress(l: DamageLaw, e: Voigt6, st: PointState) -> Voigt6 {
    let eff = ortho_apply(law_undamaged(l), e);
    let c = law_stiffness(l, damage_acting(l, st, eff.n.x >= 0.0, eff.n.y + eff.n.z >= 0.0));
    return ortho_apply(c, e);
}

// The ply axes of an entry as the columns of a matrix M: a tensor t of the global axes is
// M^T t M in the ply's.
fn entry_axes(a: DamageEntry) -> mat3x3<f32> {
    return mat3x3<f32>(
        vec3<f32>(a.a11, a.a12, a.a13),
        vec3<f32>(a.a21, a.a22, a.a23),
        vec3<f32>(a.a31, a.a32, a.a33),
    );
}

// The ply strain (Voigt, engineering shears) of the displacement gradient h.
fn ply_strain(m: mat3x3<f32>, h: mat3x3<f32>) -> Voigt6 {
    let e = transpose(m) * (0.5 * (h + transpose(h))) * m;
    return Voigt6(vec3<f32>(e[0].x, e[1].y, e[2].z), 2.0 * vec3<f32>(e[2].y, e[2].x, e[1].x));
}

// A ply stress (Voigt) as a tensor of the global axes.
fn global_stress(m: mat3x3<f32>, s: Voigt6) -> mat3x3<f32> {
    let t = mat3x3<f32>(
        vec3<f32>(s.n.x, s.s.z, s.s.y),
        vec3<f32>(s.s.z, s.n.y, s.s.x),
        vec3<f32>(s.s.y, s.s.x, s.n.z),
    );
    return m * t * transpose(m);
}
