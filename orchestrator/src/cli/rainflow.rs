//! `moorfret rainflow FILE.csv`: rainflow-count one column of a CSV file (ASTM E1049-85).
//!
//! The file has a header row; the counted column is `--column NAME` or else the first one that
//! is not a time column (`t`, `time`, or a name starting with `t_` or `time_`, such as the
//! `time_s` of moorfret's own `hotspots.csv`): time only increases, and counting it would give
//! one half cycle over the whole record.
//! Output (stdout) is JSON `{"cycles": [{"range", "mean", "count", "start_index",
//! "end_index"}, …]}` or, with `--format csv`, one row per cycle. Indices are zero-based data
//! rows (the header is not counted). A missing column, a cell that is not a finite number or a
//! file without data is an error naming the file, line and column; the process then exits
//! non-zero.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use moorfret_solver::fretting::rainflow::{count_cycles, Cycle, RainflowOptions};

/// Output formats of `moorfret rainflow`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum RainflowFormat {
    /// `{"cycles": [...]}`.
    Json,
    /// A header `range,mean,count,start_index,end_index` and one row per cycle.
    Csv,
}

/// Arguments of `moorfret rainflow`.
#[derive(Debug, Args)]
pub(crate) struct RainflowArgs {
    /// CSV file with a header row.
    pub(crate) file: PathBuf,
    /// Column to count (default: the first column that is not a time column: `t`, `time`,
    /// `t_…`, `time_…`).
    #[arg(long)]
    pub(crate) column: Option<String>,
    /// Treat the series as one period of a repeating history (closes the residue).
    #[arg(long)]
    pub(crate) repeating: bool,
    /// Hysteresis gate: ignore ripples not larger than this (unit of the column).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub(crate) gate: f64,
    /// Write JSON (the default; same as `--format json`).
    #[arg(long, conflicts_with = "format")]
    pub(crate) json: bool,
    /// Output format.
    #[arg(long, value_enum)]
    pub(crate) format: Option<RainflowFormat>,
}

/// Reads one numeric column of a CSV file; errors name the file, line and column.
pub(crate) fn read_column(
    file: &std::path::Path,
    column: Option<&str>,
) -> anyhow::Result<Vec<f64>> {
    let shown = file.display();
    let bytes = std::fs::read(file).with_context(|| format!("cannot read {shown}"))?;
    if bytes.iter().all(|b| b.is_ascii_whitespace()) {
        bail!("{shown}: the file is empty (expected a header row and data rows)");
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(bytes.as_slice());
    let headers = reader
        .headers()
        .with_context(|| format!("{shown}: cannot read the header row"))?
        .clone();
    let (col, name) = match column {
        Some(name) => match headers.iter().position(|h| h == name) {
            Some(i) => (i, name.to_string()),
            None => bail!(
                "{shown} line 1: column `{name}` not found (columns: {})",
                headers.iter().collect::<Vec<_>>().join(", ")
            ),
        },
        None => match headers.iter().position(|h| !is_time_column(h)) {
            Some(i) => (i, headers.get(i).unwrap_or("").to_string()),
            None => bail!(
                "{shown} line 1: every column is a time column ({}); name one with --column",
                headers.iter().collect::<Vec<_>>().join(", ")
            ),
        },
    };
    let mut values = Vec::new();
    for record in reader.records() {
        let record = record.with_context(|| format!("{shown}: malformed CSV"))?;
        let line = record.position().map_or(0, |p| p.line());
        let cell = record.get(col).with_context(|| {
            format!(
                "{shown} line {line}, column {} (`{name}`): missing cell",
                col + 1
            )
        })?;
        let value: f64 = cell
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .with_context(|| {
                format!(
                    "{shown} line {line}, column {} (`{name}`): `{cell}` is not a finite number",
                    col + 1
                )
            })?;
        values.push(value);
    }
    if values.is_empty() {
        bail!("{shown}: no data rows after the header");
    }
    Ok(values)
}

/// Whether a column header names time (skipped when no `--column` is given).
fn is_time_column(header: &str) -> bool {
    let h = header.trim().to_ascii_lowercase();
    h == "t" || h == "time" || h.starts_with("t_") || h.starts_with("time_") || h == "time(s)"
}

/// Writes cycles in the requested format.
pub(crate) fn write_cycles(
    out: &mut dyn Write,
    cycles: &[Cycle],
    format: RainflowFormat,
) -> anyhow::Result<()> {
    match format {
        RainflowFormat::Json => {
            // A struct keeps the documented field order (range, mean, count, indices).
            #[derive(serde::Serialize)]
            struct Output<'a> {
                cycles: &'a [Cycle],
            }
            serde_json::to_writer(&mut *out, &Output { cycles })
                .context("cannot write JSON output")?;
            writeln!(out)?;
        }
        RainflowFormat::Csv => {
            let mut w = csv::Writer::from_writer(out);
            for c in cycles {
                w.serialize(c).context("cannot write CSV output")?;
            }
            w.flush()?;
        }
    }
    Ok(())
}

/// Runs `moorfret rainflow`, writing to `out`.
pub(crate) fn run(args: &RainflowArgs, out: &mut dyn Write) -> anyhow::Result<()> {
    if !(args.gate.is_finite() && args.gate >= 0.0) {
        bail!("--gate must be finite and >= 0 (got {})", args.gate);
    }
    let values = read_column(&args.file, args.column.as_deref())?;
    let options = RainflowOptions {
        hysteresis_gate: args.gate,
        repeating: args.repeating,
    };
    let cycles = count_cycles(&values, &options)
        .with_context(|| format!("rainflow count of {}", args.file.display()))?;
    tracing::debug!(
        samples = values.len(),
        cycles = cycles.len(),
        "rainflow counted"
    );
    write_cycles(out, &cycles, args.format.unwrap_or(RainflowFormat::Json))
}

/// Executes `moorfret rainflow` on standard output.
pub(crate) fn execute(args: RainflowArgs) -> anyhow::Result<()> {
    let mut out = super::output::stdout();
    let result = run(&args, &mut out);
    out.finish(result)
}
