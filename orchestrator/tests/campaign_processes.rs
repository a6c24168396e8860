//! Crash safety of the worker loop and the campaign driver with real processes
//! (`moorfret worker`, `moorfret campaign resume`) on an SQLite store, using the test job kind
//! (sleeps, crashes) for the queue mechanics and a short lease so that expiry is quick.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use moorfret_orchestrator::store::{
    AttemptOutcome, CampaignId, JobKind, JobState, NewCampaign, PlannedJob, Store, StoreOptions,
    TestPayload,
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

/// Every job of the campaign is done and has exactly one `done` attempt.
fn assert_each_done_once(db: &str, id: CampaignId) {
    rt().block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let jobs = store.jobs_of_campaign(id).await.unwrap();
        let attempts = store.attempts_of_campaign(id).await.unwrap();
        for job in &jobs {
            assert_eq!(job.state, JobState::Done, "job {}", job.id);
            let done = attempts
                .iter()
                .filter(|a| a.job == job.id && a.outcome == Some(AttemptOutcome::Done))
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

#[test]
fn stopped_worker_releases_its_lease_without_consuming_an_attempt() {
    let _serial = serial();
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
        .args(["-TERM", &pid])
        .status()
        .unwrap()
        .success());
    let status = w.wait().unwrap();
    assert!(status.success());
    rt().block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        let job = &store.jobs_of_campaign(id).await.unwrap()[0];
        assert_eq!(job.state, JobState::Ready);
        assert_eq!((job.attempt, job.lost_count), (0, 0));
        store.close().await;
    });
}

#[test]
fn killed_driver_then_resume_completes_every_job_once() {
    let _serial = serial();
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let payloads: Vec<_> = (0..12)
        .map(|_| TestPayload::Sleep { duration_ms: 300 })
        .collect();
    let (db, id) = store_with(dir.path(), "resume", &payloads);
    // The driver and its workers in their own process group, killed together (as a reboot).
    let mut driver = moorfret(&[
        "campaign",
        "resume",
        "resume",
        "--db",
        &db,
        "--workers",
        "2",
        "--lease-ms",
        LEASE_MS,
    ])
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
    let out = moorfret(&[
        "campaign",
        "resume",
        "resume",
        "--db",
        &db,
        "--workers",
        "2",
        "--lease-ms",
        LEASE_MS,
    ])
    .output()
    .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_each_done_once(&db, id);
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
        assert_eq!(jobs[0].error_class.as_deref(), Some("lost"));
        assert_eq!(jobs[0].lost_count, 3);
        assert!(jobs[1..].iter().all(|j| j.state == JobState::Done));
        store.close().await;
    });
}

/// The real stages end to end: one short sea state of the demo campaign (10 s transient, 10 s
/// recorded, 20 strand load samples) through `campaign launch`, global then strand, then
/// `campaign status --json` (about 25 s in a debug build); then the damage inputs through
/// `query damage-inputs` and `query lifetime`.
#[test]
fn demo_sea_state_runs_through_both_real_stages() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns");
    for sub in ["data", "benchmarks"] {
        std::fs::create_dir(dir.path().join(sub)).unwrap();
    }
    for name in [
        "demo.json",
        "paper_case.json",
        "data/oc4_semi_floater.json",
        "benchmarks/strand_1_6_1.json",
    ] {
        std::fs::copy(src.join(name), dir.path().join(name)).unwrap();
    }
    std::fs::write(
        dir.path().join("data/demo_scatter.tsv"),
        "lower\tupper\t11\ttotal\n2\t2,5\t1,354\t1,354\n",
    )
    .unwrap();
    let file = dir.path().join("demo.json");
    let mut spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    spec["simulation"]["transient_s"] = serde_json::json!(10.0);
    spec["simulation"]["wave_ramp_s"] = serde_json::json!(8.0);
    spec["simulation"]["duration_s"] = serde_json::json!(10.0);
    std::fs::write(&file, spec.to_string()).unwrap();
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
            .any(|a| a.role == "contact_records"));
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
        let out = moorfret(&[
            "query",
            kind,
            "--campaign",
            "demo",
            "--db",
            &db,
            "--format",
            "json",
        ])
        .stdout(Stdio::piped())
        .output()
        .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
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
}
