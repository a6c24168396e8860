//! Driving a stored campaign with local worker processes: start `workers` children
//! (`moorfret worker --exit-when-idle` on the same store), restart any that dies while work
//! remains, show progress (an indicatif bar with jobs, occurrence covered and ETA on a
//! terminal, plain log lines otherwise) and stop the children with SIGTERM once the campaign
//! has no ready, running or blocked job left.
//!
//! A driver stopped by SIGTERM, SIGINT or SIGHUP stops its workers first (SIGTERM: each hands
//! its running job back to the queue without consuming an attempt), so nothing runs on and
//! nothing is lost: `campaign resume` completes the campaign with the same results. With
//! `--detach-workers` the workers are started in a process group of their own and left running
//! the campaign to its end when the driver stops. A driver killed outright (SIGKILL) leaves
//! its workers running too; they finish the campaign and exit when idle.

use std::io::IsTerminal;
use std::process::Stdio;
use std::time::{Duration, Instant};

use anyhow::Context;
use tokio::process::{Child, Command};

use moorfret_store::{CampaignProgress, CampaignRecord, JobState, Store};

/// Restarts of dead workers allowed per worker slot before the driver gives up.
const MAX_RESTARTS_PER_WORKER: usize = 50;

/// How to drive.
#[derive(Debug, Clone)]
pub(crate) struct DriveOptions {
    /// Worker processes.
    pub(crate) workers: usize,
    /// Store arguments handed to each worker.
    pub(crate) child_args: Vec<String>,
    /// Leave the workers running when the driver is stopped by a signal (they are started in a
    /// process group of their own, out of reach of a terminal's Ctrl-C).
    pub(crate) detach_workers: bool,
}

fn spawn_worker(options: &DriveOptions) -> anyhow::Result<Child> {
    let exe = std::env::current_exe().context("locating the moorfret executable")?;
    let mut cmd = Command::new(exe);
    cmd.arg("worker")
        .args(&options.child_args)
        .arg("--exit-when-idle")
        .stdin(Stdio::null())
        .stdout(Stdio::null());
    if std::env::var_os("RUST_LOG").is_none() {
        cmd.env("RUST_LOG", "warn");
    }
    if options.detach_workers {
        cmd.process_group(0);
    }
    cmd.spawn().context("starting a worker process")
}

/// Whether process `pid` of this host is alive and a moorfret process (a pid reused by another
/// program counts as dead). Without `/proc`, every process counts as alive: leases then end
/// when they run out.
fn is_moorfret_process(pid: i64) -> bool {
    if !std::path::Path::new("/proc/self").exists() {
        return true;
    }
    std::fs::read(format!("/proc/{pid}/cmdline"))
        .map(|c| String::from_utf8_lossy(&c).contains("moorfret"))
        .unwrap_or(false)
}

/// Asks a worker to stop (SIGTERM: it releases its lease) and waits for it.
async fn stop(mut child: Child) {
    if let Some(pid) = child.id() {
        let _ = Command::new("kill")
            .arg("-TERM")
            .arg(pid.to_string())
            .status()
            .await;
    }
    if tokio::time::timeout(Duration::from_secs(15), child.wait())
        .await
        .is_err()
    {
        let _ = child.kill().await;
    }
}

/// Stops every worker at once and waits for them all.
async fn stop_all(children: Vec<Child>) {
    let stops: Vec<_> = children
        .into_iter()
        .map(|c| tokio::spawn(stop(c)))
        .collect();
    for s in stops {
        let _ = s.await;
    }
}

/// SIGTERM, SIGINT and SIGHUP, caught from the moment the driver starts its workers.
struct StopSignals {
    term: tokio::signal::unix::Signal,
    int: tokio::signal::unix::Signal,
    hup: tokio::signal::unix::Signal,
}

impl StopSignals {
    fn install() -> anyhow::Result<Self> {
        use tokio::signal::unix::{signal, SignalKind};
        let install = |kind| signal(kind).context("installing the driver's signal handlers");
        Ok(Self {
            term: install(SignalKind::terminate())?,
            int: install(SignalKind::interrupt())?,
            hup: install(SignalKind::hangup())?,
        })
    }

    /// Resolves on the next signal, with its name.
    async fn recv(&mut self) -> &'static str {
        tokio::select! {
            _ = self.term.recv() => "SIGTERM",
            _ = self.int.recv() => "SIGINT",
            _ = self.hup.recv() => "SIGHUP",
        }
    }
}

fn open_jobs(p: &CampaignProgress) -> i64 {
    p.count(JobState::Ready) + p.count(JobState::Running) + p.count(JobState::Blocked)
}

fn finished_jobs(p: &CampaignProgress) -> u64 {
    (p.jobs_total - open_jobs(p)).max(0).unsigned_abs()
}

/// Runs the campaign to its end; returns its final progress.
pub(crate) async fn drive(
    store: &Store,
    record: &CampaignRecord,
    options: &DriveOptions,
) -> anyhow::Result<CampaignProgress> {
    let mut progress = store.progress(record.id).await?;
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(progress.jobs_total.max(0).unsigned_abs());
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {pos}/{len} jobs, {msg}, ETA {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let host = moorfret_worker::this_process().host;
    // Leases of this host's workers that died with an earlier driver (a crash, SIGKILL) end
    // now, instead of when they run out.
    let dead: Vec<i64> = store
        .running_on_host(&host)
        .await?
        .into_iter()
        .map(|(_, pid)| pid)
        .filter(|&pid| !is_moorfret_process(pid))
        .collect();
    if !dead.is_empty() {
        let swept = store.expire_leases_of(&host, &dead).await?;
        tracing::info!(
            requeued = swept.requeued.len(),
            failed = swept.failed.len(),
            "jobs of dead worker processes of this host taken back"
        );
    }
    let mut signals = StopSignals::install()?;
    let mut children = Vec::with_capacity(options.workers);
    if open_jobs(&progress) > 0 {
        for _ in 0..options.workers {
            children.push(spawn_worker(options)?);
        }
    }
    let mut restarts = 0;
    let mut last_log = Instant::now();
    let mut last_finished = u64::MAX;
    loop {
        progress = store.progress(record.id).await?;
        let finished = finished_jobs(&progress);
        let running = progress.count(JobState::Running);
        // Jobs running on workers this driver did not start (another host, a worker started
        // by hand or by a scheduler, one that died elsewhere): the campaign waits on their
        // leases, which return when those workers finish or their leases run out.
        let ours: Vec<i64> = children
            .iter()
            .filter_map(|c| c.id().map(i64::from))
            .collect();
        let held_here = if running > 0 {
            store
                .running_on_host(&host)
                .await?
                .into_iter()
                .filter(|(_, pid)| ours.contains(pid))
                .count()
        } else {
            0
        };
        let elsewhere = usize::try_from(running)
            .unwrap_or(0)
            .saturating_sub(held_here);
        let waiting = if elsewhere > 0 {
            format!(
                " ({elsewhere} on workers this driver did not start: waiting for them or for \
                 their leases to run out)"
            )
        } else {
            String::new()
        };
        let message = format!(
            "{running} running{waiting}, {} failed, occurrence covered {:.3} % of {:.3} % planned",
            progress.count(JobState::Failed),
            100.0 * progress.occurrence_covered,
            100.0 * progress.occurrence_planned
        );
        if let Some(b) = &bar {
            b.set_position(finished);
            b.set_message(message);
        } else if finished != last_finished || last_log.elapsed() > Duration::from_secs(30) {
            tracing::info!(
                "campaign {}: {finished}/{} jobs finished, {message}",
                record.name,
                progress.jobs_total
            );
            last_finished = finished;
            last_log = Instant::now();
        }
        if open_jobs(&progress) == 0 {
            break;
        }
        for child in &mut children {
            let pid = child.id();
            if let Ok(Some(status)) = child.try_wait() {
                // its leases end now: nobody else holds them
                if let Some(pid) = pid {
                    store.expire_leases_of(&host, &[i64::from(pid)]).await?;
                }
                restarts += 1;
                if restarts > MAX_RESTARTS_PER_WORKER * options.workers {
                    anyhow::bail!(
                        "worker processes keep dying ({restarts} restarts); last exit {status}"
                    );
                }
                tracing::warn!(%status, "worker exited while work remains; starting another");
                *child = spawn_worker(options)?;
            }
        }
        store.sweep_expired().await?;
        let stopped = tokio::select! {
            name = signals.recv() => Some(name),
            () = tokio::time::sleep(Duration::from_millis(500)) => None,
        };
        if let Some(name) = stopped {
            if let Some(b) = &bar {
                b.abandon();
            }
            if options.detach_workers {
                let n = children.len();
                // the children outlive the driver (`Child` does not kill on drop)
                drop(children);
                anyhow::bail!(
                    "campaign {}: driver stopped by {name}; its {n} worker(s) go on running the \
                     campaign to its end (--detach-workers)",
                    record.name
                );
            }
            let pids: Vec<i64> = children
                .iter()
                .filter_map(|c| c.id().map(i64::from))
                .collect();
            stop_all(children).await;
            // their running jobs are back in the queue (released on SIGTERM); a worker that
            // had to be killed loses its lease now rather than when it runs out
            store.expire_leases_of(&host, &pids).await?;
            anyhow::bail!(
                "campaign {}: stopped by {name}; its workers were stopped and their jobs \
                 returned to the queue (`campaign resume {}` completes it)",
                record.name,
                record.name
            );
        }
    }
    if let Some(b) = &bar {
        b.finish();
    }
    stop_all(children).await;
    tracing::info!(
        "campaign {}: {} done, {} failed, {} cancelled of {} jobs; occurrence covered {:.3} % of the year",
        record.name,
        progress.count(JobState::Done),
        progress.count(JobState::Failed),
        progress.count(JobState::Cancelled),
        progress.jobs_total,
        100.0 * progress.occurrence_covered
    );
    Ok(progress)
}
