//! Sparse Cholesky (LLᵀ or LDLᵀ) of a symmetric matrix with faer 0.22: the symbolic
//! factorisation, including the fill-reducing ordering, is computed once per pattern; each
//! `factorize` refills the numeric factor in place, with no allocation (the factor values and
//! the scratch memory are owned by the solver).
//!
//! Ordering ([`FillOrdering`]): approximate minimum degree (faer's AMD) for small matrices,
//! nested dissection (METIS, [`moorfret_ordering`]) from [`NESTED_DISSECTION_FROM`] equations
//! on. On the six-layer strand's LDLᵀ (89 928 equations) nested dissection leaves 27 M factor
//! entries instead of AMD's 43 M, and the factorisation and the solves are faster in
//! proportion (README, "Strand solver"); on small matrices AMD is as good and cheaper to
//! compute.
//!
//! Only the upper triangle is read ([`Storage::Upper`]). faer picks a simplicial or a
//! supernodal factorisation from the flop count of the symbolic analysis. Parallelism is the
//! `Par` given at construction (`Par::Seq` for one thread).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::{Conj, MatMut, Par, Side};

use super::linear_solver::{check_len, LinalgError, LinearSolver};
use super::pattern::{SparsePattern, Storage};
use super::supernodal::{FactorPrecision, SupernodalSolve};

/// Which symmetric factorisation to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CholeskyKind {
    /// LLᵀ: positive definite matrices only (fails at the first non-positive pivot).
    #[default]
    Llt,
    /// LDLᵀ without pivoting: also symmetric indefinite matrices with nonzero pivots.
    Ldlt,
}

/// Fill-reducing ordering of the symbolic factorisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FillOrdering {
    /// Nested dissection from [`NESTED_DISSECTION_FROM`] equations on, AMD below.
    #[default]
    Auto,
    /// Approximate minimum degree (faer).
    Amd,
    /// Nested dissection of the node graph (METIS).
    NestedDissection,
}

/// Size from which [`FillOrdering::Auto`] takes nested dissection.
pub const NESTED_DISSECTION_FROM: usize = 20_000;

/// Sparse Cholesky solver with a cached symbolic factorisation.
pub struct SparseCholesky {
    kind: CholeskyKind,
    pub(super) symbolic: SymbolicCholesky<usize>,
    pub(super) factor_values: Vec<f64>,
    scratch: MemBuffer,
    par: Par,
    size: usize,
    nnz: usize,
    factorized: bool,
    /// Solves split over the elimination tree ([`Self::use_tree_solve`]).
    tree: Option<SupernodalSolve>,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("kind", &self.kind)
            .field("size", &self.size)
            .field("nnz", &self.nnz)
            .field("factor_len", &self.factor_values.len())
            .field("factorized", &self.factorized)
            .finish()
    }
}

impl SparseCholesky {
    /// Symbolic analysis (ordering [`FillOrdering::Auto`], elimination tree, supernodes) of
    /// `pattern`.
    pub fn new(pattern: &SparsePattern, kind: CholeskyKind, par: Par) -> Result<Self, LinalgError> {
        Self::with_ordering(pattern, kind, par, FillOrdering::Auto)
    }

    /// [`Self::new`] with the given fill-reducing ordering.
    pub fn with_ordering(
        pattern: &SparsePattern,
        kind: CholeskyKind,
        par: Par,
        ordering: FillOrdering,
    ) -> Result<Self, LinalgError> {
        if pattern.storage() != Storage::Upper {
            return Err(LinalgError::WrongStorage {
                expected: Storage::Upper,
                found: pattern.storage(),
            });
        }
        let nested = match ordering {
            FillOrdering::Auto => pattern.size() >= NESTED_DISSECTION_FROM,
            FillOrdering::Amd => false,
            FillOrdering::NestedDissection => true,
        };
        let nd = if nested {
            Some(
                moorfret_ordering::nested_dissection(
                    pattern.size(),
                    pattern.col_ptr(),
                    pattern.row_idx(),
                )
                .map_err(backend)?,
            )
        } else {
            None
        };
        let order = match &nd {
            Some(o) => SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(
                &o.perm,
                &o.inverse,
                pattern.size(),
            )),
            None => SymmetricOrdering::Amd,
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern.symbolic(), Side::Upper, order, Default::default())
                .map_err(backend)?;
        let factor_req = match kind {
            CholeskyKind::Llt => {
                symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default())
            }
            CholeskyKind::Ldlt => {
                symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
            }
        };
        let req = StackReq::or(factor_req, symbolic.solve_in_place_scratch::<f64>(1, par));
        let scratch = MemBuffer::try_new(req).map_err(|_| LinalgError::Backend {
            reason: "out of memory for the factorisation scratch".into(),
        })?;
        let factor_values = vec![0.0; symbolic.len_val()];
        Ok(Self {
            kind,
            symbolic,
            factor_values,
            scratch,
            par,
            size: pattern.size(),
            nnz: pattern.nnz(),
            factorized: false,
            tree: None,
        })
    }

    /// Solves with the factor split over the elimination tree ([`SupernodalSolve`]: its two
    /// halves on two threads when the parallelism allows, the values in `precision`) instead
    /// of faer's sequential supernodal solve. Only for a supernodal LDLᵀ; returns whether it
    /// is used.
    pub fn use_tree_solve(&mut self, precision: FactorPrecision) -> bool {
        self.tree = match self.kind {
            CholeskyKind::Ldlt => SupernodalSolve::new(&self.symbolic, precision),
            CholeskyKind::Llt => None,
        };
        if let (Some(tree), true) = (&mut self.tree, self.factorized) {
            tree.load(&self.factor_values);
        }
        self.tree.is_some()
    }

    /// Floating-point operations of the numeric factorisation and of one solve
    /// (`SupernodalSolve::flops`), when the tree solve is used.
    pub fn tree_flops(&self) -> Option<(f64, f64)> {
        self.tree.as_ref().map(SupernodalSolve::flops)
    }

    /// Share of the factor solved on one thread by the tree solve (its top separators).
    pub fn tree_top_share(&self) -> Option<f64> {
        self.tree.as_ref().map(SupernodalSolve::top_share)
    }

    /// Number of stored values of the factor (a measure of fill-in).
    pub fn factor_len(&self) -> usize {
        self.factor_values.len()
    }

    /// Whether faer chose the supernodal (dense-block) factorisation.
    pub fn is_supernodal(&self) -> bool {
        matches!(
            self.symbolic.raw(),
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(_)
        )
    }
}

impl LinearSolver for SparseCholesky {
    fn factorize(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), LinalgError> {
        check_len("matrix values", self.nnz, values.len())?;
        check_len("pattern size", self.size, pattern.size())?;
        self.factorized = false;
        let a = pattern.matrix(values);
        let stack = MemStack::new(&mut self.scratch);
        match self.kind {
            CholeskyKind::Llt => {
                self.symbolic
                    .factorize_numeric_llt(
                        &mut self.factor_values,
                        a,
                        Side::Upper,
                        Default::default(),
                        self.par,
                        stack,
                        Default::default(),
                    )
                    .map_err(|e| match e {
                        faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot {
                            index,
                        } => LinalgError::BadPivot { index },
                    })?;
            }
            CholeskyKind::Ldlt => {
                self.symbolic
                    .factorize_numeric_ldlt(
                        &mut self.factor_values,
                        a,
                        Side::Upper,
                        Default::default(),
                        self.par,
                        stack,
                        Default::default(),
                    )
                    .map_err(|e| match e {
                        faer::linalg::cholesky::ldlt::factor::LdltError::ZeroPivot { index } => {
                            LinalgError::BadPivot { index }
                        }
                    })?;
            }
        }
        if self.factor_values.iter().any(|v| !v.is_finite()) {
            return Err(LinalgError::BadPivot { index: 0 });
        }
        if let Some(tree) = &mut self.tree {
            tree.load(&self.factor_values);
        }
        self.factorized = true;
        Ok(())
    }

    fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        check_len("right-hand side", self.size, rhs.len())?;
        if !self.factorized {
            return Err(LinalgError::NotFactorized);
        }
        if let Some(tree) = &mut self.tree {
            tree.solve_in_place(rhs, !matches!(self.par, Par::Seq));
            return Ok(());
        }
        let n = rhs.len();
        let b = MatMut::from_column_major_slice_mut(rhs, n, 1);
        let stack = MemStack::new(&mut self.scratch);
        match self.kind {
            CholeskyKind::Llt => LltRef::new(&self.symbolic, &self.factor_values)
                .solve_in_place_with_conj(Conj::No, b, self.par, stack),
            CholeskyKind::Ldlt => LdltRef::new(&self.symbolic, &self.factor_values)
                .solve_in_place_with_conj(Conj::No, b, self.par, stack),
        }
        Ok(())
    }
}

fn backend(e: impl std::fmt::Debug) -> LinalgError {
    LinalgError::Backend {
        reason: format!("{e:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::pattern::Equation;

    /// Chain of n springs k = 1 + i between equations, grounded at the left end.
    fn chain(n: usize, storage: Storage) -> (SparsePattern, Vec<f64>) {
        let mut elements = vec![vec![Equation::CONSTRAINED, Equation::free(0).unwrap()]];
        for i in 1..n {
            elements.push(vec![
                Equation::free(i - 1).unwrap(),
                Equation::free(i).unwrap(),
            ]);
        }
        let p = SparsePattern::new(n, storage, &elements).unwrap();
        let mut values = vec![0.0; p.nnz()];
        for (e, _) in elements.iter().enumerate() {
            let k = 1.0 + e as f64;
            p.add_element_matrix(&mut values, e, &[k, -k, -k, k]);
        }
        (p, values)
    }

    #[test]
    fn both_kinds_solve_a_spring_chain_to_round_off() {
        for kind in [CholeskyKind::Llt, CholeskyKind::Ldlt] {
            let (p, values) = chain(200, Storage::Upper);
            let mut solver = SparseCholesky::new(&p, kind, Par::Seq).unwrap();
            let b: Vec<f64> = (0..200).map(|i| (i as f64 * 0.37).sin()).collect();
            // refactorising the same pattern twice must give the same answer
            for _ in 0..2 {
                solver.factorize(&p, &values).unwrap();
                let mut x = b.clone();
                solver.solve_in_place(&mut x).unwrap();
                let mut ax = vec![0.0; 200];
                p.mul_vec(&values, &x, &mut ax);
                let err = ax
                    .iter()
                    .zip(&b)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(err < 1e-10, "{kind:?}: {err}");
            }
        }
    }

    #[test]
    fn every_ordering_solves_the_same_system() {
        let (p, values) = chain(300, Storage::Upper);
        let b: Vec<f64> = (0..300).map(|i| (i as f64 * 0.11).cos()).collect();
        let mut solutions = Vec::new();
        for ordering in [FillOrdering::Amd, FillOrdering::NestedDissection] {
            let mut solver =
                SparseCholesky::with_ordering(&p, CholeskyKind::Ldlt, Par::Seq, ordering).unwrap();
            solver.factorize(&p, &values).unwrap();
            let mut x = b.clone();
            solver.solve_in_place(&mut x).unwrap();
            solutions.push(x);
        }
        let diff = solutions[0]
            .iter()
            .zip(&solutions[1])
            .map(|(a, b)| (a - b).abs() / a.abs().max(1.0))
            .fold(0.0, f64::max);
        assert!(diff < 1e-9, "{diff}");
    }

    #[test]
    fn indefinite_matrix_is_a_bad_pivot_for_llt() {
        let (p, mut values) = chain(10, Storage::Upper);
        values.iter_mut().for_each(|v| *v = -*v);
        let mut solver = SparseCholesky::new(&p, CholeskyKind::Llt, Par::Seq).unwrap();
        assert!(matches!(
            solver.factorize(&p, &values),
            Err(LinalgError::BadPivot { .. })
        ));
        let mut x = vec![1.0; 10];
        assert_eq!(
            solver.solve_in_place(&mut x),
            Err(LinalgError::NotFactorized)
        );
    }

    #[test]
    fn full_storage_is_refused() {
        let (p, _) = chain(4, Storage::Full);
        assert!(matches!(
            SparseCholesky::new(&p, CholeskyKind::Llt, Par::Seq),
            Err(LinalgError::WrongStorage { .. })
        ));
    }
}
