//! `moorfret worker --db URL [--artifacts DIR] [--exit-when-idle]` (also the `moorfret-worker`
//! binary): one worker process serving every campaign of a store until SIGTERM/SIGINT, which
//! releases the running job's lease without consuming an attempt.

pub(crate) use moorfret_worker::args::{StoreArgs, WorkerArgs};
use moorfret_worker::process;

/// Runs the command: a worker until a signal (or idle, with `--exit-when-idle`).
pub(crate) fn execute(args: WorkerArgs) -> anyhow::Result<()> {
    process::run(args.options())
}
