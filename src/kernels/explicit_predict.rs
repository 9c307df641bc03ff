//! Predictor of the explicit step, $v^* = v_n + \tfrac{\Delta t}{2} a_n$ per dof (CPU twin of
//! `shaders/explicit_predict.wgsl`).

pub fn explicit_predict(dt: f64, a: &[f64], v: &mut [f64]) {
    use rayon::prelude::*;
    v.par_iter_mut()
        .with_min_len(crate::parallel::CHUNK)
        .zip(a)
        .for_each(|(v, a)| *v += 0.5 * dt * a);
}
