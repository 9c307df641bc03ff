// included by hex8_damage and hex8i_damage, which bind `params` (count: the damageable
// elements; aux, aux2: the corner slots as `store_corner` takes them), the uniform `damage`,
// `reference`, `displacement`, `velocity`, `block_nodes`, `elements`, `plies`, `entries`,
// `laws`, `state`, `records` and `corner_forces`, after `damage_common` (twins: `element::damage::hex_damage` and
// `kernels::damage_data::damage_pass`).

const DAMAGE_GAUSS: f32 = 0.57735026918962576;

// The incompatible modes' amplitudes (one vector per mode) at u and at the step before.
struct HexAmplitudes {
    a0: vec3<f32>,
    a1: vec3<f32>,
    a2: vec3<f32>,
    p0: vec3<f32>,
    p1: vec3<f32>,
    p2: vec3<f32>,
}

// A damageable hex: its corners, its displacements and the step before's, relative to corner
// 0, and its corners' block slots' element number.
struct DamageHex {
    x: HexCorners,
    u: HexCorners,
    before: HexCorners,
}

// The corner signs of `element::hex8::CORNERS`, corner k.
fn hex_corner_sign(k: u32) -> vec3<f32> {
    let x = select(-1.0, 1.0, k == 1u || k == 2u || k == 5u || k == 6u);
    let y = select(-1.0, 1.0, k == 2u || k == 3u || k == 6u || k == 7u);
    let z = select(-1.0, 1.0, k >= 4u);
    return vec3<f32>(x, y, z);
}

// Damageable element i's hex (its nodes from the block's columns) with the step dt.
fn damage_hex(e: u32) -> DamageHex {
    let ne = damage.elements;
    let n0 = block_nodes[e];
    let n1 = block_nodes[ne + e];
    let n2 = block_nodes[2u * ne + e];
    let n3 = block_nodes[3u * ne + e];
    let n4 = block_nodes[4u * ne + e];
    let n5 = block_nodes[5u * ne + e];
    let n6 = block_nodes[6u * ne + e];
    let n7 = block_nodes[7u * ne + e];
    let r0 = reference[n0];
    let d0 = displacement[n0];
    let v0 = node_velocity(n0);
    let dt = damage.dt;
    let zero = vec3<f32>(0.0);
    let x = HexCorners(
        zero,
        split_difference(reference[n1], r0),
        split_difference(reference[n2], r0),
        split_difference(reference[n3], r0),
        split_difference(reference[n4], r0),
        split_difference(reference[n5], r0),
        split_difference(reference[n6], r0),
        split_difference(reference[n7], r0),
    );
    let u = HexCorners(
        zero,
        split_difference(displacement[n1], d0),
        split_difference(displacement[n2], d0),
        split_difference(displacement[n3], d0),
        split_difference(displacement[n4], d0),
        split_difference(displacement[n5], d0),
        split_difference(displacement[n6], d0),
        split_difference(displacement[n7], d0),
    );
    // u_n = u_{n+1} - dt v_{n+1/2}, relative to corner 0
    let before = HexCorners(
        zero,
        u.c1 - dt * (node_velocity(n1) - v0),
        u.c2 - dt * (node_velocity(n2) - v0),
        u.c3 - dt * (node_velocity(n3) - v0),
        u.c4 - dt * (node_velocity(n4) - v0),
        u.c5 - dt * (node_velocity(n5) - v0),
        u.c6 - dt * (node_velocity(n6) - v0),
        u.c7 - dt * (node_velocity(n7) - v0),
    );
    return DamageHex(x, u, before);
}

// Whether damageable element i (block element e) goes on past the sieve: a damaged one
// always; without a step, none other; else where kappa U >= 1, U its elastic strain
// energy from the corner forces the force kernel wrote. Clears its dissipation.
fn damage_passes(i: u32, e: u32, rec: DamageElementRecord, u: HexCorners) -> bool {
    if (records[record_at(i, 0u)] != 0u) {
        if (damage.advance != 0u) {
            store_dissipation(i, 0.0, 0.0);
        }
        return true;
    }
    if (damage.advance == 0u) {
        return false;
    }
    store_dissipation(i, 0.0, 0.0);
    let ne = damage.elements;
    let work = dot(load_corner(ne + e), u.c1) + dot(load_corner(2u * ne + e), u.c2)
        + dot(load_corner(3u * ne + e), u.c3) + dot(load_corner(4u * ne + e), u.c4)
        + dot(load_corner(5u * ne + e), u.c5) + dot(load_corner(6u * ne + e), u.c6)
        + dot(load_corner(7u * ne + e), u.c7);
    return rec.sieve * 0.5 * work >= 1.0;
}

// Natural point k of a ply over lo..hi along `axis` (the cube's 2x2x2 Gauss point there).
fn ply_point(k: u32, axis: u32, lo: f32, hi: f32) -> vec3<f32> {
    let sgn = hex_corner_sign(k);
    let q = DAMAGE_GAUSS * sgn;
    let mid = 0.5 * (lo + hi);
    let half = 0.5 * (hi - lo);
    let along = mid + half * DAMAGE_GAUSS * select(select(sgn.z, sgn.y, axis == 1u), sgn.x, axis == 0u);
    return vec3<f32>(
        select(q.x, along, axis == 0u),
        select(q.y, along, axis == 1u),
        select(q.z, along, axis == 2u),
    );
}

// What a damageable hex's points give: its corner forces from B_u^T sigma, the modes'
// forces B_alpha^T sigma (one vector per mode; a hex8i hands them to its corners through its
// condensation), and whether they replace the elastic forces.
struct DamageForces {
    corners: HexCorners,
    r0: vec3<f32>,
    r1: vec3<f32>,
    r2: vec3<f32>,
    store: bool,
}

// Damageable element i's points: their step (or, without one, their stress), the modal
// forces, the dissipation and the element's records (twin: `element::damage::hex_damage`).
fn hex_damage_points(i: u32, e: u32, rec: DamageElementRecord, h: DamageHex, amp: HexAmplitudes) -> DamageForces {
    let a = hex_modes(h.x);
    let b = hex_modes(h.u);
    let bp = hex_modes(h.before);
    let c0 = cofactor(mat3x3<f32>(a.m1, a.m2, a.m3));
    let zero = vec3<f32>(0.0);
    var fm = HexModes(zero, zero, zero, zero, zero, zero, zero);
    var r0 = zero;
    var r1 = zero;
    var r2 = zero;
    var dissipated = 0.0;
    var fibre = 0.0;
    var first = NO_POINT;
    let advance = damage.advance != 0u;
    for (var p = 0u; p < rec.plies; p++) {
        let ply = plies[rec.first_ply + p];
        let entry = entries[ply.entry];
        let law = laws[entry.law];
        let m = entry_axes(entry);
        let half = 0.5 * (ply.hi - ply.lo);
        for (var k = 0u; k < 8u; k++) {
            let q = ply_point(k, rec.axis, ply.lo, ply.hi);
            let jq = hex_modal_gradient(a, q);
            let cj = cofactor(jq);
            let det = dot(jq[0], cj[0]);
            let inv = transpose(cj) * (1.0 / det);
            let g0 = c0[0] * (-2.0 * q.x / det);
            let g1 = c0[1] * (-2.0 * q.y / det);
            let g2 = c0[2] * (-2.0 * q.z / det);
            let hu = hex_modal_gradient(b, q) * inv + damage_outer(amp.a0, g0)
                + damage_outer(amp.a1, g1) + damage_outer(amp.a2, g2);
            let hp = hex_modal_gradient(bp, q) * inv + damage_outer(amp.p0, g0)
                + damage_outer(amp.p1, g1) + damage_outer(amp.p2, g2);
            let point = rec.first_point + 8u * p + k;
            let old = load_point(point);
            let e_now = ply_strain(m, hu);
            var sigma: Voigt6;
            if (advance) {
                let bands = vec2<f32>(ply.band_f, ply.band_m);
                let st = law_step(law, e_now, ply_strain(m, hp), old, bands, damage.dt);
                store_point(point, st.state);
                sigma = st.stress;
                dissipated += st.dissipated * half * det;
                fibre += st.fibre * half * det;
                if (first == NO_POINT && point_damaged(st.state)) {
                    first = 4u * (8u * p + k) + largest_mode(st.state.inviscid);
                }
            } else {
                sigma = law_stress(law, e_now, old);
            }
            let sg = global_stress(m, sigma);
            let wdet = half * det;
            r0 += (sg * g0) * wdet;
            r1 += (sg * g1) * wdet;
            r2 += (sg * g2) * wdet;
            let qf = (sg * cj) * half;
            fm.m1 += qf[0];
            fm.m2 += qf[1];
            fm.m3 += qf[2];
            fm.m4 += qf[0] * q.y + qf[1] * q.x;
            fm.m5 += qf[1] * q.z + qf[2] * q.y;
            fm.m6 += qf[0] * q.z + qf[2] * q.x;
            fm.m7 += qf[0] * (q.y * q.z) + qf[1] * (q.x * q.z) + qf[2] * (q.x * q.y);
        }
    }
    let was = records[record_at(i, 0u)] != 0u;
    if (advance) {
        if (!was && first == NO_POINT) {
            // checked and still undamaged: the elastic forces stand
            return DamageForces(hex_corners_of_modes(fm), r0, r1, r2, false);
        }
        if (!was) {
            records[record_at(i, 0u)] = 1u;
            records[record_at(i, 1u)] = records[0] + 1u;
            records[record_at(i, 2u)] = first;
        }
        store_dissipation(i, dissipated, fibre);
    }
    return DamageForces(hex_corners_of_modes(fm), r0, r1, r2, true);
}

// Stores a damageable element's corner forces (block element e).
fn store_hex(e: u32, f: HexCorners) {
    let ne = damage.elements;
    store_corner(e, f.c0);
    store_corner(ne + e, f.c1);
    store_corner(2u * ne + e, f.c2);
    store_corner(3u * ne + e, f.c3);
    store_corner(4u * ne + e, f.c4);
    store_corner(5u * ne + e, f.c5);
    store_corner(6u * ne + e, f.c6);
    store_corner(7u * ne + e, f.c7);
}
