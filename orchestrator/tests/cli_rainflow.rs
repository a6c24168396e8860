//! `moorfret rainflow` end to end: the real binary on the ASTM E1049-85 example and on bad CSV
//! files.

use std::path::Path;
use std::process::{Command, Output};

fn moorfret(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(args)
        .output()
        .expect("the moorfret binary runs")
}

fn write(dir: &Path, name: &str, content: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.to_str().unwrap().to_string()
}

const ASTM_CSV: &str = "time_s,tension_n\n0,-2\n1,1\n2,-3\n3,5\n4,-1\n5,3\n6,-4\n7,4\n8,-2\n";

fn by_range(cycles: &[serde_json::Value]) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = Vec::new();
    let mut pairs: Vec<(f64, f64)> = cycles
        .iter()
        .map(|c| (c["range"].as_f64().unwrap(), c["count"].as_f64().unwrap()))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (r, c) in pairs {
        match v.last_mut() {
            Some(last) if last.0 == r => last.1 += c,
            _ => v.push((r, c)),
        }
    }
    v
}

#[test]
fn astm_example_gives_the_published_cycles_as_json() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "astm.csv", ASTM_CSV);
    let out = moorfret(&["rainflow", &file, "--column", "tension_n", "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let cycles = json["cycles"].as_array().unwrap();
    assert_eq!(
        by_range(cycles),
        vec![(3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)]
    );
    for key in ["range", "mean", "count", "start_index", "end_index"] {
        assert!(cycles[0].get(key).is_some(), "missing {key}");
    }
    assert_eq!(cycles[0]["start_index"], 0);
    assert_eq!(cycles[0]["end_index"], 1);
}

#[test]
fn repeating_and_csv_output() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "astm.csv", ASTM_CSV);
    let out = moorfret(&[
        "rainflow",
        &file,
        "--column",
        "tension_n",
        "--repeating",
        "--format",
        "csv",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("range,mean,count,start_index,end_index"));
    let mut ranges: Vec<f64> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    ranges.sort_by(f64::total_cmp);
    assert_eq!(ranges, vec![3.0, 4.0, 7.0, 9.0]);
    assert!(text
        .lines()
        .skip(1)
        .all(|l| l.split(',').nth(2) == Some("1.0")));
}

fn fails_with(args: &[&str], needles: &[&str]) {
    let out = moorfret(args);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    for n in needles {
        assert!(err.contains(n), "stderr `{err}` lacks `{n}`");
    }
}

#[test]
fn missing_column_is_reported_with_the_available_columns() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "astm.csv", ASTM_CSV);
    fails_with(
        &["rainflow", &file, "--column", "slip_m"],
        &["column `slip_m` not found", "time_s, tension_n", "line 1"],
    );
}

#[test]
fn non_numeric_cell_is_reported_with_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "bad.csv",
        "time_s,tension_n\n0,1.5\n1,2.5\n2,abc\n3,1.0\n",
    );
    fails_with(
        &["rainflow", &file, "--column", "tension_n"],
        &["line 4", "column 2", "`tension_n`", "`abc`"],
    );
}

#[test]
fn empty_file_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "empty.csv", "");
    fails_with(&["rainflow", &file], &["empty.csv", "empty"]);
    let header_only = write(dir.path(), "header.csv", "tension_n\n");
    fails_with(&["rainflow", &header_only], &["no data rows"]);
}

/// Without `--column`, a time column is skipped: moorfret's own `hotspots.csv` is counted on
/// its tension, not on its time (one half cycle over the whole record).
#[test]
fn the_time_column_of_a_hot_spot_series_is_skipped_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "hotspots.csv",
        "time_s,tension_n,curvature_per_m\n0,-2,0\n1,1,0\n2,-3,0\n3,5,0\n4,-1,0\n5,3,0\n6,-4,0\n7,4,0\n8,-2,0\n",
    );
    let default = moorfret(&["rainflow", &file]);
    assert!(default.status.success(), "{default:?}");
    let named = moorfret(&["rainflow", &file, "--column", "tension_n"]);
    assert_eq!(default.stdout, named.stdout);
    let only_time = write(dir.path(), "t.csv", "t\n0\n1\n2\n");
    let out = moorfret(&["rainflow", &only_time]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("every column is a time column"));
}

/// A negative `--gate` parses and is refused by range, naming the option.
#[test]
fn a_negative_gate_is_refused_by_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "a.csv", ASTM_CSV);
    let out = moorfret(&["rainflow", &file, "--gate", "-1"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--gate must be finite and >= 0 (got -1)"),
        "{stderr}"
    );
}
