//! Fretting statistics of inter-wire contacts (`docs/damage.md`).
//!
//! - [`reversals`]: peak / valley extraction with a hysteresis gate;
//! - [`rainflow`]: batch rainflow counting, ASTM E1049-85 §5.4.4 (half cycles kept) and §5.4.5
//!   (repeating histories);
//! - [`streaming`]: the same count one sample at a time with a serialisable state;
//! - `cycles`: per-contact slip cycles with the normal and tangential forces over them;
//! - `histogram`: 2D histograms of cycles (slip amplitude × normal force);
//! - the Hertz contact of crossed cylinders (ellipse semi-axes, peak pressure) is the contact
//!   model's own, [`crate::contact::hertz`], re-exported here;
//! - `indicators`: fretting regime (Mindlin), Ruiz products, fretting S-N damage;
//! - [`life`]: fretting-fatigue life of a crossing from its contact stress field;
//! - `record`: the per-contact record the strand stage produces, and contact classes;
//! - [`runin`]: where the mean slip stops drifting (run-in to exclude from the statistics).
//!
//! Units follow the counted history (slip in m, forces in N); indices are zero-based samples.

pub(crate) mod cycles;
pub(crate) mod error;
pub(crate) mod histogram;
pub(crate) mod indicators;
pub mod life;
pub mod rainflow;
pub(crate) mod record;
pub mod reversals;
pub mod runin;
pub mod streaming;

pub use crate::contact::hertz::{
    CrossedCylinders, ElasticMaterial, HertzContact, HertzError, HertzModel,
};
pub use cycles::{ContactCycleAccumulator, ContactSample, ForceStats, SlipCycle};
pub use error::FrettingError;
pub use histogram::{BinEdges, CycleHistogram, ForceMeasure};
pub use indicators::{
    evaluate_cycle, CycleIndicators, FrettingParams, FrettingRegime, FrettingSnLaw,
    RegimeCriterion, WireStress,
};
pub use rainflow::{count_cycles, Cycle, RainflowCounter, RainflowOptions};
pub use record::{AngularPosition, ContactClass, ContactRecord};
pub use reversals::{extract_reversals, Reversal, ReversalDetector};
pub use runin::{
    detect_run_in, detect_run_in_against_load, detect_set_run_in, RunIn, RunInParams, SetRunIn,
};
pub use streaming::{SegmentSummary, StreamingRainflow};
