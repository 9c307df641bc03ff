// included by the damage kernels (`hex8_damage`, `hex8i_damage`, `tet4_damage`), which bind
// `params` (count: the damageable elements; aux, aux2: the corner slots as `store_corner`
// takes them), the uniform `damage`, `velocity`, `state`, `records` and `corner_forces`.

// No damaged point yet.
const NO_POINT: u32 = 0xffffffffu;

// Word f of damageable element i's record (flag, first step, first point, dissipation,
// the fibre modes' share of it).
fn record_at(i: u32, f: u32) -> u32 {
    return damage.records + DAMAGE_RECORD * i + f;
}

// Damageable element i's dissipation over the step and the fibre modes' share of it.
fn store_dissipation(i: u32, total: f32, fibre: f32) {
    records[record_at(i, 3u)] = bitcast<u32>(total);
    records[record_at(i, 4u)] = bitcast<u32>(fibre);
}

fn node_velocity(n: u32) -> vec3<f32> {
    return vec3<f32>(velocity[3u * n], velocity[3u * n + 1u], velocity[3u * n + 2u]);
}

// Corner k's elastic force of block slot `slot` (as `store_corner` wrote it).
fn load_corner(slot: u32) -> vec3<f32> {
    let c = params.aux;
    let s = params.aux2 + slot;
    return vec3<f32>(corner_forces[s], corner_forces[c + s], corner_forces[2u * c + s]);
}

// The outer product a b^T (column j: a b_j).
fn damage_outer(a: vec3<f32>, b: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(a * b.x, a * b.y, a * b.z);
}

// A point's state at state[POINT_STATE p ..].
fn load_point(p: u32) -> PointState {
    let s = POINT_STATE * p;
    return PointState(
        vec4<f32>(state[s], state[s + 1u], state[s + 2u], state[s + 3u]),
        vec4<f32>(state[s + 4u], state[s + 5u], state[s + 6u], state[s + 7u]),
    );
}

fn store_point(p: u32, st: PointState) {
    let s = POINT_STATE * p;
    state[s] = st.inviscid.x;
    state[s + 1u] = st.inviscid.y;
    state[s + 2u] = st.inviscid.z;
    state[s + 3u] = st.inviscid.w;
    state[s + 4u] = st.acting.x;
    state[s + 5u] = st.acting.y;
    state[s + 6u] = st.acting.z;
    state[s + 7u] = st.acting.w;
}

// The mode with the most damage in `v` (the lowest on a tie).
fn largest_mode(v: vec4<f32>) -> u32 {
    var m = 0u;
    var best = v.x;
    if (v.y > best) {
        m = 1u;
        best = v.y;
    }
    if (v.z > best) {
        m = 2u;
        best = v.z;
    }
    if (v.w > best) {
        m = 3u;
    }
    return m;
}

fn point_damaged(st: PointState) -> bool {
    return any(st.inviscid > vec4<f32>(0.0)) || any(st.acting > vec4<f32>(0.0));
}
