//! # moorfret-orchestrator
//!
//! What the `moorfret` command runs on behalf of a user, as a library:
//!
//! - [`plan`]: scatter diagram → sea states → jobs, and the campaign stored with its plan in
//!   one transaction;
//! - [`design`]: the design check: utilisation of every damage figure, pass or fail per
//!   mooring line, what governs it, damage per wave direction;
//! - [`query`]: a campaign's results from the store's views, as tables, CSV or JSON;
//! - [`report`]: the offline HTML report of a campaign;
//! - [`plot`]: SVG plots of single-stage runs.
//!
//! Campaign files are read by `moorfret-campaign`, stored by `moorfret-store` and run by
//! `moorfret-worker`; the command line itself lives in the `moorfret` binary (`src/main.rs`,
//! `src/cli/`).

pub mod design;
pub mod plan;
pub mod plot;
pub mod query;
pub mod report;
