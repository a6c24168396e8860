//! # moorfret-worker
//!
//! A worker claims sea-state jobs from a campaign store and runs them (ARCHITECTURE.md, "Data flow
//! of a campaign"):
//!
//! - [`serve`]: the claim loop: cache reuse, the stage on a blocking thread with a heartbeat
//!   task, completion guarded by the lease token, failure reports, release on shutdown;
//! - [`execute`]: one claimed job to its stage, with what a stage needs ([`context`]);
//! - [`gate`]: the gated jobs (the FE jobs of `auto` campaigns, the jobs of extra seeds): the
//!   selection from stored results, and the settling of the unselected ones;
//! - [`global_stage`]: floater + lines through one sea state, hot-spot series as artifacts;
//! - [`strand_stage`]: the strand model through a hot-spot series, with checkpoints, per-contact
//!   statistics and per-sea-state damage inputs (the FE model);
//! - [`reduced_stage`]: the reduced strand response of `reduced` and `auto` campaigns: its
//!   calibration per hot spot, and the strand jobs run through it;
//! - [`strand`]: the strand pipeline shared with `moorfret run strand` (the model built on
//!   first use, the EA of ε = T / EA and its cache);
//! - [`failure`]: failure reports of the stages;
//! - [`args`]: the command-line arguments of a worker process;
//! - [`process`]: a whole worker process (store, signals, runtime), shared by the `moorfret
//!   worker` command and the `moorfret-worker` binary.

pub mod args;
pub mod context;
pub mod execute;
pub mod failure;
pub mod gate;
pub mod global_stage;
pub mod process;
pub mod reduced_stage;
pub mod serve;
pub mod strand;
pub mod strand_stage;

pub use process::{ProcessOptions, StoreConfig};
pub use serve::{run, this_process, WorkerConfig, WorkerSummary};
