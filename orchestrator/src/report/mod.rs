//! `moorfret report`: one self-contained HTML page of a campaign's results (inline SVG, no
//! network resources), written to `DIR/index.html`.
//!
//! Content (every map with its colour bar):
//! - the design check ([`crate::design`]) and the sea states without results: failed (the first
//!   failure's diagnostic), skipped (cells left out of the plan, as stored with the campaign;
//!   cancelled jobs) and not run yet, with their sector, Hs, Tp and occurrence;
//! - for a directional climate, one scatter map per sector (occurrence, and the share of the
//!   critical class's annual fretting damage), on a log colour scale shared by the sectors;
//! - the scatter diagram (Tp × Hs) coloured by each sea state's share of the annual fretting
//!   damage of the critical contact class (largest `fretting_max` annual damage in
//!   `lifetime_class_damage`), and separately by its share of the annual T-N damage of that
//!   hot spot (first T-N measure in name order);
//! - the hot-spot tension and curvature series of one global job, read from its series artifacts
//!   artifact (the layout `run global` writes) when the artifact directory holds it;
//! - slip-amplitude histograms per layer interface: cycles per hour of the year
//!   (Σ over sea states of occurrence × seed-mean cycles per hour, summed over the angular
//!   positions and normal-force bins of the interface);
//! - tables: lifetime damage, and the damage inputs of the critical class per sea state.
//!
//! Shares are ratios of occurrence × seed-mean damage rate, the terms of the lifetime sums.

pub mod data;
mod html;
mod plots;

use std::path::Path;

use anyhow::Context;

use moorfret_store::{ArtifactStore, Store};

pub use data::ReportData;

/// Writes the report of campaign `name` into `out_dir` (created if missing); returns the page.
pub async fn write_report(
    store: &Store,
    name: &str,
    out_dir: &Path,
    artifacts: Option<&ArtifactStore>,
) -> anyhow::Result<std::path::PathBuf> {
    let data = data::gather(store, name, artifacts).await?;
    let page = html::page(&data)?;
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("creating the report directory {}", out_dir.display()))?;
    let path = out_dir.join("index.html");
    std::fs::write(&path, page).with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}
