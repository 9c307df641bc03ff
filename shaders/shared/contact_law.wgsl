// Contact laws as kinds (twin: `contact::law::ContactLaw`): a pair or a plane carries its
// law's number (`LAW_*`, one file `law_<name>.wgsl` each) and its coefficient `mu`.

// A tangential force returned onto a law's set, and whether the trial was inside it.
struct Returned {
    t: vec3<f32>,
    inside: bool,
}

// Whether the law carries a tangential force.
fn law_is_frictional(law: u32) -> bool {
    return law != LAW_FRICTIONLESS;
}

// The trial tangential impulse returned onto the law's set for the normal impulse `jn`.
fn law_returned(law: u32, mu: f32, trial: vec3<f32>, jn: f32) -> Returned {
    switch law {
        case LAW_COULOMB: {
            return coulomb_returned(mu, trial, jn);
        }
        default: {
            return frictionless_returned(trial);
        }
    }
}

// The tangential impulse `t` without its part along the unit normal `n`, returned onto the
// law's set for the normal impulse `jn` (twin: `ContactLaw::projected`).
fn law_projected(law: u32, mu: f32, t: vec3<f32>, n: vec3<f32>, jn: f32) -> vec3<f32> {
    return law_returned(law, mu, t - dot(t, n) * n, jn).t;
}

// Whether a node pressed by `jn` with the tangential impulse `t` slides (its force on the
// law's bound within 1e-6).
fn law_sliding(law: u32, mu: f32, t: vec3<f32>, jn: f32) -> bool {
    switch law {
        case LAW_COULOMB: {
            return coulomb_sliding(mu, t, jn);
        }
        default: {
            return false;
        }
    }
}
