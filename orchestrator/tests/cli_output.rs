//! Commands whose standard output goes away: a closed pipe (`| head -1`, `| true`) ends them
//! quietly with exit 0, a full disk (`> /dev/full`) is an error with exit 1; neither panics.

mod fixture;

use std::path::Path;
use std::process::{Command, Stdio};

/// The fixture campaign in an SQLite store; returns (directory, store file).
async fn fixture_store() -> (tempfile::TempDir, std::path::PathBuf) {
    let Some((store, fixture::Location::Sqlite(dir))) = fixture::open(false).await else {
        panic!("SQLite fixture");
    };
    let db = dir.path().join("fixture.sqlite");
    fixture::populate(&store, None).await;
    store.close().await;
    (dir, db)
}

/// A minimal output directory of a `run strand --load` run in `dir/run` (a strain history, no
/// contact records): enough for `strand fretting` to print its table.
fn strand_run(dir: &Path) -> std::path::PathBuf {
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    let load = dir.join("load.csv");
    let mut text = String::from("time_s,axial_strain,curvature_per_m\n");
    for i in 0..9 {
        text.push_str(&format!(
            "{},1e-3,{}\n",
            0.25 * f64::from(i),
            1e-3 * f64::from(i % 2)
        ));
    }
    std::fs::write(&load, text).unwrap();
    std::fs::write(run.join("contact_records.json"), "[]").unwrap();
    let summary = serde_json::json!({ "load": load, "samples": 9 });
    std::fs::write(run.join("summary.json"), summary.to_string()).unwrap();
    run
}

fn commands(db: &Path, dir: &Path) -> Vec<Vec<String>> {
    let run = strand_run(dir).to_string_lossy().into_owned();
    let profile = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../campaigns/benchmarks/strand_1_6_1.json")
        .to_string_lossy()
        .into_owned();
    let db = db.to_string_lossy().into_owned();
    let out = dir.join("report").to_string_lossy().into_owned();
    let s = |v: &[&str]| v.iter().map(|a| (*a).to_owned()).collect::<Vec<_>>();
    vec![
        s(&["campaign", "status", "--db", &db]),
        s(&["campaign", "status", "--json", "--db", &db]),
        s(&[
            "query",
            "sea-states",
            "--campaign",
            fixture::NAME,
            "--db",
            &db,
        ]),
        s(&[
            "query",
            "lifetime",
            "--campaign",
            fixture::NAME,
            "--db",
            &db,
            "--format",
            "csv",
        ]),
        s(&["report", fixture::NAME, "--out", &out, "--db", &db]),
        s(&[
            "run",
            "catenary",
            "--horizontal-span-m",
            "800",
            "--vertical-span-m",
            "186",
            "--length-m",
            "835.5",
            "--weight-n-per-m",
            "1000",
        ]),
        s(&["strand", "fretting", &profile, &run]),
    ]
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_closed_pipe_ends_quietly_and_a_full_disk_is_an_error() {
    let (dir, db) = fixture_store().await;
    for args in commands(&db, dir.path()) {
        // the reader is gone before the command writes
        let mut child = Command::new(env!("CARGO_BIN_EXE_moorfret"))
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?} | closed: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");

        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
            .args(&args)
            .stdout(full)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?} > /dev/full: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(
            stderr.contains("writing to standard output: No space left on device"),
            "{args:?}: {stderr}"
        );
    }
}
