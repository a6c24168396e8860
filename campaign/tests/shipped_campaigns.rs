//! Every campaign file shipped in `campaigns/` resolves, and the paper's case with the stiffer
//! elastic slip (`paper_slip_1um.json`) stays the paper's case but for that one law constant, so
//! that its lifetime figures beside `paper.json`'s measure the law and nothing else.

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
        "paper_slip_1um.json",
        "whole_year.json",
    ] {
        assert!(
            campaigns.iter().any(|c| c == name),
            "{name} not resolved: {campaigns:?}"
        );
    }
}

#[test]
fn the_stiff_slip_campaign_is_the_paper_case_but_for_its_elastic_slip() {
    let (mut paper, mut stiff) = (read_json("paper.json"), read_json("paper_slip_1um.json"));
    assert_eq!(paper["strand"]["elastic_slip_m"].as_f64(), Some(1e-5));
    assert_eq!(stiff["strand"]["elastic_slip_m"].as_f64(), Some(1e-6));
    for v in [&mut paper, &mut stiff] {
        let o = v.as_object_mut().unwrap();
        o.remove("_about");
        o.remove("name");
        o["strand"]
            .as_object_mut()
            .unwrap()
            .remove("elastic_slip_m");
    }
    assert_eq!(paper, stiff);

    // the same global jobs: one store runs them once for both campaigns
    let inputs = |name: &str| resolve(&campaigns_dir().join(name)).unwrap().inputs;
    let (paper, stiff) = (inputs("paper.json"), inputs("paper_slip_1um.json"));
    assert_eq!(paper.global_sha256(), stiff.global_sha256());
    assert_ne!(paper.results_sha256(), stiff.results_sha256());
}
