//! Every campaign file shipped in `campaigns/` resolves, and the paper's case with the stiffer
//! elastic slip (`paper_slip_1um.json`) or without the periodic seam (`paper_seamless.json`)
//! stays the paper's case but for that one setting, so that its lifetime figures beside
//! `paper.json`'s measure that setting and nothing else. The two campaigns on the lumped diagram
//! differ in their contact laws alone, and that diagram is the paper's, lumped by its stated rule.

use std::path::{Path, PathBuf};

use moorfret_campaign::resolve;
use moorfret_solver::waves::scatter::{ScatterCell, ScatterTable};
use serde_json::Value;

fn campaigns_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns")
}

fn read_json(name: &str) -> Value {
    let text = std::fs::read_to_string(campaigns_dir().join(name)).unwrap();
    serde_json::from_str(&text).unwrap()
}

#[test]
fn every_shipped_campaign_file_resolves() {
    let mut campaigns = Vec::new();
    for entry in std::fs::read_dir(campaigns_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("json") {
            continue;
        }
        let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        // the global cases (paper_case.json) have no climate of their own
        if v.get("scatter").is_none() {
            continue;
        }
        let resolved = resolve(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(resolved.inputs.spec.name, v["name"].as_str().unwrap());
        campaigns.push(path.file_name().unwrap().to_string_lossy().into_owned());
    }
    campaigns.sort();
    for name in [
        "demo.json",
        "paper.json",
        "paper_lumped_contact_mechanics.json",
        "paper_lumped_regularised.json",
        "paper_seamless.json",
        "paper_slip_1um.json",
        "whole_year.json",
    ] {
        assert!(
            campaigns.iter().any(|c| c == name),
            "{name} not resolved: {campaigns:?}"
        );
    }
}

/// `first` and `second` are equal but for `_about`, `name` and the strand settings `keys`, and
/// their global jobs are the same (one store runs them once for both) while their results differ.
fn assert_equal_but_for(first: &str, second: &str, keys: &[&str]) {
    let (mut a, mut b) = (read_json(first), read_json(second));
    for v in [&mut a, &mut b] {
        let o = v.as_object_mut().unwrap();
        o.remove("_about");
        o.remove("name");
        let strand = o["strand"].as_object_mut().unwrap();
        for key in keys {
            strand.remove(*key);
        }
    }
    assert_eq!(a, b, "{first} against {second}");

    let inputs = |name: &str| resolve(&campaigns_dir().join(name)).unwrap().inputs;
    let (a, b) = (inputs(first), inputs(second));
    assert_eq!(a.global_sha256(), b.global_sha256());
    assert_ne!(a.results_sha256(), b.results_sha256());
}

/// `variant` is `paper.json` but for `_about`, `name` and the strand setting `key`, whose values
/// are `paper_value` there and `variant_value` in `variant`; its global jobs are the paper's.
fn assert_paper_but_for(variant: &str, key: &str, paper_value: Value, variant_value: Value) {
    // a missing setting indexes as null
    assert_eq!(read_json("paper.json")["strand"][key], paper_value);
    assert_eq!(read_json(variant)["strand"][key], variant_value);
    assert_equal_but_for("paper.json", variant, &[key]);
}

#[test]
fn the_stiff_slip_campaign_is_the_paper_case_but_for_its_elastic_slip() {
    assert_paper_but_for(
        "paper_slip_1um.json",
        "elastic_slip_m",
        Value::from(1e-5),
        Value::from(1e-6),
    );
}

#[test]
fn the_seamless_campaign_is_the_paper_case_but_for_its_ends() {
    // paper.json leaves `ends` at its default, `periodic`
    assert_paper_but_for(
        "paper_seamless.json",
        "ends",
        Value::Null,
        Value::from("periodic_rotations"),
    );
}

#[test]
fn the_lumped_campaigns_differ_in_their_contact_laws_alone() {
    let (cm, reg, paper) = (
        read_json("paper_lumped_contact_mechanics.json"),
        read_json("paper_lumped_regularised.json"),
        read_json("paper.json"),
    );
    assert_eq!(cm["strand"]["contact_laws"], "contact_mechanics");
    // the regularised one keeps the paper's laws
    assert_eq!(reg["strand"]["contact_laws"], Value::Null);
    for key in ["normal_penalty_n_per_m", "elastic_slip_m"] {
        assert_eq!(reg["strand"][key], paper["strand"][key], "{key}");
        assert_eq!(cm["strand"][key], Value::Null, "{key}");
    }
    // every block's sea state runs under both laws from one set of global jobs
    assert_equal_but_for(
        "paper_lumped_contact_mechanics.json",
        "paper_lumped_regularised.json",
        &["contact_laws", "normal_penalty_n_per_m", "elastic_slip_m"],
    );
}

/// The lumped diagram's rows are the blocks of the paper's diagram that its header states: a
/// block's occurrence is the sum of its cells', its Hs (the row's bin midpoint) is
/// (Σ p Hs^4.8 / Σ p)^(1/4.8) to the printed 0.01 m, its Tp the column nearest the mean Tp
/// weighted by p Hs^4.8.
#[test]
fn the_lumped_diagram_is_the_papers_by_its_rule() {
    let read = |name: &str| {
        let text = std::fs::read_to_string(campaigns_dir().join("data").join(name)).unwrap();
        ScatterTable::parse(&text).unwrap()
    };
    let full = read("wsd_argoss_sector.tsv").cells();
    let lumped = read("wsd_argoss_sector_lumped8.csv").cells();
    type Block = fn(f64, f64) -> bool;
    let blocks: [Block; 8] = [
        |hs, _| hs < 2.0,
        |hs, _| (2.0..4.0).contains(&hs),
        |hs, tp| (4.0..5.5).contains(&hs) && tp <= 13.0,
        |hs, tp| (4.0..5.5).contains(&hs) && tp >= 14.0,
        |hs, tp| (5.5..7.0).contains(&hs) && tp <= 13.0,
        |hs, tp| (5.5..7.0).contains(&hs) && tp >= 14.0,
        |hs, tp| hs >= 7.0 && tp <= 13.0,
        |hs, tp| hs >= 7.0 && tp >= 14.0,
    ];
    let mid = |lo: f64, hi: f64| 0.5 * (lo + hi);
    let mut rows: Vec<_> = lumped.iter().filter(|c| c.value > 0.0).collect();
    rows.sort_by(|a, b| a.hs_lower_m.total_cmp(&b.hs_lower_m));
    assert_eq!(rows.len(), blocks.len());
    let mut covered = 0;
    for (row, inside) in rows.iter().zip(blocks) {
        let cells: Vec<_> = full
            .iter()
            .filter(|c| c.value > 0.0 && inside(mid(c.hs_lower_m, c.hs_upper_m), c.tp_s))
            .collect();
        covered += cells.len();
        let p: f64 = cells.iter().map(|c| c.value).sum();
        let weight = |c: &ScatterCell| c.value * mid(c.hs_lower_m, c.hs_upper_m).powf(4.8);
        let w: f64 = cells.iter().map(|c| weight(c)).sum();
        let hs = (w / p).powf(1.0 / 4.8);
        let tp = cells.iter().map(|c| weight(c) * c.tp_s).sum::<f64>() / w;
        assert!(
            (row.value - p).abs() < 5e-4,
            "block at Hs {hs}: {} against {p}",
            row.value
        );
        assert!(
            (mid(row.hs_lower_m, row.hs_upper_m) - hs).abs() < 5e-3 + 1e-9,
            "row {}-{}: Hs_eq {hs}",
            row.hs_lower_m,
            row.hs_upper_m
        );
        assert_eq!(row.tp_s, tp.round(), "block at Hs {hs}: mean Tp {tp}");
    }
    // the blocks share out every occupied cell once
    assert_eq!(covered, full.iter().filter(|c| c.value > 0.0).count());
}
