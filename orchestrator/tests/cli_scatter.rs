//! `moorfret scatter`: directional scatter tables from a series, through the real binary. A
//! synthetic hourly record with known counts (values on bin edges, calm records, missing
//! records of every kind, one time gap, directions 359° and 1° in the same north sector) gives
//! the documented tables, summary and `sectors.json`, and a campaign using that file plans its
//! sea states at the sectors' headings. Bad options are refused naming the option or the
//! column, and write nothing.

mod cli_support;

use std::path::Path;

use cli_support::{campaign_file, moorfret};
use moorfret_orchestrator::plan;
use moorfret_solver::waves::ScatterTable;
use serde_json::Value;

/// Hourly records, lines 3 to 13: five non-calm used (two from the north at 359° and 1°, one
/// on the N/NE edge at 22.5°, one from the east, one from the south), one calm, five missing
/// (Hs empty, NaN and the fill value -999; Tp the fill value 99; direction -999), one hour
/// without a record before 10:00.
const SERIES: &str = "\
# synthetic record for the test, not a site
date,HS,TP,MWD,note
2021-01-01T00:00Z,1.0,8.0,359,Hs on the 1.0 m edge
2021-01-01T01:00Z,1.4,8.4,1,
2021-01-01T02:00Z,0.5,7.5,90,Hs and Tp on edges
2021-01-01T03:00Z,0.1,6.0,,calm without direction
2021-01-01T04:00Z,,8.0,10,
2021-01-01T05:00Z,NaN,8.0,10,
2021-01-01T06:00Z,-999,8.0,10,
2021-01-01T07:00Z,1.2,99,10,
2021-01-01T08:00Z,1.2,8.0,-999,
2021-01-01T10:00Z,2.0,10.0,180,after one hour without a record
2021-01-01T11:00Z,0.9,6.2,22.5,on the N/NE edge
";

const COLUMNS: [&str; 8] = [
    "--time",
    "date",
    "--hs",
    "HS",
    "--tp",
    "TP",
    "--direction",
    "MWD",
];

fn run(dir: &Path, extra: &[&str]) -> std::process::Output {
    moorfret()
        .current_dir(dir)
        .arg("scatter")
        .arg("record.csv")
        .args(COLUMNS)
        .args(extra)
        .output()
        .unwrap()
}

/// The value of the cell at (Hs lower edge, Tp column) of `table`.
fn cell(table: &ScatterTable, hs_lower_m: f64, tp_s: f64) -> f64 {
    table
        .cells()
        .into_iter()
        .find(|c| c.hs_lower_m == hs_lower_m && c.tp_s == tp_s)
        .map_or(f64::NAN, |c| c.value)
}

#[test]
fn a_synthetic_record_gives_the_known_tables_summary_and_a_campaign_that_plans() {
    let dir = tempfile::tempdir().unwrap();
    cli_support::copy_dir(&campaign_file(""), dir.path());
    std::fs::write(dir.path().join("record.csv"), SERIES).unwrap();
    let out = run(
        dir.path(),
        &[
            "--out",
            "data/site",
            "--relative-to",
            ".",
            "--calm-hs-m",
            "0.2",
            "--missing-value",
            "99,-999",
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // the summary: counts by reason, each with its first line
    for expected in [
        "series record.csv: 2021-01-01T00:00Z to 2021-01-01T11:00Z, time step 3600 s, 1 time gap(s)",
        "records: 11 read, 6 used (1 calm, Hs below 0.2 m), 5 missing",
        "missing hs: 3 (first on line 7: ``)",
        "missing tp: 1 (first on line 10: `99`)",
        "tp below the first column (0.5 s): 0",
        "missing direction (not calm): 1 (first on line 11: `-999`)",
        "sectors: 8 of 45 deg",
        "N\t337.5\t22.5\t180\t2\t0.400\t40.000000\tsector_000.tsv",
        "NE\t22.5\t67.5\t135\t1\t0.200\t20.000000\tsector_045.tsv",
        "E\t67.5\t112.5\t90\t1\t0.200\t20.000000\tsector_090.tsv",
        "SE\t112.5\t157.5\t45\t0\t0.000\t0.000000\t-",
        "S\t157.5\t202.5\t0\t1\t0.200\t20.000000\tsector_180.tsv",
        "wrote 4 table(s) and sectors.json in data/site",
    ] {
        assert!(stdout.contains(expected), "`{expected}` in:\n{stdout}");
    }
    let site = dir.path().join("data/site");
    let mut written: Vec<String> = std::fs::read_dir(&site)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(
        written,
        [
            "sector_000.tsv",
            "sector_045.tsv",
            "sector_090.tsv",
            "sector_180.tsv",
            "sectors.json"
        ]
    );
    let table = |name: &str| {
        let t = ScatterTable::parse(&std::fs::read_to_string(site.join(name)).unwrap()).unwrap();
        assert!(t.total_mismatches().is_empty(), "{name}");
        assert!((t.cell_sum() - 100.0).abs() < 1e-9, "{name}");
        // the same grid in every sector: Hs from 0 to the 2.0 m record, Tp 6 to 10 s
        assert_eq!(t.hs_bins_m.len(), 5, "{name}");
        assert_eq!(t.hs_bins_m.last(), Some(&(2.0, 2.5)), "{name}");
        assert_eq!(t.tp_s, vec![6.0, 7.0, 8.0, 9.0, 10.0], "{name}");
        t
    };
    // north: 359° and 1°, both Hs [1.0, 1.5) (1.0 on the edge goes up) and Tp 8, with 2/5 of
    // the calm record in the lowest bin of its Tp column: 2 / 2.4 and 0.4 / 2.4
    let north = table("sector_000.tsv");
    assert_eq!(cell(&north, 1.0, 8.0), 83.333333);
    assert_eq!(cell(&north, 0.0, 6.0), 16.666667);
    assert_eq!(cell(&north, 0.5, 8.0), 0.0);
    // east: Hs 0.5 and Tp 7.5 on edges go to [0.5, 1.0) and the column of 8 ([7.5, 8.5))
    let east = table("sector_090.tsv");
    assert_eq!(cell(&east, 0.5, 8.0), 83.333333);
    assert_eq!(cell(&east, 0.0, 7.0), 0.0);
    assert_eq!(cell(&east, 0.0, 6.0), 16.666667);
    // 22.5° is the first direction of NE
    let north_east = table("sector_045.tsv");
    assert_eq!(cell(&north_east, 0.5, 6.0), 83.333333);
    let south = table("sector_180.tsv");
    assert_eq!(cell(&south, 2.0, 10.0), 83.333333);

    // the fragment: the four sectors with records, paths relative to the campaign's directory
    let fragment: Value =
        serde_json::from_str(&std::fs::read_to_string(site.join("sectors.json")).unwrap()).unwrap();
    let sectors = fragment["sectors"].as_array().unwrap();
    assert_eq!(sectors.len(), 4);
    assert_eq!(
        sectors[0],
        serde_json::json!({"label": "N", "heading_deg": 180.0, "share_percent": 40.0,
            "path": "data/site/sector_000.tsv", "direction_from_deg": 0.0})
    );
    let labels: Vec<&str> = sectors
        .iter()
        .map(|s| s["label"].as_str().unwrap())
        .collect();
    assert_eq!(labels, ["N", "NE", "E", "S"]);

    // a campaign with these sectors plans every cell at its sector's heading, the whole year
    let mut spec: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("demo.json")).unwrap())
            .unwrap();
    spec["name"] = Value::from("from_series");
    spec["scatter"] = serde_json::json!({ "sectors": fragment["sectors"] });
    let file = dir.path().join("from_series.json");
    std::fs::write(&file, serde_json::to_string_pretty(&spec).unwrap()).unwrap();
    let resolved = moorfret_campaign::resolve(&file).unwrap();
    assert_eq!(resolved.left_out().count(), 0);
    let states = plan::campaign_sea_states(&resolved);
    // two cells per sector: its records' and the calm records' (Hs 0-0.5 m, Tp 6 s)
    assert_eq!(states.len(), 8);
    let year: f64 = states.iter().map(|s| s.occurrence_fraction).sum();
    assert!((year - 1.0).abs() < 1e-9, "{year}");
    let north: Vec<_> = states
        .iter()
        .filter(|s| s.sector.as_deref() == Some("N"))
        .collect();
    assert_eq!(north.len(), 2);
    for s in &north {
        assert_eq!(s.heading_deg, 180.0);
    }
    let big = north.iter().find(|s| s.hs_m == 1.25).unwrap();
    assert_eq!(big.tp_s, 8.0);
    assert!((big.occurrence_fraction - 0.4 * 0.83333333).abs() < 1e-8);
    let ids: Vec<moorfret_store::SeaStateId> = (0..states.len() as i64)
        .map(moorfret_store::SeaStateId)
        .collect();
    let jobs = plan::jobs(
        &resolved.inputs,
        &resolved.inputs.results_sha256(),
        &states,
        &ids,
    );
    let headings: Vec<f64> = jobs
        .iter()
        .filter(|j| j.kind == moorfret_store::JobKind::Global)
        .map(|j| j.payload["heading_deg"].as_f64().unwrap_or(0.0))
        .collect();
    assert_eq!(headings, [180.0, 180.0, 135.0, 135.0, 90.0, 90.0, 0.0, 0.0]);
}

#[test]
fn bad_options_are_refused_naming_them_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("record.csv"), SERIES).unwrap();
    let refused = |args: &[&str], expected: &[&str]| {
        let mut all = vec!["--out", "site"];
        all.extend_from_slice(args);
        let out = run(dir.path(), &all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} accepted");
        for e in expected {
            assert!(err.contains(e), "{args:?}: `{e}` in {err}");
        }
        assert!(!dir.path().join("site").exists(), "{args:?} wrote files");
    };
    // a column the header does not have: named, with the option and the header's columns
    let out = moorfret()
        .current_dir(dir.path())
        .args([
            "scatter",
            "record.csv",
            "--time",
            "date",
            "--hs",
            "WAVE_HEIGHT",
            "--tp",
            "TP",
            "--direction",
            "MWD",
            "--out",
            "site",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("--hs") && err.contains("no column `WAVE_HEIGHT`"),
        "{err}"
    );
    assert!(
        err.contains("line 2") && err.contains("date, HS, TP, MWD, note"),
        "{err}"
    );
    assert!(!dir.path().join("site").exists());
    refused(&["--hs-bin-m", "-0.5"], &["--hs-bin-m", "-0.5"]);
    refused(&["--tp-bin-s", "0"], &["--tp-bin-s"]);
    refused(&["--sectors", "0"], &["--sectors", "1 to 360"]);
    refused(&["--sectors", "-4"], &["--sectors"]);
    refused(
        &["--sector-width-deg", "50"],
        &["--sector-width-deg", "divide 360"],
    );
    refused(
        &["--sectors", "8", "--sector-width-deg", "45"],
        &["--sector-width-deg"],
    );
    refused(
        &["--calm-hs-m", "0.6"],
        &["--calm-hs-m (0.6) must not exceed the lowest Hs bin's upper edge (0.5 m"],
    );
    refused(&["--calm-hs-m", "-0.1"], &["--calm-hs-m"]);
    refused(&["--hs-edges-m", "0,1,1"], &["--hs-edges-m", "increasing"]);
    refused(&["--hs-edges-m", "0.5,1"], &["--hs-edges-m", "from 0"]);
    refused(&["--hs-edges-m", "-1,1"], &["--hs-edges-m", ">= 0"]);
    refused(&["--tp-edges-s", "6"], &["--tp-edges-s", "at least two"]);
    refused(&["--tp-edges-s", "6,x"], &["--tp-edges-s"]);
    refused(
        &["--hs-edges-m", "0,1", "--hs-bin-m", "0.5"],
        &["--hs-bin-m"],
    );
    refused(&["--x-axis-bearing-deg", "inf"], &["--x-axis-bearing-deg"]);
    refused(&["--relative-to", "nowhere"], &["--relative-to"]);
    // a series line that cannot be read: named by line and column, nothing written
    std::fs::write(
        dir.path().join("record.csv"),
        "date,HS,TP,MWD\n2021-01-01T00:00Z,1,8,0\nnoon,1,8,0\n",
    )
    .unwrap();
    refused(&[], &["record.csv", "line 3, column 1 (`date`)", "noon"]);
    std::fs::write(
        dir.path().join("record.csv"),
        "date,HS,TP,MWD\n2021-01-01T00:00Z,1,8\n",
    )
    .unwrap();
    refused(&[], &["line 2: expected 4 fields"]);
    // the same column for two fields
    let out = moorfret()
        .current_dir(dir.path())
        .args([
            "scatter",
            "record.csv",
            "--time",
            "date",
            "--hs",
            "HS",
            "--tp",
            "HS",
            "--direction",
            "MWD",
            "--out",
            "site",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("--hs and --tp both name the column `HS`"),
        "{err}"
    );
    assert!(!dir.path().join("site").exists());
}

/// Bins from edges: Hs [0, 1), [1, 1.5); Tp [6, 8), [8, 12) at 7 and 10 s. The 2.0 m record is
/// above the last Hs edge: counted and left out.
#[test]
fn bin_edges_give_their_bins_and_count_the_records_beyond_them() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("record.csv"), SERIES).unwrap();
    let out = run(
        dir.path(),
        &[
            "--out",
            "site",
            "--calm-hs-m",
            "0.2",
            "--missing-value",
            "-999,99",
            "--hs-edges-m",
            "0,1,1.5",
            "--tp-edges-s",
            "6,8,12",
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("hs or tp at or above the last bin edge: 1"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(dir.path().join("site/sector_000.tsv")).unwrap();
    assert!(text.contains("Hs edges 0, 1, 1.5 m"), "{text}");
    let north = ScatterTable::parse(&text).unwrap();
    assert_eq!(north.hs_bins_m, vec![(0.0, 1.0), (1.0, 1.5)]);
    assert_eq!(north.tp_s, vec![7.0, 10.0]);
    // north: 1.0/8.0 and 1.4/8.4 (Hs [1, 1.5), Tp [8, 12)) and 0.9/6.2 (on the N/NE edge: NE)
    assert!(cell(&north, 1.0, 10.0) > 0.0);
    assert!((north.cell_sum() - 100.0).abs() < 1e-9);
}
