//! Sparse LU with partial pivoting (faer 0.22) for non-symmetric matrices, such as the full
//! consistent tangent of frictional contact or of beams loaded away from equilibrium.
//!
//! The symbolic analysis (COLAMD column ordering, supernodes) is computed once per pattern
//! ([`Storage::Full`]); each `factorize` recomputes the numeric factors. faer's high-level LU
//! owns its numeric storage, which it reallocates per factorisation and parallelises with
//! faer's global parallelism setting; the symmetric path ([`super::SparseCholesky`]) is the
//! allocation-free one.

use faer::linalg::solvers::SolveCore;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::{Conj, MatMut};

use super::linear_solver::{check_len, LinalgError, LinearSolver};
use super::pattern::{SparsePattern, Storage};

/// Sparse LU solver with a cached symbolic factorisation.
#[derive(Debug)]
pub struct SparseLu {
    symbolic: SymbolicLu<usize>,
    numeric: Option<Lu<usize, f64>>,
    size: usize,
    nnz: usize,
}

impl SparseLu {
    /// Symbolic analysis of a full-storage `pattern`.
    pub fn new(pattern: &SparsePattern) -> Result<Self, LinalgError> {
        if pattern.storage() != Storage::Full {
            return Err(LinalgError::WrongStorage {
                expected: Storage::Full,
                found: pattern.storage(),
            });
        }
        let symbolic =
            SymbolicLu::try_new(pattern.symbolic()).map_err(|e| LinalgError::Backend {
                reason: format!("{e:?}"),
            })?;
        Ok(Self {
            symbolic,
            numeric: None,
            size: pattern.size(),
            nnz: pattern.nnz(),
        })
    }
}

impl LinearSolver for SparseLu {
    fn factorize(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), LinalgError> {
        check_len("matrix values", self.nnz, values.len())?;
        check_len("pattern size", self.size, pattern.size())?;
        self.numeric = None;
        let lu = Lu::try_new_with_symbolic(self.symbolic.clone(), pattern.matrix(values)).map_err(
            |e| match e {
                faer::sparse::linalg::LuError::SymbolicSingular { index } => {
                    LinalgError::Singular { index }
                }
                other => LinalgError::Backend {
                    reason: format!("{other:?}"),
                },
            },
        )?;
        self.numeric = Some(lu);
        Ok(())
    }

    fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        check_len("right-hand side", self.size, rhs.len())?;
        let lu = self.numeric.as_ref().ok_or(LinalgError::NotFactorized)?;
        let n = rhs.len();
        lu.solve_in_place_with_conj(Conj::No, MatMut::from_column_major_slice_mut(rhs, n, 1));
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(LinalgError::Singular { index: 0 });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::pattern::Equation;

    #[test]
    fn lu_solves_a_nonsymmetric_convection_diffusion_chain() {
        let n = 150;
        let elements: Vec<Vec<Equation>> = (1..n)
            .map(|i| vec![Equation::free(i - 1).unwrap(), Equation::free(i).unwrap()])
            .collect();
        let p = SparsePattern::new(n, Storage::Full, &elements).unwrap();
        let mut values = vec![0.0; p.nnz()];
        for e in 0..elements.len() {
            // diffusion 2, upwinded convection 0.7: column-major [[2.7, -2], [-2.7, 2]] + ground
            p.add_element_matrix(&mut values, e, &[2.7, -2.7, -2.0, 2.0]);
        }
        let diag: Vec<usize> = (0..n)
            .map(|c| {
                p.col_ptr()[c]
                    + p.row_idx()[p.col_ptr()[c]..p.col_ptr()[c + 1]]
                        .iter()
                        .position(|&r| r == c)
                        .unwrap()
            })
            .collect();
        for &k in &diag {
            values[k] += 0.1;
        }
        let mut solver = SparseLu::new(&p).unwrap();
        solver.factorize(&p, &values).unwrap();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        let mut ax = vec![0.0; n];
        p.mul_vec(&values, &x, &mut ax);
        let err = ax
            .iter()
            .zip(&b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-10, "{err}");
    }
}
