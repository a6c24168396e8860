//! Workers under a real Slurm: the project's batch script `deploy/slurm/moorfret-workers.sbatch`
//! submitted, byte for byte, to a one-node Slurm cluster that the test starts on this machine
//! (`scale_support::slurm`), against a PostgreSQL store of its own. Three scenarios, one after
//! the other on the same cluster:
//!
//! 1. A two-sea-state campaign of the real stages runs as a two-task array: every job done
//!    exactly once, and every stored result and `moorfret query` table identical to the same
//!    campaign run by `moorfret campaign launch` in another database.
//! 2. `scancel` of the array while both workers hold leases: the SIGTERM path hands the leases
//!    back at once (the jobs are ready again within seconds, not after the 5-minute lease, and
//!    no attempt is counted lost), and a resubmitted array finishes the campaign.
//! 3. A one-minute allocation with the signal lead overridden (`--signal=B:TERM@20` with
//!    `MOORFRET_SIGNAL_LEAD_S=20`): the workers claim only jobs whose expected cost fits in the
//!    wall time the script gives them, the signal reaches them before the allocation ends, a
//!    job running past its estimate is handed back, and a resubmitted array finishes the rest.
//!
//! The workers are `moorfret worker` (the same loop as `moorfret-worker`) of this build, named
//! to the script by `MOORFRET_WORKER`. Needs root, Debian's `slurm-wlm` and `munge`, and the
//! PostgreSQL server of the other store tests; otherwise prints `SKIPPED (…): <reason>` and passes,
//! or fails where `MOORFRET_REQUIRE_SERVICES` is set (as `.ci/run` does).
//! All three scenarios live in one test so that only one cluster runs at a time; the daemons
//! are stopped when the cluster is dropped, on panic too.

mod scale_support;

use std::collections::HashSet;
use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use moorfret_store::{
    AttemptOutcome, AttemptRecord, CampaignId, Clock, JobId, JobKind, JobRecord, JobResults,
    JobState, PlannedJob, QueuePolicy, Store, StoreOptions, TestPayload,
};
use scale_support::pg_database::TempDatabase;
use scale_support::slurm::{self, SlurmCluster, TaskInfo, KILL_WAIT_S};
use scale_support::{campaign, postgres_reachable, postgres_url, skip_unless_required, test_job};

/// Signal lead of the time-limit scenario, s (the allocation is Slurm's minimum, 60 s).
const SHORT_LEAD_S: i64 = 20;
/// The worker's default `--wall-time-reserve-s`.
const WALL_TIME_RESERVE_S: i64 = 30;

/// Writes a line to the test's stderr past the test harness's capture, so that a skip or the
/// scenario timings show in `cargo test` output.
fn say(text: &str) {
    let _ = writeln!(std::io::stderr(), "{text}");
}

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as i64)
}

#[test]
fn worker_arrays_run_campaigns_under_a_real_slurm_cluster() {
    if let Some(reason) = slurm::unavailable() {
        skip_unless_required("Slurm cluster", &reason);
        return;
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .expect("tokio runtime");
    let admin = postgres_url();
    if !runtime.block_on(postgres_reachable(&admin)) {
        // `postgres_reachable` has said why, or failed where the services are required.
        return;
    }
    let started = Instant::now();
    let cluster = SlurmCluster::start();
    say(&format!(
        "slurm cluster test: cluster up in {:.1} s",
        started.elapsed().as_secs_f64()
    ));
    let deployment = Deployment::new(&cluster);
    let mut lap = Instant::now();
    let mut timed = |name: &str| {
        say(&format!(
            "slurm cluster test: {name} took {:.1} s",
            lap.elapsed().as_secs_f64()
        ));
        lap = Instant::now();
    };
    runtime.block_on(campaign_runs_to_the_results_of_campaign_launch(
        &deployment,
        &admin,
    ));
    timed("campaign vs campaign launch");
    runtime.block_on(scancel_hands_the_leases_back_and_a_new_array_finishes(
        &deployment,
        &admin,
    ));
    timed("scancel and resubmission");
    runtime.block_on(short_allocation_claims_only_what_fits_and_loses_nothing(
        &deployment,
        &admin,
    ));
    timed("one-minute allocation");
    drop(deployment);
    drop(cluster);
    say(&format!(
        "slurm cluster test: {:.1} s in all",
        started.elapsed().as_secs_f64()
    ));
}

/// How the test submits the repository's batch script.
struct Deployment<'a> {
    cluster: &'a SlurmCluster,
    /// `deploy/slurm/moorfret-workers.sbatch`, submitted as it is.
    script: PathBuf,
    /// Shared artifact directory of the workers.
    artifacts: PathBuf,
    /// Executable the script runs as the worker: `moorfret worker` of this build.
    worker: PathBuf,
}

impl<'a> Deployment<'a> {
    fn new(cluster: &'a SlurmCluster) -> Self {
        let script = manifest_dir().join("../deploy/slurm/moorfret-workers.sbatch");
        let artifacts = cluster.path("artifacts");
        std::fs::create_dir(&artifacts).expect("artifact directory");
        // The script runs `"$MOORFRET_WORKER" ARGS…`, and `moorfret worker` is a subcommand.
        let worker = cluster.path("moorfret-worker");
        let exe = env!("CARGO_BIN_EXE_moorfret").replace('\'', r"'\''");
        std::fs::write(&worker, format!("#!/bin/sh\nexec '{exe}' worker \"$@\"\n"))
            .expect("write worker launcher");
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&worker, std::fs::Permissions::from_mode(0o755))
            .expect("worker launcher mode");
        Self {
            cluster,
            script,
            artifacts,
            worker,
        }
    }

    /// Submits a two-task array of the script serving `db`, its output in files named after
    /// `label`, with `options` overriding the script's directives and `env` added to the
    /// environment it exports. Checks that Slurm holds the repository's script byte for byte.
    fn submit(
        &self,
        db: &TempDatabase,
        label: &str,
        options: &[&str],
        env: &[(&str, &str)],
    ) -> u64 {
        let jobs = self.cluster.jobs_dir();
        let mut all = vec![
            "--array=0-1".to_owned(),
            // Two workers side by side on this (2-core) node.
            "--cpus-per-task=1".to_owned(),
            "--mem=256M".to_owned(),
            format!("--output={}/{label}-%A_%a.log", jobs.display()),
            format!("--chdir={}", jobs.display()),
            "--export=ALL".to_owned(),
        ];
        all.extend(options.iter().map(|o| (*o).to_owned()));
        let mut vars = vec![
            ("MOORFRET_DB", db.url()),
            ("MOORFRET_ARTIFACTS", self.artifacts.display().to_string()),
            ("MOORFRET_WORKER", self.worker.display().to_string()),
        ];
        vars.extend(env.iter().map(|(k, v)| (*k, (*v).to_owned())));
        let job = self.cluster.sbatch(&all, &self.script, &vars);
        let held = self.cluster.batch_script(job);
        let ours = std::fs::read(&self.script).expect("read the batch script");
        assert!(
            held == ours,
            "Slurm runs a script other than {}",
            self.script.display()
        );
        job
    }

    /// Output of every task of array `job` submitted as `label`, one per task.
    fn task_logs(&self, label: &str, job: u64) -> Vec<String> {
        let prefix = format!("{label}-{job}_");
        let mut logs: Vec<(String, String)> = std::fs::read_dir(self.cluster.jobs_dir())
            .expect("jobs directory")
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                name.starts_with(&prefix)
                    .then(|| (name, std::fs::read_to_string(e.path()).unwrap_or_default()))
            })
            .collect();
        logs.sort();
        logs.into_iter().map(|(_, text)| text).collect()
    }

    /// Waits for array `job` to end; panics with the tasks' output if it takes over `limit`.
    fn wait(&self, label: &str, job: u64, limit: Duration) -> Vec<TaskInfo> {
        let tasks = self.cluster.wait_finished(job, limit);
        assert_eq!(
            tasks.len(),
            2,
            "{label}: {tasks:?}\n{}",
            self.task_logs(label, job).join("\n")
        );
        tasks
    }

    /// Asserts that every task of `job` completed with exit code 0.
    fn assert_completed(&self, label: &str, job: u64, tasks: &[TaskInfo]) {
        for task in tasks {
            assert!(
                task.state == "COMPLETED" && task.exit_code == "0:0",
                "{label}: task {} ended {} ({}):\n{}",
                task.array_task,
                task.state,
                task.exit_code,
                self.task_logs(label, job).join("\n")
            );
        }
    }
}

fn store_options() -> StoreOptions {
    StoreOptions {
        clock: Clock::Database,
        policy: QueuePolicy::default(),
        max_connections: 2,
        postgres_schema: None,
    }
}

async fn open(db: &TempDatabase) -> Store {
    Store::open(&db.url(), store_options())
        .await
        .expect("open store")
}

async fn jobs_and_attempts(store: &Store, id: CampaignId) -> (Vec<JobRecord>, Vec<AttemptRecord>) {
    let jobs = store.jobs_of_campaign(id).await.expect("jobs");
    let attempts = store.attempts_of_campaign(id).await.expect("attempts");
    (jobs, attempts)
}

/// Every job is done, by exactly one attempt that ended `done`, and no attempt was lost.
fn assert_each_done_once(what: &str, jobs: &[JobRecord], attempts: &[AttemptRecord]) {
    for job in jobs {
        assert_eq!(job.state, JobState::Done, "{what}: job {}", job.id);
        assert_eq!(job.lost_count, 0, "{what}: job {}", job.id);
        let done = attempts
            .iter()
            .filter(|a| a.job == job.id && a.outcome == Some(AttemptOutcome::Done))
            .count();
        assert_eq!(done, 1, "{what}: job {} completed {done} times", job.id);
    }
    let lost: Vec<_> = attempts
        .iter()
        .filter(|a| a.outcome == Some(AttemptOutcome::Lost))
        .collect();
    assert!(lost.is_empty(), "{what}: attempts lost: {lost:?}");
}

/// Polls `check` on the store every 200 ms until it holds; panics naming `what` after `limit`.
async fn poll<T, F, Fut>(limit: Duration, what: &str, mut check: F) -> T
where
    F: FnMut() -> Fut,
    Fut: std::future::Future<Output = Option<T>>,
{
    let start = Instant::now();
    loop {
        if let Some(value) = check().await {
            return value;
        }
        assert!(start.elapsed() < limit, "timed out waiting until {what}");
        tokio::time::sleep(Duration::from_millis(200)).await;
    }
}

// --- 1. the campaign, against `moorfret campaign launch` ---------------------------------------

/// What `moorfret query TABLE --campaign NAME --db URL --format csv` prints.
fn query_csv(db: &TempDatabase, campaign: &str, table: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(["query", table, "--campaign", campaign, "--db", &db.url()])
        .args(["--format", "csv"])
        .stdin(Stdio::null())
        .output()
        .expect("run moorfret query");
    assert!(
        out.status.success(),
        "query {table}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("CSV is text")
}

/// Each job's kind and stored results, in plan order.
async fn campaign_results(store: &Store, id: CampaignId) -> Vec<(JobKind, JobResults)> {
    let mut out = Vec::new();
    for job in store.jobs_of_campaign(id).await.expect("jobs") {
        let results = store.results_of(job.id).await.expect("results");
        out.push((job.kind, results));
    }
    out
}

async fn campaign_runs_to_the_results_of_campaign_launch(deployment: &Deployment<'_>, admin: &str) {
    let file = manifest_dir().join("tests/campaigns/slurm_two_sea_states.json");
    let name = "slurm_two_sea_states";

    // Reference: `moorfret campaign launch` with two local workers, in a database of its own.
    let reference_db = TempDatabase::create(admin).await;
    let reference_artifacts = deployment.cluster.path("reference-artifacts");
    let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(["campaign", "launch"])
        .arg(&file)
        .args(["--db", &reference_db.url(), "--artifacts"])
        .arg(&reference_artifacts)
        .args(["--workers", "2"])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .output()
        .expect("run moorfret campaign launch");
    assert!(
        out.status.success(),
        "campaign launch: {}",
        String::from_utf8_lossy(&out.stderr)
    );

    // Under Slurm: the same file planned into the store, then a two-task array.
    let db = TempDatabase::create(admin).await;
    let store = open(&db).await;
    let resolved = moorfret_campaign::resolve(&file).expect("resolve the campaign file");
    let (id, planned) = moorfret_orchestrator::plan::create(&store, &resolved)
        .await
        .expect("plan the campaign");
    assert_eq!(planned.len(), 4, "two global and two strand jobs");
    let job = deployment.submit(&db, "campaign", &[], &[]);
    let tasks = deployment.wait("campaign", job, Duration::from_secs(240));
    deployment.assert_completed("campaign", job, &tasks);

    let (jobs, attempts) = jobs_and_attempts(&store, id).await;
    assert_each_done_once("campaign", &jobs, &attempts);
    assert_eq!(
        attempts.len(),
        jobs.len(),
        "one claim per job: {attempts:?}"
    );
    let workers: HashSet<i64> = attempts.iter().map(|a| a.pid).collect();
    say(&format!(
        "slurm cluster test: campaign jobs ran in {} worker process(es)",
        workers.len()
    ));
    let got = campaign_results(&store, id).await;
    store.close().await;

    let reference = Store::open(&reference_db.url(), store_options())
        .await
        .expect("open reference store");
    let reference_id = reference
        .campaign_by_name(name)
        .await
        .expect("find reference campaign")
        .expect("reference campaign exists");
    let want = campaign_results(&reference, reference_id).await;
    reference.close().await;
    assert_eq!(got.len(), want.len());
    for (n, ((kind, got), (want_kind, want))) in got.iter().zip(&want).enumerate() {
        assert_eq!(kind, want_kind, "job {n}");
        assert_eq!(got.result, want.result, "job {n} ({kind}): result");
        assert_eq!(got.artifacts, want.artifacts, "job {n} ({kind}): artifacts");
        assert!(got == want, "job {n} ({kind}): stored rows differ");
    }
    for table in ["sea-states", "damage-inputs", "lifetime"] {
        let got = query_csv(&db, name, table);
        assert!(got.lines().count() > 1, "query {table} has no rows:\n{got}");
        assert_eq!(got, query_csv(&reference_db, name, table), "query {table}");
    }
    db.finish().await;
    reference_db.finish().await;
}

// --- 2. scancel in the middle ---------------------------------------------------------------

async fn scancel_hands_the_leases_back_and_a_new_array_finishes(
    deployment: &Deployment<'_>,
    admin: &str,
) {
    const JOBS: usize = 8;
    let db = TempDatabase::create(admin).await;
    let store = open(&db).await;
    let id = campaign(&store, "scancel").await;
    let plan: Vec<PlannedJob> = (0..JOBS)
        .map(|_| PlannedJob {
            expected_cost_s: 5.0,
            ..test_job(TestPayload::Sleep { duration_ms: 5_000 })
        })
        .collect();
    store.insert_plan(id, &plan).await.expect("plan");

    let job = deployment.submit(&db, "scancel", &[], &[]);
    poll(
        Duration::from_secs(90),
        "two jobs are done and two running",
        || async {
            let progress = store.progress(id).await.expect("progress");
            (progress.count(JobState::Done) >= 2 && progress.count(JobState::Running) == 2)
                .then_some(())
        },
    )
    .await;
    let cancelled_at_ms = now_ms();
    let cancelled_at = Instant::now();
    deployment.cluster.scancel(job);

    // Back in the queue as soon as the workers have handed their leases back.
    poll(
        Duration::from_secs(30),
        "no job is running after the cancel",
        || async {
            let (jobs, attempts) = jobs_and_attempts(&store, id).await;
            let quiet = jobs.iter().all(|j| j.state != JobState::Running)
                && attempts.iter().all(|a| a.ended_at_ms.is_some());
            quiet.then_some(())
        },
    )
    .await;
    let requeued_after = cancelled_at.elapsed();
    let lease = Duration::from_millis(QueuePolicy::default().lease_ms.unsigned_abs());
    say(&format!(
        "slurm cluster test: jobs back in the queue {:.1} s after scancel (lease {} s)",
        requeued_after.as_secs_f64(),
        lease.as_secs()
    ));
    assert!(requeued_after < lease / 10, "{requeued_after:?}");
    let tasks = deployment.wait("scancel", job, Duration::from_secs(60));
    for task in &tasks {
        assert_eq!(task.state, "CANCELLED", "{tasks:?}");
    }
    let (jobs, attempts) = jobs_and_attempts(&store, id).await;
    let released: Vec<&AttemptRecord> = attempts
        .iter()
        .filter(|a| a.outcome == Some(AttemptOutcome::Cancelled))
        .collect();
    assert!(
        !released.is_empty(),
        "no lease was handed back: {attempts:?}"
    );
    for attempt in &released {
        let ended = attempt.ended_at_ms.expect("ended");
        assert!(
            ended - cancelled_at_ms < 1_000 * KILL_WAIT_S as i64,
            "lease handed back {} ms after the cancel, Slurm's KILL comes after {KILL_WAIT_S} s",
            ended - cancelled_at_ms
        );
        let job = jobs.iter().find(|j| j.id == attempt.job).expect("job");
        assert_eq!(job.state, JobState::Ready, "job {}", job.id);
    }
    assert!(attempts
        .iter()
        .all(|a| a.outcome != Some(AttemptOutcome::Lost)));
    assert!(jobs.iter().all(|j| j.lost_count == 0));
    let logs = deployment.task_logs("scancel", job);
    assert_eq!(logs.len(), 2);
    for log in &logs {
        assert!(log.contains("stop signal received"), "{log}");
    }
    assert!(
        logs.iter()
            .filter(|l| l.contains("lease released on shutdown"))
            .count()
            >= released.len().min(2),
        "{}",
        logs.join("\n")
    );

    let again = deployment.submit(&db, "scancel-again", &[], &[]);
    let tasks = deployment.wait("scancel-again", again, Duration::from_secs(120));
    deployment.assert_completed("scancel-again", again, &tasks);
    let (jobs, attempts) = jobs_and_attempts(&store, id).await;
    assert_eq!(jobs.len(), JOBS);
    assert_each_done_once("after scancel", &jobs, &attempts);
    store.close().await;
    db.finish().await;
}

// --- 3. a one-minute allocation --------------------------------------------------------------

async fn short_allocation_claims_only_what_fits_and_loses_nothing(
    deployment: &Deployment<'_>,
    admin: &str,
) {
    const SHORT: usize = 6;
    const SHORT_COST_S: f64 = 3.0;
    let db = TempDatabase::create(admin).await;
    let store = open(&db).await;
    let id = campaign(&store, "time-limit").await;
    // Highest priority first: the hour-long job would be offered first if it fitted; the slow
    // one is estimated at 5 s but runs 45 s, past the signal; then the short ones.
    let big = PlannedJob {
        expected_cost_s: 3_600.0,
        priority: 3,
        ..test_job(TestPayload::Succeed)
    };
    let slow = PlannedJob {
        expected_cost_s: 5.0,
        priority: 2,
        ..test_job(TestPayload::Sleep {
            duration_ms: 45_000,
        })
    };
    let short = PlannedJob {
        expected_cost_s: SHORT_COST_S,
        priority: 1,
        ..test_job(TestPayload::Sleep { duration_ms: 3_000 })
    };
    let mut plan = vec![big, slow];
    plan.extend(std::iter::repeat_n(short, SHORT));
    let ids = store.insert_plan(id, &plan).await.expect("plan");
    let (big, slow, shorts): (JobId, JobId, &[JobId]) = (ids[0], ids[1], &ids[2..]);

    let lead = SHORT_LEAD_S.to_string();
    let job = deployment.submit(
        &db,
        "time-limit",
        &["--time=1", &format!("--signal=B:TERM@{lead}")],
        &[("MOORFRET_SIGNAL_LEAD_S", &lead)],
    );
    let tasks = deployment.wait("time-limit", job, Duration::from_secs(180));
    let logs = deployment.task_logs("time-limit", job);
    // The workers stopped on the signal and the batch shells exited before Slurm's limit.
    deployment.assert_completed("time-limit", job, &tasks);
    let mut latest_start = 0;
    for task in &tasks {
        let (start, end) = (task.start_s.expect("start"), task.end_s.expect("end"));
        say(&format!(
            "slurm cluster test: one-minute task {} ended {} s after its start (signal asked \
             {SHORT_LEAD_S} s before the end)",
            task.array_task,
            end - start
        ));
        assert!(end - start < 60, "{task:?}");
        latest_start = latest_start.max(start);
    }
    for log in &logs {
        assert!(log.contains("stop signal received"), "{log}");
    }

    // Nothing is running, nothing was lost, and the slow job is back in the queue.
    let (jobs, attempts) = jobs_and_attempts(&store, id).await;
    let job_of = |id: JobId| jobs.iter().find(|j| j.id == id).expect("job");
    assert!(
        jobs.iter()
            .all(|j| j.state != JobState::Running && j.lost_count == 0),
        "{jobs:?}"
    );
    assert!(
        attempts
            .iter()
            .all(|a| a.ended_at_ms.is_some() && a.outcome != Some(AttemptOutcome::Lost)),
        "{attempts:?}"
    );
    let attempts_of = |id: JobId| attempts.iter().filter(move |a| a.job == id);
    assert_eq!(attempts_of(big).count(), 0, "the hour-long job was claimed");
    let slow_attempts: Vec<_> = attempts_of(slow).collect();
    assert!(
        matches!(slow_attempts.as_slice(), [a] if a.outcome == Some(AttemptOutcome::Cancelled)),
        "the slow job must have been handed back on the signal: {slow_attempts:?}\n{}",
        logs.join("\n")
    );
    assert_eq!(job_of(slow).state, JobState::Ready);
    // Every claim fitted in the wall time the script gave: (time left − lead) − reserve.
    let claims_until_s = latest_start + 60 - SHORT_LEAD_S - WALL_TIME_RESERVE_S;
    for attempt in &attempts {
        let cost_s = if attempt.job == slow {
            5.0
        } else {
            SHORT_COST_S
        };
        assert!(
            attempt.started_at_ms as f64 / 1000.0 + cost_s <= claims_until_s as f64 + 2.0,
            "claimed {} s after the start, too late to fit: {attempt:?}",
            attempt.started_at_ms / 1000 - latest_start
        );
    }
    let done = shorts
        .iter()
        .filter(|&&s| job_of(s).state == JobState::Done)
        .count();
    let never_claimed = shorts
        .iter()
        .filter(|&&s| attempts_of(s).count() == 0)
        .count();
    say(&format!(
        "slurm cluster test: in the one-minute allocation {done} of {SHORT} short jobs were \
         done, {never_claimed} not started for want of time"
    ));
    assert!(done >= 1, "no short job fitted at the start");
    assert!(never_claimed >= 1, "the wall time did not limit the claims");

    // A normal allocation finishes the campaign.
    let again = deployment.submit(&db, "time-limit-rest", &[], &[]);
    let tasks = deployment.wait("time-limit-rest", again, Duration::from_secs(120));
    deployment.assert_completed("time-limit-rest", again, &tasks);
    let (jobs, attempts) = jobs_and_attempts(&store, id).await;
    assert_each_done_once("after the one-minute allocation", &jobs, &attempts);
    store.close().await;
    db.finish().await;
}
