//! Log output of the strand studies: `RUST_LOG` filters, plain text on stderr, time since
//! start (e.g. `RUST_LOG=moorfret_solver::linalg=trace` for every Newton iteration and GMRES
//! solve).

/// Installs the subscriber; call once at the start of `main`.
pub fn init() {
    tracing_subscriber::fmt()
        .with_env_filter(tracing_subscriber::EnvFilter::from_default_env())
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .with_timer(tracing_subscriber::fmt::time::uptime())
        .init();
}
