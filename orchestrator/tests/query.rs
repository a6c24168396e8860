//! Per-class damage rows, the result views and `moorfret query`, on a store populated by the
//! test fixture (hand-made rows, see `fixture/mod.rs`), on SQLite and PostgreSQL.

mod fixture;

use moorfret_orchestrator::query::{self, QueryKind};
use moorfret_solver::fretting::AngularPosition;
use moorfret_store::Store;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

async fn finish(store: Store) {
    store.drop_postgres_schema().await.unwrap();
}

async fn views_aggregate_the_class_rows(postgres: bool) {
    let Some((store, _location)) = fixture::open(postgres).await else {
        return;
    };
    let id = fixture::populate(&store, None).await;

    // Round trip of the stored rows of one strand job.
    let jobs = store.jobs_of_campaign(id).await.unwrap();
    let strand = jobs
        .iter()
        .find(|j| j.payload.get("seed").is_some())
        .unwrap();
    let back = store.results_of(strand.id).await.unwrap();
    let expected = fixture::strand_results(0, 0);
    let mut want = expected.class_damage_inputs.clone();
    want.sort_by_key(|r| r.layer_interface);
    assert_eq!(back.class_damage_inputs, want);

    // Per sea state: seed means (1e-6 and 4e-6 for the critical class, fretting_max).
    let rows = store.sea_state_class_damage(id).await.unwrap();
    assert_eq!(
        rows.len(),
        2 * 2 * 4,
        "2 sea states × 2 classes × 4 measures"
    );
    for (s, mean) in [(0, 1e-6), (1, 4e-6)] {
        let r = rows
            .iter()
            .find(|r| {
                r.sea_state_index == s
                    && r.layer_interface == 2
                    && r.angular_position == AngularPosition::OuterArc
                    && r.measure == "fretting_max"
            })
            .unwrap();
        assert_eq!(r.seeds, 2);
        assert!(rel(r.damage_seed_mean, mean) < 1e-12);
        assert!(rel(r.damage_rate_per_s, mean / fixture::T_EFF_S) < 1e-12);
        // seeds 0 and 1: 100 and 101 partial-slip cycles per hour; Ruiz maxima over seeds.
        assert!(rel(r.partial_slip_cycles_per_hour, 100.5) < 1e-12);
        assert_eq!(r.ruiz_f1_max, 51.0);
        let m = rows
            .iter()
            .find(|m| {
                m.sea_state_index == s && m.layer_interface == 2 && m.measure == "fretting_mean"
            })
            .unwrap();
        assert!(rel(m.damage_seed_mean, 0.25 * mean) < 1e-12);
    }

    // Lifetime: the reference annual damage, occurrence covered reported.
    let life = store.lifetime_class_damage(id).await.unwrap();
    let critical = life
        .iter()
        .find(|r| r.layer_interface == 2 && r.measure == "fretting_max")
        .unwrap();
    assert!(rel(critical.annual_damage, fixture::ANNUAL_REFERENCE) < 1e-9);
    assert!(rel(critical.occurrence_covered, 0.43758) < 1e-12);
    // The rope S-N law per slip cycle beside it: the fixture's rows carry twice the rate.
    let rope = life
        .iter()
        .find(|r| r.layer_interface == 2 && r.measure == "rope_tn_max")
        .unwrap();
    assert!(rel(rope.annual_damage, 2.0 * fixture::ANNUAL_REFERENCE) < 1e-9);
    assert_eq!(critical.sea_states, 2);
    let tn = store.lifetime_damage(id).await.unwrap();
    assert_eq!(tn.len(), 1);
    assert!(rel(tn[0].annual_damage, 10.0 * fixture::ANNUAL_REFERENCE) < 1e-9);

    // Queries.
    let table = query::run(
        &store,
        fixture::NAME,
        QueryKind::DamageInputs,
        "fretting_max",
    )
    .await
    .unwrap();
    assert_eq!(
        table.rows.len(),
        4,
        "one row per sea state and contact class"
    );
    let table = query::run(&store, fixture::NAME, QueryKind::SeaStates, "")
        .await
        .unwrap();
    assert_eq!(table.rows.len(), 2);
    let k = table
        .columns
        .iter()
        .position(|c| c == "tn_dnv_spiral_rope_rate_per_s_hs0")
        .unwrap();
    let rate = table.rows[1][k].as_f64().unwrap();
    assert!(rel(rate, 40e-6 / fixture::T_EFF_S) < 1e-12);
    let table = query::run(&store, fixture::NAME, QueryKind::Lifetime, "")
        .await
        .unwrap();
    // 1 T-N curve, 2 classes × 4 fretting measures
    assert_eq!(table.rows.len(), 1 + 2 * 4);
    let table = query::run(&store, fixture::NAME, QueryKind::Contacts, "")
        .await
        .unwrap();
    assert_eq!(table.rows.len(), 4);
    let unknown = query::run(&store, "nope", QueryKind::Lifetime, "").await;
    assert!(format!("{:#}", unknown.unwrap_err()).contains("campaign `nope`"));
    let bad = query::run(&store, fixture::NAME, QueryKind::DamageInputs, "x").await;
    assert!(format!("{:#}", bad.unwrap_err()).contains("--measure `x`"));
    finish(store).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn views_aggregate_the_class_rows_sqlite() {
    views_aggregate_the_class_rows(false).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn views_aggregate_the_class_rows_postgres() {
    views_aggregate_the_class_rows(true).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn query_command_prints_json_csv_and_tables() {
    let Some((store, fixture::Location::Sqlite(dir))) = fixture::open(false).await else {
        panic!("SQLite fixture");
    };
    fixture::populate(&store, None).await;
    store.close().await;
    let db = dir.path().join("fixture.sqlite");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_moorfret"))
            .arg("query")
            .args(args)
            .arg("--db")
            .arg(&db)
            .output()
            .unwrap();
        (
            out.status.success(),
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        )
    };
    let (ok, json, err) = run(&["damage-inputs", "--campaign", "fixture", "--format", "json"]);
    assert!(ok, "{err}");
    let rows: serde_json::Value = serde_json::from_str(&json).unwrap();
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 4);
    assert_eq!(rows[0]["angular_position"], "neutral_axis");
    let (ok, csv, _) = run(&["lifetime", "--campaign", "fixture", "--format", "csv"]);
    assert!(ok);
    assert!(
        csv.starts_with("hot_spot_index,layer_interface,angular_position,measure,annual_damage,")
    );
    // header, 2 classes × 4 fretting measures, 1 T-N curve
    assert_eq!(csv.lines().count(), 1 + 2 * 4 + 1);
    let (ok, table, _) = run(&["sea-states", "--campaign", "fixture", "--wide"]);
    assert!(ok);
    assert_eq!(table.lines().count(), 3);
    // without --wide: the columns that fit 120 characters, and the others named
    let (ok, fitted, _) = run(&["sea-states", "--campaign", "fixture"]);
    assert!(ok);
    assert!(fitted.lines().all(|l| l.chars().count() <= 120), "{fitted}");
    let widest = table.lines().map(|l| l.chars().count()).max().unwrap_or(0);
    assert!(
        widest > 120,
        "the fixture's sea-state table is {widest} wide"
    );
    assert!(fitted.contains("more columns (--wide"), "{fitted}");
    let hidden = table.lines().next().unwrap().split_whitespace().count()
        - fitted.lines().next().unwrap().split_whitespace().count();
    assert!(
        fitted.contains(&format!("{hidden} more columns")),
        "{fitted}"
    );
    // a mistyped measure is refused by every query, naming the known ones
    for kind in [
        "lifetime",
        "sea-states",
        "damage-inputs",
        "seeds",
        "contacts",
        "fidelity",
    ] {
        let (ok, _, err) = run(&[kind, "--campaign", "fixture", "--measure", "foo"]);
        assert!(!ok, "{kind}");
        assert!(
            err.contains(
                "--measure `foo` is not a fretting measure (one of fretting_max, fretting_mean, \
                 rope_tn_max, rope_tn_mean)"
            ),
            "{kind}: {err}"
        );
    }
    let (ok, _, err) = run(&["contacts", "--campaign", "missing"]);
    assert!(!ok);
    assert!(
        err.contains("campaign `missing` is not in the store"),
        "{err}"
    );
}
