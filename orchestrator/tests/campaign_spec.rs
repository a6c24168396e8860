//! Bad campaign inputs through the real `moorfret campaign launch` process: each gives a clear
//! error naming the file or field and the reason, exits with code 1, and leaves an existing
//! store untouched. The good campaign files of `campaigns/` resolve and plan.

use std::path::{Path, PathBuf};
use std::process::Command;

use moorfret_campaign::resolve;
use moorfret_campaign::stiffness::AxialStiffnessRule;
use moorfret_orchestrator::plan;
use moorfret_store::{NewCampaign, Store, StoreOptions};

fn campaigns_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns")
}

/// A copy of `campaigns/` (demo and paper files with their data) in a temporary directory.
fn campaign_copy() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let src = campaigns_dir();
    std::fs::create_dir(dir.path().join("data")).unwrap();
    std::fs::create_dir(dir.path().join("benchmarks")).unwrap();
    std::fs::copy(
        src.join("benchmarks/strand_1_6_1.json"),
        dir.path().join("benchmarks/strand_1_6_1.json"),
    )
    .unwrap();
    for name in ["demo.json", "paper.json", "paper_case.json"] {
        std::fs::copy(src.join(name), dir.path().join(name)).unwrap();
    }
    for entry in std::fs::read_dir(src.join("data")).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(
            entry.path(),
            dir.path().join("data").join(entry.file_name()),
        )
        .unwrap();
    }
    dir
}

fn edit_json(path: &Path, edit: impl FnOnce(&mut serde_json::Value)) {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    edit(&mut v);
    std::fs::write(path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
}

/// A store with one existing campaign; returns its location.
fn existing_store(dir: &Path) -> String {
    let db = dir.join("store.sqlite").to_string_lossy().into_owned();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        store
            .create_campaign(&NewCampaign {
                name: "existing".into(),
                spec: serde_json::json!({}),
                spec_sha256: "0".into(),
            })
            .await
            .unwrap();
        store.close().await;
    });
    settle(&db);
    db
}

/// Waits until the last connection to `db` has checkpointed its log into the file and removed
/// it (on a thread of its own, after the pool is closed), so that the store's bytes are
/// settled before a test compares them.
fn settle(db: &str) {
    let wal = format!("{db}-wal");
    for _ in 0..200 {
        if !Path::new(&wal).exists() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(25));
    }
}

fn campaign_names(db: &str) -> Vec<String> {
    let rt = tokio::runtime::Runtime::new().unwrap();
    let names = rt.block_on(async {
        let store = Store::open(db, StoreOptions::default()).await.unwrap();
        let names = store
            .campaigns()
            .await
            .unwrap()
            .into_iter()
            .map(|c| c.name)
            .collect();
        store.close().await;
        names
    });
    settle(db);
    names
}

/// Runs `campaign launch FILE --db DB`; returns (exit code, stderr).
fn launch(file: &Path, db: &str) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(["campaign", "launch"])
        .arg(file)
        .args(["--db", db, "--workers", "1"])
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The files of the store `db` (the database, and its -wal and -shm when present) with their
/// bytes.
fn store_files(db: &str) -> Vec<(String, Option<Vec<u8>>)> {
    ["", "-wal", "-shm"]
        .iter()
        .map(|suffix| {
            let path = format!("{db}{suffix}");
            let bytes = std::fs::read(&path).ok();
            (path, bytes)
        })
        .collect()
}

/// A launch of `dir/demo.json` on the store `db` is refused with every `expected` text and
/// leaves the store's files as they were, byte for byte.
fn assert_refused(dir: &Path, db: &str, expected: &[&str]) {
    let before = store_files(db);
    let (code, stderr) = launch(&dir.join("demo.json"), db);
    assert_eq!(code, 1, "{stderr}");
    for e in expected {
        assert!(stderr.contains(e), "expected '{e}' in: {stderr}");
    }
    for ((path, a), (_, b)) in before.iter().zip(store_files(db)) {
        assert!(
            *a == b,
            "{path} changed ({:?} → {:?} bytes): {stderr}",
            a.as_ref().map(Vec::len),
            b.as_ref().map(Vec::len)
        );
    }
    assert_eq!(campaign_names(db), vec!["existing".to_owned()], "{stderr}");
}

#[test]
fn malformed_json_is_refused_with_its_position() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    std::fs::write(dir.path().join("demo.json"), "{\"name\": \"demo\",,}").unwrap();
    assert_refused(
        dir.path(),
        &db,
        &["not a valid campaign description", "line 1"],
    );
}

#[test]
fn unknown_field_is_named() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("demo.json"), |v| {
        v["simulation"]["durations"] = serde_json::json!(3.0);
    });
    assert_refused(dir.path(), &db, &["unknown field `durations`"]);
}

#[test]
fn out_of_range_value_is_named_by_its_path() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("demo.json"), |v| {
        v["simulation"]["duration_s"] = serde_json::json!(-30.0);
    });
    assert_refused(
        dir.path(),
        &db,
        &["simulation.duration_s must be > 0 (got -30)"],
    );
}

#[test]
fn profile_without_helical_layers_and_doubled_scatter_rows_are_refused() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("benchmarks/strand_1_6_1.json"), |v| {
        v["layers"] = serde_json::json!([]);
    });
    assert_refused(dir.path(), &db, &["strand.profile", "no helical layer"]);
    let dir = campaign_copy();
    let path = dir.path().join("data/demo_scatter.tsv");
    let text = std::fs::read_to_string(&path).unwrap();
    // the first data row twice: its sea states would be planned, and counted, twice
    let mut lines: Vec<&str> = text.lines().collect();
    let row = lines
        .iter()
        .position(|l| l.chars().next().is_some_and(|c| c.is_ascii_digit()))
        .unwrap();
    lines.insert(row + 1, lines[row]);
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    assert_refused(dir.path(), &db, &["scatter.path", "overlap"]);
}

/// The inputs that got through or aborted before (a step or a friction coefficient that makes
/// every job fail, 2³² − 1 seeds, a repeated hot spot, cells above the year) are refused by
/// `campaign launch` naming their field, the store left as it was byte for byte.
#[test]
fn inputs_that_would_fail_every_job_are_refused_before_the_store_is_touched() {
    type Edit = fn(&mut serde_json::Value);
    let cases: [(Edit, &[&str]); 4] = [
        (
            |v| v["simulation"]["time_step_s"] = serde_json::json!(1e-9),
            &["simulation.time_step_s"],
        ),
        (
            |v| v["strand"]["friction_coefficient"] = serde_json::json!(1e6),
            &["strand.friction_coefficient"],
        ),
        (
            |v| v["simulation"]["seeds_per_sea_state"] = serde_json::json!(4_294_967_295_u64),
            &["simulation.seeds_per_sea_state"],
        ),
        (
            |v| {
                v["hot_spots"] = serde_json::json!([
                    {"line": 1, "arc_length_m": 79.0},
                    {"line": 1, "arc_length_m": 79.0}
                ])
            },
            &["hot_spots[1]"],
        ),
    ];
    for (edit, expected) in cases {
        let dir = campaign_copy();
        let db = existing_store(dir.path());
        edit_json(&dir.path().join("demo.json"), edit);
        assert_refused(dir.path(), &db, expected);
    }
    // the year's cells summing to more than 100 %
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    let path = dir.path().join("data/demo_scatter.tsv");
    let text = std::fs::read_to_string(&path).unwrap();
    // two cells of 60 % of the year each
    let scaled = text.replace("1,354", "60").replace("0,423", "60");
    std::fs::write(&path, scaled).unwrap();
    assert_refused(dir.path(), &db, &["scatter.path"]);
}

/// Files saved by spreadsheets and some editors start with a UTF-8 byte-order mark.
#[test]
fn a_byte_order_mark_is_not_content() {
    let dir = campaign_copy();
    let plain = resolve(&dir.path().join("demo.json")).unwrap();
    for file in ["demo.json", "data/demo_scatter.tsv"] {
        let path = dir.path().join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, format!("\u{feff}{text}")).unwrap();
    }
    let marked = resolve(&dir.path().join("demo.json")).unwrap();
    assert_eq!(marked.inputs.spec, plain.inputs.spec);
    assert_eq!(marked.scatter, plain.scatter);
}

#[test]
fn hot_spot_on_a_chain_is_refused() {
    for arc in [10.0, 572.0] {
        let dir = campaign_copy();
        let db = existing_store(dir.path());
        edit_json(&dir.path().join("demo.json"), |v| {
            v["hot_spots"] = serde_json::json!([{"line": 1, "arc_length_m": arc}]);
        });
        assert_refused(
            dir.path(),
            &db,
            &[
                "hot_spots[0].arc_length_m",
                "lies on a chain segment",
                "30-190 m",
            ],
        );
    }
}

#[test]
fn unusable_artifact_directory_is_refused_before_the_campaign_is_stored() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    let artifacts = dir.path().join("store.sqlite.artifacts");
    let _ = std::fs::remove_dir_all(&artifacts);
    std::fs::write(&artifacts, b"a file where the artifact directory goes").unwrap();
    assert_refused(dir.path(), &db, &["artifact directory"]);
}

/// Every command that takes `--db` reads `MOORFRET_DB` too, and says so in its help.
#[test]
fn every_store_command_honours_moorfret_db() {
    let dir = tempfile::tempdir().unwrap();
    let typo = dir.path().join("from-env.db");
    for args in [
        vec!["campaign", "status"],
        vec!["campaign", "resume", "demo"],
        vec!["campaign", "cancel", "demo"],
        vec!["query", "lifetime", "--campaign", "demo"],
        vec!["report", "demo", "--out", "r"],
    ] {
        let help = Command::new(env!("CARGO_BIN_EXE_moorfret"))
            .args(&args[..args.len().min(2)])
            .arg("--help")
            .output()
            .unwrap();
        let help = String::from_utf8_lossy(&help.stdout);
        assert!(help.contains("[env: MOORFRET_DB="), "{args:?}: {help}");
        let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
            .args(&args)
            .env("MOORFRET_DB", &typo)
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains("from-env.db"), "{args:?}: {stderr}");
    }
}

#[test]
fn commands_that_read_a_store_never_create_one() {
    let dir = tempfile::tempdir().unwrap();
    let typo = dir.path().join("typo.db");
    for args in [
        vec!["campaign", "status"],
        vec!["campaign", "resume", "demo"],
        vec!["campaign", "cancel", "demo"],
        vec!["query", "lifetime", "--campaign", "demo"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
            .args(&args)
            .arg("--db")
            .arg(&typo)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("no such database file"),
            "{args:?}: {stderr}"
        );
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(left.is_empty(), "{args:?} left {left:?}");
    }
    let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(["campaign", "status", "--db", "mysql://x"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("unknown scheme `mysql`"), "{stderr}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn missing_data_file_is_named_with_its_field() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    std::fs::remove_file(dir.path().join("data/demo_scatter.tsv")).unwrap();
    assert_refused(
        dir.path(),
        &db,
        &["scatter.path: cannot read", "demo_scatter.tsv"],
    );
}

#[test]
fn negative_scatter_cell_is_refused_with_line_and_column() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    let path = dir.path().join("data/demo_scatter.tsv");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("0,423", "-0,423");
    std::fs::write(&path, text).unwrap();
    assert_refused(
        dir.path(),
        &db,
        &["scatter.path", "negative value -0.423", "line 5"],
    );
}

#[test]
fn non_numeric_scatter_cell_is_refused_with_line_and_column() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    let path = dir.path().join("data/demo_scatter.tsv");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("1,354\t0", "x1\t0");
    std::fs::write(&path, text).unwrap();
    assert_refused(
        dir.path(),
        &db,
        &["scatter.path", "'x1' is not a number", "line 4"],
    );
}

#[test]
fn store_of_a_newer_schema_is_refused_and_left_untouched() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    let rt = tokio::runtime::Runtime::new().unwrap();
    let url = format!("sqlite://{db}");
    rt.block_on(async {
        let pool = sqlx::SqlitePool::connect(&url).await.unwrap();
        sqlx::query("UPDATE schema_info SET value = '99' WHERE key = 'schema_version'")
            .execute(&pool)
            .await
            .unwrap();
        pool.close().await;
    });
    let (code, stderr) = launch(&dir.path().join("demo.json"), &db);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("99"), "{stderr}");
    rt.block_on(async {
        let pool = sqlx::SqlitePool::connect(&url).await.unwrap();
        let version: String =
            sqlx::query_scalar("SELECT value FROM schema_info WHERE key = 'schema_version'")
                .fetch_one(&pool)
                .await
                .unwrap();
        let names: Vec<String> = sqlx::query_scalar("SELECT name FROM campaigns")
            .fetch_all(&pool)
            .await
            .unwrap();
        assert_eq!(version, "99");
        assert_eq!(names, vec!["existing".to_owned()]);
        pool.close().await;
    });
}

#[test]
fn paper_campaign_plans_every_non_zero_cell_of_the_scatter_diagram() {
    let resolved = resolve(&campaigns_dir().join("paper.json")).unwrap();
    let table = &resolved.scatter;
    let non_zero = table.cells().iter().filter(|c| c.value > 0.0).count();
    let states = plan::sea_states(
        table,
        resolved.inputs.spec.scatter.reading,
        resolved.inputs.spec.simulation.seeds_per_sea_state,
        plan::extra_seeds_per_sea_state(&resolved.inputs),
        resolved.inputs.spec.seed,
    );
    assert_eq!(states.len(), non_zero);
    // cells are percent of the year: their sum, 43.517 %, is the year fraction covered
    let covered: f64 = states.iter().map(|s| s.occurrence_fraction).sum();
    assert!((covered - 0.43517).abs() < 1e-9, "{covered}");
    // the printed totals that disagree with their cells are all found
    assert!(!resolved.scatter_mismatches.is_empty());
    // every referenced file is hashed
    let fields: Vec<&str> = resolved.files.iter().map(|f| f.field.as_str()).collect();
    assert!(fields.contains(&"scatter.path"));
    assert!(fields.contains(&"strand.profiles_path"));
    assert_eq!(resolved.inputs.hot_spot_axial_stiffness_n, vec![3.6e8]);
    assert_eq!(
        resolved.inputs.spec.strand.axial_stiffness,
        Some(AxialStiffnessRule::StrandModel)
    );
}

/// A campaign file without `strand.axial_stiffness` takes the strand model's EA and stores that
/// choice, so its jobs' cache keys say it; the demo's stand-in strand keeps the line type's;
/// stored inputs without the setting (campaigns planned before it) keep the line type's EA
/// they were planned with.
#[test]
fn the_tension_to_strain_rule_is_stored_with_the_campaign() {
    let dir = tempfile::tempdir().unwrap();
    let src = campaigns_dir();
    for sub in ["data", "benchmarks"] {
        std::fs::create_dir(dir.path().join(sub)).unwrap();
    }
    for name in [
        "paper.json",
        "paper_case.json",
        "data/wsd_argoss_sector.tsv",
        "data/oc4_semi_floater.json",
        "data/strand_profiles.json",
    ] {
        std::fs::copy(src.join(name), dir.path().join(name)).unwrap();
    }
    let file = dir.path().join("paper.json");
    let mut spec: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    spec["strand"]
        .as_object_mut()
        .unwrap()
        .remove("axial_stiffness");
    std::fs::write(&file, spec.to_string()).unwrap();
    let resolved = resolve(&file).unwrap();
    let stored = serde_json::to_value(&resolved.inputs).unwrap();
    assert_eq!(stored["spec"]["strand"]["axial_stiffness"], "strand_model");

    let demo = resolve(&src.join("demo.json")).unwrap();
    assert_eq!(
        demo.inputs.spec.strand.axial_stiffness_rule(),
        AxialStiffnessRule::LineType
    );

    let mut before: moorfret_campaign::CampaignInputs = serde_json::from_value(stored).unwrap();
    before.spec.strand.axial_stiffness = None;
    assert_eq!(
        before.spec.strand.axial_stiffness_rule(),
        AxialStiffnessRule::LineType
    );
}
