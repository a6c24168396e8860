//! Errors of the coupled global stage. Input errors name the offending field by its path;
//! solver errors carry time, line, node and residual so a failed run can be diagnosed. All
//! variants are deterministic (the same input fails the same way): none is worth a retry.

use crate::floater::FloaterError;
use crate::mooring::{LineError, NodeId};
use crate::waves::WavesError;

/// Everything that can go wrong in a global run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GlobalError {
    /// The case document is not valid JSON for [`super::case::CaseSpec`].
    #[error("case file is not a valid case description: {message}")]
    CaseJson {
        /// Parser message with line and column.
        message: String,
    },
    /// A field of the case is non-physical or inconsistent.
    #[error("{field} {reason} (got {value})")]
    InvalidCase {
        /// Path of the field, e.g. `mooring.segments[1].length_m`.
        field: String,
        /// Value found, formatted.
        value: String,
        /// What the value must satisfy.
        reason: String,
    },
    /// A line failed to build or to solve.
    #[error("line {line}: {source}")]
    Line {
        /// Line id (0 when not attributable).
        line: u32,
        /// What the line model reported.
        source: Box<LineError>,
    },
    /// The floater failed to build or to move.
    #[error("floater: {0}")]
    Floater(#[from] FloaterError),
    /// The sea state could not be realised.
    #[error("sea state: {0}")]
    Waves(#[from] WavesError),
    /// The coupled static equilibrium was not found.
    #[error(
        "coupled statics not converged after {iterations} iterations, scaled floater residual \
         {residual:e}"
    )]
    StaticsDiverged {
        /// Newton iterations done.
        iterations: usize,
        /// Largest floater residual component scaled by the weight (forces) and weight × 10 m
        /// (moments).
        residual: f64,
    },
    /// A coupled time step did not converge.
    #[error(
        "coupled step ending at t = {time_s} s not converged after {iterations} iterations \
         and {step_cuts} step halvings: scaled floater residual {residual:e}{}",
        location(.line, .node)
    )]
    StepDiverged {
        /// Time (s) the step was aiming at.
        time_s: f64,
        /// Halvings of the coupled step tried.
        step_cuts: usize,
        /// Coupling iterations done.
        iterations: usize,
        /// Scaled floater residual (or the line residual in N when a line failed).
        residual: f64,
        /// Line id that failed, if a line did.
        line: Option<u32>,
        /// Node of that line with the largest residual.
        node: Option<NodeId>,
    },
    /// A value of the solution became non-finite.
    #[error("non-finite {what} at t = {time_s} s")]
    NonFinite {
        /// Quantity.
        what: &'static str,
        /// Time (s).
        time_s: f64,
    },
}

fn location(line: &Option<u32>, node: &Option<NodeId>) -> String {
    match (line, node) {
        (Some(l), Some(n)) => format!(" (line {l} failing, largest residual at node {n})"),
        (Some(l), None) => format!(" (line {l} failing)"),
        _ => String::new(),
    }
}

impl GlobalError {
    /// Wraps a line error with the line id; a line step divergence is reported as a coupled
    /// step divergence naming the line and node.
    pub(crate) fn from_line(line: u32, e: LineError) -> Self {
        match e {
            LineError::StepDiverged {
                time_s,
                halvings,
                residual_norm,
                node,
                ..
            } => GlobalError::StepDiverged {
                time_s,
                step_cuts: 0,
                iterations: halvings,
                residual: residual_norm,
                line: Some(line),
                node: Some(node),
            },
            other => GlobalError::Line {
                line,
                source: Box::new(other),
            },
        }
    }
}
