//! Every campaign file shipped in `campaigns/` resolves, and the paper's case with the stiffer
//! elastic slip (`paper_slip_1um.json`) or without the periodic seam (`paper_seamless.json`)
//! stays the paper's case but for that one setting, so that its lifetime figures beside
//! `paper.json`'s measure that setting and nothing else.

use std::path::{Path, PathBuf};

use moorfret_campaign::resolve;
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

/// `variant` is `paper.json` but for `_about`, `name` and the strand setting `key`, whose values
/// are `paper_value` there and `variant_value` in `variant`; its global jobs are the paper's.
fn assert_paper_but_for(variant: &str, key: &str, paper_value: Value, variant_value: Value) {
    let (mut paper, mut other) = (read_json("paper.json"), read_json(variant));
    // a missing setting indexes as null
    assert_eq!(paper["strand"][key], paper_value);
    assert_eq!(other["strand"][key], variant_value);
    for v in [&mut paper, &mut other] {
        let o = v.as_object_mut().unwrap();
        o.remove("_about");
        o.remove("name");
        o["strand"].as_object_mut().unwrap().remove(key);
    }
    assert_eq!(paper, other, "{variant}");

    // the same global jobs: one store runs them once for both campaigns
    let inputs = |name: &str| resolve(&campaigns_dir().join(name)).unwrap().inputs;
    let (paper, other) = (inputs("paper.json"), inputs(variant));
    assert_eq!(paper.global_sha256(), other.global_sha256());
    assert_ne!(paper.results_sha256(), other.results_sha256());
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
