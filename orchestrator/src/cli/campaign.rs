//! `moorfret campaign launch|resume|status|cancel`.
//!
//! - `launch FILE [--db URL] [--workers N]`: resolve the campaign file (every referenced file
//!   read, hashed and checked; a bad campaign writes nothing), store it with its whole plan in
//!   one transaction, then drive it ([`super::drive`]).
//! - `resume NAME [--workers N]`: drive an interrupted campaign again (its plan is stored).
//! - `status [NAME] [--json]`: jobs per state and occurrence covered.
//! - `cancel NAME`: cancel every unfinished job; running workers lose their leases.
//!
//! Exit codes: 0 when the campaign ended with every job done (or for status/cancel), 1 on any
//! error or when jobs failed (their diagnostics are printed).

use crate::cli::output::outln;
use std::path::PathBuf;

use anyhow::{bail, Context};
use clap::Subcommand;
use serde_json::json;

use super::drive::{drive, DriveOptions};
use super::worker::StoreArgs;
use moorfret_campaign::resolve;
use moorfret_orchestrator::plan;
use moorfret_solver::waves::scatter::TotalKind;
use moorfret_store::{CampaignProgress, CampaignRecord, JobState, Store};

/// `campaign` subcommands.
#[derive(Debug, Subcommand)]
pub(crate) enum CampaignCommand {
    /// Plan a campaign file into the store and run it with local workers.
    Launch {
        /// Campaign file (JSON).
        file: PathBuf,
        /// Store, artifacts.
        #[command(flatten)]
        store: StoreArgs,
        /// Local worker processes (default: the number of cores).
        #[arg(long, allow_negative_numbers = true, value_parser = worker_count)]
        workers: Option<usize>,
        /// Leave the workers running the campaign to its end when this driver is stopped by
        /// SIGTERM, SIGINT or SIGHUP (by default they are stopped with it, their jobs returned
        /// to the queue).
        #[arg(long)]
        detach_workers: bool,
    },
    /// Run an interrupted campaign to its end with local workers.
    Resume {
        /// Campaign name.
        name: String,
        /// Store, artifacts.
        #[command(flatten)]
        store: StoreArgs,
        /// Local worker processes (default: the number of cores).
        #[arg(long, allow_negative_numbers = true, value_parser = worker_count)]
        workers: Option<usize>,
        /// Leave the workers running the campaign to its end when this driver is stopped by
        /// SIGTERM, SIGINT or SIGHUP (by default they are stopped with it, their jobs returned
        /// to the queue).
        #[arg(long)]
        detach_workers: bool,
    },
    /// Jobs per state and occurrence covered, of one campaign or all.
    Status {
        /// Campaign name (all campaigns when absent).
        name: Option<String>,
        /// Store.
        #[command(flatten)]
        store: StoreArgs,
        /// Machine-readable output.
        #[arg(long)]
        json: bool,
    },
    /// Cancel every unfinished job of a campaign.
    Cancel {
        /// Campaign name.
        name: String,
        /// Store.
        #[command(flatten)]
        store: StoreArgs,
    },
}

/// A number of local worker processes: a whole number of at least 1 (a negative number is
/// read as a value, so that it is refused by `--workers`' name, not as an unknown option).
fn worker_count(text: &str) -> Result<usize, String> {
    match text.trim().parse::<i64>() {
        Ok(n) if n >= 1 => usize::try_from(n).map_err(|e| e.to_string()),
        Ok(n) => Err(format!("{n} workers: must be at least 1")),
        Err(_) => Err(format!("{text}: must be a whole number of at least 1")),
    }
}

/// Runs a `campaign` subcommand.
pub(crate) fn execute(cmd: CampaignCommand) -> anyhow::Result<()> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    runtime.block_on(async move {
        match cmd {
            CampaignCommand::Launch {
                file,
                store,
                workers,
                detach_workers,
            } => launch(&file, &store, workers, detach_workers).await,
            CampaignCommand::Resume {
                name,
                store,
                workers,
                detach_workers,
            } => {
                let db = store.config().open_existing().await?;
                let record = find(&db, &name).await?;
                if record.state == moorfret_store::CampaignState::Cancelled {
                    bail!("campaign {name} was cancelled; it cannot be resumed");
                }
                check_artifacts_writable(&store)?;
                run_to_end(&db, &store, &record, workers, detach_workers).await
            }
            CampaignCommand::Status { name, store, json } => status(&store, name, json).await,
            CampaignCommand::Cancel { name, store } => {
                let db = store.config().open_existing().await?;
                let record = find(&db, &name).await?;
                let report = db.cancel_campaign(record.id).await?;
                if report.jobs_cancelled == 0 {
                    outln!(
                        "campaign {name}: nothing left to cancel (every job is finished; it \
                         stays {})",
                        record.state.as_str()
                    )?;
                } else {
                    outln!("campaign {name}: {} jobs cancelled", report.jobs_cancelled)?;
                }
                Ok(())
            }
        }
    })
}

/// The artifact directory must take files before a campaign is stored or resumed: a worker
/// that cannot write its results would only fail and be restarted.
fn check_artifacts_writable(args: &StoreArgs) -> anyhow::Result<()> {
    args.config()
        .artifact_store()?
        .check_writable()
        .context("the artifact directory is not writable")
}

async fn launch(
    file: &std::path::Path,
    args: &StoreArgs,
    workers: Option<usize>,
    detach_workers: bool,
) -> anyhow::Result<()> {
    let resolved = resolve(file).with_context(|| format!("in campaign file {}", file.display()))?;
    report_climate(&resolved);
    // What stands where the artifact directory goes is checked before the store is opened,
    // so that a refusal leaves the store's files as they were. An existing file must be a
    // moorfret store (it is refused untouched otherwise); a new store is created only once the
    // artifact directory is known to take files.
    args.config().check_existing_artifacts()?;
    let existing = args.config().open_if_present().await?;
    if let Err(err) = check_artifacts_writable(args) {
        if let Some(store) = existing {
            store.close().await;
        }
        return Err(err);
    }
    let store = match existing {
        Some(store) => store,
        None => args.config().open().await?,
    };
    let started = std::time::Instant::now();
    let (id, jobs) = plan::create(&store, &resolved)
        .await
        .with_context(|| format!("storing campaign {}", resolved.inputs.spec.name))?;
    tracing::info!(
        campaign = %resolved.inputs.spec.name,
        id = %id,
        jobs = jobs.len(),
        seconds = started.elapsed().as_secs_f64(),
        "campaign planned"
    );
    let record = find(&store, &resolved.inputs.spec.name).await?;
    run_to_end(&store, args, &record, workers, detach_workers).await
}

async fn find(store: &Store, name: &str) -> anyhow::Result<CampaignRecord> {
    let all = store.campaigns().await?;
    let known: Vec<String> = all.iter().map(|c| c.name.clone()).collect();
    all.into_iter().find(|c| c.name == name).with_context(|| {
        format!(
            "no campaign named {name} in this store (it has: {})",
            known.join(", ")
        )
    })
}

async fn run_to_end(
    store: &Store,
    args: &StoreArgs,
    record: &CampaignRecord,
    workers: Option<usize>,
    detach_workers: bool,
) -> anyhow::Result<()> {
    let workers = workers
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let progress = drive(
        store,
        record,
        &DriveOptions {
            workers,
            child_args: args.config().child_args(),
            detach_workers,
        },
    )
    .await?;
    let failed = progress.count(JobState::Failed);
    if failed > 0 {
        let jobs = store.jobs_of_campaign(record.id).await?;
        for job in jobs.iter().filter(|j| j.state == JobState::Failed) {
            eprintln!(
                "job {} ({}) failed: {}: {}",
                job.id,
                job.kind,
                job.error_class.map_or("?", |c| c.as_str()),
                job.error_message.as_deref().unwrap_or("")
            );
        }
        let done = progress.count(JobState::Done);
        if failed == progress.jobs_total {
            bail!("campaign {}: all {failed} jobs failed", record.name);
        }
        bail!(
            "campaign {}: {failed} of {} jobs failed, {done} done",
            record.name,
            progress.jobs_total
        );
    }
    Ok(())
}

/// What the wave cut-offs of a campaign's sea states keep: the least energy kept, and the
/// sea states flagged for keeping less than 90 % with their occurrence (`None` when the
/// store holds no energy kept for them: planned before it was stored).
pub(crate) struct EnergySummary {
    least: f64,
    flagged: usize,
    occurrence_flagged: f64,
}

impl EnergySummary {
    fn of(states: &[moorfret_store::SeaStateStatus]) -> Option<Self> {
        let known: Vec<_> = states
            .iter()
            .filter_map(|s| s.wave_energy_kept.map(|k| (s.occurrence_fraction, k)))
            .collect();
        if known.is_empty() {
            return None;
        }
        let flagged: Vec<_> = known
            .iter()
            .filter(|(_, k)| moorfret_orchestrator::query::energy_flagged(*k))
            .collect();
        Some(Self {
            least: known.iter().map(|(_, k)| *k).fold(f64::INFINITY, f64::min),
            flagged: flagged.len(),
            occurrence_flagged: flagged.iter().map(|(o, _)| o).sum::<f64>() + 0.0,
        })
    }
}

/// The `--json` form of a campaign's status.
pub(crate) fn status_json(
    record: &CampaignRecord,
    p: &CampaignProgress,
    energy: Option<&EnergySummary>,
) -> serde_json::Value {
    let jobs: serde_json::Map<String, serde_json::Value> = JobState::ALL
        .iter()
        .map(|s| (s.as_str().to_owned(), json!(p.count(*s))))
        .collect();
    json!({
        "campaign": record.name,
        "state": record.state.as_str(),
        "jobs": jobs,
        "jobs_total": p.jobs_total,
        "occurrence_planned": p.occurrence_planned,
        "occurrence_covered": p.occurrence_covered,
        "wave_energy_kept_min": energy.map(|e| e.least),
        "sea_states_energy_flagged": energy.map(|e| e.flagged),
        "occurrence_energy_flagged": energy.map(|e| e.occurrence_flagged),
    })
}

async fn status(args: &StoreArgs, name: Option<String>, as_json: bool) -> anyhow::Result<()> {
    let store = args.config().open_existing().await?;
    let records = match &name {
        Some(n) => vec![find(&store, n).await?],
        None => store.campaigns().await?,
    };
    let mut out = Vec::new();
    for record in &records {
        let p = store.progress(record.id).await?;
        let energy = EnergySummary::of(&store.sea_state_status(record.id).await?);
        if as_json {
            out.push(status_json(record, &p, energy.as_ref()));
        } else {
            outln!(
                "{} ({}): {} jobs: {} done, {} running, {} ready, {} blocked, {} failed, {} cancelled; occurrence covered {:.3} % of the year ({:.3} % planned)",
                record.name,
                record.state.as_str(),
                p.jobs_total,
                p.count(JobState::Done),
                p.count(JobState::Running),
                p.count(JobState::Ready),
                p.count(JobState::Blocked),
                p.count(JobState::Failed),
                p.count(JobState::Cancelled),
                100.0 * p.occurrence_covered,
                100.0 * p.occurrence_planned
            )?;
            if let Some(e) = &energy {
                outln!(
                    "  wave energy kept: at least {:.1} % per sea state; {} sea state(s), {:.4} % \
                     of the year, below {:.0} % (flagged)",
                    100.0 * e.least,
                    e.flagged,
                    100.0 * e.occurrence_flagged,
                    100.0 * moorfret_campaign::sea_limits::FLAG_ENERGY_KEPT
                )?;
            }
        }
    }
    if as_json {
        let value = if name.is_some() {
            out.pop().unwrap_or_default()
        } else {
            serde_json::Value::Array(out)
        };
        outln!("{value}")?;
    }
    Ok(())
}

/// Logs what resolution found in the climate's tables: printed totals that differ from their
/// cells, cells left out of the plan, sea states whose wave cut-off keeps little energy, and
/// the directional sectors with their shares.
fn report_climate(resolved: &moorfret_campaign::ResolvedCampaign) {
    for f in &resolved.inputs.hot_spot_screening {
        tracing::info!(
            "hot spot found on line {} at s = {} m: equivalent strain range {:.3e}, most from Hs {} m, Tp {} s{}",
            f.line,
            f.arc_length_m,
            f.equivalent_strain_range,
            f.governing_hs_m,
            f.governing_tp_s,
            f.governing_sector
                .as_deref()
                .map_or(String::new(), |s| format!(" in sector {s}"))
        );
    }
    for sector in &resolved.sectors {
        for m in &sector.mismatches {
            let which = match m.kind {
                TotalKind::Row {
                    hs_lower_m,
                    hs_upper_m,
                } => format!("row total of Hs {hs_lower_m}-{hs_upper_m} m"),
                TotalKind::Column { tp_s } => format!("column total of Tp {tp_s} s"),
                TotalKind::Grand => "grand total".to_owned(),
            };
            tracing::warn!(
                "scatter diagram {} line {}: printed {which} {} differs from the sum of its cells {:.4}; the cells are used",
                sector.source.path,
                m.line,
                m.printed,
                m.computed
            );
        }
    }
    for (sector, c) in resolved.left_out() {
        tracing::warn!(
            "sea state Hs {} m, Tp {} s ({:.4} % of the year{}) left out of the plan: {}; its \
             occurrence is neither planned nor covered",
            c.limits.hs_m,
            c.limits.tp_s,
            100.0 * plan::occurrence_fraction(c.value, sector.source.reading),
            sector
                .source
                .label
                .as_deref()
                .map(|l| format!(", sector {l}"))
                .unwrap_or_default(),
            c.limits.faults.join("; ")
        );
    }
    for (sector, l) in resolved
        .sectors
        .iter()
        .flat_map(|s| s.planned_limits.iter().map(move |l| (s, l)))
    {
        if !l.flags.is_empty() {
            tracing::warn!(
                "sea state Hs {} m, Tp {} s{} flagged: {}",
                l.hs_m,
                l.tp_s,
                sector
                    .source
                    .label
                    .as_deref()
                    .map(|l| format!(" (sector {l})"))
                    .unwrap_or_default(),
                l.flags.join("; ")
            );
        }
    }
    for sector in &resolved.sectors {
        if let (Some(label), moorfret_campaign::spec::ScatterReading::Sector { share_percent }) =
            (&sector.source.label, sector.source.reading)
        {
            tracing::info!(
                "sector {label}: heading {} deg, {share_percent} % of the year, {} sea states \
                 from {}",
                sector.source.heading_deg,
                sector.planned_limits.len(),
                sector.source.path
            );
        }
    }
}
