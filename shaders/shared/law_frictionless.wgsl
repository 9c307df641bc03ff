// Frictionless contact (twin: `contact::law::frictionless`): no tangential force; only a zero
// trial is inside the law's set.

const LAW_FRICTIONLESS: u32 = 0u;

fn frictionless_returned(trial: vec3<f32>) -> Returned {
    return Returned(vec3<f32>(0.0), all(trial == vec3<f32>(0.0)));
}
