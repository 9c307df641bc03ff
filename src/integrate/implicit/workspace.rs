//! The implicit step's working vectors, allocated once per run: nothing in them is carried
//! from one step to the next.

/// Vectors of every dof (`ndof`) or of the free dofs in equation order (`free`).
pub(super) struct Workspace {
    /// Internal forces at the iterate.
    pub(super) f_int: Vec<f64>,
    /// Nodal contact forces of the current multipliers.
    pub(super) f_c: Vec<f64>,
    /// The contact forces of the last solve.
    pub(super) f_last: Vec<f64>,
    /// The last full solve's contact forces and iterate: the base the contact space's
    /// iterations move from ([`super::ImplicitSolver::recover`]).
    pub(super) f_base: Vec<f64>,
    pub(super) u_base: Vec<f64>,
    /// $w = M^{-1} \bar f_c$.
    pub(super) w: Vec<f64>,
    /// The effective equation's right-hand side, then its solution (free dofs).
    pub(super) rhs: Vec<f64>,
    /// The consistent mass solve's right-hand side (free dofs).
    pub(super) tmp: Vec<f64>,
    /// Newmark's predictors.
    pub(super) u_tilde: Vec<f64>,
    pub(super) v_tilde: Vec<f64>,
    /// M (u - u_tilde) and u - u_tilde on the free dofs.
    pub(super) inertia: Vec<f64>,
    pub(super) increment: Vec<f64>,
    /// The iterate: the end-of-step state under the current multipliers.
    pub(super) u_new: Vec<f64>,
    pub(super) v_new: Vec<f64>,
    pub(super) a_new: Vec<f64>,
}

impl Workspace {
    pub(super) fn new(ndof: usize, free: usize) -> Self {
        let zeros = |n| vec![0.0; n];
        Workspace {
            f_int: zeros(ndof),
            f_c: zeros(ndof),
            f_last: zeros(ndof),
            f_base: zeros(ndof),
            u_base: zeros(ndof),
            w: zeros(ndof),
            rhs: zeros(free),
            tmp: zeros(free),
            u_tilde: zeros(ndof),
            v_tilde: zeros(ndof),
            inertia: zeros(free),
            increment: zeros(free),
            u_new: zeros(ndof),
            v_new: zeros(ndof),
            a_new: zeros(ndof),
        }
    }
}
