//! Directional climates and the design check, through the real `moorfret` process: a demo
//! campaign split into two wave sectors plans its sea states at their headings and runs them
//! there; `query lines`, `utilisation` and `directions` agree with the lifetime figures; the
//! design fatigue factor and design life move every utilisation; the report opens with the
//! verdicts and draws the damage by direction. A climate of one sector plans what the same
//! table plans without sectors.

mod browser;
mod cli_support;

use std::path::{Path, PathBuf};
use std::process::Command;

use moorfret_campaign::resolve;
use moorfret_orchestrator::plan;
use moorfret_store::SeaStateId;
use serde_json::Value;

fn campaigns_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns")
}

/// `campaigns/` copied into a temporary directory.
fn campaign_copy() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    cli_support::copy_dir(&campaigns_dir(), dir.path());
    dir
}

/// The demo campaign with its climate as sectors: `(label, heading, share, table)` each.
fn sector_demo(dir: &Path, name: &str, sectors: &[(&str, f64, f64, &str)]) -> PathBuf {
    let mut spec: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("demo.json")).unwrap()).unwrap();
    spec["name"] = Value::from(name);
    let mut list = Vec::new();
    for (label, heading, share, table) in sectors {
        let path = format!("data/{label}.tsv");
        std::fs::write(dir.join(&path), table).unwrap();
        list.push(serde_json::json!({
            "label": label, "heading_deg": heading, "share_percent": share, "path": path,
        }));
    }
    spec["scatter"] = serde_json::json!({ "sectors": list });
    let file = dir.join(format!("{name}.json"));
    std::fs::write(&file, serde_json::to_string_pretty(&spec).unwrap()).unwrap();
    file
}

fn moorfret(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(args)
        .current_dir(dir)
        .env("RUST_LOG", "warn")
        .output()
        .unwrap()
}

fn query(dir: &Path, kind: &str, campaign: &str) -> Vec<Value> {
    let out = moorfret(
        dir,
        &[
            "query",
            kind,
            "--campaign",
            campaign,
            "--db",
            "s.sqlite",
            "--format",
            "json",
        ],
    );
    assert!(
        out.status.success(),
        "query {kind}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice::<Value>(&out.stdout)
        .unwrap()
        .as_array()
        .unwrap()
        .clone()
}

/// The demo table's three cells, percent within a sector, one or two of them.
const WEST: &str = "lower\tupper\t11\t12\n2\t2.5\t80\t0\n4\t4.5\t0\t20\n";
const NORTH: &str = "lower\tupper\t14\n6\t6.5\t100\n";

#[test]
fn a_climate_of_one_sector_plans_what_its_table_plans() {
    let dir = campaign_copy();
    // the demo's cells, 1.354 + 0.423 + 0.096 = 1.873 % of the year, as one sector
    let cells = [1.354, 0.423, 0.096];
    let share: f64 = cells.iter().sum();
    let table = format!(
        "lower\tupper\t11\t12\t14\n2\t2.5\t{}\t0\t0\n4\t4.5\t0\t{}\t0\n6\t6.5\t0\t0\t{}\n",
        100.0 * cells[0] / share,
        100.0 * cells[1] / share,
        100.0 * cells[2] / share
    );
    let file = sector_demo(dir.path(), "one_sector", &[("W", 0.0, share, &table)]);
    let sectors = resolve(&file).unwrap();
    let plain = resolve(&dir.path().join("demo.json")).unwrap();
    let a = plan::campaign_sea_states(&sectors);
    let b = plan::campaign_sea_states(&plain);
    assert_eq!(a.len(), 3);
    for (x, y) in a.iter().zip(&b) {
        assert_eq!((x.index, x.hs_m, x.tp_s), (y.index, y.hs_m, y.tp_s));
        assert_eq!(x.seeds, y.seeds);
        assert!((x.occurrence_fraction - y.occurrence_fraction).abs() < 1e-15);
        assert_eq!(x.heading_deg, 0.0);
        assert_eq!(x.sector.as_deref(), Some("W"));
        assert_eq!(y.sector, None);
    }
    // the global jobs, whose payloads carry no heading at the campaign's own, share their keys
    let keys = |r: &moorfret_campaign::ResolvedCampaign| -> Vec<String> {
        let states = plan::campaign_sea_states(r);
        let ids: Vec<SeaStateId> = (0..states.len() as i64).map(SeaStateId).collect();
        plan::jobs(&r.inputs, &r.inputs.results_sha256(), &states, &ids)
            .into_iter()
            .filter(|j| j.kind == moorfret_store::JobKind::Global)
            .map(|j| j.cache_key.unwrap())
            .collect()
    };
    assert_eq!(keys(&sectors), keys(&plain));
}

#[test]
fn sectors_run_at_their_headings_and_the_design_check_reads_them() {
    let dir = campaign_copy();
    let file = sector_demo(
        dir.path(),
        "two_sectors",
        &[("W", 0.0, 60.0, WEST), ("N", 90.0, 40.0, NORTH)],
    );
    let resolved = resolve(&file).unwrap();
    let states = plan::campaign_sea_states(&resolved);
    assert_eq!(states.len(), 3);
    assert_eq!(
        states.iter().map(|s| s.heading_deg).collect::<Vec<_>>(),
        [0.0, 0.0, 90.0]
    );
    let year: f64 = states.iter().map(|s| s.occurrence_fraction).sum();
    assert!((year - 1.0).abs() < 1e-12, "{year}");
    let ids: Vec<SeaStateId> = (0..3).map(SeaStateId).collect();
    let jobs = plan::jobs(
        &resolved.inputs,
        &resolved.inputs.results_sha256(),
        &states,
        &ids,
    );
    let headings: Vec<Value> = jobs
        .iter()
        .filter(|j| j.kind == moorfret_store::JobKind::Global)
        .map(|j| j.payload["heading_deg"].clone())
        .collect();
    assert_eq!(headings, [Value::Null, Value::Null, Value::from(90.0)]);

    let out = moorfret(
        dir.path(),
        &[
            "campaign",
            "launch",
            file.to_str().unwrap(),
            "--db",
            "s.sqlite",
            "--workers",
            "2",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    // every figure's utilisation is γ_F · D · T over the whole year
    let figures = query(dir.path(), "utilisation", "two_sectors");
    assert!(!figures.is_empty());
    for f in &figures {
        let d = f["annual_damage"].as_f64().unwrap();
        let u = f["utilisation"].as_f64().unwrap();
        assert!(
            (u - 5.0 * 25.0 * d).abs() <= 1e-12 * u.abs().max(1e-300),
            "{f}"
        );
        let covered = f["year_covered"].as_f64().unwrap();
        assert!((covered - 1.0).abs() < 1e-9, "{f}");
        let expected = if u > 1.0 { "FAIL" } else { "PASS" };
        assert_eq!(f["verdict"], expected, "{f}");
    }
    // one line, governed by its design figure of largest utilisation
    let lines = query(dir.path(), "lines", "two_sectors");
    assert_eq!(lines.len(), 1);
    let line = &lines[0];
    assert_eq!(line["line"], 1);
    let largest = figures
        .iter()
        .filter(|f| f["check"] == "design")
        .map(|f| f["utilisation"].as_f64().unwrap())
        .fold(0.0, f64::max);
    assert_eq!(line["utilisation"].as_f64().unwrap(), largest);
    assert!(
        ["W", "N"].contains(&line["sector"].as_str().unwrap()),
        "{line}"
    );
    // the damage per sector sums to the governing figure's annual damage
    let directions = query(dir.path(), "directions", "two_sectors");
    assert_eq!(directions.len(), 2, "{directions:?}");
    let by_sector: f64 = directions
        .iter()
        .map(|d| d["annual_damage"].as_f64().unwrap())
        .sum();
    let governing = figures
        .iter()
        .find(|f| f["utilisation"].as_f64().unwrap() == largest && f["check"] == "design")
        .unwrap();
    let annual = governing["annual_damage"].as_f64().unwrap();
    assert!(
        (by_sector - annual).abs() <= 1e-9 * annual,
        "{by_sector} vs {annual}"
    );
    for d in &directions {
        let expected_share = if d["sector"] == "W" { 0.6 } else { 0.4 };
        assert!((d["year_share"].as_f64().unwrap() - expected_share).abs() < 1e-12);
    }

    // the report opens with the verdicts and draws one rose
    let out = moorfret(
        dir.path(),
        &[
            "report",
            "two_sectors",
            "--db",
            "s.sqlite",
            "--out",
            "report",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(dir.path().join("report/index.html")).unwrap();
    let check = page.find("<h2>Design check</h2>").unwrap();
    let scatter = page.find("<h2>Scatter diagram").unwrap();
    assert!(check < scatter, "the design check opens the report");
    assert!(page.contains("line 1: PASS") || page.contains("line 1: FAIL"));
    assert_eq!(
        page.matches("<path d=\"M ").count(),
        2,
        "one wedge per sector"
    );
    // one map per sector of occurrence and of damage, and one rose, each with its colour bar
    assert_eq!(page.matches("sector-map occurrence").count(), 2);
    assert_eq!(page.matches("sector-map damage").count(), 2);
    assert!(page.contains("sector W (heading 0°): occurrence"));
    assert!(page.contains("sector N (heading 90°): occurrence"));
    assert_eq!(page.matches("class=\"fig map rose\"").count(), 1);
    browser::every_map_has_a_colour_bar(&page);
    assert!(page.contains("Governing figure and sea state of each line"));
    assert!(page.contains("Every sea state of the climate has its results."));
}

/// The figures of `page` marked as maps (`class="fig map…"`), each up to its `</svg>`.
/// A sector demo planned into a store (nothing run): one cell of sector N too steep for the
/// wave model and left out, the first global job failed, the rest cancelled. The report names
/// the failed and the skipped sea states with their sector, Hs, Tp and why, draws a map per
/// sector with its colour bar, and renders in headless Chromium.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn failed_and_skipped_sea_states_are_named_and_every_map_has_its_colour_bar() {
    use moorfret_store::{
        ClaimFilter, FailureClass, FailureKind, JobFailure, Store, StoreOptions, WorkerInfo,
    };
    let dir = campaign_copy();
    // Hs 6-6.5 m at Tp 6 s: steepness 0.11 above the limit 1/15, left out
    let north = "lower\tupper\t6\t14\n6\t6.5\t10\t90\n";
    let file = sector_demo(
        dir.path(),
        "unfinished",
        &[("W", 0.0, 60.0, WEST), ("N", 90.0, 40.0, north)],
    );
    let mut spec: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    spec["scatter"]["cells_outside_model"] = Value::from("leave_out");
    std::fs::write(&file, spec.to_string()).unwrap();
    let resolved = resolve(&file).unwrap();
    assert_eq!(resolved.left_out().count(), 1);
    let db = dir.path().join("s.sqlite");
    let store = Store::open(db.to_str().unwrap(), StoreOptions::default())
        .await
        .unwrap();
    plan::create(&store, &resolved).await.unwrap();
    let worker = store
        .register_worker(&WorkerInfo {
            host: "test".into(),
            pid: 1,
            version: "test".into(),
        })
        .await
        .unwrap();
    let lease = store
        .claim(
            &worker,
            &ClaimFilter {
                kinds: vec![moorfret_store::JobKind::Global],
                ..ClaimFilter::default()
            },
        )
        .await
        .unwrap()
        .unwrap();
    let diagnostic = "the global stage did not converge at t = 12.5 s";
    store
        .fail(
            &lease,
            &JobFailure {
                kind: FailureKind::Permanent,
                error_class: FailureClass::GlobalDiverged,
                message: diagnostic.into(),
            },
        )
        .await
        .unwrap();
    let failed_index = lease.payload["sea_state_index"].as_i64().unwrap();
    store.close().await;
    let out = moorfret(
        dir.path(),
        &["campaign", "cancel", "unfinished", "--db", "s.sqlite"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = moorfret(
        dir.path(),
        &[
            "report",
            "unfinished",
            "--db",
            "s.sqlite",
            "--out",
            "report",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page_path = dir.path().join("report/index.html");
    let page = std::fs::read_to_string(&page_path).unwrap();

    let table = &page[page.find("<table class=\"unfinished\">").unwrap()..];
    let table = &table[..table.find("</table>").unwrap()];
    let rows: Vec<&str> = table.split("<tr><td>").skip(1).collect();
    // three planned sea states (one failed, two cancelled) and the cell left out
    assert_eq!(rows.len(), 4, "{table}");
    assert!(rows[0].starts_with("failed</td>"), "{}", rows[0]);
    assert!(
        rows[0].contains(&format!("<td>{failed_index}</td>"))
            && rows[0].contains("global job")
            && rows[0].contains("(global_diverged)")
            && rows[0].contains(diagnostic),
        "{}",
        rows[0]
    );
    assert!(
        rows[1].starts_with(
            "skipped</td><td>N</td><td>not planned</td><td>6.250</td>\
                             <td>6.000</td>"
        ) && rows[1].contains("left out of the plan (outside the wave model): steepness"),
        "{}",
        rows[1]
    );
    // 10 % of sector N's 40 % of the year
    assert!(rows[1].contains("<td>4.000</td>"), "{}", rows[1]);
    for row in &rows[2..] {
        assert!(
            row.starts_with("skipped</td>") && row.contains("campaign cancelled"),
            "{row}"
        );
    }
    // a map per sector (occurrence only: no damage is stored), each with its colour bar
    assert_eq!(page.matches("sector-map occurrence").count(), 2);
    assert_eq!(page.matches("sector-map damage").count(), 0);
    browser::every_map_has_a_colour_bar(&page);

    let Some(browser) = browser::chromium_or_skip() else {
        return;
    };
    let shot = shot_of(&browser, &page_path, dir.path(), "report");
    // MOORFRET_KEEP_SCREENSHOT=path keeps a copy for inspection.
    if let Ok(keep) = std::env::var("MOORFRET_KEEP_SCREENSHOT") {
        std::fs::write(keep, &shot).unwrap();
    }
    // the same window on an empty page: what a blank screenshot weighs
    let blank_path = dir.path().join("blank.html");
    std::fs::write(&blank_path, "<!DOCTYPE html><html><body></body></html>").unwrap();
    let blank = shot_of(&browser, &blank_path, dir.path(), "blank");
    assert!(
        shot.len() > 5 * blank.len() && shot.len() > 30_000,
        "screenshot of {} bytes against {} for an empty page",
        shot.len(),
        blank.len()
    );
}

#[test]
fn bad_sector_climates_are_refused_naming_the_field() {
    let dir = campaign_copy();
    let file = sector_demo(
        dir.path(),
        "bad",
        &[("W", 0.0, 70.0, WEST), ("N", 90.0, 40.0, NORTH)],
    );
    let out = moorfret(
        dir.path(),
        &[
            "campaign",
            "launch",
            file.to_str().unwrap(),
            "--db",
            "s.sqlite",
        ],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("scatter.sectors") && err.contains("100"),
        "{err}"
    );
    assert!(!dir.path().join("s.sqlite").exists(), "nothing is written");
    // a table that cannot be read names its sector's field
    std::fs::write(
        dir.path().join("data/N.tsv"),
        "lower\tupper\t14\n6\t6.5\tx\n",
    )
    .unwrap();
    let mut spec: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    spec["scatter"]["sectors"][0]["share_percent"] = Value::from(50.0);
    std::fs::write(&file, spec.to_string()).unwrap();
    let out = moorfret(
        dir.path(),
        &[
            "campaign",
            "launch",
            file.to_str().unwrap(),
            "--db",
            "s.sqlite",
        ],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("scatter.sectors[1].path"), "{err}");
}

/// A screenshot of `page` into `dir/NAME.png`, its profile in `dir/NAME-profile`: the PNG's
/// bytes.
fn shot_of(browser: &Path, page: &Path, dir: &Path, name: &str) -> Vec<u8> {
    let png = dir.join(format!("{name}.png"));
    browser::screenshot(browser, page, &png, &dir.join(format!("{name}-profile")))
}
