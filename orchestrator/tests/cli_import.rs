//! `moorfret import moordyn`: the commands of docs/global-stage.md run as written, from a copy of
//! `campaigns/examples/moordyn/`. The paper's line imported from a MoorDyn v2 deck, under a
//! prescribed motion in calm water, gives the fairlead and hot-spot tensions of the same case
//! written by hand, and its hot-spot series chains into the strand stage. A deck moorfret cannot
//! represent is refused naming its row; what does not map is warned about by row.

mod cli_support;

use std::path::Path;
use std::process::Output;

use cli_support::{campaign_file, csv_rows, moorfret};

const EXAMPLE: &str = "campaigns/examples/moordyn";

/// A working directory holding `campaigns/examples/moordyn/` as in the repository.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let to = dir.path().join(EXAMPLE);
    std::fs::create_dir_all(&to).unwrap();
    for f in ["paper_line.dat", "surge.csv", "paper_line_case.json"] {
        std::fs::copy(campaign_file(&format!("examples/moordyn/{f}")), to.join(f)).unwrap();
    }
    std::fs::create_dir_all(dir.path().join("campaigns/benchmarks")).unwrap();
    std::fs::copy(
        campaign_file("benchmarks/strand_1_6_1.json"),
        dir.path().join("campaigns/benchmarks/strand_1_6_1.json"),
    )
    .unwrap();
    dir
}

/// `moorfret ARGS` (a documented command line without its program name) in `dir`.
fn run_in(dir: &Path, command: &str) -> Output {
    let out = moorfret()
        .current_dir(dir)
        .env("MOORFRET_CACHE_DIR", dir.join("cache"))
        .args(command.split_whitespace())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "moorfret {command}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Largest relative difference of column `c` between two CSV files of equal shape.
fn largest_relative_difference(a: &Path, b: &Path, c: usize) -> f64 {
    let ((ha, ra), (hb, rb)) = (csv_rows(a, 0), csv_rows(b, 0));
    assert_eq!(ha, hb);
    assert_eq!(ra.len(), rb.len());
    ra.iter()
        .zip(&rb)
        .map(|(x, y)| (x[c] - y[c]).abs() / y[c].abs())
        .fold(0.0, f64::max)
}

#[test]
fn the_papers_line_from_a_moordyn_deck_matches_the_case_written_by_hand() {
    let dir = workdir();
    let d = dir.path();
    // The commands of docs/global-stage.md, exactly.
    let import = run_in(
        d,
        "import moordyn campaigns/examples/moordyn/paper_line.dat --motion \
         campaigns/examples/moordyn/surge.csv --hot-spot 1:79 --out out/line.json",
    );
    run_in(d, "run global out/line.json --out out/line");
    run_in(
        d,
        "run global campaigns/examples/moordyn/paper_line_case.json --out out/line_by_hand",
    );
    run_in(
        d,
        "run strand campaigns/benchmarks/strand_1_6_1.json --load out/line/hotspots.csv \
         --hot-spot 0 --axial-stiffness-n 3.6e8 --out out/line_strand",
    );

    // What did not map is warned about by deck row.
    let warnings = String::from_utf8_lossy(&import.stderr);
    for expected in [
        "warning: deck row 9: BA/-zeta -1 of chain not used",
        "warning: deck row 17: point 3 is a pin between two ropes",
        "warning: deck row 32: dtM 0.0005 s not used",
    ] {
        assert!(warnings.contains(expected), "{expected} in {warnings}");
    }
    let case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/line.json")).unwrap()).unwrap();
    assert!(case.get("sea_state").is_none(), "calm water: no sea_state");
    assert_eq!(
        case["floater"]["prescribed_motion"]["csv_path"],
        "../campaigns/examples/moordyn/surge.csv"
    );

    // Same statics (first row) and the same dynamics under the prescribed motion: the deck's
    // volume-equivalent diameters with scaled coefficients give the same forces per metre, so
    // only rounding separates the two (measured 4e-12 at the fairlead, 2e-10 at the hot spot).
    let out = d.join("out");
    let (_, by_hand) = csv_rows(&out.join("line_by_hand/fairleads.csv"), 0);
    let (_, imported) = csv_rows(&out.join("line/fairleads.csv"), 0);
    let static_difference = (imported[0][1] - by_hand[0][1]).abs() / by_hand[0][1];
    assert!(static_difference < 1e-3, "{static_difference}");
    let fairlead = largest_relative_difference(
        &out.join("line/fairleads.csv"),
        &out.join("line_by_hand/fairleads.csv"),
        1,
    );
    let hot_spot = largest_relative_difference(
        &out.join("line/hotspots.csv"),
        &out.join("line_by_hand/hotspots.csv"),
        1,
    );
    assert!(fairlead < 1e-8 && hot_spot < 1e-8, "{fairlead} {hot_spot}");
    // The motion moves the line: the tension is not a constant.
    let (lo, hi) = by_hand
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), r| (l.min(r[1]), h.max(r[1])));
    assert!(hi - lo > 0.2 * hi, "{lo}..{hi}");

    // The strand stage read the hot spot's series as written: every sample, and its monitors
    // at the series' own times.
    let (_, monitors) = csv_rows(&out.join("line_strand/monitors.csv"), 0);
    let (_, series) = csv_rows(&out.join("line/hotspots.csv"), 0);
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("line_strand/summary.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(summary["samples"].as_u64(), Some(series.len() as u64));
    assert!(monitors.len() >= 2);
    assert!(monitors.iter().all(|m| series.iter().any(|s| s[0] == m[0])));
}

#[test]
fn an_unsupported_deck_is_refused_naming_its_row() {
    let dir = workdir();
    let d = dir.path();
    let deck = d.join(EXAMPLE).join("paper_line.dat");
    let text = std::fs::read_to_string(&deck).unwrap();
    std::fs::write(&deck, text.replacen("4.93e+08", "4.93e+08|5e8", 1)).unwrap();
    let out = moorfret()
        .current_dir(d)
        .args([
            "import",
            "moordyn",
            "campaigns/examples/moordyn/paper_line.dat",
        ])
        .args([
            "--motion",
            "campaigns/examples/moordyn/surge.csv",
            "--out",
            "x.json",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("deck row 9: EA '4.93e+08|5e8': a non-linear or viscoelastic value"),
        "{err}"
    );
    assert!(!d.join("x.json").exists(), "nothing written");
}

/// A negative or zero `--duration-s` / `--time-step-s` parses and is refused naming the option,
/// not as a fault of the deck.
#[test]
fn import_options_out_of_range_are_named() {
    let dir = tempfile::tempdir().unwrap();
    for (option, value) in [("--duration-s", "-1"), ("--time-step-s", "0")] {
        let out = moorfret()
            .args(["import", "moordyn"])
            .arg(campaign_file("examples/moordyn/paper_line.dat"))
            .arg("--motion")
            .arg(campaign_file("examples/moordyn/surge.csv"))
            .arg("--out")
            .arg(dir.path().join("line.json"))
            .args([option, value])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains(&format!(
                "{option} must be a positive number of seconds (got {value})"
            )),
            "{stderr}"
        );
        assert!(!dir.path().join("line.json").exists());
    }
}
