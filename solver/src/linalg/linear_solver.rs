//! The linear-solver interface the Newton driver calls, and its errors.
//!
//! A solver is created once for a [`SparsePattern`] (symbolic analysis, fill-reducing
//! ordering), then factorises new values of that same pattern as often as needed and solves
//! with the last factorisation. Implementations: [`super::SparseCholesky`] (symmetric,
//! LLᵀ / LDLᵀ) and [`super::SparseLu`] (general).

use thiserror::Error;

use super::pattern::{SparsePattern, Storage};

/// Errors of the sparse direct solvers.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinalgError {
    /// The pattern stores the wrong part of the matrix for this solver.
    #[error("solver needs {expected:?} storage, pattern has {found:?}")]
    WrongStorage {
        /// Storage the solver needs.
        expected: Storage,
        /// Storage of the pattern given.
        found: Storage,
    },
    /// A vector or value array has the wrong length.
    #[error("{what}: length {found}, expected {expected}")]
    SizeMismatch {
        /// Which array.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// Cholesky met a non-positive pivot (matrix not positive definite, e.g. past a limit
    /// point) or LDLᵀ a zero pivot; `index` is in the permuted ordering.
    #[error(
        "factorisation broke down at pivot {index} (matrix not positive definite or singular)"
    )]
    BadPivot {
        /// Pivot position.
        index: usize,
    },
    /// LU found the structure rank-deficient.
    #[error("matrix structurally singular at pivot {index}")]
    Singular {
        /// Pivot position.
        index: usize,
    },
    /// `solve` called before a successful `factorize`.
    #[error("solve called without a valid factorisation")]
    NotFactorized,
    /// Any other failure reported by faer (allocation, index overflow).
    #[error("sparse solver failure: {reason}")]
    Backend {
        /// faer's description.
        reason: String,
    },
}

/// A direct solver that factorises values on a fixed pattern.
pub trait LinearSolver {
    /// Numeric factorisation of `values` (laid out on `pattern`, the pattern the solver was
    /// built for).
    fn factorize(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), LinalgError>;
    /// As [`Self::factorize`], with a symmetric surrogate of the matrix (values on the same
    /// pattern) that a preconditioned iterative solver may factorise instead of the matrix's
    /// own symmetric part; direct solvers ignore it.
    fn factorize_preconditioned(
        &mut self,
        pattern: &SparsePattern,
        values: &[f64],
        surrogate: Option<&[f64]>,
    ) -> Result<(), LinalgError> {
        let _ = surrogate;
        self.factorize(pattern, values)
    }
    /// Overwrites `rhs` with A⁻¹ rhs using the last factorisation.
    fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError>;
    /// Relative residual ‖b − A x‖ / ‖b‖ the next solves may leave (an inexact Newton method's
    /// forcing term); iterative solvers use the larger of this and their own tolerance, direct
    /// solvers ignore it. `None` restores the solver's own tolerance.
    fn set_forcing(&mut self, relative_residual: Option<f64>) {
        let _ = relative_residual;
    }
}

pub(crate) fn check_len(
    what: &'static str,
    expected: usize,
    found: usize,
) -> Result<(), LinalgError> {
    if expected == found {
        Ok(())
    } else {
        Err(LinalgError::SizeMismatch {
            what,
            expected,
            found,
        })
    }
}
