//! Adversarial campaign files: the demo campaign with one value replaced by an extreme number or
//! a value of the wrong type, resolved with its files. Resolution never panics or aborts, and a
//! refusal names a field of the campaign file by its path.

use std::path::Path;

use moorfret_campaign::{resolve, CampaignError};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use serde_json::Value;

/// The demo campaign and the files it names, copied into `dir`.
fn copy_demo(dir: &Path) {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns");
    for f in [
        "demo.json",
        "paper_case.json",
        "data/demo_scatter.tsv",
        "data/oc4_semi_floater.json",
        "benchmarks/strand_1_6_1.json",
    ] {
        let to = dir.join(f);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(src.join(f), to).unwrap();
    }
}

/// Paths (JSON pointers) of every number in `v`.
fn number_paths(v: &Value, at: &str, out: &mut Vec<String>) {
    match v {
        Value::Number(_) => out.push(at.to_owned()),
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                number_paths(item, &format!("{at}/{i}"), out);
            }
        }
        Value::Object(map) => {
            for (k, item) in map {
                number_paths(item, &format!("{at}/{k}"), out);
            }
        }
        _ => {}
    }
}

fn replacement() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(serde_json::json!(0.0)),
        Just(serde_json::json!(-1.0)),
        Just(serde_json::json!(1e-300)),
        Just(serde_json::json!(1e300)),
        Just(serde_json::json!(4294967295_u64)),
        Just(serde_json::json!(u64::MAX)),
        (-1e4..1e4_f64).prop_map(|x| serde_json::json!(x)),
        Just(Value::Null),
        Just(serde_json::json!("text")),
    ]
}

/// Whether a field path names a place of the campaign file (or a file it names).
fn names_a_field(field: &str) -> bool {
    let top = field.split(['.', '[', ':', ' ']).next().unwrap_or_default();
    matches!(
        top,
        "name"
            | "design_life_years"
            | "seed"
            | "scatter"
            | "global"
            | "simulation"
            | "hot_spots"
            | "strand"
            | "fatigue"
            | "jobs"
            | "campaign"
    )
}

proptest! {
    #![proptest_config(Config {
        cases: 160,
        rng_seed: RngSeed::Fixed(20261126),
        failure_persistence: None,
        ..Config::default()
    })]

    #[test]
    fn a_campaign_with_one_bad_value_is_refused_by_field_or_resolves(
        pick in any::<prop::sample::Index>(),
        value in replacement(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        copy_demo(dir.path());
        let file = dir.path().join("demo.json");
        let mut spec: Value =
            serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
        let mut paths = Vec::new();
        number_paths(&spec, "", &mut paths);
        let path = &paths[pick.index(paths.len())];
        *spec.pointer_mut(path).unwrap() = value.clone();
        std::fs::write(&file, spec.to_string()).unwrap();
        match resolve(&file) {
            Ok(_) => {}
            Err(CampaignError::Invalid { field, .. }) => {
                prop_assert!(names_a_field(&field), "{path} = {value}: {field}");
            }
            Err(e) => {
                let text = e.to_string();
                prop_assert!(!text.is_empty() && text.len() < 2000, "{path} = {value}: {text}");
            }
        }
    }
}
