//! The reduced strand response on the command line
//! (`moorfret_solver::strand::reduced`): `moorfret run strand … --load LOAD.csv --fidelity
//! reduced`, and `moorfret strand calibrate`.
//!
//! A calibration belongs to one FE model (profile, regularisation, ends, the settings of the
//! FE history run) and covers one load range. Calibrations are kept in a cache
//! (`<cache>/reduced/<model key>/<range key>.json`, the cache directory of the EA values), so a
//! model is calibrated once: a history run looks for a calibration of its model whose range
//! covers the history, and calibrates one over the history's range (widened by
//! `--calibration-margin` on each side) when there is none. `--calibration FILE` uses a given
//! file instead, refused if it belongs to another model or does not cover the history.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use clap::Args;
use moorfret_campaign::stiffness::replace_file;
use moorfret_solver::strand::history::{HistoryObserver, HistoryOptions, LoadSample};
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::Strand;
use moorfret_solver::strand::reduced::{
    calibrate, model_key, CalibrationOptions, LoadRange, ReducedStrand,
};
use serde::Serialize;
use sha2::{Digest, Sha256};

/// Fidelity of a strand history run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Fidelity {
    /// The strand FE model.
    #[default]
    Fe,
    /// The per-contact response calibrated on the FE model (seconds instead of minutes).
    Reduced,
}

impl Fidelity {
    pub(crate) fn as_str(self) -> &'static str {
        match self {
            Self::Fe => "fe",
            Self::Reduced => "reduced",
        }
    }
}

/// Options of the reduced response.
#[derive(Debug, Args)]
pub(crate) struct ReducedArgs {
    /// Model of a history run: `fe`, the strand FE model, or `reduced`, its calibrated
    /// per-contact response (same output files).
    #[arg(long, value_enum, default_value_t = Fidelity::Fe)]
    pub(crate) fidelity: Fidelity,
    /// Calibration of the reduced response to use (from `moorfret strand calibrate --out`);
    /// default: a cached calibration of the model covering the load, else a new one.
    #[arg(long)]
    pub(crate) calibration: Option<PathBuf>,
    /// Margin on each side of the load's range when a calibration is made for it, as a
    /// fraction of the range.
    #[arg(long, default_value_t = 0.05)]
    pub(crate) calibration_margin: f64,
}

/// Where the calibration of a run came from.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct CalibrationSource {
    /// "given" (`--calibration`), "cached", or "calibrated" (by this run).
    pub(crate) source: &'static str,
    /// Its file (null if it could not be cached).
    pub(crate) file: Option<String>,
    /// The load range it covers.
    pub(crate) range: LoadRange,
    /// Wall time of the calibration's FE run (s).
    pub(crate) calibration_wall_time_s: f64,
    /// Samples of this run below the lowest strain the calibration's design visited (near
    /// slack; run with the fitted laws continued, see `strand::reduced::design`).
    pub(crate) samples_below_design_strain: usize,
}

/// The cache directory: `dir`, else `$XDG_CACHE_HOME/moorfret`, else `~/.cache/moorfret`.
pub(crate) fn cache_root(dir: Option<&Path>) -> Option<PathBuf> {
    match dir {
        Some(d) => Some(d.to_path_buf()),
        None => Some(
            std::env::var_os("XDG_CACHE_HOME")
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
                .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?
                .join("moorfret"),
        ),
    }
}

fn sha256_hex(text: &str) -> String {
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn read_calibration(path: &Path) -> anyhow::Result<ReducedStrand> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading calibration {}", path.display()))?;
    ReducedStrand::from_json(text.as_bytes())
        .with_context(|| format!("in calibration {}", path.display()))
}

/// The cached calibration of `key` covering `range` with the narrowest range, if any.
fn cached(dir: &Path, range: &LoadRange) -> Option<(PathBuf, ReducedStrand)> {
    let mut best: Option<(f64, PathBuf, ReducedStrand)> = None;
    for entry in std::fs::read_dir(dir).ok()?.flatten() {
        let path = entry.path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let Ok(reduced) = read_calibration(&path) else {
            continue;
        };
        if !reduced.range.covers(range) {
            continue;
        }
        let r = &reduced.range;
        let size = (r.strain[1] - r.strain[0]) * (r.curvature_per_m[1] - r.curvature_per_m[0]);
        if best.as_ref().is_none_or(|b| size < b.0) {
            best = Some((size, path, reduced));
        }
    }
    best.map(|(_, p, r)| (p, r))
}

/// What a run needs to find or make a calibration.
pub(crate) struct CalibrationRequest<'a> {
    pub(crate) strand: &'a Strand,
    pub(crate) params: &'a StrandModelParameters,
    pub(crate) cache_dir: Option<&'a Path>,
    pub(crate) given: Option<&'a Path>,
    pub(crate) threads: usize,
    /// Recalibrate even if the cache holds a covering calibration.
    pub(crate) refresh: bool,
}

/// A calibration of the model for `range`: the given file, a cached one, or a new one over
/// `calibrate_over` (made on the model `build()` returns, cached).
pub(crate) fn calibration_for(
    req: &CalibrationRequest<'_>,
    range: &LoadRange,
    calibrate_over: LoadRange,
    build: &mut dyn FnMut() -> anyhow::Result<StrandModel>,
    observer: &mut dyn HistoryObserver,
) -> anyhow::Result<(ReducedStrand, CalibrationSource)> {
    let options = CalibrationOptions {
        history: HistoryOptions {
            threads: req.threads,
            ..HistoryOptions::default()
        },
        ..CalibrationOptions::default()
    };
    let key = model_key(req.strand, req.params, &options);
    let source = |s, file: Option<&Path>, r: &ReducedStrand| CalibrationSource {
        source: s,
        file: file.map(|f| f.display().to_string()),
        range: r.range,
        calibration_wall_time_s: r.calibration.fe_wall_time_s,
        samples_below_design_strain: 0,
    };
    if let Some(path) = req.given {
        let reduced = read_calibration(path)?;
        if reduced.model_key != key {
            bail!(
                "calibration {} was made on another strand model or with other settings (its \
                 model key {:.12}…, this run's {:.12}…); calibrate this model with `moorfret \
                 strand calibrate`",
                path.display(),
                reduced.model_key,
                key
            );
        }
        if !reduced.range.covers(range) {
            bail!(
                "calibration {} covers strain {:?} and curvature {:?} 1/m, not this load's \
                 strain {:?} and curvature {:?} 1/m; calibrate over a range that covers it",
                path.display(),
                reduced.range.strain,
                reduced.range.curvature_per_m,
                range.strain,
                range.curvature_per_m
            );
        }
        let s = source("given", Some(path), &reduced);
        return Ok((reduced, s));
    }
    let dir = cache_root(req.cache_dir).map(|d| d.join("reduced").join(&key));
    if !req.refresh {
        if let Some((path, reduced)) = dir.as_deref().and_then(|d| cached(d, range)) {
            if reduced.model_key == key {
                let s = source("cached", Some(&path), &reduced);
                return Ok((reduced, s));
            }
        }
    }
    let calibrate_over = calibrate_over.union(*range);
    tracing::info!(
        "calibrating the reduced strand response over strain {:?}, curvature {:?} 1/m",
        calibrate_over.strain,
        calibrate_over.curvature_per_m
    );
    let model = build()?;
    let mut reduced = calibrate(&model, calibrate_over, &options, observer)
        .context("calibrating the reduced strand response")?;
    reduced.model_key = key;
    let file = dir.map(|d| {
        d.join(format!(
            "{}.json",
            &sha256_hex(&format!("{:?}", reduced.range))[..16]
        ))
    });
    let written = match &file {
        Some(f) => match serde_json::to_vec(&reduced)
            .map_err(std::io::Error::other)
            .and_then(|b| replace_file(f, &b))
        {
            Ok(()) => true,
            Err(e) => {
                tracing::warn!(error = %e, file = %f.display(), "calibration not cached");
                false
            }
        },
        None => false,
    };
    let s = source("calibrated", file.as_deref().filter(|_| written), &reduced);
    Ok((reduced, s))
}

/// Writes a calibration to `path` (temp file and rename).
pub(crate) fn write_calibration(path: &Path, reduced: &ReducedStrand) -> anyhow::Result<()> {
    replace_file(path, &serde_json::to_vec(reduced)?)
        .with_context(|| format!("writing {}", path.display()))
}

/// The range of `samples`, or an error naming the empty history.
pub(crate) fn range_of(samples: &[LoadSample]) -> anyhow::Result<LoadRange> {
    LoadRange::of(samples).ok_or_else(|| anyhow!("the load history has no samples"))
}
