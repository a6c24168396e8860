//! The FE history run of a strand load, resumed from a checkpoint when there is one: what a
//! campaign's FE strand job and `moorfret run strand` both run.

use moorfret_solver::strand::history::checkpoint::HistoryCheckpoint;
use moorfret_solver::strand::history::{
    run_history_from, HistoryError, HistoryObserver, HistoryOptions, HistoryResult, LoadSample,
};
use moorfret_solver::strand::model::StrandModel;

/// What a run does with a checkpoint the solver refuses as another model's or history's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RefusedCheckpoint {
    /// Log it and start over (a campaign's job: its checkpoint may be another build's).
    StartOver,
    /// Return the solver's error (`run strand --resume`: the user named the file).
    Fail,
}

/// The result of an FE run and whether it continued from the checkpoint.
#[derive(Debug)]
pub struct FeRun {
    /// The solver's result.
    pub result: HistoryResult,
    /// Whether the run continued from the checkpoint it was given.
    pub resumed: bool,
}

/// Runs `model` through `samples` from `resume` if given (results identical to the bit to an
/// uninterrupted run), handing progress and checkpoints to `observer`.
pub fn run_fe(
    model: &StrandModel,
    samples: &[LoadSample],
    options: &HistoryOptions,
    resume: Option<&HistoryCheckpoint>,
    refused: RefusedCheckpoint,
    observer: &mut dyn HistoryObserver,
) -> Result<FeRun, HistoryError> {
    if let Some(cp) = resume {
        tracing::info!(
            segment = cp.next_segment,
            segments = cp.kept_samples.len().saturating_sub(1),
            "strand history resumes from its checkpoint"
        );
    }
    match run_history_from(model, samples, options, resume, observer) {
        Ok(result) => Ok(FeRun {
            result,
            resumed: resume.is_some(),
        }),
        Err(HistoryError::Checkpoint { reason })
            if resume.is_some() && refused == RefusedCheckpoint::StartOver =>
        {
            tracing::warn!(%reason, "checkpoint refused; starting over");
            let result = run_history_from(model, samples, options, None, observer)?;
            Ok(FeRun {
                result,
                resumed: false,
            })
        }
        Err(e) => Err(e),
    }
}
