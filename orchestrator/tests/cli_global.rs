//! `moorfret run global` on the paper case with a short duration: every output file is written,
//! finite and consistent with the others; non-physical input fails naming the field.

mod cli_support;

use cli_support::{campaign_file, csv_rows, moorfret};
use std::path::PathBuf;

fn case_path() -> PathBuf {
    campaign_file("paper_case.json")
}

fn rows(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    csv_rows(path, 0)
}

#[test]
fn run_global_writes_consistent_outputs_for_the_paper_case() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let status = moorfret()
        .args(["run", "global"])
        .arg(case_path())
        .arg("--out")
        .arg(&out)
        .args(["--duration-s", "2", "--transient-s", "2", "--threads", "2"])
        .status()
        .unwrap();
    assert!(status.success());

    let (h, hs) = rows(&out.join("hotspots.csv"));
    assert_eq!(h, ["time_s", "tension_n_0", "curvature_per_m_0"]);
    // 2 s at 0.1 s, both ends included.
    assert_eq!(hs.len(), 21);
    assert!((hs[0][0]).abs() < 1e-9 && (hs[20][0] - 2.0).abs() < 1e-9);
    assert!(hs.iter().flatten().all(|v| v.is_finite()));
    assert!(
        hs.iter().all(|r| r[1] > 0.0 && r[2] >= 0.0),
        "{:?}",
        hs.iter().map(|r| (r[1], r[2])).collect::<Vec<_>>()
    );

    let (h, fl) = rows(&out.join("fairleads.csv"));
    assert_eq!(h.len(), 7);
    assert_eq!(fl.len(), hs.len());
    for (a, b) in fl.iter().zip(&hs) {
        assert_eq!(a[0], b[0]);
    }

    let (h, env) = rows(&out.join("envelopes.csv"));
    assert_eq!(h[0], "line");
    // The envelope of line 1 contains the hot-spot tension extremes up to the interpolation
    // between nodes (s = 79 m sits between nodes 1 m apart).
    let t_hot_max = hs.iter().map(|r| r[1]).fold(f64::MIN, f64::max);
    let line1_max = env
        .iter()
        .filter(|r| r[0] == 1.0 && (r[2] - 79.0).abs() <= 1.0)
        .map(|r| r[4])
        .fold(f64::MIN, f64::max);
    assert!(
        (t_hot_max - line1_max).abs() < 0.05 * line1_max,
        "{t_hot_max} vs {line1_max}"
    );
    for r in &env {
        assert!(r[3] <= r[4] && r[6] >= 0.0);
    }
    // The fairlead tension of line 1 equals the tension envelope at s = 0 within its range.
    let f1: Vec<f64> = fl.iter().map(|r| r[1]).collect();
    let f1_max = f1.iter().copied().fold(f64::MIN, f64::max);
    assert!(f1_max > 0.0);

    let (h, fm) = rows(&out.join("floater.csv"));
    assert_eq!(h.len(), 7);
    assert_eq!(fm.len(), hs.len());

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let t = &summary["hot_spots"][0]["tension_n"];
    assert!((t["max"].as_f64().unwrap() - t_hot_max).abs() < 1e-6 * t_hot_max);
    assert_eq!(summary["samples"].as_u64(), Some(21));
    assert_eq!(summary["lines"].as_array().map(Vec::len), Some(6));

    for svg in ["hotspots.svg", "static_shapes.svg"] {
        let text = std::fs::read_to_string(out.join(svg)).unwrap();
        assert!(
            text.starts_with("<svg") && text.contains("polyline"),
            "{svg}"
        );
    }
    // the series chains into the strand stage as written: `run strand --load hotspots.csv`
    // (the 1+6+1 benchmark strand, EA given so that the rope's tension is a moderate strain)
    let strand_out = dir.path().join("strand");
    let run = moorfret()
        .env("MOORFRET_CACHE_DIR", dir.path().join("cache"))
        .args(["run", "strand"])
        .arg(campaign_file("benchmarks/strand_1_6_1.json"))
        .arg("--load")
        .arg(out.join("hotspots.csv"))
        .args(["--hot-spot", "0", "--axial-stiffness-n", "3e8"])
        .args(["--monitors", "every-sample", "--out"])
        .arg(&strand_out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (h, m) = rows(&strand_out.join("monitors.csv"));
    assert_eq!(&h[..3], ["time_s", "strain", "curvature_per_m"]);
    assert_eq!(m.len(), hs.len());
    for (a, b) in m.iter().zip(&hs) {
        assert_eq!(a[0], b[0]);
        assert!((a[1] - b[1] / 3e8).abs() <= 1e-12 * a[1].abs().max(1e-9));
        assert_eq!(a[2], b[2]);
    }
}

#[test]
fn non_physical_case_fails_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(case_path())
        .unwrap()
        .replace("\"tp_s\": 16.5", "\"tp_s\": -1.0");
    let case = dir.path().join("bad.json");
    std::fs::write(&case, text).unwrap();
    // The floater file is resolved relative to the case file.
    std::fs::create_dir_all(dir.path().join("data")).unwrap();
    std::fs::copy(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../campaigns/data/oc4_semi_floater.json"
        ),
        dir.path().join("data/oc4_semi_floater.json"),
    )
    .unwrap();
    let out = moorfret()
        .args(["run", "global"])
        .arg(&case)
        .arg("--out")
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("sea_state.tp_s must be > 0"), "{err}");
}

/// Thread counts out of range are usage errors (exit code 2), not slow runs or stalls.
#[test]
fn thread_counts_out_of_range_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    for threads in ["0", "1000", "100000"] {
        let out = moorfret()
            .args(["run", "global"])
            .arg(case_path())
            .arg("--out")
            .arg(dir.path().join("out"))
            .args(["--duration-s", "1", "--threads", threads])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--threads {threads}: {stderr}");
        assert!(stderr.contains("--threads"), "{stderr}");
    }
    assert!(!dir.path().join("out").exists());
    let out = moorfret()
        .args(["run", "strand"])
        .arg(campaign_file("benchmarks/strand_1_6_1.json"))
        .args(["--load", "x.csv", "--checkpoint-every", "0", "--out"])
        .arg(dir.path().join("strand"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// A fault in a value given on the command line names the option, not the case file, and a
/// negative value parses, to be refused by range with the option's name.
#[test]
fn a_bad_option_value_is_blamed_on_the_option() {
    let dir = tempfile::tempdir().unwrap();
    for (option, value, field) in [
        ("--duration-s", "0", "timing.duration_s"),
        ("--duration-s", "-1", "timing.duration_s"),
        ("--transient-s", "-5", "timing.transient_s"),
        ("--tp-s", "0", "sea_state.tp_s"),
        ("--hs-m", "-2", "sea_state.hs_m"),
    ] {
        let out = moorfret()
            .args(["run", "global"])
            .arg(case_path())
            .arg("--out")
            .arg(dir.path().join("out"))
            .args([option, value])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{option} {value}: {stderr}");
        assert!(
            stderr.contains(&format!("command-line option {option} {value}:")),
            "{option} {value}: {stderr}"
        );
        assert!(stderr.contains(field), "{stderr}");
        assert!(!stderr.contains("in case file"), "{stderr}");
    }
}

/// A JSON type error in a case file names the field path.
#[test]
fn a_case_file_type_error_names_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let mut case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(case_path()).unwrap()).unwrap();
    case["timing"]["duration_s"] = serde_json::json!("30");
    let file = dir.path().join("case.json");
    std::fs::write(&file, serde_json::to_string_pretty(&case).unwrap()).unwrap();
    let out = moorfret()
        .args(["run", "global"])
        .arg(&file)
        .arg("--out")
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("field `timing.duration_s`"), "{stderr}");
}
