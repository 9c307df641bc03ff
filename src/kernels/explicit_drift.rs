//! Position update of the explicit step, $u_{n+1} = u_n + \Delta t\, v_{n+1/2}$ (CPU twin of
//! `shaders/explicit_drift.wgsl`, which keeps u as a split f32 pair added by two-sum).

pub fn explicit_drift(dt: f64, v: &[f64], u: &mut [f64]) {
    use rayon::prelude::*;
    u.par_iter_mut()
        .with_min_len(crate::parallel::CHUNK)
        .zip(v)
        .for_each(|(u, v)| *u += dt * v);
}
