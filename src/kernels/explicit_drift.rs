//! Position update of the explicit step, $u_{n+1} = u_n + \Delta t\, v_{n+1/2}$ (CPU twin of
//! `shaders/explicit_drift.wgsl`, which keeps u as a split f32 pair added by two-sum).

pub fn explicit_drift(dt: f64, v: &[f64], u: &mut [f64]) {
    for (u, v) in u.iter_mut().zip(v) {
        *u += dt * v;
    }
}
