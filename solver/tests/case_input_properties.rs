//! Adversarial case files: the paper case with one value replaced by an extreme number or a value
//! of the wrong type. Reading and validating never panics; a refusal names a field of the case
//! by its path; a case that validates builds its model and solves its statics, or reports why,
//! without a panic and without non-finite results.

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

/// Extreme numbers, ordinary ones, and values of the wrong type.
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
fn names_a_field(field: &str) -> bool {
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

proptest! {
    #![proptest_config(Config {
        cases: 160,
        rng_seed: RngSeed::Fixed(20261126),
        failure_persistence: None,
        ..Config::default()
    })]

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
                    prop_assert!(names_a_field(field), "{path} = {value}: {e}");
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
