//! Settings of the coupled dynamics ([`super::dynamics::run_dynamics`] and the coupled step it
//! repeats): coupling tolerance and passes, step cuts, the line integrator's settings and the
//! precomputation of the sea kinematics.

use crate::mooring::dynamics::DynamicParams;
use crate::waves::{SeriesParams, TableParams};

/// Settings of the coupled dynamics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicsParams {
    /// Scaled floater residual accepted.
    pub tolerance: f64,
    /// Coupling passes (line solves) per step before the step is cut.
    pub max_iterations: usize,
    /// Floater Newton iterations per pass against the linearised line forces.
    pub floater_iterations: usize,
    /// Halvings of a coupled step tried before the run fails.
    pub max_step_cuts: usize,
    /// Line integrator settings (its spectral radius is overridden by the case's).
    pub line: DynamicParams,
    /// Whether line kinematics are precomputed at the static quadrature points.
    pub precompute_line_kinematics: bool,
    /// Precomputation settings.
    pub series: SeriesParams,
    /// Distance beyond which a cached point is not used (m).
    pub guard_distance_m: f64,
    /// Resolution of the floater's kinematics table; `None` samples the floater's sea by direct
    /// summation.
    pub floater_table: Option<TableParams>,
    /// Whether a line that is the mirror image of another about the waves' vertical plane is
    /// written as that mirror image instead of being solved (`super::mirror`).
    pub mirror_lines: bool,
}

impl Default for DynamicsParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-7,
            max_iterations: 12,
            floater_iterations: 4,
            max_step_cuts: 6,
            // Slack events of the light rope under the clump mass make the line's Newton
            // iterations piecewise smooth: allow more iterations and step cuts than a line
            // driven alone needs.
            line: DynamicParams {
                max_iterations: 30,
                max_halvings: 6,
                ..DynamicParams::default()
            },
            precompute_line_kinematics: true,
            series: SeriesParams {
                samples_per_shortest_period: 16.0,
                chebyshev_tolerance: 1e-8,
                max_chebyshev_nodes: 32,
                threads: 1,
            },
            guard_distance_m: 30.0,
            floater_table: Some(TableParams::default()),
            mirror_lines: true,
        }
    }
}
