//! The strand pipeline shared by a campaign's strand jobs ([`crate::strand_stage`],
//! [`crate::reduced_stage`]) and `moorfret run strand`: a load file read and turned into
//! strand samples ([`load`]), the strand model built on first use ([`model`]), the EA of the
//! tension → strain rule with its cache ([`stiffness`]), the checkpoints of a history run
//! ([`checkpoint`]), the FE run resumed from its checkpoint ([`run`]). The callers parse their
//! arguments or payloads into these, and print or store what they return.

pub mod checkpoint;
pub mod load;
pub mod model;
pub mod run;
pub mod stiffness;

pub use model::LazyModel;
pub use run::{run_fe, FeRun, RefusedCheckpoint};
pub use stiffness::{
    measured_ea_n, AxialStiffness, StiffnessError, StiffnessRequest, StiffnessSource,
    StraightStrandEstimates,
};
