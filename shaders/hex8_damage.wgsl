// The damage pass of a hex8 block's damageable elements, after `hex8_forces` (twin:
// `kernels::hex8_damage`): an element already damaged, or whose elastic strain energy
// passes its sieve, takes its points' step, and its forces replace the elastic ones. One
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
// include: damage_hex

@compute @workgroup_size(64)
fn hex8_damage(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = item_index(gid, params);
    if (i >= params.count) {
        return;
    }
    let rec = elements[i];
    let h = damage_hex(rec.element);
    if (!damage_passes(i, rec.element, rec, h.u)) {
        return;
    }
    let zero = vec3<f32>(0.0);
    let out = hex_damage_points(i, rec.element, rec, h, HexAmplitudes(zero, zero, zero, zero, zero, zero));
    if (out.store) {
        store_hex(rec.element, out.corners);
    }
}
