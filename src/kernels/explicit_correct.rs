//! Corrector of the explicit step over one body's nodes and the body's history sums per
//! workgroup (CPU twin of `shaders/explicit_correct.wgsl`).
//!
//! For node `first + i`, `i < count`: $a_{n+1} = a_{ext} - f_{int} / m$ per dof (zero inverse
//! mass on prescribed dofs), $v_{n+1} = v_{n+1/2} + \tfrac{\Delta t}{2} a_{n+1}$; `v` holds
//! $v_{n+1/2}$ on entry. Each group of [`GROUP`] nodes gives [`FIELDS`] sums: kinetic
//! $\tfrac12 m v_{n+1/2}^2$, strain $\tfrac12 u_n \cdot f_{int}$ with
//! $u_n = u_{n+1} - \Delta t\, v_{n+1/2}$, gravity $-f_{ext} \cdot (u_n + u_{n+1})/2$, and
//! momentum $m v_{n+1}$ (3).

/// Nodes per workgroup (the WGSL `@workgroup_size`).
pub const GROUP: usize = 64;
/// Sums per workgroup.
pub const FIELDS: usize = 6;

/// Lumped data of one node.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LumpedNode {
    pub mass: f64,
    /// Inverse mass of each dof, zero where prescribed.
    pub inv_mass: [f64; 3],
    /// Body-force acceleration of each dof ($f_{ext}/m$), zero where prescribed.
    pub ext_acc: [f64; 3],
}

#[allow(clippy::too_many_arguments)]
pub fn explicit_correct(
    dt: f64,
    first: usize,
    count: usize,
    u: &[f64],
    forces: &[f64],
    lumped: &[LumpedNode],
    v: &mut [f64],
    a: &mut [f64],
) -> Vec<[f64; FIELDS]> {
    let mut partials = vec![[0.0; FIELDS]; count.div_ceil(GROUP)];
    for i in 0..count {
        let n = first + i;
        let lm = lumped[n];
        let q = &mut partials[i / GROUP];
        for ax in 0..3 {
            let d = 3 * n + ax;
            let vh = v[d];
            let f = forces[d];
            let acc = lm.ext_acc[ax] - f * lm.inv_mass[ax];
            let v1 = vh + 0.5 * dt * acc;
            a[d] = acc;
            v[d] = v1;
            q[0] += 0.5 * lm.mass * vh * vh;
            q[1] += 0.5 * (u[d] - dt * vh) * f;
            q[2] -= lm.mass * lm.ext_acc[ax] * (u[d] - 0.5 * dt * vh);
            q[3 + ax] += lm.mass * v1;
        }
    }
    partials
}
