//! Solver for nearly symmetric matrices A = S + N, with S = (A + Aᵀ)/2 the symmetric part and
//! N the skew part: the LDLᵀ factorisation of S, or of a symmetric surrogate of A that the
//! problem assembles ([`LinearSolver::factorize_preconditioned`]; faer, approximate minimum
//! degree ordering) preconditions restarted GMRES on A itself (right preconditioning, Saad 2003, *Iterative
//! Methods for Sparse Linear Systems*, Alg. 9.5). The solution therefore is that of A, to the
//! GMRES tolerance, not of S.
//!
//! This is the solver of the frictional strand tangents: contact friction and the follower terms
//! of the corotational beams make them non-symmetric, but only mildly so, and their LDLᵀ costs a
//! small fraction of a sparse LU with partial pivoting (1+6+1 strand, 2 226 equations: 0.7 ms
//! against 40 ms for faer's LU, `studies/src/bin/linear_solver_study.rs`). When S cannot be
//! factorised (a zero pivot) or GMRES does not reach its tolerance, the solve falls back to
//! faer's sparse LU of A, built on first need, and the next few solves go straight to it. That
//! happens when many contacts slide: the friction–normal coupling μ ∂f_N/∂g_N of a sliding
//! contact is not symmetric and the symmetric part is then a poor (indefinite) approximation
//! (1+6+1 strand at κ = 1 1/m with μ = 0.5: GMRES stalls near 1e-3).

use faer::Par;

use super::cholesky::{CholeskyKind, SparseCholesky};
use super::linear_solver::{check_len, LinalgError, LinearSolver};
use super::lu::SparseLu;
use super::pattern::{SparsePattern, Storage};
use super::rows::RowMajor;
use super::supernodal::FactorPrecision;

/// GMRES settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GmresParams {
    /// Converged when ‖b − A x‖ ≤ this × ‖b‖.
    pub relative_tolerance: f64,
    /// Krylov vectors kept before a restart.
    pub restart: usize,
    /// Total GMRES iterations allowed before the LU fallback.
    pub max_iterations: usize,
    /// After a solve fell back to LU, this many further solves go straight to LU (their
    /// matrices, from the next Newton iterations, are alike).
    pub lu_streak: usize,
    /// Preconditioner reuse: a new matrix keeps the LDLᵀ factorisation of an earlier one as
    /// long as the last solve needed at most this many GMRES iterations more than the first
    /// solve after that factorisation (`None`: factorise every matrix). GMRES still solves the
    /// new matrix to its tolerance; only the preconditioner is older. A solve with the older
    /// preconditioner gets that many iterations at most before the preconditioner is refreshed,
    /// and after such a refresh the next 2, 4, 8, … matrices (doubling with every consecutive
    /// refresh, at most 64) are factorised afresh: while the tangent changes fast (contacts
    /// switching in the first iterations of a step) the reuse attempts cost more than they save.
    pub reuse_margin: Option<usize>,
    /// Precision in which the LDLᵀ factor is applied (its solves split over the elimination
    /// tree, [`crate::linalg::SupernodalSolve`], when faer's factor is supernodal).
    pub preconditioner_precision: FactorPrecision,
}

impl Default for GmresParams {
    fn default() -> Self {
        Self {
            relative_tolerance: 1e-10,
            restart: 60,
            max_iterations: 60,
            lu_streak: 3,
            reuse_margin: None,
            preconditioner_precision: FactorPrecision::Double,
        }
    }
}

/// Work counts of the solver.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SplitStats {
    /// Solves done by GMRES.
    pub solves: usize,
    /// GMRES iterations in all.
    pub iterations: usize,
    /// Solves that fell back to LU.
    pub lu_fallbacks: usize,
    /// LDLᵀ factorisations of the preconditioner.
    pub factorisations: usize,
    /// Matrices solved with the preconditioner of an earlier one.
    pub reuses: usize,
    /// Solves whose older preconditioner ran out of iterations and was refreshed.
    pub refreshes: usize,
}

impl std::ops::Add for SplitStats {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        Self {
            solves: self.solves + other.solves,
            iterations: self.iterations + other.iterations,
            lu_fallbacks: self.lu_fallbacks + other.lu_fallbacks,
            factorisations: self.factorisations + other.factorisations,
            reuses: self.reuses + other.reuses,
            refreshes: self.refreshes + other.refreshes,
        }
    }
}

/// LDLᵀ of the symmetric part as preconditioner of GMRES on the full matrix.
#[derive(Debug)]
pub struct SplitSolver {
    upper: SparsePattern,
    /// Upper nonzero of every nonzero of the full pattern.
    to_upper: Vec<usize>,
    /// Whether the full nonzero is on the diagonal.
    diagonal: Vec<bool>,
    ldlt: SparseCholesky,
    symmetric: Vec<f64>,
    /// Values of A at the last factorisation (for the LU fallback).
    values: Vec<f64>,
    /// The same by rows, for the products A z.
    rows: RowMajor,
    /// Whether the products run on two threads.
    parallel: bool,
    full: SparsePattern,
    params: GmresParams,
    lu: Option<SparseLu>,
    /// Whether the last factorisation of S succeeded (otherwise solves go to LU).
    ldlt_ok: bool,
    /// Whether the factorisation is of the current surrogate (not of an earlier matrix's).
    ldlt_current: bool,
    /// GMRES iterations of the first solve after the factorisation, and of the last solve.
    fresh_iterations: Option<usize>,
    last_iterations: usize,
    lu_current: bool,
    /// Solves still to go straight to LU.
    skip_gmres: usize,
    /// Looser relative tolerance asked for by the caller ([`LinearSolver::set_forcing`]).
    forcing: Option<f64>,
    /// Matrices still to be factorised afresh after a refresh, and consecutive refreshes.
    reuse_backoff: usize,
    refresh_streak: u32,
    stats: SplitStats,
    // GMRES workspace: the Krylov basis v_k and the preconditioned vectors z_k = M⁻¹ v_k
    basis: Vec<Vec<f64>>,
    preconditioned: Vec<Vec<f64>>,
    hessenberg: Vec<Vec<f64>>,
    product: Vec<f64>,
}

impl SplitSolver {
    /// Symbolic analysis of the symmetric part of a full-storage `pattern`; one thread.
    pub fn new(pattern: &SparsePattern, params: GmresParams) -> Result<Self, LinalgError> {
        Self::with_parallelism(pattern, params, Par::Seq)
    }

    /// [`Self::new`] with the LDLᵀ factorisation and solves run on `par` (e.g.
    /// `Par::rayon(2)`).
    pub(crate) fn with_parallelism(
        pattern: &SparsePattern,
        params: GmresParams,
        par: Par,
    ) -> Result<Self, LinalgError> {
        if pattern.storage() != Storage::Full {
            return Err(LinalgError::WrongStorage {
                expected: Storage::Full,
                found: pattern.storage(),
            });
        }
        let (upper, to_upper) = pattern.symmetric_upper();
        let mut diagonal = Vec::with_capacity(pattern.nnz());
        for col in 0..pattern.size() {
            let range = pattern.col_ptr()[col]..pattern.col_ptr()[col + 1];
            diagonal.extend(pattern.row_idx()[range].iter().map(|&row| row == col));
        }
        let mut ldlt = SparseCholesky::new(&upper, CholeskyKind::Ldlt, par)?;
        ldlt.use_tree_solve(params.preconditioner_precision);
        let n = pattern.size();
        let m = params.restart.max(1);
        Ok(Self {
            symmetric: vec![0.0; upper.nnz()],
            upper,
            to_upper,
            diagonal,
            ldlt,
            values: vec![0.0; pattern.nnz()],
            rows: RowMajor::new(pattern),
            parallel: !matches!(par, Par::Seq),
            full: pattern.clone(),
            params,
            lu: None,
            ldlt_ok: false,
            ldlt_current: false,
            fresh_iterations: None,
            last_iterations: 0,
            lu_current: false,
            skip_gmres: 0,
            forcing: None,
            reuse_backoff: 0,
            refresh_streak: 0,
            stats: SplitStats::default(),
            basis: vec![vec![0.0; n]; m + 1],
            preconditioned: vec![vec![0.0; n]; m],
            hessenberg: vec![vec![0.0; m + 1]; m],
            product: vec![0.0; n],
        })
    }

    /// Work counts so far.
    pub fn stats(&self) -> SplitStats {
        self.stats
    }

    /// Forgets every factorisation and the reuse and fallback history, as in a new solver:
    /// the next matrix is factorised afresh. A run resumed from a checkpoint with a new solver
    /// repeats the uninterrupted run to the bit when that run resets its solver at the same
    /// point.
    pub(crate) fn reset(&mut self) {
        self.ldlt_ok = false;
        self.ldlt_current = false;
        self.fresh_iterations = None;
        self.last_iterations = 0;
        self.lu_current = false;
        self.skip_gmres = 0;
        self.reuse_backoff = 0;
        self.refresh_streak = 0;
    }

    fn lu_solve(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        if self.lu.is_none() {
            self.lu = Some(SparseLu::new(&self.full)?);
        }
        let lu = self.lu.as_mut().expect("created above");
        if !self.lu_current {
            lu.factorize(&self.full, &self.values)?;
            self.lu_current = true;
        }
        self.stats.lu_fallbacks += 1;
        lu.solve_in_place(rhs)
    }

    /// LDLᵀ of the current symmetric surrogate.
    fn refactorize(&mut self) -> Result<(), LinalgError> {
        self.stats.factorisations += 1;
        self.fresh_iterations = None;
        self.ldlt_current = true;
        self.ldlt_ok = match self.ldlt.factorize(&self.upper, &self.symmetric) {
            Ok(()) => true,
            Err(LinalgError::BadPivot { .. }) => false,
            Err(e) => return Err(e),
        };
        Ok(())
    }

    /// GMRES on `rhs` (a copy of which is in `b`) with at most `max_iterations`, counting its
    /// iterations; false when it did not converge, with `rhs` restored.
    fn try_gmres(
        &mut self,
        rhs: &mut [f64],
        b: &[f64],
        max_iterations: usize,
    ) -> Result<bool, LinalgError> {
        let before = self.stats.iterations;
        self.stats.solves += 1;
        let converged = self.gmres(rhs, max_iterations)? && rhs.iter().all(|v| v.is_finite());
        self.last_iterations = self.stats.iterations - before;
        tracing::trace!(
            iterations = self.last_iterations,
            converged,
            fresh_preconditioner = self.fresh_iterations.is_none(),
            "GMRES"
        );
        if converged {
            self.fresh_iterations.get_or_insert(self.last_iterations);
        } else {
            rhs.copy_from_slice(b);
        }
        Ok(converged)
    }

    /// Right-preconditioned restarted GMRES from x = 0; returns x in `rhs` when converged.
    fn gmres(&mut self, rhs: &mut [f64], max_iterations: usize) -> Result<bool, LinalgError> {
        let n = rhs.len();
        let b_norm = norm(rhs);
        if b_norm == 0.0 {
            return Ok(true);
        }
        let relative = match self.forcing {
            Some(f) => f.max(self.params.relative_tolerance),
            None => self.params.relative_tolerance,
        };
        let tol = relative * b_norm;
        let m = self.params.restart.max(1);
        let mut x = vec![0.0; n];
        let mut r = rhs.to_vec();
        let mut iterations = 0;
        let (mut cs, mut sn, mut g) = (vec![0.0; m], vec![0.0; m], vec![0.0; m + 1]);
        loop {
            let beta = norm(&r);
            if beta <= tol {
                rhs.copy_from_slice(&x);
                return Ok(true);
            }
            if iterations >= max_iterations {
                tracing::debug!(
                    iterations,
                    relative_residual = beta / b_norm,
                    current_preconditioner = self.ldlt_current,
                    "GMRES did not converge"
                );
                return Ok(false);
            }
            for (v, ri) in self.basis[0].iter_mut().zip(&r) {
                *v = ri / beta;
            }
            g.iter_mut().for_each(|v| *v = 0.0);
            g[0] = beta;
            let mut k = 0;
            while k < m && iterations < max_iterations {
                // z_k = M⁻¹ v_k, kept for the update of x; w = A z_k
                let z = &mut self.preconditioned[k];
                z.copy_from_slice(&self.basis[k]);
                self.ldlt.solve_in_place(z)?;
                self.rows.mul_vec(z, &mut self.product, self.parallel);
                // modified Gram–Schmidt
                for i in 0..=k {
                    let h = dot(&self.product, &self.basis[i]);
                    self.hessenberg[k][i] = h;
                    for (w, v) in self.product.iter_mut().zip(&self.basis[i]) {
                        *w -= h * v;
                    }
                }
                let h_next = norm(&self.product);
                self.hessenberg[k][k + 1] = h_next;
                if h_next > 0.0 {
                    for (v, w) in self.basis[k + 1].iter_mut().zip(&self.product) {
                        *v = w / h_next;
                    }
                }
                // previous Givens rotations, then a new one zeroing H[k+1, k]
                let col = &mut self.hessenberg[k];
                for i in 0..k {
                    let (a, b) = (col[i], col[i + 1]);
                    col[i] = cs[i] * a + sn[i] * b;
                    col[i + 1] = -sn[i] * a + cs[i] * b;
                }
                let (a, b) = (col[k], col[k + 1]);
                let rho = a.hypot(b);
                if rho == 0.0 {
                    return Ok(false);
                }
                cs[k] = a / rho;
                sn[k] = b / rho;
                col[k] = rho;
                col[k + 1] = 0.0;
                g[k + 1] = -sn[k] * g[k];
                g[k] *= cs[k];
                iterations += 1;
                k += 1;
                if g[k].abs() <= tol || h_next == 0.0 {
                    break;
                }
            }
            // y = H⁻¹ g (upper triangular k × k), x += M⁻¹ V y = Z y (the z_k kept above save
            // the preconditioner solve of M⁻¹ (V y), as in flexible GMRES, Saad 2003, Alg. 9.6)
            let mut y = vec![0.0; k];
            for i in (0..k).rev() {
                let mut s = g[i];
                for (j, yj) in y.iter().enumerate().skip(i + 1) {
                    s -= self.hessenberg[j][i] * yj;
                }
                y[i] = s / self.hessenberg[i][i];
            }
            for (j, yj) in y.iter().enumerate() {
                for (xi, z) in x.iter_mut().zip(&self.preconditioned[j]) {
                    *xi += yj * z;
                }
            }
            // true residual r = b − A x
            self.rows.mul_vec(&x, &mut self.product, self.parallel);
            for ((ri, bi), ax) in r.iter_mut().zip(rhs.iter()).zip(&self.product) {
                *ri = bi - ax;
            }
            self.stats.iterations += k;
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

impl LinearSolver for SplitSolver {
    fn factorize(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), LinalgError> {
        self.factorize_preconditioned(pattern, values, None)
    }

    /// Factorises the symmetric part of `surrogate` if given (a symmetric positive definite
    /// stand-in for the matrix, assembled by the problem), else of `values`.
    fn factorize_preconditioned(
        &mut self,
        pattern: &SparsePattern,
        values: &[f64],
        surrogate: Option<&[f64]>,
    ) -> Result<(), LinalgError> {
        check_len("matrix values", self.values.len(), values.len())?;
        check_len("pattern size", self.full.size(), pattern.size())?;
        if let Some(p) = surrogate {
            check_len("surrogate values", self.values.len(), p.len())?;
        }
        self.values.copy_from_slice(values);
        self.rows.load(values);
        self.lu_current = false;
        self.symmetric.iter_mut().for_each(|v| *v = 0.0);
        for ((&u, &d), &v) in self
            .to_upper
            .iter()
            .zip(&self.diagonal)
            .zip(surrogate.unwrap_or(values))
        {
            self.symmetric[u] += if d { v } else { 0.5 * v };
        }
        let reuse = match (self.params.reuse_margin, self.fresh_iterations) {
            (Some(margin), Some(fresh)) => {
                self.ldlt_ok
                    && self.skip_gmres == 0
                    && self.reuse_backoff == 0
                    && self.last_iterations <= fresh + margin
            }
            _ => false,
        };
        self.reuse_backoff = self.reuse_backoff.saturating_sub(1);
        if reuse {
            self.ldlt_current = false;
            self.stats.reuses += 1;
            Ok(())
        } else {
            self.refactorize()
        }
    }

    fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        check_len("right-hand side", self.full.size(), rhs.len())?;
        if self.ldlt_ok && self.skip_gmres == 0 {
            let b = rhs.to_vec();
            let max = self.params.max_iterations;
            let budget = match (self.ldlt_current, self.fresh_iterations) {
                // an older preconditioner may take the reuse margin more than a fresh one did
                (false, Some(fresh)) => max.min(fresh + self.params.reuse_margin.unwrap_or(0)),
                _ => max,
            };
            if self.try_gmres(rhs, &b, budget)? {
                if !self.ldlt_current {
                    self.refresh_streak = 0;
                }
                return Ok(());
            }
            if !self.ldlt_current {
                // the preconditioner of an earlier matrix: refresh it before giving up, and
                // factorise the next few matrices afresh
                self.stats.refreshes += 1;
                self.refresh_streak += 1;
                self.reuse_backoff = 1 << self.refresh_streak.min(6);
                self.refactorize()?;
                if self.ldlt_ok && self.try_gmres(rhs, &b, max)? {
                    return Ok(());
                }
            }
            self.skip_gmres = self.params.lu_streak;
        } else {
            self.skip_gmres = self.skip_gmres.saturating_sub(1);
        }
        self.lu_solve(rhs)
    }

    fn set_forcing(&mut self, relative_residual: Option<f64>) {
        self.forcing = relative_residual;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::pattern::Equation;

    /// Convection–diffusion chain: symmetric diffusion plus a skew convection part of
    /// relative size `peclet`.
    fn chain(n: usize, peclet: f64) -> (SparsePattern, Vec<f64>) {
        let elements: Vec<Vec<Equation>> = (1..n)
            .map(|i| vec![Equation::free(i - 1).unwrap(), Equation::free(i).unwrap()])
            .collect();
        let p = SparsePattern::new(n, Storage::Full, &elements).unwrap();
        let mut values = vec![0.0; p.nnz()];
        for e in 0..elements.len() {
            // column-major [[2 + c, -2 + c], [-2 - c, 2 - c]]
            let c = peclet;
            p.add_element_matrix(&mut values, e, &[2.0 + c, -2.0 - c, -2.0 + c, 2.0 - c]);
        }
        let values = shifted(&p, &values, 0.05);
        (p, values)
    }

    fn residual(p: &SparsePattern, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let mut ax = vec![0.0; x.len()];
        p.mul_vec(values, x, &mut ax);
        let r: f64 = ax.iter().zip(b).map(|(a, b)| (a - b).powi(2)).sum();
        r.sqrt() / b.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    #[test]
    fn a_forcing_term_stops_gmres_at_that_residual_with_fewer_iterations() {
        let (p, values) = chain(300, 0.6);
        let b: Vec<f64> = (0..300).map(|i| 1.0 + (i % 5) as f64).collect();
        let solve = |forcing: Option<f64>| {
            let mut solver = SplitSolver::new(&p, GmresParams::default()).unwrap();
            solver.factorize(&p, &values).unwrap();
            solver.set_forcing(forcing);
            let mut x = b.clone();
            solver.solve_in_place(&mut x).unwrap();
            (residual(&p, &values, &x, &b), solver.stats().iterations)
        };
        let (tight, n_tight) = solve(None);
        let (loose, n_loose) = solve(Some(1e-3));
        assert!(tight < 1e-9, "{tight}");
        assert!(loose < 1e-3, "{loose}");
        assert!(n_loose < n_tight, "{n_loose} vs {n_tight}");
        // a forcing below the solver's own tolerance does not tighten it
        let (_, n_floor) = solve(Some(1e-14));
        assert_eq!(n_floor, n_tight);
    }

    #[test]
    fn solves_the_nonsymmetric_system_not_its_symmetric_part() {
        let (p, values) = chain(300, 0.6);
        let mut solver = SplitSolver::new(&p, GmresParams::default()).unwrap();
        solver.factorize(&p, &values).unwrap();
        let b: Vec<f64> = (0..300).map(|i| 1.0 + (i % 5) as f64).collect();
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        assert!(residual(&p, &values, &x, &b) < 1e-9);
        let s = solver.stats();
        assert_eq!((s.solves, s.lu_fallbacks), (1, 0));
        assert!(s.iterations > 1 && s.iterations < 100, "{s:?}");
        // the symmetric part alone would be off by far more than the tolerance
        let mut xs = b.clone();
        solver.ldlt.solve_in_place(&mut xs).unwrap();
        assert!(residual(&p, &values, &xs, &b) > 1e-3);
    }

    /// `values` with `shift` added to every diagonal entry.
    fn shifted(p: &SparsePattern, values: &[f64], shift: f64) -> Vec<f64> {
        let mut v = values.to_vec();
        for c in 0..p.size() {
            let range = p.col_ptr()[c]..p.col_ptr()[c + 1];
            let k = range.start + p.row_idx()[range].iter().position(|&r| r == c).unwrap();
            v[k] += shift;
        }
        v
    }

    /// Factorises and solves A x = b for every matrix in turn, asserting each residual.
    fn solve_each(solver: &mut SplitSolver, p: &SparsePattern, matrices: &[&[f64]], b: &[f64]) {
        for values in matrices {
            solver.factorize(p, values).unwrap();
            let mut x = b.to_vec();
            solver.solve_in_place(&mut x).unwrap();
            assert!(residual(p, values, &x, b) < 1e-9);
        }
    }

    #[test]
    fn a_reused_preconditioner_still_solves_the_new_matrix() {
        let params = GmresParams {
            reuse_margin: Some(10),
            ..GmresParams::default()
        };
        let (p, first) = chain(300, 0.6);
        let second = shifted(&p, &first, 0.01);
        let mut solver = SplitSolver::new(&p, params).unwrap();
        let b: Vec<f64> = (0..300).map(|i| 1.0 + (i % 7) as f64).collect();
        // the second matrix, solved with the first one's factorisation, to the tolerance
        solve_each(&mut solver, &p, &[&first, &second], &b);
        let s = solver.stats();
        assert_eq!(
            (s.factorisations, s.reuses, s.lu_fallbacks),
            (1, 1, 0),
            "{s:?}"
        );
        // without reuse: one factorisation per matrix
        let mut fresh = SplitSolver::new(&p, GmresParams::default()).unwrap();
        solve_each(&mut fresh, &p, &[&first, &second], &b);
        assert_eq!((fresh.stats().factorisations, fresh.stats().reuses), (2, 0));
    }

    #[test]
    fn a_stale_preconditioner_that_fails_is_refreshed_before_lu() {
        // the factorisation of a nearly symmetric chain (a few GMRES iterations) preconditions
        // the chain shifted by 5 I badly (eigenvalues of M⁻¹A from 1 to ~100): 30 iterations
        // are not enough, so the solver refactorises the current matrix and GMRES converges
        // without LU
        let params = GmresParams {
            reuse_margin: Some(1000),
            max_iterations: 30,
            ..GmresParams::default()
        };
        let (p, first) = chain(300, 0.05);
        let second = shifted(&p, &first, 5.0);
        let mut solver = SplitSolver::new(&p, params).unwrap();
        let b: Vec<f64> = (0..300).map(|i| (0.1 * i as f64).cos()).collect();
        solve_each(&mut solver, &p, &[&first, &second], &b);
        let s = solver.stats();
        assert_eq!(
            (s.reuses, s.factorisations, s.lu_fallbacks, s.solves),
            (1, 2, 0, 3),
            "{s:?}"
        );
    }

    #[test]
    fn a_symmetric_matrix_needs_one_iteration() {
        let (p, values) = chain(200, 0.0);
        let mut solver = SplitSolver::new(&p, GmresParams::default()).unwrap();
        solver.factorize(&p, &values).unwrap();
        let b: Vec<f64> = (0..200).map(|i| (i as f64).sin()).collect();
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        assert!(residual(&p, &values, &x, &b) < 1e-10);
        assert!(solver.stats().iterations <= 2, "{:?}", solver.stats());
    }

    #[test]
    fn a_singular_symmetric_part_falls_back_to_lu() {
        // [[0, 1], [-1, 0]] + 0.1 I has the symmetric part 0.1 I, then skew so strong that GMRES
        // still converges; a zero symmetric part ([[0, 1], [-1, 0]]) cannot be factorised.
        let eqs = vec![vec![Equation::free(0).unwrap(), Equation::free(1).unwrap()]];
        let p = SparsePattern::new(2, Storage::Full, &eqs).unwrap();
        let mut values = vec![0.0; p.nnz()];
        p.add_element_matrix(&mut values, 0, &[0.0, -1.0, 1.0, 0.0]);
        let mut solver = SplitSolver::new(&p, GmresParams::default()).unwrap();
        solver.factorize(&p, &values).unwrap();
        let b = [1.0, 2.0];
        let mut x = b;
        solver.solve_in_place(&mut x).unwrap();
        // A x = b: x₂ = 1, −x₁ = 2
        assert!(
            (x[0] + 2.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12,
            "{x:?}"
        );
        assert_eq!(solver.stats().lu_fallbacks, 1);
    }
}
