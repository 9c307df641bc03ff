//! Predictor of the explicit step, $v^* = v_n + \tfrac{\Delta t}{2} a_n$ per dof (CPU twin of
//! `shaders/explicit_predict.wgsl`).

pub fn explicit_predict(dt: f64, a: &[f64], v: &mut [f64]) {
    for (v, a) in v.iter_mut().zip(a) {
        *v += 0.5 * dt * a;
    }
}
