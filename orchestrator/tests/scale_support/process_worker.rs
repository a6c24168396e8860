//! A worker process on the store API for the fault tests: the test binary starts itself again
//! with `MOORFRET_FAULT_WORKER_DB` set, and [`run_if_requested`] then runs this loop instead of
//! the tests.
//!
//! The loop is the store protocol a worker follows (ARCHITECTURE.md, "Data flow of a campaign"):
//! register; claim (sweeping expired leases first when nothing is ready); heartbeat from a separate
//! task while the job runs; complete guarded by the lease token. Every store call goes through
//! [`RetryPolicy::run`], so a database that goes away is waited for. Test jobs sleep for their
//! payload's duration. Each event is printed on stdout as one line (`CLAIMED job=…`,
//! `COMPLETED job=…`, `REJECTED job=…`) for the test to read.

use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use moorfret_store::{
    complete_with_retry, CampaignId, ClaimFilter, Clock, JobResults, QueuePolicy, RetryPolicy,
    Store, StoreError, StoreOptions, TestPayload, WorkerInfo,
};
use serde_json::json;

const DB_VAR: &str = "MOORFRET_FAULT_WORKER_DB";
const NAME_VAR: &str = "MOORFRET_FAULT_WORKER_NAME";
/// The fault tests' databases hold one campaign, the first.
const CAMPAIGN: CampaignId = CampaignId(1);

/// Lease and heartbeat of the fault tests: short, so that a cut-off worker's lease expires
/// within seconds.
pub fn fault_policy() -> QueuePolicy {
    QueuePolicy {
        lease_ms: 2_000,
        heartbeat_interval_ms: 400,
        max_lost: 5,
        backoff_base_ms: 100,
        backoff_cap_ms: 1_000,
    }
}

/// Backoff for store calls: retries for up to a minute, so a test fails rather than hangs.
pub fn fault_retry() -> RetryPolicy {
    RetryPolicy {
        initial_delay: Duration::from_millis(50),
        max_delay: Duration::from_secs(1),
        give_up_after: Duration::from_secs(60),
    }
}

/// A worker process, killed if dropped before it exited.
pub struct WorkerProcess {
    child: Option<Child>,
}

impl WorkerProcess {
    /// Starts `command` with stdout and stderr captured (its output must stay below the pipe
    /// buffer, a few tens of kB, until it is read after exit).
    pub fn start(mut command: Command) -> Self {
        let child = command
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start worker process");
        Self { child: Some(child) }
    }

    /// Process id.
    pub fn pid(&self) -> i64 {
        i64::from(self.child.as_ref().expect("worker process").id())
    }

    /// Waits (at most `limit`) for the process to exit; returns whether it succeeded and the
    /// event lines it printed.
    pub async fn finish(mut self, limit: Duration) -> (bool, Vec<String>) {
        let start = std::time::Instant::now();
        let mut child = self.child.take().expect("worker process");
        loop {
            if let Some(status) = child.try_wait().expect("wait for worker") {
                return (status.success(), read_events(&mut child));
            }
            if start.elapsed() > limit {
                let _ = child.kill();
                let _ = child.wait();
                panic!("worker did not exit within {limit:?}");
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }
}

impl Drop for WorkerProcess {
    fn drop(&mut self) {
        if let Some(child) = self.child.as_mut() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Starts this test binary as a worker named `name` on `url`, through `launcher` (e.g.
/// `ip netns exec NS`) if given; its event lines are read by [`WorkerProcess::finish`].
pub fn spawn(launcher: Option<Command>, url: &str, name: &str) -> WorkerProcess {
    let exe = std::env::current_exe().expect("test binary path");
    let mut command = match launcher {
        Some(mut prefix) => {
            prefix.arg(&exe);
            prefix
        }
        None => Command::new(&exe),
    };
    command
        .env(DB_VAR, url)
        .env(NAME_VAR, name)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map(|child| WorkerProcess { child: Some(child) })
        .expect("start worker process")
}

/// Starts `moorfret worker` against `url` with the fault tests' lease ([`fault_policy`]), idle
/// exit and artifacts in `artifacts`, behind `launcher` if given (e.g. `ip netns exec …`).
pub fn spawn_moorfret(
    launcher: Option<Command>,
    url: &str,
    artifacts: &std::path::Path,
) -> WorkerProcess {
    let exe = env!("CARGO_BIN_EXE_moorfret");
    let mut command = match launcher {
        Some(mut prefix) => {
            prefix.arg(exe);
            prefix
        }
        None => Command::new(exe),
    };
    command
        .args(["worker", "--db", url, "--artifacts"])
        .arg(artifacts)
        .args(["--exit-when-idle", "--poll-ms", "100", "--lease-ms"])
        .arg(fault_policy().lease_ms.to_string())
        .env("RUST_LOG", "info")
        .env("NO_COLOR", "1");
    WorkerProcess::start(command)
}

/// Runs the worker loop and exits if this process was started as a worker; returns otherwise.
pub fn run_if_requested() {
    let Ok(url) = std::env::var(DB_VAR) else {
        return;
    };
    let name = std::env::var(NAME_VAR).unwrap_or_else(|_| "worker".into());
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("tokio runtime");
    let code = match runtime.block_on(work(&url, &name)) {
        Ok(()) => 0,
        Err(err) => {
            eprintln!("worker {name}: {err}");
            1
        }
    };
    std::process::exit(code);
}

async fn work(url: &str, name: &str) -> Result<(), StoreError> {
    let retry = fault_retry();
    let options = StoreOptions {
        clock: Clock::Database,
        policy: fault_policy(),
        max_connections: 2,
        postgres_schema: None,
    };
    let store = retry
        .run("open store", || Store::open(url, options.clone()))
        .await?;
    let info = WorkerInfo {
        host: name.to_owned(),
        pid: i64::from(std::process::id()),
        version: "fault-test".into(),
    };
    let worker = retry
        .run("register worker", || store.register_worker(&info))
        .await?;
    let heartbeat_every = Duration::from_millis(fault_policy().heartbeat_interval_ms as u64);
    let any = ClaimFilter::default();
    loop {
        let claimed = retry
            .run("claim job", || store.claim(&worker, &any))
            .await?;
        let Some(lease) = claimed else {
            let swept = retry.run("sweep", || store.sweep_expired()).await?;
            if !swept.requeued.is_empty() {
                continue;
            }
            let progress = retry.run("progress", || store.progress(CAMPAIGN)).await?;
            if progress.jobs_by_state[..3].iter().all(|(_, n)| *n == 0) {
                println!("IDLE");
                break;
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
            continue;
        };
        println!(
            "CLAIMED job={} attempt_id={}",
            lease.job, lease.attempt_id.0
        );
        let lost = Arc::new(AtomicBool::new(false));
        let heartbeat = {
            let (store, lease, lost) = (store.clone(), lease.clone(), lost.clone());
            tokio::spawn(async move {
                loop {
                    tokio::time::sleep(heartbeat_every).await;
                    match store.heartbeat(&lease).await {
                        Ok(_) => {}
                        Err(StoreError::LeaseLost { .. }) => {
                            lost.store(true, Ordering::SeqCst);
                            return;
                        }
                        // Cut off or restarting: keep trying while the job runs.
                        Err(err) => eprintln!("heartbeat of job {}: {err}", lease.job),
                    }
                }
            })
        };
        let payload: TestPayload =
            serde_json::from_value(lease.payload.clone()).map_err(|source| StoreError::Json {
                field: "jobs.payload_json",
                source,
            })?;
        if let TestPayload::Sleep { duration_ms } = payload {
            tokio::time::sleep(Duration::from_millis(duration_ms)).await;
        }
        heartbeat.abort();
        // Complete even when the heartbeat saw the lease lost: the store must refuse it.
        let results = JobResults {
            result: json!({ "by": name }),
            ..JobResults::default()
        };
        match complete_with_retry(&store, &lease, &results, &retry).await {
            Ok(()) => println!("COMPLETED job={}", lease.job),
            Err(StoreError::LeaseLost { .. }) => println!(
                "REJECTED job={} heartbeat_saw_loss={}",
                lease.job,
                lost.load(Ordering::SeqCst)
            ),
            Err(err) => return Err(err),
        }
    }
    store.close().await;
    Ok(())
}

/// Lines a worker printed on stdout, then on stderr if captured, read after it exited.
fn read_events(child: &mut Child) -> Vec<String> {
    use std::io::Read;
    let mut text = String::new();
    if let Some(mut out) = child.stdout.take() {
        let _ = out.read_to_string(&mut text);
    }
    if let Some(mut err) = child.stderr.take() {
        let _ = err.read_to_string(&mut text);
    }
    text.lines().map(str::to_owned).collect()
}
