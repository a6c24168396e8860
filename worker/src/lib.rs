//! # moorfret-worker
//!
//! The `moorfret-worker` binary: the worker loop of `moorfret_orchestrator::worker` (claim,
//! run the global then strand stages, heartbeat, checkpoint, complete atomically) as its own
//! executable for cluster schedulers. The loop itself lives in the orchestrator so that
//! `moorfret worker` and `moorfret campaign launch` share it.
