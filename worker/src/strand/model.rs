//! The strand model of a run, built on first use: a run that finds EA and its calibration in a
//! cache never builds it.

use moorfret_solver::strand::model::{StrandModel, StrandModelError, StrandModelParameters};
use moorfret_solver::strand::profile::Strand;

/// The strand model of `strand` with `params`, built on first use (or given, built already).
pub struct LazyModel<'a> {
    /// The strand.
    pub strand: &'a Strand,
    /// The model parameters.
    pub params: &'a StrandModelParameters,
    given: Option<&'a StrandModel>,
    model: Option<StrandModel>,
}

impl<'a> LazyModel<'a> {
    /// The model of `strand` with `params`, not built yet.
    pub fn new(strand: &'a Strand, params: &'a StrandModelParameters) -> Self {
        Self::with_model(strand, params, None)
    }

    /// The model of `strand` with `params`, `model` when it is built already.
    pub fn with_model(
        strand: &'a Strand,
        params: &'a StrandModelParameters,
        model: Option<&'a StrandModel>,
    ) -> Self {
        Self {
            strand,
            params,
            given: model,
            model: None,
        }
    }

    /// The model, built now if it was not yet.
    pub fn get(&mut self) -> Result<&StrandModel, StrandModelError> {
        if let Some(model) = self.given {
            return Ok(model);
        }
        let model = match self.model.take() {
            Some(model) => model,
            None => StrandModel::new(self.strand, self.params)?,
        };
        Ok(self.model.insert(model))
    }

    /// The model if it is built.
    pub fn built(&self) -> Option<&StrandModel> {
        self.given.or(self.model.as_ref())
    }
}
