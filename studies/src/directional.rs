//! Directional finite-difference check of an assembled strand tangent, shared by the probe
//! studies.

use moorfret_solver::beam::frame::FrameError;
use moorfret_solver::contact::ContactStatus;
use moorfret_solver::linalg::NonlinearProblem;
use moorfret_solver::strand::problem::StrandProblem;

/// Euclidean norm.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Status of every contact at the last evaluation of `problem`.
pub fn statuses(problem: &StrandProblem<'_>) -> Vec<Option<ContactStatus>> {
    problem
        .responses()
        .iter()
        .map(|r| r.map(|r| r.status))
        .collect()
}

/// What a step h δu from the state of `problem` gives.
pub struct DirectionalCheck {
    /// r(u + h δu) (not every study prints it).
    pub residual: Vec<f64>,
    /// (r(u + h δu) − r(u)) / h − K δu.
    pub mismatch: Vec<f64>,
    /// Contacts whose status differs from `status`.
    pub flips: usize,
}

/// Evaluates a copy of `problem` at u + h δu (load factor `load_factor`) against its residual
/// `r`, K δu `kdu` and contact statuses `status` at u.
pub fn directional_check(
    problem: &StrandProblem<'_>,
    load_factor: f64,
    r: &[f64],
    kdu: &[f64],
    du: &[f64],
    h: f64,
    status: &[Option<ContactStatus>],
) -> Result<DirectionalCheck, FrameError> {
    let mut trial = problem.clone();
    let step: Vec<f64> = du.iter().map(|v| v * h).collect();
    trial.apply_increment(&step);
    let mut residual = vec![0.0; r.len()];
    trial.evaluate(load_factor, &mut residual, None)?;
    let flips = statuses(&trial)
        .iter()
        .zip(status)
        .filter(|(a, b)| a != b)
        .count();
    let mismatch = residual
        .iter()
        .zip(r)
        .zip(kdu)
        .map(|((a, b), c)| (a - b) / h - c)
        .collect();
    Ok(DirectionalCheck {
        residual,
        mismatch,
        flips,
    })
}
