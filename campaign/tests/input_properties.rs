//! Adversarial inputs: one value of a file replaced by an extreme number or a value of the wrong
//! type.
//! - The demo campaign, resolved with its files: resolution never panics or aborts, and a
//!   refusal names a field of the campaign file by its path.
//! - The paper's global case: reading and validating never panic, a refusal names a field of
//!   the case by its path, and a case that validates builds its model and solves its statics,
//!   or reports why, without a panic and without non-finite results. (It found an abort:
//!   `segments[i].elements` 4294967295 allocated until the process was killed.)

use std::path::Path;

use moorfret_campaign::{resolve, CampaignError};
use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::case::CaseSpec;
use moorfret_solver::global::system::{solve_coupled_statics, StaticsParams};
use moorfret_solver::global::{FloaterInput, GlobalError, GlobalModel};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError};
use serde_json::Value;

const CASE: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/paper_case.json"
));
const FLOATER: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/oc4_semi_floater.json"
));

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
        Just(serde_json::json!(-1e300)),
        Just(serde_json::json!(4294967295_u64)),
        Just(serde_json::json!(u64::MAX)),
        (-1e4..1e4_f64).prop_map(|x| serde_json::json!(x)),
        Just(Value::Null),
        Just(serde_json::json!("text")),
        Just(serde_json::json!([])),
    ]
}

/// Whether a dotted field path (`mooring.segments[1].length_m`) names a place of the case.
fn names_a_case_field(field: &str) -> bool {
    let top = field
        .split(['.', '['])
        .next()
        .unwrap_or_default()
        .split(':')
        .next()
        .unwrap_or_default();
    matches!(
        top,
        "site" | "sea_state" | "timing" | "floater" | "mooring" | "hot_spots" | "wind"
    )
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

    #[test]
    fn a_case_with_one_bad_value_is_refused_by_field_or_solves(
        pick in any::<prop::sample::Index>(),
        value in replacement(),
    ) {
        let mut case: Value = serde_json::from_str(CASE).unwrap();
        let mut paths = Vec::new();
        number_paths(&case, "", &mut paths);
        let path = &paths[pick.index(paths.len())];
        *case.pointer_mut(path).unwrap() = value.clone();
        let spec = match CaseSpec::from_json_str(&case.to_string()) {
            Ok(spec) => spec,
            Err(GlobalError::CaseJson { message }) => {
                prop_assert!(message.contains("line"), "{path} = {value}: {message}");
                return Ok(());
            }
            Err(e) => return Err(TestCaseError::fail(format!("{path} = {value}: {e}"))),
        };
        if let Err(e) = spec.validate() {
            match &e {
                GlobalError::InvalidCase { field, .. } => {
                    prop_assert!(names_a_case_field(field), "{path} = {value}: {e}");
                }
                other => prop_assert!(!other.to_string().is_empty()),
            }
            return Ok(());
        }
        let floater = FloaterInput::RigidBody(Box::new(FloaterSpec::from_json_str(FLOATER).unwrap()));
        let model = match GlobalModel::new(&spec, floater, Some(1.0)) {
            Ok(m) => m,
            Err(e) => {
                prop_assert!(!e.to_string().is_empty());
                return Ok(());
            }
        };
        if let Ok(eq) = solve_coupled_statics(&model, &StaticsParams::default(), None) {
            for s in &eq.line_solutions {
                prop_assert!(
                    s.fairlead_force_n.iter().all(|f| f.is_finite()),
                    "{path} = {value}: fairlead force {}",
                    s.fairlead_force_n
                );
            }
        }
    }
}
