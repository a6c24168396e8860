//! `moorfret scatter SERIES --time COL --hs COL --tp COL --direction COL --out DIR`: directional
//! scatter tables from a hindcast, reanalysis or buoy series
//! (`moorfret_solver::waves::climate`), one table per direction sector with records
//! (`sector_<centre>.tsv`, cells percent within the sector) and `sectors.json`, whose
//! `sectors` list goes into a campaign file's `scatter` as it is. A summary names what was
//! read, used, calm and left out (by reason, with the first line of each) and every sector's
//! share. Every option is checked, and the whole series read, before anything is written.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::Args;
use moorfret_solver::text::Num;
use moorfret_solver::waves::climate::{
    ClimateError, ClimateSettings, DirectionalClimate, Fault, SeriesColumns, SeriesField, TimeKind,
};
use serde_json::json;

use crate::cli::import::relative_path;
use crate::cli::output::outln;

/// Name of the sectors' file in the output directory.
const SECTORS_FILE: &str = "sectors.json";

/// Arguments of `scatter`.
#[derive(Debug, Args)]
pub(crate) struct ScatterArgs {
    /// The series: text with a header row, fields separated by tabs, semicolons, commas or
    /// blanks; `#` lines are comments.
    pub(crate) series: PathBuf,
    /// Column of the record's time (`YYYY-MM-DD[Thh:mm[:ss]][Z|±hh:mm]` or a plain number).
    #[arg(long)]
    pub(crate) time: String,
    /// Column of the significant wave height (m).
    #[arg(long)]
    pub(crate) hs: String,
    /// Column of the peak period (s).
    #[arg(long)]
    pub(crate) tp: String,
    /// Column of the direction the waves come from (deg clockwise from north).
    #[arg(long)]
    pub(crate) direction: String,
    /// Directory of the tables and `sectors.json` (created if missing; files of the same
    /// names are replaced).
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// Hs bin width (m): bins [k·w, (k+1)·w) from 0.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub(crate) hs_bin_m: f64,
    /// Tp bin width (s): columns centred on multiples c of it, each [c − w/2, c + w/2).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub(crate) tp_bin_s: f64,
    /// Hs bin edges (m), comma separated from 0, instead of --hs-bin-m: bins [e_k, e_k+1);
    /// records at or above the last edge are counted and left out.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with = "hs_bin_m"
    )]
    pub(crate) hs_edges_m: Option<Vec<f64>>,
    /// Tp bin edges (s), comma separated, instead of --tp-bin-s: columns [e_j, e_j+1) at their
    /// centres; records outside the edges are counted and left out.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        conflicts_with = "tp_bin_s"
    )]
    pub(crate) tp_edges_s: Option<Vec<f64>>,
    /// Number of direction sectors, the first centred on north (default 8).
    #[arg(
        long,
        allow_negative_numbers = true,
        conflicts_with = "sector_width_deg"
    )]
    pub(crate) sectors: Option<i64>,
    /// Width of a direction sector (deg), dividing 360 (instead of --sectors).
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) sector_width_deg: Option<f64>,
    /// Records with Hs below this (m) are calm: spread over the sectors by their shares, into
    /// the lowest Hs bin; at most --hs-bin-m.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub(crate) calm_hs_m: f64,
    /// Compass bearing of the model's +x axis (deg clockwise from north): the sectors' model
    /// headings follow from it.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub(crate) x_axis_bearing_deg: f64,
    /// A value marking missing data in the hs, tp and direction columns (e.g. -999 or 9999);
    /// repeatable, or comma separated.
    #[arg(
        long = "missing-value",
        allow_hyphen_values = true,
        value_delimiter = ','
    )]
    pub(crate) missing_values: Vec<f64>,
    /// Directory the campaign file will be in: the tables' paths in `sectors.json` are written
    /// relative to it (by default, relative to --out).
    #[arg(long)]
    pub(crate) relative_to: Option<PathBuf>,
}

/// The command-line option of a setting of [`ClimateSettings`].
fn option_of(field: &str) -> &'static str {
    match field {
        "hs_bin_m" => "--hs-bin-m",
        "tp_bin_s" => "--tp-bin-s",
        "hs_edges_m" => "--hs-edges-m",
        "tp_edges_s" => "--tp-edges-s",
        "sectors" => "--sectors",
        "calm_hs_m" => "--calm-hs-m",
        "x_axis_bearing_deg" => "--x-axis-bearing-deg",
        "missing_values" => "--missing-value",
        _ => "an option",
    }
}

/// The command-line option naming the column of `field`.
fn column_option(field: SeriesField) -> &'static str {
    match field {
        SeriesField::Time => "--time",
        SeriesField::Hs => "--hs",
        SeriesField::Tp => "--tp",
        SeriesField::Direction => "--direction",
    }
}

/// The error of the library in the words of the command line: settings by their options,
/// columns by the option naming them, anything else by the series' line and column.
fn climate_error(e: ClimateError, series: &Path) -> anyhow::Error {
    match &e {
        ClimateError::InvalidSetting { field, value, rule } => {
            let rule = rule.replace("finite (NaN is always missing)", "a finite number");
            anyhow::anyhow!("{} must be {rule}, got {}", option_of(field), Num(*value))
        }
        ClimateError::CalmAboveFirstBin {
            calm_hs_m,
            hs_bin_m,
        } => anyhow::anyhow!(
            "--calm-hs-m ({}) must not exceed the lowest Hs bin's upper edge ({} m: --hs-bin-m, \
             or the second of --hs-edges-m): calm records go into that bin",
            Num(*calm_hs_m),
            Num(*hs_bin_m)
        ),
        ClimateError::SharedColumn {
            first,
            second,
            name,
        } => anyhow::anyhow!(
            "{} and {} both name the column `{name}`",
            column_option(*first),
            column_option(*second)
        ),
        ClimateError::MissingColumn { field, .. } | ClimateError::AmbiguousColumn { field, .. } => {
            anyhow::anyhow!(
                "{}: in series {}: {e}",
                column_option(*field),
                series.display()
            )
        }
        _ => anyhow::anyhow!("in series {}: {e}", series.display()),
    }
}

/// The number of sectors from `--sectors` or `--sector-width-deg`.
fn sector_count(args: &ScatterArgs) -> anyhow::Result<usize> {
    match (args.sectors, args.sector_width_deg) {
        (Some(n), _) => {
            if !(1..=360).contains(&n) {
                bail!("--sectors must be a whole number from 1 to 360, got {n}");
            }
            Ok(n as usize)
        }
        (None, Some(w)) => {
            let n = 360.0 / w;
            if !(w.is_finite()
                && w > 0.0
                && (n - n.round()).abs() <= 1e-9 * n
                && n.round() <= 360.0)
            {
                bail!(
                    "--sector-width-deg must divide 360 into 1 to 360 sectors (e.g. 45, 30, \
                     22.5), got {}",
                    Num(w)
                );
            }
            Ok(n.round() as usize)
        }
        (None, None) => Ok(8),
    }
}

/// One summary line of a fault: `  <what>: <count> (first on line <l>: `<text>`)`.
fn fault_line(what: &str, fault: &Fault) -> String {
    match &fault.first {
        Some((line, text)) => format!("  {what}: {} (first on line {line}: `{text}`)", fault.count),
        None => format!("  {what}: 0"),
    }
}

/// Runs the command.
pub(crate) fn execute(args: ScatterArgs) -> anyhow::Result<()> {
    let settings = ClimateSettings {
        columns: SeriesColumns {
            time: args.time.clone(),
            hs: args.hs.clone(),
            tp: args.tp.clone(),
            direction: args.direction.clone(),
        },
        hs_bin_m: args.hs_bin_m,
        tp_bin_s: args.tp_bin_s,
        sectors: sector_count(&args)?,
        hs_edges_m: args.hs_edges_m.clone(),
        tp_edges_s: args.tp_edges_s.clone(),
        calm_hs_m: args.calm_hs_m,
        x_axis_bearing_deg: args.x_axis_bearing_deg,
        missing_values: args.missing_values.clone(),
    };
    // the options by their names, before the series is read or anything written
    settings
        .validate()
        .map_err(|e| climate_error(e, &args.series))?;
    if let Some(dir) = &args.relative_to {
        if !dir.is_dir() {
            bail!(
                "--relative-to {} must be an existing directory (where the campaign file will be)",
                dir.display()
            );
        }
    }
    if args.out.exists() && !args.out.is_dir() {
        bail!("--out {} is a file, not a directory", args.out.display());
    }
    let bytes = std::fs::read(&args.series)
        .with_context(|| format!("reading the series {}", args.series.display()))?;
    let text = String::from_utf8(bytes)
        .map_err(|e| anyhow::anyhow!("series {}: not UTF-8 text: {e}", args.series.display()))?;
    let climate = DirectionalClimate::from_series(&text, &settings)
        .map_err(|e| climate_error(e, &args.series))?;
    // the tables name the series by its file name only
    let source = args
        .series
        .file_name()
        .map_or_else(|| "series".to_owned(), |n| n.to_string_lossy().into_owned());
    let tables: Vec<(String, String)> = climate
        .sectors
        .iter()
        .enumerate()
        .filter_map(|(i, s)| Some((s.path.clone()?, climate.table_text(i, &source)?)))
        .collect();

    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let prefix = match &args.relative_to {
        Some(dir) => relative_path(&args.out, dir)?,
        None => PathBuf::new(),
    };
    for (name, table) in &tables {
        let path = args.out.join(name);
        std::fs::write(&path, table).with_context(|| format!("writing {}", path.display()))?;
    }
    // only sectors with a share: a campaign's sector needs a table and a share above 0
    let entries: Vec<serde_json::Value> = climate
        .sectors
        .iter()
        .filter(|s| s.share_percent > 0.0)
        .filter_map(|s| {
            let path = prefix.join(s.path.as_ref()?);
            // forward slashes on every platform: the file is shared
            let path = path
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/");
            Some(json!({
                "label": s.label,
                // + 0.0: a heading of −0 is 0
                "heading_deg": s.heading_deg + 0.0,
                "share_percent": s.share_percent,
                "path": path,
                "direction_from_deg": s.direction_from_deg,
            }))
        })
        .collect();
    let sectors_path = args.out.join(SECTORS_FILE);
    let fragment = serde_json::to_string_pretty(&json!({ "sectors": entries }))?;
    std::fs::write(&sectors_path, fragment + "\n")
        .with_context(|| format!("writing {}", sectors_path.display()))?;

    let c = &climate.counts;
    let step = match (c.time_step, c.time_kind) {
        (Some(s), TimeKind::Calendar) => format!("time step {} s", Num(s)),
        (Some(s), TimeKind::Number) => format!("time step {} (the column's unit)", Num(s)),
        (None, _) => "one record".to_owned(),
    };
    outln!(
        "series {}: {} to {}, {step}, {} time gap(s) (intervals without a record, not filled)",
        source,
        c.time_span.0,
        c.time_span.1,
        c.gaps
    )?;
    outln!(
        "records: {} read, {} used ({} calm, Hs below {} m), {} missing",
        c.records_read,
        c.records_used,
        c.calm,
        Num(settings.calm_hs_m),
        c.records_missing
    )?;
    outln!("{}", fault_line("missing hs", &c.hs_missing))?;
    outln!("{}", fault_line("missing tp", &c.tp_missing))?;
    outln!(
        "{}",
        fault_line(
            &format!(
                "tp below the first column ({} s)",
                Num(settings
                    .tp_edges_s
                    .as_ref()
                    .map_or(settings.tp_bin_s / 2.0, |e| e[0]))
            ),
            &c.tp_below_first_bin
        )
    )?;
    if settings.hs_edges_m.is_some() || settings.tp_edges_s.is_some() {
        outln!(
            "{}",
            fault_line(
                "hs or tp at or above the last bin edge",
                &c.beyond_last_edge
            )
        )?;
    }
    outln!(
        "{}",
        fault_line("missing direction (not calm)", &c.direction_missing)
    )?;
    outln!(
        "sectors: {} of {} deg, from north clockwise; model heading with +x to bearing {} deg",
        settings.sectors,
        Num(360.0 / settings.sectors as f64),
        Num(settings.x_axis_bearing_deg)
    )?;
    outln!("label\tfrom_deg\tto_deg\theading_deg\trecords\tcalm\tshare_percent\ttable")?;
    for s in &climate.sectors {
        outln!(
            "{}\t{}\t{}\t{}\t{}\t{:.3}\t{:.6}\t{}",
            s.label,
            Num(s.from_deg),
            Num(s.to_deg),
            Num(s.heading_deg + 0.0),
            s.records,
            s.calm_records,
            s.share_percent,
            s.path.as_deref().unwrap_or("-")
        )?;
    }
    let left = climate
        .sectors
        .iter()
        .filter(|s| s.path.is_some() && s.share_percent <= 0.0)
        .count();
    if left > 0 {
        outln!(
            "{left} sector(s) with records but a share that rounds to 0 % are not in {SECTORS_FILE}"
        )?;
    }
    outln!(
        "wrote {} table(s) and {} in {} (its \"sectors\" go into a campaign file's \"scatter\")",
        tables.len(),
        SECTORS_FILE,
        args.out.display()
    )?;
    Ok(())
}
