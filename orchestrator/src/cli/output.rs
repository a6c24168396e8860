//! Standard output of the commands. Every line goes through [`outln!`] (or a writer wrapped in
//! [`Guarded`]), which flushes and turns a failed write into [`StdoutError`] instead of the
//! panic of `println!`: `main` ends quietly with exit 0 when the reader went away (a closed
//! pipe, `| head -1`), as Unix tools do, and with exit 1 on any other failure (a full disk).

use std::io::Write;

/// Standard output could not be written.
#[derive(Debug)]
pub(crate) struct StdoutError(pub(crate) std::io::Error);

impl StdoutError {
    /// Whether the reader closed the pipe (nothing is wrong: the output is not wanted).
    pub(crate) fn is_closed_pipe(&self) -> bool {
        self.0.kind() == std::io::ErrorKind::BrokenPipe
    }
}

impl std::fmt::Display for StdoutError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "writing to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.0)
    }
}

/// Writes `args` on standard output and flushes it.
pub(crate) fn write_out(args: std::fmt::Arguments<'_>) -> Result<(), StdoutError> {
    let mut lock = std::io::stdout().lock();
    lock.write_fmt(args)
        .and_then(|()| lock.flush())
        .map_err(StdoutError)
}

/// `println!` that returns a [`StdoutError`] instead of panicking.
macro_rules! outln {
    () => {
        $crate::cli::output::write_out(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::cli::output::write_out(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use outln;

/// A writer that keeps the first error of the writer it wraps, so that a command writing
/// through a library (CSV, JSON) can tell a failed standard output from its own errors.
pub(crate) struct Guarded<W: Write> {
    inner: W,
    error: Option<std::io::Error>,
}

impl<W: Write> Guarded<W> {
    /// Wraps `inner`.
    pub(crate) fn new(inner: W) -> Self {
        Self { inner, error: None }
    }

    /// Flushes, then returns the first write error as a [`StdoutError`], or `result`.
    pub(crate) fn finish<T>(mut self, result: anyhow::Result<T>) -> anyhow::Result<T> {
        let _ = self.flush();
        match self.error.take() {
            Some(e) => Err(StdoutError(e).into()),
            None => result,
        }
    }

    fn keep<T>(&mut self, r: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &r {
            if self.error.is_none() {
                self.error = Some(std::io::Error::new(e.kind(), e.to_string()));
            }
        }
        r
    }
}

impl<W: Write> Write for Guarded<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = self.inner.write(buf);
        self.keep(r)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let r = self.inner.flush();
        self.keep(r)
    }
}

/// Standard output behind a [`Guarded`] writer.
pub(crate) fn stdout() -> Guarded<std::io::StdoutLock<'static>> {
    Guarded::new(std::io::stdout().lock())
}
