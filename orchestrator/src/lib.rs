//! # moorfret-orchestrator
//!
//! Campaign specifications, planning (scatter diagram → sea-state jobs), the campaign store,
//! the local worker pool, aggregation, queries, reports, and the `moorfret` command line.

pub mod campaign;
pub mod cli;
pub mod plot;
pub mod query;
pub mod report;
pub mod store;
pub mod worker;
