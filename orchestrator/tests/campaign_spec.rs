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
        // the demo and paper files use no data subdirectory
        if entry.file_type().unwrap().is_dir() {
            continue;
        }
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
/// it (on a thread of its own, after the pool is closed), then until the store's files have
/// stopped changing, so that their bytes are settled before a test compares them. The stores
/// here are closed in this process, so the log does go: on a loaded machine the checkpoint
/// took longer than 5 s (seen twice in CI), hence up to 60 s.
fn settle(db: &str) {
    let wal = format!("{db}-wal");
    for _ in 0..2400 {
        if !Path::new(&wal).exists() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(25));
    }
    let mut last = store_files(db);
    let mut stable = 0;
    for _ in 0..200 {
        std::thread::sleep(std::time::Duration::from_millis(50));
        let now = store_files(db);
        stable = if now == last { stable + 1 } else { 0 };
        if stable == 4 {
            return;
        }
        last = now;
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
    assert_eq!(marked.sectors[0].table, plain.sectors[0].table);
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
    assert_eq!(resolved.sectors.len(), 1);
    let table = &resolved.sectors[0].table;
    let non_zero = table.cells().iter().filter(|c| c.value > 0.0).count();
    let states = plan::sea_states(
        table,
        resolved.sectors[0].source.reading,
        resolved.inputs.spec.simulation.seeds_per_sea_state,
        plan::extra_seeds_per_sea_state(&resolved.inputs),
        resolved.inputs.spec.seed,
    );
    // one cell, Hs 0-0.5 m at Tp 3 s, lies mostly above the wave cut-off (1.98 rad/s, the
    // floater's kinematics table): it is left out, by the file's `cells_outside_model`
    let left_out: Vec<_> = resolved.left_out().map(|(_, c)| c).collect();
    assert_eq!(left_out.len(), 1);
    let out = &left_out[0].limits;
    assert_eq!((out.hs_m, out.tp_s), (0.25, 3.0));
    assert!(out.energy_kept < 0.5, "{out:?}");
    assert_eq!(states.len(), non_zero);
    assert_eq!(states.len(), 152);
    assert_eq!(resolved.planned_limits().count(), 152);
    // its Tp 4 and 5 s cells keep about 64 % and 83 % of their energy: planned, and flagged
    let flagged: Vec<_> = resolved
        .planned_limits()
        .filter(|l| !l.flags.is_empty())
        .collect();
    assert_eq!(flagged.len(), 5, "{flagged:?}");
    for l in &flagged {
        let expected = if l.tp_s == 4.0 { 0.64 } else { 0.83 };
        assert!((l.energy_kept - expected).abs() < 0.01, "{l:?}");
    }
    // cells are percent of the year: their sum, 43.517 % less the 0.005 % left out, is the
    // year fraction planned
    let covered: f64 = states.iter().map(|s| s.occurrence_fraction).sum();
    assert!((covered - 0.43512).abs() < 1e-9, "{covered}");
    // the printed totals that disagree with their cells are all found
    assert!(!resolved.sectors[0].mismatches.is_empty());
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

/// Another program's SQLite database (one table of its own) at `path`, in WAL mode if `wal`
/// (else with a rollback journal).
fn foreign_database(path: &Path, wal: bool) {
    use sqlx::sqlite::SqliteJournalMode;
    use sqlx::{ConnectOptions, Connection};
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let mut conn = sqlx::sqlite::SqliteConnectOptions::new()
            .filename(path)
            .create_if_missing(true)
            .journal_mode(if wal {
                SqliteJournalMode::Wal
            } else {
                SqliteJournalMode::Delete
            })
            .connect()
            .await
            .unwrap();
        sqlx::query("CREATE TABLE notes (id INTEGER PRIMARY KEY, body TEXT)")
            .execute(&mut conn)
            .await
            .unwrap();
        sqlx::query("INSERT INTO notes (body) VALUES ('field notes')")
            .execute(&mut conn)
            .await
            .unwrap();
        conn.close().await.unwrap();
    });
}

/// The names in `dir`, sorted.
fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Every command but `campaign launch` into a new path opens an existing moorfret store or
/// refuses, touching nothing: another program's SQLite file and an empty file stay byte for
/// byte as they were, and no `-wal`, `-shm`, `.artifacts` or output directory appears.
#[test]
fn a_file_that_is_not_a_moorfret_store_is_never_written() {
    let dir = campaign_copy();
    let foreign = dir.path().join("other.sqlite");
    foreign_database(&foreign, false);
    let foreign_wal = dir.path().join("other-wal.sqlite");
    foreign_database(&foreign_wal, true);
    let empty = dir.path().join("empty.sqlite");
    std::fs::write(&empty, b"").unwrap();
    let demo = dir.path().join("demo.json").to_string_lossy().into_owned();
    let out = dir.path().join("report-out").to_string_lossy().into_owned();
    for (db, why) in [
        (&foreign, "another program's"),
        (&foreign_wal, "another program's"),
        (&empty, "empty"),
    ] {
        let listing = names_in(dir.path());
        let before = std::fs::read(db).unwrap();
        let db_text = db.to_string_lossy().into_owned();
        for args in [
            vec!["query", "lifetime", "--campaign", "demo"],
            vec!["query", "sea-states", "--campaign", "demo"],
            vec!["report", "demo", "--out", &out],
            vec!["campaign", "status"],
            vec!["campaign", "status", "demo", "--json"],
            vec!["campaign", "cancel", "demo"],
            vec!["campaign", "resume", "demo", "--workers", "1"],
            vec!["worker", "--exit-when-idle"],
            vec!["campaign", "launch", &demo, "--workers", "1"],
        ] {
            let result = Command::new(env!("CARGO_BIN_EXE_moorfret"))
                .args(&args)
                .args(["--db", &db_text])
                .current_dir(dir.path())
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&result.stderr);
            assert_eq!(
                result.status.code(),
                Some(1),
                "{args:?} on {db_text}: {stderr}"
            );
            assert!(
                stderr.contains("not a moorfret store"),
                "{args:?}: {stderr}"
            );
            assert!(stderr.contains(why), "{args:?}: {stderr}");
            assert!(
                std::fs::read(db).unwrap() == before,
                "{args:?} changed {db_text}: {stderr}"
            );
            assert_eq!(names_in(dir.path()), listing, "{args:?}: {stderr}");
        }
    }
}

/// Every command but `campaign launch` given a mistyped store path refuses with exit 1, naming
/// the path, and creates nothing: neither a store nor its `.artifacts` directory, the missing
/// directories of the path or the report's output directory.
#[test]
fn a_mistyped_store_path_is_refused_and_creates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report-out").to_string_lossy().into_owned();
    for typo in [
        dir.path().join("typo.sqlite"),
        dir.path().join("no/such/dir/typo.sqlite"),
    ] {
        let typo_text = typo.to_string_lossy().into_owned();
        for args in [
            vec!["query", "lifetime", "--campaign", "demo"],
            vec!["query", "damage-inputs", "--campaign", "demo"],
            vec!["report", "demo", "--out", &out],
            vec!["campaign", "status"],
            vec!["campaign", "status", "demo", "--json"],
            vec!["campaign", "cancel", "demo"],
            vec!["campaign", "resume", "demo", "--workers", "1"],
            vec!["worker", "--exit-when-idle"],
            vec!["worker"],
        ] {
            for db in [typo_text.clone(), format!("sqlite://{typo_text}")] {
                let result = Command::new(env!("CARGO_BIN_EXE_moorfret"))
                    .args(&args)
                    .args(["--db", &db])
                    .current_dir(dir.path())
                    .output()
                    .unwrap();
                let stderr = String::from_utf8_lossy(&result.stderr);
                assert_eq!(
                    result.status.code(),
                    Some(1),
                    "{args:?} --db {db}: {stderr}"
                );
                assert!(stderr.contains(&typo_text), "{args:?}: {stderr}");
                assert!(
                    stderr.contains("no such database file"),
                    "{args:?}: {stderr}"
                );
                assert_eq!(
                    names_in(dir.path()),
                    Vec::<String>::new(),
                    "{args:?} --db {db}: {stderr}"
                );
            }
        }
    }
}

/// `dir/data/cells.tsv` with the given rows under Tp columns `tps`, and `demo.json` reading it.
fn scatter_of(dir: &Path, tps: &[&str], rows: &[&str]) {
    let mut text = format!("lower\tupper\t{}\n", tps.join("\t"));
    for r in rows {
        text.push_str(r);
        text.push('\n');
    }
    std::fs::write(dir.join("data/cells.tsv"), text).unwrap();
    edit_json(&dir.join("demo.json"), |v| {
        v["scatter"]["path"] = serde_json::json!("data/cells.tsv");
    });
}

/// Sea states the wave model cannot carry are refused, each named with why, before anything is
/// stored: a spectrum wholly above the cut-off (Tp 0.5 s, which ran in calm water and counted
/// as covered), one mostly above it (Tp 3 s), waves steeper than DNV-RP-C205 allows and Hs
/// at the water depth.
#[test]
fn sea_states_the_wave_model_cannot_carry_are_refused() {
    for (tps, row, expected) in [
        (
            ["11", "0.5"],
            "0\t0.5\t1\t1",
            vec!["Tp 0.5 s", "keeps 0.0 %"],
        ),
        (
            ["11", "3"],
            "0\t0.5\t1\t1",
            vec!["Tp 3 s", "of the spectrum's energy", "min_wave_energy_kept"],
        ),
        (
            ["11", "6"],
            "6\t7\t1\t1",
            vec!["Hs 6-7 m, Tp 6 s", "DNV-RP-C205"],
        ),
        (
            ["11", "20"],
            "99.5\t100.5\t0\t1",
            vec!["Tp 20 s", "of the water depth"],
        ),
    ] {
        let dir = campaign_copy();
        let db = existing_store(dir.path());
        scatter_of(dir.path(), &tps, &[row]);
        let mut all = vec!["scatter.path", "cannot carry", "cells_outside_model"];
        all.extend(expected);
        assert_refused(dir.path(), &db, &all);
    }
}

/// With `scatter.cells_outside_model = "leave_out"` such cells are left out of the plan and
/// named; the others are planned with the energy their cut-off keeps.
#[test]
fn cells_outside_the_model_may_be_left_out_explicitly() {
    let dir = campaign_copy();
    scatter_of(dir.path(), &["11", "3"], &["0\t0.5\t1\t0.5"]);
    edit_json(&dir.path().join("demo.json"), |v| {
        v["scatter"]["cells_outside_model"] = serde_json::json!("leave_out");
    });
    let resolved = resolve(&dir.path().join("demo.json")).unwrap();
    let left_out: Vec<_> = resolved.left_out().map(|(_, c)| c).collect();
    assert_eq!(left_out.len(), 1);
    assert_eq!(left_out[0].limits.tp_s, 3.0);
    let states = plan::sea_states(
        &resolved.sectors[0].table,
        resolved.sectors[0].source.reading,
        1,
        0,
        1,
    );
    assert_eq!(states.len(), 1);
    assert_eq!(states[0].tp_s, 11.0);
    let limits: Vec<_> = resolved.planned_limits().collect();
    assert_eq!(limits.len(), 1);
    assert!(limits[0].energy_kept > 0.99);
}

/// Every non-zero cell makes a valid case before anything is stored: a Tp = 0 column after a
/// valid cell was stored and failed only when its job ran.
#[test]
fn every_cell_is_checked_before_anything_is_stored() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    scatter_of(dir.path(), &["11", "0"], &["2\t2.5\t1\t0", "4\t4.5\t0\t1"]);
    assert_refused(
        dir.path(),
        &db,
        &[
            "scatter.path",
            "Hs 4-4.5 m, Tp 0 s (row 2, period column 2)",
            "tp_s",
        ],
    );
}

/// Output or load intervals too coarse for the waves are refused, not turned into a lower
/// damage.
#[test]
fn intervals_that_cannot_resolve_the_waves_are_refused() {
    // (output interval, load interval): Tp 11 s needs 1.1 s or less
    for (field, output, load) in [
        ("strand.load_interval_s", 0.1, 15.0),
        ("simulation.output_interval_s", 1.5, 1.5),
    ] {
        let dir = campaign_copy();
        let db = existing_store(dir.path());
        edit_json(&dir.path().join("demo.json"), |v| {
            v["simulation"]["output_interval_s"] = serde_json::json!(output);
            v["strand"]["load_interval_s"] = serde_json::json!(load);
        });
        assert_refused(
            dir.path(),
            &db,
            &[field, "cannot resolve the waves", "Tp 11 s"],
        );
    }
}

/// Each timing fault names the field at fault: a time step coarser than the output interval,
/// a transient too long for any step, a wave ramp longer than the transient.
#[test]
fn timing_faults_blame_the_field_at_fault() {
    for (section, field, value, expected) in [
        (
            "simulation",
            "time_step_s",
            serde_json::json!(0.2),
            vec![
                "simulation.time_step_s",
                "must not exceed simulation.output_interval_s",
            ],
        ),
        (
            "simulation",
            "transient_s",
            serde_json::json!(1e9),
            vec!["simulation.transient_s", "time steps"],
        ),
        (
            "simulation",
            "wave_ramp_s",
            serde_json::json!(25.0),
            vec![
                "simulation.wave_ramp_s",
                "must not exceed simulation.transient_s",
            ],
        ),
    ] {
        let dir = campaign_copy();
        let db = existing_store(dir.path());
        edit_json(&dir.path().join("demo.json"), |v| {
            v[section][field] = value;
        });
        assert_refused(dir.path(), &db, &expected);
    }
}

/// A hot spot at the junction of a chain and a rope says so, instead of claiming that a point
/// inside the rope's printed span lies on a chain.
#[test]
fn hot_spot_at_a_chain_junction_says_so() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("demo.json"), |v| {
        v["hot_spots"] = serde_json::json!([{"line": 1, "arc_length_m": 30.0}]);
    });
    assert_refused(
        dir.path(),
        &db,
        &[
            "hot_spots[0].arc_length_m",
            "junction of chain segment `chain-1` and rope segment `wire-rope-1`",
            "ends at a chain excluded",
        ],
    );
}

/// A negative slip-histogram edge bounds a bin no amplitude can fall in: refused.
#[test]
fn a_negative_histogram_edge_is_refused() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("demo.json"), |v| {
        v["fatigue"] = serde_json::json!({"slip_amplitude_edges_m": [-1e-6, 1e-6, 1e-5, 1e-4]});
    });
    assert_refused(
        dir.path(),
        &db,
        &["fatigue.slip_amplitude_edges_m", "negative edge -0.000001"],
    );
}

/// A JSON type error names the field path as well as the line and column.
#[test]
fn a_json_type_error_names_the_field() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("demo.json"), |v| {
        v["simulation"]["duration_s"] = serde_json::json!("30");
    });
    assert_refused(
        dir.path(),
        &db,
        &["field `simulation.duration_s`", "invalid type", "line"],
    );
}

/// Hs above 0.6 of the water depth (a sea state that has broken on the bottom before reaching
/// the site) is refused, even when gentle and wholly below the wave cut-off: Hs 65 m in the
/// 100 m of `paper_case.json` at Tp 40 s (steepness 0.026, under DNV's 1/25). The limit used
/// to be McCowan's 0.78, which bounds single waves, not Hs.
#[test]
fn hs_above_the_depth_limited_breaking_height_is_refused() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    scatter_of(
        dir.path(),
        &["11", "40"],
        &["2\t2.5\t1\t0", "64.5\t65.5\t0\t1"],
    );
    assert_refused(
        dir.path(),
        &db,
        &[
            "scatter.path",
            "cell Hs 64.5-65.5 m, Tp 40 s (row 2, period column 2)",
            "Hs is 0.65 of the water depth 100 m",
            "depth-induced breaking limit 0.6",
        ],
    );
}

/// Runs `moorfret ARGS…` and returns (exit code, stdout, stderr).
fn moorfret(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A sea state whose wave cut-off keeps between half and 90 % of its energy (Tp 5 s: its waves
/// above the floater table's 1.98 rad/s are dropped) is planned but flagged, and the energy
/// every sea state keeps is stored with it: `query sea-states` reads it from the store and
/// marks the flagged one, `campaign status` counts it with its share of the year, the report
/// lists it. It used to be planned with a log line at most, and the energy kept recomputed.
#[test]
fn partly_kept_sea_states_are_flagged_and_their_energy_stored() {
    let dir = campaign_copy();
    scatter_of(dir.path(), &["11", "5"], &["0.5\t1\t1\t0.5"]);
    let resolved = resolve(&dir.path().join("demo.json")).unwrap();
    let limits: Vec<_> = resolved.planned_limits().cloned().collect();
    assert_eq!(limits.len(), 2);
    let (long, short) = (&limits[0], &limits[1]);
    assert_eq!((long.hs_m, long.tp_s), (0.75, 11.0));
    assert!(long.energy_kept > 0.99 && long.flags.is_empty(), "{long:?}");
    assert_eq!((short.hs_m, short.tp_s), (0.75, 5.0));
    assert!((0.5..0.9).contains(&short.energy_kept), "{short:?}");
    assert!(short.faults.is_empty(), "{short:?}");
    assert_eq!(short.flags.len(), 1, "{short:?}");
    assert!(short.flags[0].contains("less than 90 %"), "{short:?}");
    assert!(
        (short.kept_hs_m() - 0.75 * short.energy_kept.sqrt()).abs() < 1e-12,
        "{short:?}"
    );

    // planned without running: the sea states carry the energy their checks found
    let db = dir
        .path()
        .join("plan.sqlite")
        .to_string_lossy()
        .into_owned();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let store = Store::open(&db, StoreOptions::default()).await.unwrap();
        plan::create(&store, &resolved).await.unwrap();
        store.close().await;
    });
    settle(&db);

    let (code, stdout, stderr) = moorfret(&[
        "query",
        "sea-states",
        "--campaign",
        "demo",
        "--db",
        &db,
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let rows: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 2, "{stdout}");
    for (row, limits, flagged) in [(&rows[0], long, false), (&rows[1], short, true)] {
        assert_eq!(row["tp_s"].as_f64(), Some(limits.tp_s), "{stdout}");
        assert_eq!(
            row["wave_energy_kept"].as_f64(),
            Some(limits.energy_kept),
            "{stdout}"
        );
        assert_eq!(
            row["wave_energy_flagged"].as_bool(),
            Some(flagged),
            "{stdout}"
        );
    }

    let (code, stdout, stderr) = moorfret(&["campaign", "status", "demo", "--db", &db, "--json"]);
    assert_eq!(code, 0, "{stderr}");
    let status: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(
        status["sea_states_energy_flagged"].as_u64(),
        Some(1),
        "{stdout}"
    );
    assert!(
        (status["occurrence_energy_flagged"].as_f64().unwrap() - 0.005).abs() < 1e-15,
        "{stdout}"
    );
    assert_eq!(
        status["wave_energy_kept_min"].as_f64(),
        Some(short.energy_kept),
        "{stdout}"
    );
    let (code, stdout, stderr) = moorfret(&["campaign", "status", "demo", "--db", &db]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("1 sea state(s), 0.5000 % of the year, below 90 % (flagged)"),
        "{stdout}"
    );

    let out = dir.path().join("report");
    let out_text = out.to_string_lossy().into_owned();
    let (code, _, stderr) = moorfret(&["report", "demo", "--out", &out_text, "--db", &db]);
    assert_eq!(code, 0, "{stderr}");
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains("Wave energy kept per sea state"), "{page}");
    assert!(
        page.contains("1 sea state(s), 0.5000 % of the year, keep less than 90 %"),
        "{page}"
    );
}

/// The counts of `campaign launch|resume --workers` and `worker --poll-ms` take negative
/// numbers as values and refuse them by the option's name (they were refused as unknown
/// arguments), as `--workers 0` is refused (it silently ran one worker); nothing is written.
#[test]
fn negative_and_zero_counts_are_refused_by_the_option_name() {
    let dir = campaign_copy();
    let db = dir
        .path()
        .join("none.sqlite")
        .to_string_lossy()
        .into_owned();
    let file = dir.path().join("demo.json").to_string_lossy().into_owned();
    for (args, option, reason) in [
        (
            vec!["campaign", "launch", &file, "--db", &db, "--workers", "-1"],
            "--workers",
            "must be at least 1",
        ),
        (
            vec!["campaign", "launch", &file, "--db", &db, "--workers", "0"],
            "--workers",
            "must be at least 1",
        ),
        (
            vec!["campaign", "resume", "demo", "--db", &db, "--workers", "-3"],
            "--workers",
            "must be at least 1",
        ),
        (
            vec!["worker", "--db", &db, "--poll-ms", "-1"],
            "--poll-ms",
            "must not be negative",
        ),
    ] {
        let (code, _, stderr) = moorfret(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(option), "{args:?}: {stderr}");
        assert!(stderr.contains(reason), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("unexpected argument"),
            "{args:?}: {stderr}"
        );
        assert!(!Path::new(&db).exists(), "{args:?} created a store");
    }
}

/// Every table of a directional climate is checked, cell by cell, before anything is stored:
/// a sea state the wave model cannot carry in the third sector names that sector's table, its
/// cell and why; a type error in a sector names the sector's field path.
#[test]
fn every_sector_is_checked_and_named() {
    let good = "lower\tupper\t11\n2\t2.5\t100\n";
    let bad = "lower\tupper\t11\t0.5\n2\t2.5\t90\t0\n0\t0.5\t0\t10\n";
    let sectors = |third: serde_json::Value| {
        serde_json::json!({ "sectors": [
            {"label": "N", "heading_deg": 0.0, "share_percent": 30.0, "path": "data/n.tsv"},
            {"label": "E", "heading_deg": 90.0, "share_percent": 30.0, "path": "data/e.tsv"},
            third,
        ]})
    };
    for (third, expected) in [
        (
            serde_json::json!(
                {"label": "S", "heading_deg": 180.0, "share_percent": 40.0, "path": "data/s.tsv"}
            ),
            vec![
                "scatter.sectors[2].path",
                "cell Hs 0-0.5 m, Tp 0.5 s (row 2, period column 2)",
                "keeps 0.0 %",
            ],
        ),
        (
            serde_json::json!(
                {"label": "S", "heading_deg": 180.0, "share_percent": "40", "path": "data/s.tsv"}
            ),
            vec![
                "field `scatter.sectors[2].share_percent`",
                "invalid type",
                "line",
            ],
        ),
    ] {
        let dir = campaign_copy();
        let db = existing_store(dir.path());
        for (name, table) in [("n", good), ("e", good), ("s", bad)] {
            std::fs::write(dir.path().join(format!("data/{name}.tsv")), table).unwrap();
        }
        edit_json(&dir.path().join("demo.json"), |v| {
            v["scatter"] = sectors(third);
        });
        assert_refused(dir.path(), &db, &expected);
    }
}

/// A type error in the floater file the case names gives the field path too (it gave a line
/// and column only).
#[test]
fn a_floater_type_error_names_the_field() {
    let dir = campaign_copy();
    let db = existing_store(dir.path());
    edit_json(&dir.path().join("data/oc4_semi_floater.json"), |v| {
        v["members"][2]["diameter_m"] = serde_json::json!("12");
    });
    assert_refused(
        dir.path(),
        &db,
        &[
            "floater.rigid_body.spec_path",
            "field `members[2].diameter_m`",
            "invalid type",
            "line",
        ],
    );
}

/// `"hot_spots": "auto"`: one hot spot per line, on its rope, found by a screening run of the
/// severest sea state and stored with the campaign; resolved again, the same hot spots and the
/// same cache keys. Screening settings with listed hot spots are refused by field.
#[test]
fn automatic_hot_spots_are_found_on_every_line_s_rope() {
    let dir = campaign_copy();
    let file = dir.path().join("demo.json");
    edit_json(&file, |v| {
        v["hot_spots"] = serde_json::json!("auto");
        v["hot_spot_screening"] = serde_json::json!({"duration_s": 20.0});
    });
    let resolved = resolve(&file).unwrap();
    let inputs = &resolved.inputs;
    let found = &inputs.hot_spot_screening;
    let lines: Vec<u32> = found.iter().map(|f| f.line).collect();
    assert_eq!(lines, [1, 2, 3, 4, 5, 6]);
    for f in found {
        let line_type =
            moorfret_campaign::resolve::hot_spot_line_type(&inputs.base_case, f.arc_length_m)
                .unwrap();
        assert!(
            line_type.is_rope(),
            "line {} at {} m",
            f.line,
            f.arc_length_m
        );
        assert!(f.arc_length_m > 30.0, "not at the chain junction: {f:?}");
        assert!(
            f.equivalent_strain_range > 1e-6 && f.equivalent_strain_range < 1e-2,
            "{f:?}"
        );
        // the demo's severest sea state, the one screened
        assert_eq!(
            (f.governing_hs_m, f.governing_sector.as_deref()),
            (6.25, None)
        );
    }
    let listed: Vec<_> = found.iter().map(|f| f.hot_spot()).collect();
    assert_eq!(inputs.spec.hot_spots.to_vec(), listed);
    assert_eq!(inputs.base_case.hot_spots, listed);
    assert_eq!(inputs.hot_spot_axial_stiffness_n, vec![3.6e8; 6]);
    let (stored, _) = resolved.stored_spec();
    assert!(stored["inputs"]["spec"]["hot_spots"].is_array());
    assert_eq!(
        stored["inputs"]["hot_spot_screening"]
            .as_array()
            .map(Vec::len),
        Some(6)
    );
    let again = resolve(&file).unwrap();
    assert_eq!(again.inputs.results_sha256(), inputs.results_sha256());
    assert_eq!(again.inputs.hot_spot_screening, *found);

    edit_json(&file, |v| {
        v["hot_spots"] = serde_json::json!([{"line": 1, "arc_length_m": 79.0}]);
    });
    let e = resolve(&file).unwrap_err().to_string();
    assert!(e.contains("hot_spot_screening"), "{e}");
}
