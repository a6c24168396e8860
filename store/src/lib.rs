//! Campaign store and job queue (ARCHITECTURE.md, "Data flow of a campaign" and the store).
//!
//! - [`Store`] ([`campaign_store`]): campaigns, sea states, jobs and their dependencies,
//!   attempts, workers, results; claim / heartbeat / complete / fail / sweep / cancel; cache
//!   reuse; progress and lifetime views. SQLite (default, one WAL file) or PostgreSQL, chosen
//!   by the location; the same behaviour on both.
//! - [`ArtifactStore`] ([`artifacts`]): content-addressed files for large series and
//!   checkpoints.
//! - [`Clock`], [`QueuePolicy`]: time source and queue settings.
//! - `TestPayload` (`test_kind`): payload of the test-only job kind, built with the
//!   `test-support` feature only (the tests of this crate and of its dependents enable it).
//! - [`RetryPolicy`] ([`retry`]): capped exponential backoff while the database is away.
//! - [`WallTimeBudget`] ([`wall_time`]): which jobs fit in a worker's remaining wall time.
//!
//! The schema lives in `migrations/sqlite` and `migrations/postgres`, embedded in the binary.
//! Times are integer ms since the Unix epoch; JSON columns hold text.

pub mod artifacts;
pub mod campaign_store;
pub mod clock;
mod dialect;
pub mod error;
pub mod filesystem;
pub mod model;
pub mod policy;
mod postgres;
pub mod results;
pub mod retry;
mod sqlite;
#[cfg(feature = "test-support")]
pub mod test_kind;
pub mod types;
pub mod wall_time;

pub use artifacts::ArtifactStore;
pub use campaign_store::{Store, StoreLocation, StoreOptions};
pub use clock::{Clock, ManualClock};
pub use error::StoreError;
pub use model::*;
pub use policy::QueuePolicy;
pub use results::*;
pub use retry::{complete_with_retry, RetryPolicy};
#[cfg(feature = "test-support")]
pub use test_kind::TestPayload;
pub use types::*;
pub use wall_time::WallTimeBudget;
