//! Wall-time accounting of the Newton work: wrappers around a [`NonlinearProblem`] and a
//! [`LinearSolver`] that add the time spent in assembly (residual and tangent evaluations),
//! numeric factorisation and triangular solves to a [`WorkTimes`].

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::linalg::{LinalgError, LinearSolver, NonlinearProblem, SparsePattern};

/// Accumulated wall times (s).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WorkTimes {
    /// Residual and tangent evaluations (element work and assembly).
    pub assembly_s: f64,
    /// Numeric factorisations.
    pub factorisation_s: f64,
    /// Solves with a factorisation.
    pub solve_s: f64,
}

impl WorkTimes {
    /// Adds `other`.
    pub fn add(&mut self, other: &Self) {
        self.assembly_s += other.assembly_s;
        self.factorisation_s += other.factorisation_s;
        self.solve_s += other.solve_s;
    }
}

/// A linear solver that times its calls.
#[derive(Debug)]
pub struct TimedSolver<S> {
    /// The solver.
    pub inner: S,
    /// Factorisation and solve times so far.
    pub times: WorkTimes,
}

impl<S: LinearSolver> LinearSolver for TimedSolver<S> {
    fn factorize(&mut self, pattern: &SparsePattern, values: &[f64]) -> Result<(), LinalgError> {
        let t = Instant::now();
        let r = self.inner.factorize(pattern, values);
        self.times.factorisation_s += t.elapsed().as_secs_f64();
        r
    }

    fn factorize_preconditioned(
        &mut self,
        pattern: &SparsePattern,
        values: &[f64],
        surrogate: Option<&[f64]>,
    ) -> Result<(), LinalgError> {
        let t = Instant::now();
        let r = self
            .inner
            .factorize_preconditioned(pattern, values, surrogate);
        self.times.factorisation_s += t.elapsed().as_secs_f64();
        r
    }

    fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), LinalgError> {
        let t = Instant::now();
        let r = self.inner.solve_in_place(rhs);
        self.times.solve_s += t.elapsed().as_secs_f64();
        r
    }

    fn set_forcing(&mut self, relative_residual: Option<f64>) {
        self.inner.set_forcing(relative_residual);
    }
}

/// A problem whose evaluations are timed.
#[derive(Debug)]
pub struct TimedProblem<'p, P> {
    /// The problem.
    pub inner: &'p mut P,
    /// Evaluation time so far (in `assembly_s`).
    pub times: WorkTimes,
}

impl<P: NonlinearProblem> NonlinearProblem for TimedProblem<'_, P> {
    type Error = P::Error;

    fn evaluate(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        tangent: Option<&mut [f64]>,
    ) -> Result<f64, Self::Error> {
        let t = Instant::now();
        let r = self.inner.evaluate(load_factor, residual, tangent);
        self.times.assembly_s += t.elapsed().as_secs_f64();
        r
    }

    fn apply_increment(&mut self, increment: &[f64]) {
        self.inner.apply_increment(increment);
    }

    fn commit(&mut self, load_factor: f64) {
        self.inner.commit(load_factor);
    }

    fn restore(&mut self) {
        self.inner.restore();
    }

    fn begin_iteration(&mut self, iteration: usize) {
        self.inner.begin_iteration(iteration);
    }

    fn merit_weights(&self) -> Option<&[f64]> {
        self.inner.merit_weights()
    }

    fn preconditioner(&self) -> Option<&[f64]> {
        self.inner.preconditioner()
    }
}
