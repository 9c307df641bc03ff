// The damage pass of a tet4 block's damageable elements, after `tet4_forces` (twin:
// `kernels::tet4_damage`): an element already damaged, or whose elastic strain energy
// passes its sieve, takes its one point's step, and its forces replace the elastic ones. One
// invocation per damageable element. Layouts as in `hex8i_damage.wgsl`.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<uniform> damage: DamageParams;
@group(0) @binding(2) var<storage, read> reference: array<Split3>;
@group(0) @binding(3) var<storage, read> displacement: array<Split3>;
@group(0) @binding(4) var<storage, read> velocity: array<f32>;
@group(0) @binding(5) var<storage, read> block_nodes: array<u32>;
@group(0) @binding(6) var<storage, read> elements: array<DamageElementRecord>;
@group(0) @binding(7) var<storage, read> plies: array<DamagePlyRecord>;
@group(0) @binding(8) var<storage, read> entries: array<DamageEntry>;
@group(0) @binding(9) var<storage, read> laws: array<DamageLaw>;
@group(0) @binding(10) var<storage, read_write> state: array<f32>;
@group(0) @binding(11) var<storage, read_write> records: array<u32>;
@group(0) @binding(12) var<storage, read_write> corner_forces: array<f32>;

// include: store_corner
// include: damage_common

// The displacement gradient sum_k u_k g_k^T of corners 1..3 (corner 0's relative zero).
fn tet_gradient(t: TetGradients, u1: vec3<f32>, u2: vec3<f32>, u3: vec3<f32>) -> mat3x3<f32> {
    return damage_outer(u1, t.g1) + damage_outer(u2, t.g2) + damage_outer(u3, t.g3);
}

@compute @workgroup_size(64)
fn tet4_damage(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let rec = elements[i];
    let e = rec.element;
    let ne = damage.elements;
    let n0 = block_nodes[e];
    let n1 = block_nodes[ne + e];
    let n2 = block_nodes[2u * ne + e];
    let n3 = block_nodes[3u * ne + e];
    let r0 = reference[n0];
    let d0 = displacement[n0];
    let v0 = node_velocity(n0);
    let u1 = split_difference(displacement[n1], d0);
    let u2 = split_difference(displacement[n2], d0);
    let u3 = split_difference(displacement[n3], d0);
    let advance = damage.advance != 0u;
    let was = records[record_at(i, 0u)] != 0u;
    if (advance) {
        store_dissipation(i, 0.0, 0.0);
    }
    if (!was) {
        if (!advance) {
            return;
        }
        let work = dot(load_corner(ne + e), u1) + dot(load_corner(2u * ne + e), u2)
            + dot(load_corner(3u * ne + e), u3);
        if (rec.sieve * 0.5 * work < 1.0) {
            return;
        }
    }
    let t = tet_gradients(
        split_difference(reference[n1], r0),
        split_difference(reference[n2], r0),
        split_difference(reference[n3], r0),
    );
    let dt = damage.dt;
    let h = tet_gradient(t, u1, u2, u3);
    let hp = tet_gradient(
        t,
        u1 - dt * (node_velocity(n1) - v0),
        u2 - dt * (node_velocity(n2) - v0),
        u3 - dt * (node_velocity(n3) - v0),
    );
    let ply = plies[rec.first_ply];
    let entry = entries[ply.entry];
    let law = laws[entry.law];
    let m = entry_axes(entry);
    let old = load_point(rec.first_point);
    let e_now = ply_strain(m, h);
    var sigma: Voigt6;
    if (advance) {
        let bands = vec2<f32>(ply.band_f, ply.band_m);
        let st = law_step(law, e_now, ply_strain(m, hp), old, bands, dt);
        store_point(rec.first_point, st.state);
        sigma = st.stress;
        let damaged = point_damaged(st.state);
        if (!was && !damaged) {
            return;
        }
        if (!was) {
            records[record_at(i, 0u)] = 1u;
            records[record_at(i, 1u)] = records[0] + 1u;
            records[record_at(i, 2u)] = largest_mode(st.state.inviscid);
        }
        store_dissipation(i, st.dissipated * t.volume, st.fibre * t.volume);
    } else {
        sigma = law_stress(law, e_now, old);
    }
    let s = global_stress(m, sigma) * t.volume;
    store_corner(e, s * t.g0);
    store_corner(ne + e, s * t.g1);
    store_corner(2u * ne + e, s * t.g2);
    store_corner(3u * ne + e, s * t.g3);
}
