//! Sparse linear algebra for the implicit solvers: the assembly pattern built once from
//! element connectivities, faer's sparse Cholesky (symbolic analysis once, numeric
//! refactorisation per iteration) and LU, and the Newton driver with load-step cut-back.

pub(crate) mod cholesky;
pub(crate) mod linear_solver;
pub(crate) mod lu;
pub(crate) mod newton;
pub(crate) mod pattern;
pub(crate) mod rows;
pub(crate) mod split;
pub(crate) mod supernodal;

pub use cholesky::{CholeskyKind, FillOrdering, SparseCholesky, NESTED_DISSECTION_FROM};
pub use linear_solver::{LinalgError, LinearSolver};
pub use lu::SparseLu;
pub use newton::{
    solve_load_path, NewtonError, NewtonParams, NewtonStats, NewtonWorkspace, NonlinearProblem,
};
pub use pattern::{Equation, PatternError, SparsePattern, Storage};
pub use split::{GmresParams, SplitSolver, SplitStats};
pub use supernodal::{FactorPrecision, SupernodalSolve};
