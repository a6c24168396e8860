//! # moorfret-worker
//!
//! Worker processes: claim jobs from the campaign store, run the global then strand stages,
//! heartbeat, checkpoint and complete atomically.
