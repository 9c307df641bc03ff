// The damage pass of a hex8i block's damageable elements, after `hex8i_forces` (twin:
// `kernels::hex8i_damage`): an element already damaged, or whose elastic strain energy
// passes its sieve, takes its points' step with its modes condensed elastically (alpha =
// A_0 u, at u and at the step before), and its forces replace the elastic ones. One
// invocation per damageable element.
//
// Layouts: element i's condensation entry (r, j) (mode r / 3's component r % 3, corner
// displacement j) at condensation[(24 r + j) D + i] (D = params.count); its records at
// records[damage.records + DAMAGE_RECORD i ..] (flag, first step, first point, dissipation),
// the step counter at records[0]; its points' states at state[POINT_STATE p ..].

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
@group(0) @binding(10) var<storage, read> condensation: array<f32>;
@group(0) @binding(11) var<storage, read_write> state: array<f32>;
@group(0) @binding(12) var<storage, read_write> records: array<u32>;
@group(0) @binding(13) var<storage, read_write> corner_forces: array<f32>;

// include: store_corner
// include: damage_common
// include: damage_hex

// Mode r / 3's component r % 3 of the amplitudes A_0 d of corner displacements d (corner 0's
// zero).
fn amplitude(i: u32, r: u32, d: HexCorners) -> f32 {
    let n = params.count;
    let at = 24u * r * n + i;
    return condensation[at + 3u * n] * d.c1.x + condensation[at + 4u * n] * d.c1.y
        + condensation[at + 5u * n] * d.c1.z + condensation[at + 6u * n] * d.c2.x
        + condensation[at + 7u * n] * d.c2.y + condensation[at + 8u * n] * d.c2.z
        + condensation[at + 9u * n] * d.c3.x + condensation[at + 10u * n] * d.c3.y
        + condensation[at + 11u * n] * d.c3.z + condensation[at + 12u * n] * d.c4.x
        + condensation[at + 13u * n] * d.c4.y + condensation[at + 14u * n] * d.c4.z
        + condensation[at + 15u * n] * d.c5.x + condensation[at + 16u * n] * d.c5.y
        + condensation[at + 17u * n] * d.c5.z + condensation[at + 18u * n] * d.c6.x
        + condensation[at + 19u * n] * d.c6.y + condensation[at + 20u * n] * d.c6.z
        + condensation[at + 21u * n] * d.c7.x + condensation[at + 22u * n] * d.c7.y
        + condensation[at + 23u * n] * d.c7.z;
}

fn mode_amplitude(i: u32, m: u32, d: HexCorners) -> vec3<f32> {
    return vec3<f32>(amplitude(i, 3u * m, d), amplitude(i, 3u * m + 1u, d), amplitude(i, 3u * m + 2u, d));
}

// Corner k's (k < 8) share of the modes' forces r (one vector per mode): sum over mode m and
// component a of A_0[3 m + a][3 k + c] r_m[a], component c.
fn mode_force(i: u32, k: u32, r0: vec3<f32>, r1: vec3<f32>, r2: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(mode_force_component(i, 3u * k, r0, r1, r2),
        mode_force_component(i, 3u * k + 1u, r0, r1, r2),
        mode_force_component(i, 3u * k + 2u, r0, r1, r2));
}

// Corner displacement j's row of A_0^T r.
fn mode_force_component(i: u32, j: u32, r0: vec3<f32>, r1: vec3<f32>, r2: vec3<f32>) -> f32 {
    let n = params.count;
    let at = j * n + i;
    return dot(vec3<f32>(condensation[at], condensation[at + 24u * n], condensation[at + 48u * n]), r0)
        + dot(vec3<f32>(condensation[at + 72u * n], condensation[at + 96u * n], condensation[at + 120u * n]), r1)
        + dot(vec3<f32>(condensation[at + 144u * n], condensation[at + 168u * n], condensation[at + 192u * n]), r2);
}

@compute @workgroup_size(64)
fn hex8i_damage(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let rec = elements[i];
    let h = damage_hex(rec.element);
    if (!damage_passes(i, rec.element, rec, h.u)) {
        return;
    }
    let amp = HexAmplitudes(
        mode_amplitude(i, 0u, h.u),
        mode_amplitude(i, 1u, h.u),
        mode_amplitude(i, 2u, h.u),
        mode_amplitude(i, 0u, h.before),
        mode_amplitude(i, 1u, h.before),
        mode_amplitude(i, 2u, h.before),
    );
    let out = hex_damage_points(i, rec.element, rec, h, amp);
    if (out.store) {
        let f = out.corners;
        let a = out.r0;
        let b = out.r1;
        let c = out.r2;
        let total = HexCorners(
            f.c0 + mode_force(i, 0u, a, b, c),
            f.c1 + mode_force(i, 1u, a, b, c),
            f.c2 + mode_force(i, 2u, a, b, c),
            f.c3 + mode_force(i, 3u, a, b, c),
            f.c4 + mode_force(i, 4u, a, b, c),
            f.c5 + mode_force(i, 5u, a, b, c),
            f.c6 + mode_force(i, 6u, a, b, c),
            f.c7 + mode_force(i, 7u, a, b, c),
        );
        store_hex(rec.element, total);
    }
}
