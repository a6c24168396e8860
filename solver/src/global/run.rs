//! One global run end to end: model, coupled statics, coupled dynamics, with the work split
//! timed and the thread count passed explicitly.

use std::time::Instant;

use super::dynamics::run_dynamics;
use super::error::GlobalError;
use super::params::DynamicsParams;
use super::results::GlobalResult;
use super::system::{line_pool, solve_coupled_statics, GlobalModel, StaticsParams};

/// Settings of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunParams {
    /// Worker threads for the lines (1 = serial).
    pub threads: usize,
    /// Coupled statics.
    pub statics: StaticsParams,
    /// Coupled dynamics.
    pub dynamics: DynamicsParams,
}

impl Default for RunParams {
    fn default() -> Self {
        Self {
            threads: 1,
            statics: StaticsParams::default(),
            dynamics: DynamicsParams::default(),
        }
    }
}

/// Statics then dynamics of `model`; `progress` gets (t, t_end) after every step.
pub fn run(
    model: &GlobalModel,
    params: &RunParams,
    progress: impl FnMut(f64, f64),
) -> Result<GlobalResult, GlobalError> {
    let pool = line_pool(params.threads)?;
    let clock = Instant::now();
    let eq = solve_coupled_statics(model, &params.statics, pool.as_ref())?;
    let statics_s = clock.elapsed().as_secs_f64();
    tracing::info!(
        iterations = eq.iterations,
        residual = eq.residual,
        seconds = statics_s,
        "coupled statics converged"
    );
    let mut result = run_dynamics(model, &eq, &params.dynamics, pool.as_ref(), progress)?;
    result.stats.statics_s = statics_s;
    Ok(result)
}
