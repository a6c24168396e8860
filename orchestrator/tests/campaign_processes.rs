//! Crash safety of the worker loop and the campaign driver with real processes
//! (`moorfret worker`, `moorfret campaign resume`) on an SQLite store, using the test job kind
//! (sleeps, crashes) for the queue mechanics and a short lease so that expiry is quick; then
//! the real stages: one short sea state end to end, and a worker killed in the middle of a
//! strand job whose successor resumes from the job's checkpoint (campaign files of their own
//! in `tests/campaigns/`).

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use moorfret_store::{
    AttemptOutcome, CampaignId, JobKind, JobResults, JobState, NewCampaign, PlannedJob, Store,
    StoreOptions, TestPayload,
};

/// The tests run one at a time: each starts several processes on a 2-core machine, and a
/// standalone worker starved of CPU by the others misses the test's deadlines.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// Lease of the processes under test, ms: long enough for a heartbeat every 100 ms.
const LEASE_MS: &str = "1000";

fn rt() -> tokio::runtime::Runtime {
    tokio::runtime::Runtime::new().unwrap()
}

/// A store with one campaign of test jobs.
fn store_with(dir: &Path, name: &str, payloads: &[TestPayload]) -> (String, CampaignId) {
    let db = dir.join("store.sqlite").to_string_lossy().into_owned();
    let id = rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let id = store
            .create_campaign(&NewCampaign {
                name: name.into(),
                spec: serde_json::json!({}),
                spec_sha256: "0".into(),
            })
            .await
            .unwrap();
        let plan: Vec<PlannedJob> = payloads
            .iter()
            .map(|p| PlannedJob::new(JobKind::Test, serde_json::to_value(p).unwrap()))
            .collect();
        store.insert_plan(id, &plan).await.unwrap();
        store.close().await;
        id
    });
    (db, id)
}

fn moorfret(args: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_moorfret"));
    cmd.args(args).stdout(Stdio::null()).stderr(Stdio::piped());
    cmd
}

/// Standard output of `moorfret query KIND --campaign CAMPAIGN --db DB EXTRA…`, which must
/// succeed.
fn query_output(db: &str, campaign: &str, kind: &str, extra: &[&str]) -> Vec<u8> {
    let mut args = vec!["query", kind, "--campaign", campaign, "--db", db];
    args.extend_from_slice(extra);
    let out = moorfret(&args).stdout(Stdio::piped()).output().unwrap();
    assert!(
        out.status.success(),
        "query {kind}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// A standalone worker on `db` whose log goes to `log` (read back by [`wait_until`] when a
/// test times out, so that a worker that exited early shows why).
fn worker(db: &str, log: &Path) -> Child {
    let log = std::fs::File::create(log).unwrap();
    moorfret(&[
        "worker",
        "--db",
        db,
        "--lease-ms",
        LEASE_MS,
        "--exit-when-idle",
        "--poll-ms",
        "50",
    ])
    .stderr(log)
    .spawn()
    .unwrap()
}

/// Waits until `f` holds, polling the store through one connection pool (opening a store
/// per poll would contend for the write lock with the workers under test). On timeout the
/// worker log `log`, if any, is part of the message.
fn wait_until(
    db: &str,
    what: &str,
    f: impl Fn(&[JobState]) -> bool,
    id: CampaignId,
    log: Option<&Path>,
) {
    let rt = rt();
    rt.block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let deadline = Instant::now() + Duration::from_secs(90);
        loop {
            let jobs = store.jobs_of_campaign(id).await.unwrap();
            let states: Vec<JobState> = jobs.iter().map(|j| j.state).collect();
            if f(&states) {
                break;
            }
            if Instant::now() >= deadline {
                let log = log
                    .map(|p| std::fs::read_to_string(p).unwrap_or_default())
                    .unwrap_or_default();
                panic!("timed out waiting for {what}: {states:?}\nworker log:\n{log}");
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
        store.close().await;
    });
}

fn job_states(db: &str, id: CampaignId) -> Vec<JobState> {
    rt().block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        store.close().await;
        jobs.iter().map(|j| j.state).collect()
    })
}

/// Every job of the campaign is done and has exactly one `done` attempt, or, an unselected
/// gated job settled by another (`settled_by` in its result), none at all.
fn assert_each_done_once(db: &str, id: CampaignId) {
    rt().block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let attempts = store.attempts_of_campaign(id).await.unwrap();
        for job in &jobs {
            assert_eq!(job.state, JobState::Done, "job {}", job.id);
            let settled = job
                .result
                .as_ref()
                .is_some_and(|r| r.get("settled_by").is_some());
            let of_job = attempts.iter().filter(|a| a.job == job.id);
            if settled {
                assert_eq!(of_job.count(), 0, "settled job {} was claimed", job.id);
                continue;
            }
            let done = of_job
                .filter(|a| a.outcome == Some(AttemptOutcome::Done))
                .count();
            assert_eq!(done, 1, "job {} completed {done} times", job.id);
        }
        store.close().await;
    });
}

#[test]
fn killed_worker_job_is_reclaimed_after_lease_expiry_and_completed_once() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let mut payloads = vec![TestPayload::Sleep { duration_ms: 1500 }];
    payloads.extend((0..4).map(|_| TestPayload::Succeed));
    let (db, id) = store_with(dir.path(), "kill9", &payloads);
    let first_log = dir.path().join("first.log");
    let mut first = worker(&db, &first_log);
    wait_until(
        &db,
        "the sleeping job to run",
        |s| s[0] == JobState::Running,
        id,
        Some(&first_log),
    );
    first.kill().unwrap(); // SIGKILL: no chance to release the lease
    first.wait().unwrap();
    assert_eq!(job_states(&db, id)[0], JobState::Running);
    let second_log = dir.path().join("second.log");
    let status = worker(&db, &second_log).wait().unwrap();
    assert!(
        status.success(),
        "{}",
        std::fs::read_to_string(&second_log).unwrap_or_default()
    );
    assert_each_done_once(&db, id);
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        assert_eq!(jobs[0].lost_count, 1);
        // a lost lease is not a failed attempt
        assert_eq!(jobs[0].attempt, 1);
        let attempts = store.attempts_of_campaign(id).await.unwrap();
        let lost = attempts
            .iter()
            .filter(|a| a.outcome == Some(AttemptOutcome::Lost))
            .count();
        assert_eq!(lost, 1);
        store.close().await;
    });
}

/// SIGTERM (`kill`, the scheduler) and SIGHUP (a closed terminal) both stop a worker with its
/// lease handed back at once.
#[test]
fn stopped_worker_releases_its_lease_without_consuming_an_attempt() {
    let _serial = serial();
    for signal in ["-TERM", "-HUP"] {
        let dir = tempfile::tempdir().unwrap();
        let (db, id) = store_with(
            dir.path(),
            "sigterm",
            &[TestPayload::Sleep {
                duration_ms: 60_000,
            }],
        );
        let log = dir.path().join("worker.log");
        let mut w = worker(&db, &log);
        wait_until(
            &db,
            "the job to run",
            |s| s[0] == JobState::Running,
            id,
            Some(&log),
        );
        let pid = w.id().to_string();
        assert!(Command::new("kill")
            .args([signal, &pid])
            .status()
            .unwrap()
            .success());
        let status = w.wait().unwrap();
        assert!(status.success(), "{signal}");
        rt().block_on(async {
            let store = Store::open(&db, StoreOptions::default()).await.unwrap();
            let job = &store.jobs_of_campaign(id).await.unwrap()[0];
            assert_eq!(
                job.state,
                JobState::Ready,
                "{signal}: {}",
                std::fs::read_to_string(&log).unwrap_or_default()
            );
            assert_eq!((job.attempt, job.lost_count), (0, 0), "{signal}");
            store.close().await;
        });
    }
}

/// A job leased by a worker the driver did not start (here the test, as another host): the
/// driver's progress says it is waiting on that lease, and the campaign ends once the lease
/// runs out and the job is re-run.
#[test]
fn progress_says_when_the_campaign_waits_on_a_lease_held_elsewhere() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let payloads = [
        TestPayload::Sleep { duration_ms: 100 },
        TestPayload::Sleep { duration_ms: 100 },
    ];
    let (db, id) = store_with(dir.path(), "elsewhere", &payloads);
    rt().block_on(async {
        let options = StoreOptions {
            policy: moorfret_store::QueuePolicy {
                lease_ms: 3000,
                heartbeat_interval_ms: 1000,
                ..moorfret_store::QueuePolicy::default()
            },
            ..StoreOptions::default()
        };
        let store = Store::open(&db, options).await.unwrap();
        let worker = store
            .register_worker(&moorfret_store::WorkerInfo {
                host: "another-host".into(),
                pid: 1,
                version: "test".into(),
            })
            .await
            .unwrap();
        let lease = store
            .claim(&worker, &moorfret_store::ClaimFilter::default())
            .await
            .unwrap();
        assert!(lease.is_some());
        store.close().await;
    });
    let out = moorfret(&[
        "campaign",
        "resume",
        "elsewhere",
        "--db",
        &db,
        "--workers",
        "1",
    ])
    .output()
    .unwrap();
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    assert!(
        log.contains("(1 on workers this driver did not start: waiting for them or for their leases to run out)"),
        "{log}"
    );
    assert_each_done_once(&db, id);
}

/// Twelve sleeping jobs run by `campaign resume` with two workers and leases of `lease_ms`;
/// the driver and its workers are killed together (as a reboot) once three are done, and a
/// second `campaign resume` finishes the campaign: every job done once. Returns the wall time
/// of the second resume.
fn killed_driver_then_resume(lease_ms: &str) -> Duration {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let payloads: Vec<_> = (0..12)
        .map(|_| TestPayload::Sleep { duration_ms: 300 })
        .collect();
    let (db, id) = store_with(dir.path(), "resume", &payloads);
    let resume = || {
        moorfret(&[
            "campaign",
            "resume",
            "resume",
            "--db",
            &db,
            "--workers",
            "2",
            "--lease-ms",
            lease_ms,
        ])
    };
    let mut driver = resume()
        .stderr(Stdio::null())
        .process_group(0)
        .spawn()
        .unwrap();
    wait_until(
        &db,
        "some jobs done",
        |s| s.iter().filter(|&&x| x == JobState::Done).count() >= 3,
        id,
        None,
    );
    let group = format!("-{}", driver.id());
    assert!(Command::new("kill")
        .args(["-KILL", "--", &group])
        .status()
        .unwrap()
        .success());
    driver.wait().unwrap();
    let states = job_states(&db, id);
    assert!(states.iter().any(|&s| s != JobState::Done), "{states:?}");
    let start = Instant::now();
    let out = resume().output().unwrap();
    let took = start.elapsed();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_each_done_once(&db, id);
    took
}

#[test]
fn killed_driver_then_resume_completes_every_job_once() {
    let _serial = serial();
    killed_driver_then_resume(LEASE_MS);
}

/// The resumed driver sees that the killed workers of its host are gone and takes their jobs
/// back at once: with 10 min leases, the campaign still finishes in seconds.
#[test]
fn resume_takes_back_the_jobs_of_dead_workers_without_waiting_for_their_leases() {
    let _serial = serial();
    let took = killed_driver_then_resume("600000");
    assert!(took < Duration::from_secs(60), "resume took {took:?}");
}

#[test]
fn always_crashing_job_fails_after_the_allowed_losses_and_the_rest_completes() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let mut payloads = vec![TestPayload::Crash];
    payloads.extend((0..5).map(|_| TestPayload::Succeed));
    let (db, id) = store_with(dir.path(), "crashing", &payloads);
    let out = moorfret(&[
        "campaign",
        "resume",
        "crashing",
        "--db",
        &db,
        "--workers",
        "2",
        "--lease-ms",
        LEASE_MS,
    ])
    .output()
    .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lease expired 3 times"), "{stderr}");
    assert!(stderr.contains("1 of 6 jobs failed"), "{stderr}");
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        assert_eq!(jobs[0].state, JobState::Failed);
        assert_eq!(jobs[0].error_class.map(|c| c.as_str()), Some("lost"));
        assert_eq!(jobs[0].lost_count, 3);
        assert!(jobs[1..].iter().all(|j| j.state == JobState::Done));
        store.close().await;
    });
}

/// A copy of the demo campaign in `dir` with the scatter diagram `scatter` and short histories
/// (10 s transient, 10 s recorded), edited by `edit`; returns the campaign file.
fn short_demo(
    dir: &Path,
    scatter: &str,
    edit: impl FnOnce(&mut serde_json::Value),
) -> std::path::PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns");
    for sub in ["data", "benchmarks"] {
        std::fs::create_dir(dir.join(sub)).unwrap();
    }
    for name in [
        "demo.json",
        "paper_case.json",
        "data/oc4_semi_floater.json",
        "benchmarks/strand_1_6_1.json",
    ] {
        std::fs::copy(src.join(name), dir.join(name)).unwrap();
    }
    std::fs::write(dir.join("data/demo_scatter.tsv"), scatter).unwrap();
    let file = dir.join("demo.json");
    let mut spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    spec["simulation"]["transient_s"] = serde_json::json!(10.0);
    spec["simulation"]["wave_ramp_s"] = serde_json::json!(8.0);
    spec["simulation"]["duration_s"] = serde_json::json!(10.0);
    edit(&mut spec);
    std::fs::write(&file, spec.to_string()).unwrap();
    file
}

/// The real stages end to end: one short sea state of the demo campaign (10 s transient, 10 s
/// recorded, 20 strand load samples) through `campaign launch`, global then strand, then
/// `campaign status --json` (about 25 s in a debug build); then the damage inputs through
/// `query damage-inputs` and `query lifetime`.
#[test]
fn demo_sea_state_runs_through_both_real_stages() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let file = short_demo(
        dir.path(),
        "lower\tupper\t11\ttotal\n2\t2,5\t1,354\t1,354\n",
        |_| {},
    );
    let db = dir.path().join("e2e.sqlite").to_string_lossy().into_owned();
    let file = file.to_string_lossy().into_owned();
    let out = moorfret(&["campaign", "launch", &file, "--db", &db, "--workers", "2"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = moorfret(&["campaign", "status", "demo", "--db", &db, "--json"])
        .stdout(Stdio::piped())
        .output()
        .unwrap();
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(status["jobs"]["done"], 2, "{status}");
    assert!((status["occurrence_covered"].as_f64().unwrap() - 0.01354).abs() < 1e-12);
    let classes = rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let id = store.campaign_by_name("demo").await.unwrap().unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let strand = jobs.iter().find(|j| j.kind == JobKind::Strand).unwrap();
        let results = store.results_of(strand.id).await.unwrap();
        // 1+6+1: six core-layer-1 line contacts and the outer wire's crossings
        assert!(!results.contacts.is_empty());
        assert!(results
            .artifacts
            .iter()
            .any(|a| a.role == moorfret_store::ArtifactRole::ContactRecords));
        // one class row per (layer interface, angular position) the contacts fall in
        let mut classes: Vec<(i64, String)> = results
            .contacts
            .iter()
            .map(|c| {
                let position = c.statistics["position_class"].as_str().unwrap();
                (c.layer_interface, position.to_owned())
            })
            .collect();
        classes.sort();
        classes.dedup();
        let mut stored: Vec<(i64, String)> = results
            .class_damage_inputs
            .iter()
            .map(|c| (c.layer_interface, c.angular_position.as_str().to_owned()))
            .collect();
        stored.sort();
        assert_eq!(stored, classes);
        store.close().await;
        classes
    });
    let query = |kind: &str| -> Vec<serde_json::Value> {
        serde_json::from_slice(&query_output(&db, "demo", kind, &["--format", "json"])).unwrap()
    };
    // the test scatter has one sea state: one row per contact class
    let rows = query("damage-inputs");
    let mut listed: Vec<(i64, String)> = rows
        .iter()
        .map(|r| {
            assert_eq!(r["sea_state_index"], 0, "{r}");
            assert_eq!(r["seeds"], 1, "{r}");
            let rate = r["damage_rate_per_s"].as_f64().unwrap();
            assert!(rate.is_finite() && rate >= 0.0, "{r}");
            let position = r["angular_position"].as_str().unwrap().to_owned();
            (r["layer_interface"].as_i64().unwrap(), position)
        })
        .collect();
    listed.sort();
    assert_eq!(listed, classes);
    let lifetime = query("lifetime");
    for r in &lifetime {
        let d = r["annual_damage"].as_f64().unwrap();
        assert!(d.is_finite() && d >= 0.0, "{r}");
    }
    let measures: Vec<&str> = lifetime
        .iter()
        .map(|r| r["measure"].as_str().unwrap())
        .collect();
    // T-N (default curves of the paper's rope line type) and fretting rows are all present
    for m in [
        "tn_dnv_spiral_rope",
        "tn_api_spiral_strand",
        "fretting_max",
        "fretting_mean",
    ] {
        assert!(measures.contains(&m), "{m} missing from {measures:?}");
    }
    // the wave cut-off keeps almost all of the Tp 11 s spectrum (99.2 %), and says so
    let states = query("sea-states");
    let kept = states[0]["wave_energy_kept"].as_f64().unwrap();
    assert!(kept > 0.98 && kept <= 1.0, "{kept}");
    // a finished campaign has nothing left to cancel and keeps its state
    let out = moorfret(&["campaign", "cancel", "demo", "--db", &db])
        .stdout(Stdio::piped())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("nothing left to cancel"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let out = moorfret(&["campaign", "status", "demo", "--db", &db, "--json"])
        .stdout(Stdio::piped())
        .output()
        .unwrap();
    let after: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(after["state"], status["state"], "{after}");
    assert_ne!(after["state"], "cancelled", "{after}");
}

/// Lease of the workers of the strand crash test, ms: the strand solver keeps both cores
/// busy, so heartbeats (every 300 ms) get more slack than with the sleeping test jobs.
const STRAND_LEASE_MS: &str = "3000";

/// Plans the strand crash-test campaign (`tests/campaigns/strand_resume.json`: one sea
/// state, one `global` and one `strand` job) into a new store `db`.
fn plan_strand_resume_campaign(db: &str) -> CampaignId {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/campaigns/strand_resume.json");
    let resolved = moorfret_campaign::resolve(&file).unwrap();
    rt().block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let (id, jobs) = moorfret_orchestrator::plan::create(&store, &resolved)
            .await
            .unwrap();
        assert_eq!(jobs.len(), 2);
        store.close().await;
        id
    })
}

/// A standalone worker on `db` with lease `lease_ms` (the store default if `None`), its log
/// to `log`; it exits once the store has no work left.
fn strand_worker(db: &str, lease_ms: Option<&str>, log: &Path) -> Child {
    let mut args = vec!["worker", "--db", db, "--exit-when-idle", "--poll-ms", "50"];
    if let Some(lease) = lease_ms {
        args.extend(["--lease-ms", lease]);
    }
    moorfret(&args)
        .stderr(std::fs::File::create(log).unwrap())
        .spawn()
        .unwrap()
}

/// Waits for `worker` to exit successfully; its log in the message otherwise.
fn wait_success(mut worker: Child, log: &Path) {
    let status = worker.wait().unwrap();
    assert!(
        status.success(),
        "worker exited with {status}:\n{}",
        std::fs::read_to_string(log).unwrap_or_default()
    );
}

/// Everything a campaign run leaves as results: the stored results of every job (with the
/// strand job's `resumed_from_checkpoint` marker taken out into `resumed`, as it tells how
/// the result was reached rather than what it is) and what `moorfret query` prints from the
/// result views, as CSV.
struct CampaignResults {
    jobs: Vec<(JobKind, JobResults)>,
    queries: Vec<(String, String)>,
}

/// The [`CampaignResults`] of the done campaign `id` of `strand_resume.json` in `db`, and
/// whether its strand job was resumed from a checkpoint.
fn campaign_results(db: &str, id: CampaignId) -> (CampaignResults, bool) {
    let mut resumed = None;
    let jobs = rt().block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let mut out = Vec::new();
        for job in store.jobs_of_campaign(id).await.unwrap() {
            assert_eq!(job.state, JobState::Done, "job {}", job.id);
            let mut results = store.results_of(job.id).await.unwrap();
            if job.kind == JobKind::Strand {
                let marker = results
                    .result
                    .as_object_mut()
                    .and_then(|r| r.remove("resumed_from_checkpoint"));
                resumed = marker.as_ref().and_then(serde_json::Value::as_bool);
            }
            out.push((job.kind, results));
        }
        store.close().await;
        out
    });
    let mut queries = Vec::new();
    for (kind, measure) in [
        ("contacts", "fretting_max"),
        ("damage-inputs", "fretting_max"),
        ("damage-inputs", "fretting_mean"),
        ("sea-states", "fretting_max"),
        ("lifetime", "fretting_max"),
    ] {
        let out = query_output(
            db,
            "strand_resume",
            kind,
            &["--format", "csv", "--measure", measure],
        );
        let csv = String::from_utf8(out).unwrap();
        assert!(csv.lines().count() > 1, "query {kind} has no rows:\n{csv}");
        queries.push((format!("{kind} {measure}"), csv));
    }
    let resumed = resumed.expect("the strand job's result says whether it was resumed");
    (CampaignResults { jobs, queries }, resumed)
}

/// The real stages (not the test job kind): a worker is killed with SIGKILL while the strand
/// job runs, after it has written a checkpoint; a second worker re-claims the job once the
/// lease has expired, resumes from the checkpoint and completes it. The campaign's results
/// equal those of an uninterrupted run in another store, row for row and to the bit.
#[test]
fn killed_strand_job_resumes_from_its_checkpoint_with_the_uninterrupted_results() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();

    // reference: one worker, no interruption, the default (long) lease
    let reference_db = dir.path().join("reference.sqlite");
    let reference_db = reference_db.to_string_lossy().into_owned();
    let reference_id = plan_strand_resume_campaign(&reference_db);
    let log = dir.path().join("reference.log");
    wait_success(strand_worker(&reference_db, None, &log), &log);
    let (reference, resumed) = campaign_results(&reference_db, reference_id);
    assert!(!resumed);

    // crash: the first worker is killed once the strand job has written a checkpoint
    let db = dir
        .path()
        .join("crash.sqlite")
        .to_string_lossy()
        .into_owned();
    let id = plan_strand_resume_campaign(&db);
    let first_log = dir.path().join("first.log");
    let mut first = strand_worker(&db, Some(STRAND_LEASE_MS), &first_log);
    let strand_job = rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let strand = jobs
            .into_iter()
            .find(|j| j.kind == JobKind::Strand)
            .unwrap();
        let pointer = dir
            .path()
            .join("crash.sqlite.artifacts/checkpoints")
            .join(strand.cache_key.as_deref().unwrap());
        let deadline = Instant::now() + Duration::from_secs(240);
        loop {
            let state = store.job(strand.id).await.unwrap().state;
            assert_ne!(
                state,
                JobState::Done,
                "the strand job completed before a checkpoint was seen:\n{}",
                std::fs::read_to_string(&first_log).unwrap_or_default()
            );
            if state == JobState::Running && pointer.exists() {
                break;
            }
            if Instant::now() >= deadline {
                panic!(
                    "timed out waiting for a strand checkpoint (job {state:?}):\n{}",
                    std::fs::read_to_string(&first_log).unwrap_or_default()
                );
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
        store.close().await;
        strand.id
    });
    first.kill().unwrap(); // SIGKILL: no chance to release the lease
    first.wait().unwrap();
    let first_log_text = std::fs::read_to_string(&first_log).unwrap_or_default();
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let job = store.job(strand_job).await.unwrap();
        assert_eq!(job.state, JobState::Running, "{first_log_text}");
        store.close().await;
    });
    let second_log = dir.path().join("second.log");
    let second = strand_worker(&db, Some(STRAND_LEASE_MS), &second_log);
    let second_pid = i64::from(second.id());
    wait_success(second, &second_log);
    let second_log_text = std::fs::read_to_string(&second_log).unwrap();
    assert!(
        second_log_text.contains("strand history resumes from its checkpoint"),
        "{second_log_text}"
    );

    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let job = store.job(strand_job).await.unwrap();
        assert_eq!(job.state, JobState::Done);
        assert_eq!(job.lost_count, 1);
        let mut attempts: Vec<_> = store
            .attempts_of_campaign(id)
            .await
            .unwrap()
            .into_iter()
            .filter(|a| a.job == strand_job)
            .collect();
        attempts.sort_by_key(|a| a.claim_number);
        let outcomes: Vec<_> = attempts.iter().map(|a| a.outcome).collect();
        assert_eq!(
            outcomes,
            [Some(AttemptOutcome::Lost), Some(AttemptOutcome::Done)],
            "{attempts:?}"
        );
        assert_eq!(attempts[0].pid, i64::from(first.id()));
        assert_eq!(attempts[1].pid, second_pid);
        // re-claimed only after the sweep found the first lease expired
        let lost_at = attempts[0].ended_at_ms.unwrap();
        let lease_ms: i64 = STRAND_LEASE_MS.parse().unwrap();
        assert!(
            lost_at >= attempts[0].started_at_ms + lease_ms,
            "{attempts:?}"
        );
        assert!(attempts[1].started_at_ms >= lost_at, "{attempts:?}");
        store.close().await;
    });
    assert_each_done_once(&db, id);

    let (crashed, resumed) = campaign_results(&db, id);
    assert!(resumed);
    // nothing doubled: one row per contact of the strand result
    let (_, strand) = crashed
        .jobs
        .iter()
        .find(|(kind, _)| *kind == JobKind::Strand)
        .unwrap();
    assert_eq!(
        strand.contacts.len() as u64,
        strand.result["contacts"].as_u64().unwrap()
    );
    assert_same_results(&crashed, &reference);
}

/// `got` equals `want` to the bit, compared part by part so that a failure names the part.
fn assert_same_results(got: &CampaignResults, want: &CampaignResults) {
    assert_eq!(got.jobs.len(), want.jobs.len());
    for ((kind, got), (want_kind, want)) in got.jobs.iter().zip(&want.jobs) {
        assert_eq!(kind, want_kind);
        // the strand result holds the hash of the full contact records and the work counts
        assert_eq!(got.result, want.result, "{kind} job result");
        assert_eq!(got.artifacts, want.artifacts, "{kind} job artifacts");
        assert!(got.hot_spots == want.hot_spots, "{kind} job hot-spot rows");
        assert!(got.contacts == want.contacts, "{kind} job contact rows");
        assert!(
            got.damage_inputs == want.damage_inputs,
            "{kind} job damage input rows"
        );
        assert!(
            got.class_damage_inputs == want.class_damage_inputs,
            "{kind} job class damage input rows"
        );
    }
    assert_eq!(got.queries, want.queries);
}

/// The `auto` strand fidelity end to end on a reduced copy of the paper campaign's layout: two
/// short sea states of the demo campaign (the 1+6+1 strand), planned as two global jobs, one
/// calibration, two reduced strand jobs and two FE strand jobs of which the rule runs one
/// (`auto_fe.sea_states = 1`), and a second seed where half the first-seed damage is
/// (`extra_seeds`: two more global and reduced jobs, gated). The driver and its workers are
/// killed with SIGKILL once the first seeds' reduced jobs are done, while the gated jobs decide,
/// and `campaign resume` finishes: every job done exactly once (or settled), the FE result
/// counted for the selected sea state and the reduced one for the other, the pair compared, the
/// selected sea states with two seeds and a spread, the diagram's occurrence covered.
#[test]
fn auto_fidelity_campaign_survives_a_killed_driver() {
    let _serial = serial();
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let file = short_demo(
        dir.path(),
        "lower\tupper\t11\ttotal\n2\t2,5\t1,354\t1,354\n3\t3,5\t0,5\t0,5\n",
        |spec| {
            spec["name"] = serde_json::json!("auto");
            spec["strand"]["fidelity"] = serde_json::json!("auto");
            spec["strand"]["auto_fe"] = serde_json::json!({ "sea_states": 1 });
            spec["strand"]["contact_records"] = serde_json::json!(false);
            spec["simulation"]["extra_seeds"] =
                serde_json::json!({ "seeds": 2, "damage_share": 0.5 });
        },
    );
    let db = dir
        .path()
        .join("auto.sqlite")
        .to_string_lossy()
        .into_owned();
    let file = file.to_string_lossy().into_owned();
    let mut driver = moorfret(&[
        "campaign",
        "launch",
        &file,
        "--db",
        &db,
        "--workers",
        "2",
        "--lease-ms",
        STRAND_LEASE_MS,
    ])
    .stderr(Stdio::null())
    .process_group(0)
    .spawn()
    .unwrap();
    // the campaign exists once the driver has planned it
    let deadline = Instant::now() + Duration::from_secs(60);
    let id = loop {
        let found = Path::new(&db).exists()
            && rt()
                .block_on(async {
                    let store = Store::open(&db, StoreOptions::default()).await.ok()?;
                    let id = store.campaign_by_name("auto").await.ok().flatten();
                    store.close().await;
                    id
                })
                .is_some();
        if found {
            break rt().block_on(async {
                let store = Store::open(&db, StoreOptions::default()).await.unwrap();
                let id = store.campaign_by_name("auto").await.unwrap().unwrap();
                store.close().await;
                id
            });
        }
        assert!(Instant::now() < deadline, "the campaign was not planned");
        std::thread::sleep(Duration::from_millis(200));
    };
    wait_until(
        &db,
        "the first seeds' globals, calibration and reduced jobs done",
        |s| s.iter().filter(|&&x| x == JobState::Done).count() >= 5,
        id,
        None,
    );
    let group = format!("-{}", driver.id());
    assert!(Command::new("kill")
        .args(["-KILL", "--", &group])
        .status()
        .unwrap()
        .success());
    driver.wait().unwrap();
    let out = moorfret(&[
        "campaign",
        "resume",
        "auto",
        "--db",
        &db,
        "--workers",
        "2",
        "--lease-ms",
        STRAND_LEASE_MS,
    ])
    .output()
    .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_each_done_once(&db, id);
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let count = |k: JobKind| jobs.iter().filter(|j| j.kind == k).count();
        // first seeds: 2 global, 1 calibration, 2 reduced, 2 FE; extra: 2 global, 2 reduced
        assert_eq!(count(JobKind::Global), 4);
        assert_eq!(count(JobKind::Calibrate), 1);
        assert_eq!(count(JobKind::StrandReduced), 4);
        assert_eq!(count(JobKind::Strand), 2);
        // one FE job ran (the selected sea state), the other ended without results
        let mut selected = Vec::new();
        for job in jobs.iter().filter(|j| j.kind == JobKind::Strand) {
            let results = store.results_of(job.id).await.unwrap();
            let chosen = results.result["selected"].as_bool().unwrap();
            assert_eq!(results.class_damage_inputs.is_empty(), !chosen);
            if chosen {
                assert_eq!(results.result["fidelity"], "fe");
                selected.push(results.result["seed_index"].clone());
            }
        }
        assert_eq!(selected.len(), 1, "exactly one sea state runs FE");
        let mut extra_cells = Vec::new();
        for job in jobs.iter().filter(|j| j.kind == JobKind::StrandReduced) {
            let results = store.results_of(job.id).await.unwrap();
            if job.payload["global"]["extra_seed"] == true {
                if results.result["selected"] == false {
                    assert!(results.class_damage_inputs.is_empty());
                    continue;
                }
                extra_cells.push(job.payload["global"]["sea_state_index"].as_i64().unwrap());
            }
            assert_eq!(results.result["fidelity"], "reduced");
            assert!(!results.class_damage_inputs.is_empty());
            // `contact_records: false`: rows only, no records artifact
            assert!(!results.contacts.is_empty());
            assert!(results
                .artifacts
                .iter()
                .all(|a| a.role != moorfret_store::ArtifactRole::ContactRecords));
            assert!(results.result["contact_records_sha256"].is_null());
        }
        // counted: FE for one sea state, reduced for the other; the FE one is compared
        let rows = store.sea_state_class_damage(id).await.unwrap();
        let fidelity = |s: i64| {
            let mut f: Vec<&str> = rows
                .iter()
                .filter(|r| r.sea_state_index == s)
                .map(|r| r.fidelity.as_str())
                .collect();
            f.dedup();
            f
        };
        // half the damage: one sea state or both get the second seed
        assert!(!extra_cells.is_empty(), "no extra seed ran");
        for c in rows.iter().filter(|r| r.measure == "fretting_max") {
            let extra = extra_cells.contains(&c.sea_state_index);
            assert_eq!(c.seeds, if extra { 2 } else { 1 }, "{c:?}");
            assert_eq!(c.damage_rate_sd.is_some(), extra, "{c:?}");
        }
        // the FE sea state counts its FE first seed (with a reduced second seed: `mixed`)
        let fe_like = |f: &[&str]| f == ["fe"] || f == ["mixed"];
        let (a, b) = (fidelity(0), fidelity(1));
        assert!(
            (fe_like(&a) && b == ["reduced"]) || (a == ["reduced"] && fe_like(&b)),
            "{a:?} {b:?}"
        );
        let fe_sea_state = if fe_like(&a) { 0 } else { 1 };
        let compared = store.fidelity_comparison(id).await.unwrap();
        assert!(!compared.is_empty());
        assert!(compared.iter().all(|c| c.sea_state_index == fe_sea_state));
        let progress = store.progress(id).await.unwrap();
        assert!((progress.occurrence_covered - 0.01854).abs() < 1e-12);
        store.close().await;
    });
}

/// Launches the short demo campaign `name` of `scatter`, edited by `edit`, on two workers in a
/// store of `dir`, to its end; checks that every job is done once and returns the store and
/// the campaign.
fn launch_to_end(
    dir: &Path,
    name: &str,
    scatter: &str,
    edit: impl FnOnce(&mut serde_json::Value),
) -> (String, CampaignId) {
    let file = short_demo(dir, scatter, |spec| {
        spec["name"] = serde_json::json!(name);
        edit(spec);
    });
    let db = dir
        .join(format!("{name}.sqlite"))
        .to_string_lossy()
        .into_owned();
    let file = file.to_string_lossy().into_owned();
    let started = Instant::now();
    let out = moorfret(&["campaign", "launch", &file, "--db", &db, "--workers", "2"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("campaign {name}: {:?}", started.elapsed());
    let id = rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let id = store.campaign_by_name(name).await.unwrap().unwrap();
        store.close().await;
        id
    });
    assert_each_done_once(&db, id);
    (db, id)
}

/// The check of a calibration that started from the largest and smallest seas: in 30 s
/// histories of four demo cells, Hs 4.25 m reaches a strain that Hs 2.25 and 8.25 m do not
/// (with `strand.calibration_hs_fraction` 0.9 and the default 5 % margin), so the check
/// calibrates again over every global job, and every reduced job reads the new calibration.
#[test]
fn a_load_outside_the_first_calibration_makes_the_check_calibrate_again() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let (db, id) = launch_to_end(
        dir.path(),
        "recalibrated",
        "lower\tupper\t11\t12\t14\ttotal\n2\t2,5\t1,354\t0\t0\t1,354\n\
         4\t4,5\t0\t0,423\t0\t0,423\n6\t6,5\t0\t0\t0,2\t0,2\n8\t8,5\t0,05\t0\t0\t0,05\n",
        |spec| {
            spec["strand"]["fidelity"] = serde_json::json!("reduced");
            spec["strand"]["contact_records"] = serde_json::json!(false);
            spec["strand"]["calibration_hs_fraction"] = serde_json::json!(0.9);
        },
    );
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let calibrations: Vec<_> = jobs
            .iter()
            .filter(|j| j.kind == JobKind::Calibrate)
            .collect();
        assert_eq!(calibrations.len(), 2);
        let first = store.results_of(calibrations[0].id).await.unwrap();
        let check = store.results_of(calibrations[1].id).await.unwrap();
        let range = |r: &serde_json::Value, k: &str| -> [f64; 4] {
            let v = |f: &str, i: usize| r[k][f][i].as_f64().unwrap();
            [
                v("strain", 0),
                v("strain", 1),
                v("curvature_per_m", 0),
                v("curvature_per_m", 1),
            ]
        };
        let covers = |outer: [f64; 4], inner: [f64; 4]| {
            outer[0] <= inner[0]
                && inner[1] <= outer[1]
                && outer[2] <= inner[2]
                && inner[3] <= outer[3]
        };
        let all_loads = range(&check.result, "load_range");
        assert!(!covers(range(&first.result, "calibrated_range"), all_loads));
        // calibrated again, over every global job's load
        assert!(check.result["kept"].is_null(), "{}", check.result);
        assert_eq!(
            (
                first.result["global_jobs"].clone(),
                check.result["global_jobs"].clone()
            ),
            (2.into(), 4.into())
        );
        assert!(check.result["design_samples"].as_u64().unwrap() > 0);
        assert!(covers(range(&check.result, "calibrated_range"), all_loads));
        assert_ne!(check.artifacts, first.artifacts);
        for job in jobs.iter().filter(|j| j.kind == JobKind::StrandReduced) {
            let results = store.results_of(job.id).await.unwrap();
            assert_eq!(
                results.result["calibration"]["range"],
                check.result["calibrated_range"]
            );
        }
    });
}

/// `strand.skip_mild_share` end to end on four short demo cells (reduced): the test computes
/// each cell's fibre-strain measure x = σ_T/EA + (D/2) σ_κ and proxy w x^4.8/T_p from the stored
/// global summaries itself, and the cells skipped must be the mildest by x whose proxy fits the
/// share; the skipped reduced jobs write the T-N rows of the tension and no strand rows, the
/// others run the strand model; the design check counts the skipped year as covered and
/// charges the strand figures by 1/(1 − q), and the T-N figures cover every sea state.
#[test]
fn mild_sea_states_are_skipped_within_their_proxy_share_and_charged_in_the_design_check() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let share = 0.05;
    let (db, id) = launch_to_end(
        dir.path(),
        "mild",
        "lower\tupper\t11\t12\t14\ttotal\n2\t2,5\t1,354\t0\t0\t1,354\n\
         4\t4,5\t0\t0,423\t0\t0,423\n6\t6,5\t0\t0\t0,2\t0,2\n8\t8,5\t0,05\t0\t0\t0,05\n",
        |spec| {
            spec["strand"]["fidelity"] = serde_json::json!("reduced");
            spec["strand"]["contact_records"] = serde_json::json!(false);
            spec["strand"]["skip_mild_share"] = serde_json::json!(share);
        },
    );
    let inputs = moorfret_campaign::resolve(&dir.path().join("demo.json"))
        .unwrap()
        .inputs;
    let diameter = inputs.profile.validate().unwrap().outer_diameter_m();
    let (skipped, q, year_skipped, year, lifetime) = rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let attempts = store.attempts_of_campaign(id).await.unwrap();
        let states = store.sea_state_status(id).await.unwrap();
        let occurrence = |i: i64| {
            states
                .iter()
                .find(|s| s.sea_state_index == i)
                .unwrap()
                .occurrence_fraction
        };
        // EA from a reduced job that ran
        let mut ea = None;
        let mut skipped = Vec::new();
        let mut q_stored = None;
        for job in jobs.iter().filter(|j| j.kind == JobKind::StrandReduced) {
            let results = store.results_of(job.id).await.unwrap();
            let index = job.payload["global"]["sea_state_index"].as_i64().unwrap();
            if results.result["skipped"] == "mild" {
                // no strand model: no contact or class rows, the T-N rows of the tension only
                assert!(results.class_damage_inputs.is_empty() && results.artifacts.is_empty());
                assert!(results.contacts.is_empty());
                assert!(!results.damage_inputs.is_empty());
                assert!(results
                    .damage_inputs
                    .iter()
                    .all(|d| d.measure.starts_with("tn_")));
                assert!(attempts.iter().any(|a| a.job == job.id));
                q_stored = results.result["mild_seas"]["proxy_share"].as_f64();
                skipped.push(index);
            } else {
                assert!(!results.class_damage_inputs.is_empty());
                ea = results.result["axial_stiffness"]["ea_n"].as_f64();
            }
        }
        let ea = ea.expect("a reduced job ran");
        // (sea state, w, T_p, x) from the global summaries
        let mut cells = Vec::new();
        for job in jobs.iter().filter(|j| j.kind == JobKind::Global) {
            let results = store.results_of(job.id).await.unwrap();
            let s = &results.hot_spots[0].summary;
            let x = s["tension_n"]["std"].as_f64().unwrap() / ea
                + 0.5 * diameter * s["curvature_per_m"]["std"].as_f64().unwrap();
            let index = job.payload["sea_state_index"].as_i64().unwrap();
            let tp = job.payload["tp_s"].as_f64().unwrap();
            cells.push((index, occurrence(index), tp, x));
        }
        cells.sort_by(|a, b| a.3.total_cmp(&b.3));
        let proxy = |c: &(i64, f64, f64, f64)| c.1 * c.3.powf(4.8) / c.2;
        let total: f64 = cells.iter().map(proxy).sum();
        let mut expected = Vec::new();
        let mut held = 0.0;
        for c in &cells {
            if held + proxy(c) > share * total {
                break;
            }
            held += proxy(c);
            expected.push(c.0);
        }
        skipped.sort_unstable();
        expected.sort_unstable();
        assert_eq!(skipped, expected, "cells (index, w, Tp, x): {cells:?}");
        assert!(
            !skipped.is_empty() && skipped.len() < cells.len(),
            "{cells:?}"
        );
        let q = held / total;
        assert!(q <= share);
        assert!((q_stored.unwrap() - q).abs() < 1e-12 * q.max(1e-300));
        let year_skipped: f64 = skipped.iter().map(|&i| occurrence(i)).sum();
        let year: f64 = states.iter().map(|s| s.occurrence_fraction).sum();
        let lifetime = store.lifetime_class_damage(id).await.unwrap();
        store.close().await;
        (skipped, q, year_skipped, year, lifetime)
    });
    eprintln!("skipped {skipped:?}, q {q:e}");
    let figures: Vec<serde_json::Value> = serde_json::from_slice(&query_output(
        &db,
        "mild",
        "utilisation",
        &["--format", "json"],
    ))
    .unwrap();
    let tn: Vec<_> = figures
        .iter()
        .filter(|f| f["measure"].as_str().is_some_and(|m| m.starts_with("tn_")))
        .collect();
    assert!(!tn.is_empty());
    for f in tn {
        let covered = f["year_covered"].as_f64().unwrap();
        assert!((covered - year).abs() < 1e-12, "{f}");
    }
    let mut checked = 0;
    for l in lifetime.iter().filter(|l| l.measure == "fretting_max") {
        let position = serde_json::to_value(l.angular_position).unwrap();
        let class = format!(
            "interface {} / {}",
            l.layer_interface,
            position.as_str().unwrap()
        );
        let f = figures
            .iter()
            .find(|f| f["measure"] == "fretting_max" && f["class"] == class.as_str())
            .unwrap_or_else(|| panic!("no figure for {l:?}"));
        let charged = f["annual_damage"].as_f64().unwrap();
        assert!(
            (charged - l.annual_damage / (1.0 - q)).abs() <= 1e-12 * charged,
            "{f} {l:?}"
        );
        let covered = f["year_covered"].as_f64().unwrap();
        assert!(
            (covered - (l.occurrence_covered + year_skipped)).abs() < 1e-12,
            "{f} {l:?}"
        );
        checked += 1;
    }
    assert!(checked > 0);
}

/// `simulation.extra_seeds` end to end: three short sea states of the demo campaign (FE
/// strand), one seed each, and two seeds in all for the sea states holding half of the
/// governing class's first-seed fretting damage. Every job is done once (or settled); the
/// selected sea states have two seeds in the views with a seed spread, the others one; every
/// unselected extra-seed strand job was settled without a claim by the first extra-seed job
/// that ran; `query seeds` and `query lifetime` show the spread and the band.
#[test]
fn extra_seeds_run_where_the_damage_is_and_the_rest_is_settled_at_once() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let (db, id) = launch_to_end(
        dir.path(),
        "seeds",
        "lower\tupper\t11\t14\ttotal\n2\t2,5\t1,354\t0\t1,354\n\
         6\t6,5\t0\t0,2\t0,2\n8\t8,5\t0,05\t0\t0,05\n",
        |spec| {
            spec["simulation"]["extra_seeds"] =
                serde_json::json!({ "seeds": 2, "damage_share": 0.5 });
            spec["strand"]["contact_records"] = serde_json::json!(false);
        },
    );
    let selected: Vec<i64> = rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let attempts = store.attempts_of_campaign(id).await.unwrap();
        // 3 sea states × (first + extra seed) × (global + strand)
        assert_eq!(jobs.len(), 12);
        let mut selected = Vec::new();
        let mut settled = 0;
        for job in &jobs {
            let payload = &job.payload;
            let extra = payload["extra_seed"] == true || payload["global"]["extra_seed"] == true;
            if !extra {
                continue;
            }
            let results = store.results_of(job.id).await.unwrap();
            let ran = results.result.get("selected").is_none();
            let index = payload["sea_state_index"]
                .as_i64()
                .or(payload["global"]["sea_state_index"].as_i64())
                .unwrap();
            if ran {
                if job.kind == JobKind::Strand {
                    assert!(!results.class_damage_inputs.is_empty());
                    selected.push(index);
                }
                continue;
            }
            assert_eq!(results.result["selected"], false);
            assert!(results.class_damage_inputs.is_empty() && results.artifacts.is_empty());
            if results.result.get("settled_by").is_some() {
                settled += 1;
                assert!(attempts.iter().all(|a| a.job != job.id));
            } else {
                assert_ne!(job.kind, JobKind::Strand, "a strand job waited for a claim");
            }
        }
        selected.sort();
        // the rule keeps the sea states holding half the damage: at least one, not all here
        assert!(!selected.is_empty() && selected.len() < 3, "{selected:?}");
        // the unselected strand jobs at least were settled in one go
        assert!(settled >= 3 - selected.len(), "{settled}");
        let cells = store.sea_state_class_damage(id).await.unwrap();
        for c in cells.iter().filter(|c| c.measure == "fretting_max") {
            let extra = selected.contains(&c.sea_state_index);
            assert_eq!(c.seeds, if extra { 2 } else { 1 }, "{c:?}");
            assert_eq!(c.damage_rate_sd.is_some(), extra, "{c:?}");
        }
        let lifetime = store.lifetime_class_damage(id).await.unwrap();
        for l in &lifetime {
            assert_eq!(l.band.sea_states_with_spread, selected.len() as i64);
            assert_eq!(l.band.sea_states_without_spread, 3 - selected.len() as i64);
            assert!(l.band.annual_damage_se.is_finite() && l.band.annual_damage_se >= 0.0);
            assert!(l.band.annual_damage_low <= l.annual_damage);
            assert!(l.band.annual_damage_high >= l.annual_damage);
        }
        store.close().await;
        selected
    });
    let query = |kind: &str| -> Vec<serde_json::Value> {
        serde_json::from_slice(&query_output(&db, "seeds", kind, &["--format", "json"])).unwrap()
    };
    let seeds = query("seeds");
    assert!(!seeds.is_empty());
    for r in &seeds {
        let index = r["sea_state_index"].as_i64().unwrap();
        let n = r["seeds"].as_i64().unwrap();
        assert_eq!(n == 2, selected.contains(&index), "{r}");
        assert_eq!(r["annual_damage_se"].is_null(), n == 1, "{r}");
    }
    for r in &query("lifetime") {
        for column in [
            "annual_damage_se",
            "annual_damage_low",
            "annual_damage_high",
        ] {
            assert!(r[column].as_f64().is_some(), "{column}: {r}");
        }
    }
}

/// `simulation.extra_seeds` with the `auto` fidelity: four short sea states, one FE sea state
/// (`auto_fe.sea_states = 1`), two seeds in all where half the reduced first-seed damage is.
/// The extra seeds run the reduced response only; the unselected FE jobs that were still
/// waiting when the first FE job found the selection were settled by it without a claim (with
/// two workers at most two FE jobs run at once, so of the three unselected at least one waits).
#[test]
fn auto_campaign_settles_its_unselected_fe_jobs_and_runs_extra_seeds_reduced() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let (db, id) = launch_to_end(
        dir.path(),
        "autoseeds",
        "lower\tupper\t11\t12\t14\ttotal\n2\t2,5\t1,354\t0\t0\t1,354\n\
         4\t4,5\t0\t0,423\t0\t0,423\n6\t6,5\t0\t0\t0,2\t0,2\n8\t8,5\t0,05\t0\t0\t0,05\n",
        |spec| {
            spec["simulation"]["extra_seeds"] =
                serde_json::json!({ "seeds": 2, "damage_share": 0.5 });
            spec["strand"]["fidelity"] = serde_json::json!("auto");
            spec["strand"]["auto_fe"] = serde_json::json!({ "sea_states": 1 });
            spec["strand"]["contact_records"] = serde_json::json!(false);
            spec["strand"]["calibration_hs_fraction"] = serde_json::json!(0.9);
            spec["strand"]["calibration_margin"] = serde_json::json!(1.0);
        },
    );
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let count = |k: JobKind| jobs.iter().filter(|j| j.kind == k).count();
        // first seeds: 4 global, 2 calibrations (the first from Hs 2.25 and 8.25 m, the check
        // after all four), 4 reduced, 4 FE; extra: 4 global, 4 reduced
        assert_eq!(
            (
                count(JobKind::Global),
                count(JobKind::Calibrate),
                count(JobKind::StrandReduced),
                count(JobKind::Strand)
            ),
            (8, 2, 8, 4)
        );
        let calibrations: Vec<_> = jobs
            .iter()
            .filter(|j| j.kind == JobKind::Calibrate)
            .collect();
        let first = store.results_of(calibrations[0].id).await.unwrap();
        let check = store.results_of(calibrations[1].id).await.unwrap();
        assert_eq!(first.result["global_jobs"], 2);
        assert_eq!(check.result["global_jobs"], 4);
        // the other two cells stay inside the range of Hs 2.25 and 8.25 m widened by the
        // margin (30 s of Hs 8.25 m reach only 2/3 of the strain of Hs 4.25 m: without the
        // margin the check calibrates again): kept, the same artifact, no FE run of its own
        assert_eq!(check.result["kept"], true, "{}", check.result);
        assert_eq!(
            check.result["check_of"].as_str(),
            calibrations[0].cache_key.as_deref()
        );
        assert_eq!(check.artifacts, first.artifacts);
        assert!(check.result["fe_wall_time_s"].is_null());
        let (mut fe_ran, mut fe_settled) = (0, 0);
        for job in jobs.iter().filter(|j| j.kind == JobKind::Strand) {
            assert_ne!(job.payload["global"]["extra_seed"], true);
            let result = job.result.clone().unwrap();
            if result["selected"] == true {
                fe_ran += 1;
            } else if result.get("settled_by").is_some() {
                fe_settled += 1;
            }
        }
        assert_eq!(fe_ran, 1);
        assert!(fe_settled >= 1, "no unselected FE job was settled");
        let mut extra_cells = Vec::new();
        for job in jobs.iter().filter(|j| j.kind == JobKind::StrandReduced) {
            if job.payload["global"]["extra_seed"] != true {
                continue;
            }
            let results = store.results_of(job.id).await.unwrap();
            if results.result.get("selected").is_none() {
                assert_eq!(results.result["fidelity"], "reduced");
                assert!(!results.class_damage_inputs.is_empty());
                extra_cells.push(job.payload["global"]["sea_state_index"].as_i64().unwrap());
            }
        }
        assert!(
            !extra_cells.is_empty() && extra_cells.len() < 4,
            "{extra_cells:?}"
        );
        for c in store.sea_state_class_damage(id).await.unwrap() {
            let extra = extra_cells.contains(&c.sea_state_index);
            assert_eq!(c.seeds, if extra { 2 } else { 1 }, "{c:?}");
            if extra {
                assert!(c.fidelity == "reduced" || c.fidelity == "mixed", "{c:?}");
            }
        }
        store.close().await;
    });
}

/// A driver stopped by `signal` (`campaign resume` of 12 sleeping jobs on 2 workers, driver
/// in a process group of its own so that only it gets the signal) stops its workers: no job
/// runs or completes after it is gone, every lease is back, and a later `resume` completes
/// every job once. With `--detach-workers` the workers run the campaign to its end alone.
fn stopped_driver(signal: &str, detach: bool) {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let payloads: Vec<_> = (0..12)
        .map(|_| TestPayload::Sleep { duration_ms: 400 })
        .collect();
    let (db, id) = store_with(dir.path(), "stop", &payloads);
    let resume = |extra: &[&str]| {
        let mut args = vec![
            "campaign",
            "resume",
            "stop",
            "--db",
            &db,
            "--workers",
            "2",
            "--lease-ms",
            LEASE_MS,
        ];
        args.extend_from_slice(extra);
        moorfret(&args)
    };
    let extra: &[&str] = if detach { &["--detach-workers"] } else { &[] };
    let driver = resume(extra).process_group(0).spawn().unwrap();
    wait_until(&db, "a job done", |s| s.contains(&JobState::Done), id, None);
    assert!(Command::new("kill")
        .args([&format!("-{signal}"), &driver.id().to_string()])
        .status()
        .unwrap()
        .success());
    let out = driver.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!("stopped by SIG{signal}")),
        "{stderr}"
    );
    if detach {
        assert!(stderr.contains("--detach-workers"), "{stderr}");
        wait_until(
            &db,
            "the detached workers finish the campaign",
            |s| s.iter().all(|&x| x == JobState::Done),
            id,
            None,
        );
        assert_each_done_once(&db, id);
        return;
    }
    assert!(stderr.contains("campaign resume stop"), "{stderr}");
    let after_stop = job_states(&db, id);
    assert!(
        !after_stop.contains(&JobState::Running),
        "a lease is still held: {after_stop:?}"
    );
    let done = |s: &[JobState]| s.iter().filter(|&&x| x == JobState::Done).count();
    assert!(done(&after_stop) < 12, "{after_stop:?}");
    // nobody runs the campaign on: the remaining jobs stay ready
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(job_states(&db, id), after_stop);
    let out = resume(&[]).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_each_done_once(&db, id);
}

#[test]
fn a_driver_stopped_by_sigterm_stops_its_workers_and_loses_nothing() {
    let _serial = serial();
    stopped_driver("TERM", false);
}

#[test]
fn a_driver_stopped_by_sigint_stops_its_workers_and_loses_nothing() {
    let _serial = serial();
    stopped_driver("INT", false);
}

#[test]
fn detached_workers_run_the_campaign_to_its_end_after_the_driver_stops() {
    let _serial = serial();
    stopped_driver("TERM", true);
}

/// The demo campaign (two short sea states, real stages) driven by `campaign launch`, stopped by
/// SIGTERM once its first job is done: no lease is left, nothing runs on, and `campaign resume`
/// completes it with the results of an uninterrupted launch, to the bit in every `query` table.
#[test]
fn a_stopped_demo_campaign_resumes_to_the_uninterrupted_results() {
    use std::os::unix::process::CommandExt;
    let _serial = serial();
    let scatter = "lower\tupper\t11\t12\ttotal\n2\t2,5\t1,354\t0,5\t1,854\n";
    // 30 s recorded: long enough for the stop to find work left
    let longer = |spec: &mut serde_json::Value| {
        spec["simulation"]["duration_s"] = serde_json::json!(30.0);
    };
    let reference = tempfile::tempdir().unwrap();
    let (reference_db, _) = launch_to_end(reference.path(), "demo", scatter, longer);
    let dir = tempfile::tempdir().unwrap();
    let file = short_demo(dir.path(), scatter, longer);
    let db = dir
        .path()
        .join("stop.sqlite")
        .to_string_lossy()
        .into_owned();
    let file = file.to_string_lossy().into_owned();
    let driver = moorfret(&["campaign", "launch", &file, "--db", &db, "--workers", "2"])
        .process_group(0)
        .spawn()
        .unwrap();
    // the campaign appears once it is planned
    let started = Instant::now();
    let id = loop {
        assert!(started.elapsed() < Duration::from_secs(60), "never planned");
        let found = rt().block_on(async {
            let store = Store::open_existing(&db, StoreOptions::default())
                .await
                .ok()?;
            let id = store.campaign_by_name("demo").await.ok().flatten();
            store.close().await;
            id
        });
        match found {
            Some(id) => break id,
            None => std::thread::sleep(Duration::from_millis(20)),
        }
    };
    wait_until(&db, "a job done", |s| s.contains(&JobState::Done), id, None);
    assert!(Command::new("kill")
        .args(["-TERM", &driver.id().to_string()])
        .status()
        .unwrap()
        .success());
    let out = driver.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("stopped by SIGTERM"), "{stderr}");
    let stopped = job_states(&db, id);
    assert!(!stopped.contains(&JobState::Running), "{stopped:?}");
    std::thread::sleep(Duration::from_millis(1000));
    assert_eq!(job_states(&db, id), stopped, "work went on after the stop");
    let out = moorfret(&["campaign", "resume", "demo", "--db", &db, "--workers", "2"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_each_done_once(&db, id);
    for kind in ["lifetime", "damage-inputs", "sea-states"] {
        assert_eq!(
            query_output(&db, "demo", kind, &["--format", "csv"]),
            query_output(&reference_db, "demo", kind, &["--format", "csv"]),
            "query {kind}"
        );
    }
}
