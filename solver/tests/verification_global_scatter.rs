//! The global stage over the paper scatter diagram: the short-period cells (Tp ≤ 6 s), whose
//! shortest waves the floater's kinematics table cannot resolve, run without failure once the
//! stage cuts the sea off at the frequency it resolves; no sea state of the accepted input
//! ranges makes the stage, or a kinematics table query, panic.
//!
//! Before the cut-off, these cells failed within their first 20 s (Hs 0.25 m Tp 3 s at
//! t = 0.0016 s, Tp 4 s at 0.28 s, Hs 0.75 m Tp 5 s at 13-20 s) or panicked (Hs 1.75 m Tp 5 s,
//! an index out of the table), so 60 s of simulated time exercises every one of those failures.

use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::global::case::{CaseSpec, GammaSpec};
use moorfret_solver::global::{run, CutOffLimit, FloaterInput, GlobalModel, RunParams};
use moorfret_solver::waves::{
    IrregularSea, Jonswap, PeakEnhancement, PlaneKinematicsTable, RealisationParams, ScatterTable,
    TableParams, TableRegion, WavesError,
};
use nalgebra::Vector3;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError};

const CASE: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/paper_case.json"
));
const FLOATER: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/oc4_semi_floater.json"
));
const SCATTER: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/wsd_argoss_sector.tsv"
));

fn floater() -> FloaterInput {
    FloaterInput::RigidBody(Box::new(FloaterSpec::from_json_str(FLOATER).unwrap()))
}

/// The paper case in the sea state (hs, tp, γ, seed) for `seconds` of simulated time: a 10 s
/// transient with a 10 s ramp, then the rest recorded.
fn case(hs: f64, tp: f64, gamma: f64, seed: u64, seconds: f64) -> CaseSpec {
    let mut c = CaseSpec::from_json_str(CASE).unwrap();
    c.sea_state.hs_m = hs;
    c.sea_state.tp_s = tp;
    c.sea_state.gamma = GammaSpec::Value(gamma);
    c.sea_state.seed = seed;
    c.timing.transient_s = 10.0;
    c.timing.wave_ramp_s = 10.0;
    c.timing.duration_s = seconds - 10.0;
    c
}

#[test]
fn every_short_period_cell_of_the_paper_diagram_runs_a_minute() {
    let table = ScatterTable::parse(SCATTER).unwrap();
    let cells: Vec<(f64, f64)> = table
        .cells()
        .into_iter()
        .filter(|c| c.value > 0.0 && c.tp_s <= 6.0)
        .map(|c| (0.5 * (c.hs_lower_m + c.hs_upper_m), c.tp_s))
        .collect();
    assert_eq!(cells.len(), 11, "{cells:?}");
    for (hs, tp) in cells {
        let model = GlobalModel::new(&case(hs, tp, 1.3, 1, 60.0), floater(), None).unwrap();
        let cut = model.wave_cut_off;
        // The table limit decides for every short-period cell: k Δ = 1 with Δ = 2.5 m.
        assert_eq!(cut.limited_by, CutOffLimit::FloaterTable, "Hs {hs} Tp {tp}");
        assert!((cut.cut_off_rad_s - 1.981).abs() < 1e-3);
        assert!(cut.highest_component_rad_s <= cut.cut_off_rad_s);
        assert!(cut.kept_m0_fraction > 0.1 && cut.kept_m0_fraction < 1.0);
        let r = run(&model, &RunParams::default(), |_, _| {})
            .unwrap_or_else(|e| panic!("Hs {hs} Tp {tp}: {e}"));
        let s = r.stats;
        println!(
            "Hs {hs} Tp {tp}: {} steps, {} passes (max {}), {} cut steps, kept m0 {:.3}",
            s.steps,
            s.coupling_iterations,
            s.max_coupling_iterations,
            s.cut_coupled_steps,
            cut.kept_m0_fraction
        );
        // Work counts (measured: no cut, 600 steps, at most 3 passes a step): a step cut or
        // extra passes would mean the floater sees unresolved waves again.
        assert_eq!(s.steps, 600, "Hs {hs} Tp {tp}");
        assert_eq!(s.cut_coupled_steps, 0, "Hs {hs} Tp {tp}");
        assert!(s.max_coupling_iterations <= 3, "Hs {hs} Tp {tp}: {s:?}");
        assert_eq!(s.floater_table_misses, 0);
        assert!(!s.floater_table_unresolved);
        // The summary records the choice.
        assert_eq!(r.summary().wave_cut_off, cut);
    }
}

/// The severe sea state's band lies below the cut-off: its sea is the uncut realisation,
/// component for component, so the showcase results are unchanged.
#[test]
fn the_severe_sea_state_is_not_cut() {
    let c = CaseSpec::from_json_str(CASE).unwrap();
    let model = GlobalModel::new(&c, floater(), None).unwrap();
    assert_eq!(model.wave_cut_off.limited_by, CutOffLimit::None);
    assert_eq!(model.wave_cut_off.kept_m0_fraction, 1.0);
    let s = &c.sea_state;
    let spectrum = Jonswap::new(s.hs_m, s.tp_s, PeakEnhancement::Given(1.3)).unwrap();
    let uncut = IrregularSea::new(
        &spectrum,
        &RealisationParams {
            duration_s: c.timing.transient_s + c.timing.duration_s,
            seed: s.seed,
            depth_m: c.site.water_depth_m,
            water_density_kg_m3: c.site.water_density_kg_m3,
            ..RealisationParams::default()
        },
    )
    .unwrap();
    assert_eq!(model.sea.field().components(), uncut.field().components());
}

fn config() -> Config {
    Config {
        cases: 12,
        rng_seed: RngSeed::Fixed(20261126),
        failure_persistence: None,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// Any sea state of the accepted ranges (Hs > 0, Tp > 0, γ in [1, 7]) either runs or ends
    /// with a typed error; two seconds of simulated time cover model building, statics, the
    /// precomputations and the first steps, where the unresolved sea states failed.
    #[test]
    fn no_sea_state_makes_the_stage_panic(
        hs in 0.01..16.0f64,
        tp in 1.0..26.0f64,
        gamma in 1.0..=7.0f64,
        seed in any::<u64>(),
    ) {
        let mut c = case(hs, tp, gamma, seed, 12.0);
        c.timing.transient_s = 1.0;
        c.timing.wave_ramp_s = 1.0;
        c.timing.duration_s = 1.0;
        match GlobalModel::new(&c, floater(), None) {
            Ok(model) => {
                let cut = model.wave_cut_off;
                prop_assert!(cut.highest_component_rad_s <= cut.cut_off_rad_s);
                prop_assert!((0.0..=1.0).contains(&cut.kept_m0_fraction));
                if let Err(e) = run(&model, &RunParams::default(), |_, _| {}) {
                    // A typed error with its message, never a panic.
                    prop_assert!(!e.to_string().is_empty());
                }
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }

    /// A kinematics table answers every query, however far or non-finite the position or the
    /// time, with a value or an OutsideTable error naming the range.
    #[test]
    fn table_queries_never_index_outside_the_table(
        x in prop_oneof![-1e3..1e3f64, any::<f64>()],
        z in prop_oneof![-150.0..20.0f64, any::<f64>()],
        t in prop_oneof![-5.0..40.0f64, any::<f64>()],
    ) {
        let table = short_table();
        match table.kinematics(&Vector3::new(x, 0.3 * x, z), t) {
            Ok(k) => prop_assert!(k.velocity.iter().all(|v| v.is_finite())),
            Err(WavesError::OutsideTable { lower, upper, .. }) => prop_assert!(lower < upper),
            Err(e) => return Err(TestCaseError::fail(format!("unexpected error {e}"))),
        }
        match table.elevation(x, -x, t) {
            Ok(e) => prop_assert!(e.is_finite()),
            Err(WavesError::OutsideTable { lower, upper, .. }) => prop_assert!(lower < upper),
            Err(e) => return Err(TestCaseError::fail(format!("unexpected error {e}"))),
        }
    }
}

/// A small table of a moderate sea over 30 s.
fn short_table() -> PlaneKinematicsTable {
    let s = Jonswap::new(2.0, 8.0, PeakEnhancement::Given(1.3)).unwrap();
    let sea = IrregularSea::new(
        &s,
        &RealisationParams {
            duration_s: 30.0,
            seed: 5,
            cut_off_rad_s: Some(1.98),
            ..RealisationParams::default()
        },
    )
    .unwrap();
    let region = TableRegion {
        along_m: (-20.0, 20.0),
        lowest_stretched_m: -30.0,
        end_time_s: 30.0,
    };
    PlaneKinematicsTable::new(&sea, &region, &TableParams::default()).unwrap()
}
