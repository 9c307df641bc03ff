// Each bonded pair's step of the resident explicit path, one pair per invocation (twin:
// `kernels::cohesive_pairs`; the law's: `material::CohesiveLaw`): the separation, the upper
// node's displacement less the lower's, opens the pair along its normal and slides it
// across; the mixed-mode bilinear law with the BK toughness gives the traction, the damage
// (never less than before) and the energy dissipated, and where the law has friction the
// damaged share's Coulomb friction where the faces press. Writes the pair's force (area
// times traction, on the upper node), its area times the step's dissipation and times its
// stored-energy offset, and where Params.aux is 1 its damage and slip.

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> displacement: array<Split3>;
@group(0) @binding(2) var<storage, read> laws: array<CohesiveLaw>;
@group(0) @binding(3) var<storage, read> pairs: array<CohesivePair>;
@group(0) @binding(4) var<storage, read_write> state: array<PairState>;
@group(0) @binding(5) var<storage, read_write> outputs: array<PairOutput>;

// The onset and final separations and the toughness at mixity b: (l0, lf, Gc).
fn envelope(l: CohesiveLaw, b: f32) -> vec3<f32> {
    let dn = l.strength_n / l.stiffness;
    let ds = l.strength_s / l.stiffness;
    let w = select(0.0, pow(b, l.bk), b > 0.0);
    let l0 = sqrt(dn * dn + (ds * ds - dn * dn) * w);
    let gc = l.toughness_i + (l.toughness_ii - l.toughness_i) * w;
    return vec3<f32>(l0, 2.0 * gc / (l.stiffness * l0), gc);
}

// The energy per area dissipated from damage d_old to d along envelope e: the twin's
// difference Gc (r(d) - r(d_old)) / (lf - l0), r(d) = lf l0 / (lf - d (lf - l0)), in the form
// that keeps f32's digits for small steps.
fn dissipated_between(e: vec3<f32>, d_old: f32, d: f32) -> f32 {
    let span = e.y - e.x;
    let a = e.y - d_old * span;
    let b = e.y - d * span;
    return e.z * e.y * e.x * (d - d_old) / (a * b);
}

@compute @workgroup_size(64)
fn cohesive_pairs(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = item_index(gid, params);
    if (p >= params.count) {
        return;
    }
    let pair = pairs[p];
    let l = laws[pair.law];
    let s = state[p];
    let n = vec3_of(pair.normal);
    let delta = split_difference(displacement[pair.upper], displacement[pair.lower]);
    let dn = dot(delta, n);
    let ds = delta - dn * n;
    let open = max(dn, 0.0);
    let slide2 = dot(ds, ds);
    let lambda2 = open * open + slide2;
    let b = select(0.0, slide2 / lambda2, lambda2 > 0.0);
    let e = envelope(l, b);
    let lambda = sqrt(lambda2);
    var d_now = 0.0;
    if (lambda > e.x) {
        d_now = min(e.y * (lambda - e.x) / (lambda * (e.y - e.x)), 1.0);
    }
    let d_old = s.damage;
    let d = max(d_old, d_now);
    var dissipated = 0.0;
    if (d > d_old) {
        dissipated = dissipated_between(e, d_old, d);
    }
    let k = l.stiffness;
    var t = (1.0 - d) * k * (open * n + ds) + k * min(dn, 0.0) * n;
    // the damaged share's friction where the faces press (apart or bonded, the slip
    // follows the slide)
    var slip = vec3<f32>(0.0);
    var offset = 0.0;
    if (l.friction > 0.0) {
        slip = ds;
        let limit = l.friction * k * max(-dn, 0.0);
        if (limit > 0.0 && d > 0.0) {
            let old = vec3_of(s.slip);
            let trial = k * (ds - old);
            let size = length(trial);
            var tf = trial;
            slip = old;
            if (size > limit) {
                tf = trial * (limit / size);
                slip = ds - tf / k;
            }
            let stretch = ds - slip;
            dissipated += d * dot(tf, slip - old) - 0.5 * (d - d_old) * k * dot(stretch, stretch);
            offset = -0.5 * d * dot(tf, slip);
            t += d * tf;
        }
    }
    outputs[p] = PairOutput(float3(pair.area * t), pair.area * dissipated, pair.area * offset);
    if (params.aux == 1u) {
        state[p] = PairState(d, float3(slip));
    }
}
