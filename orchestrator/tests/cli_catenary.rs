//! `moorfret run catenary` through the real binary: the MoorPy reference line, the readable
//! table, and two bad inputs that must fail with a message naming the problem.

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_moorfret"))
        .args(["run", "catenary"])
        .args(args)
        .env("RUST_LOG", "warn")
        .output()
        .expect("the moorfret binary runs")
}

/// MoorPy's catenary test: X_F = 400 m, Z_F = 200 m, L = 500 m, w = 800 N/m, EA = 7.51e12 N.
const MOORPY: [&str; 10] = [
    "--horizontal-span-m",
    "400",
    "--vertical-span-m",
    "200",
    "--length-m",
    "500",
    "--weight-n-per-m",
    "800",
    "--axial-stiffness-n",
    "7.51e12",
];

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn json_output_matches_the_moorpy_reference_line() {
    let out = run(&[&MOORPY[..], &["--json"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let value: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let object = value.as_object().unwrap();
    let mut keys: Vec<&str> = object.keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "anchor_tension_n",
            "fairlead_tension_n",
            "fairlead_vertical_tension_n",
            "horizontal_tension_n",
            "laid_length_m"
        ]
    );
    let get = |k: &str| object[k].as_f64().unwrap();
    // MoorPy tests/test_catenary.py (C_B = 0): H = 96643.428 N, V = 237751.755 N, 202.810 m.
    assert!(rel(get("horizontal_tension_n"), 96643.42815934008) < 1e-6);
    assert!(rel(get("fairlead_vertical_tension_n"), 237751.75535996316) < 1e-6);
    assert!(rel(get("laid_length_m"), 202.81030580004602) < 1e-6);
    assert!(rel(get("anchor_tension_n"), 96643.42815934008) < 1e-6);
    let t_f = 96643.42815934008f64.hypot(237751.75535996316);
    assert!(rel(get("fairlead_tension_n"), t_f) < 1e-6);
}

#[test]
fn default_stiffness_is_inextensible_and_the_table_is_readable() {
    let out = run(&MOORPY[..8]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("horizontal tension H"), "{text}");
    assert!(text.contains("laid length"), "{text}");
    // The inextensible line carries H = 96643.48 N (MoorPy's EA = 7.51e12 N line 5e-7 less).
    let h_line = text
        .lines()
        .find(|l| l.starts_with("horizontal tension"))
        .unwrap();
    let h: f64 = h_line.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!(rel(h, 96643.48) < 1e-6, "{h}");
}

#[test]
fn line_too_short_to_reach_fails_and_says_by_how_much() {
    let mut args = MOORPY[..8].to_vec();
    args[5] = "400"; // chord √(400² + 200²) = 447.214 m
    let out = run(&args);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("too short"), "{err}");
    assert!(err.contains("by 47.213"), "{err}");
    assert!(out.stdout.is_empty());
}

#[test]
fn non_positive_weight_fails_naming_the_option() {
    let mut args = MOORPY.to_vec();
    args[7] = "-800";
    let out = run(&args);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--weight-n-per-m"), "{err}");
    assert!(err.contains("must be finite and > 0"), "{err}");
}
