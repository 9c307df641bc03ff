// Coulomb friction (twin: `contact::law::coulomb`): a tangential force up to mu times the
// normal one; a trial outside the cone is scaled back onto it, and a pressed node on the
// cone slides.

const LAW_COULOMB: u32 = 1u;

fn coulomb_returned(mu: f32, trial: vec3<f32>, jn: f32) -> Returned {
    let radius = mu * jn;
    let size = length(trial);
    if (size > radius) {
        return Returned(trial * (radius / size), false);
    }
    return Returned(trial, true);
}

fn coulomb_sliding(mu: f32, t: vec3<f32>, jn: f32) -> bool {
    return mu > 0.0 && jn > 0.0 && length(t) >= mu * jn * (1.0 - 1e-6);
}
