//! The reduced strand response of the paper's six-layer strand, pinned against a stored FE
//! reference: the calibration, the load history and the FE run's damage per contact class
//! are in `campaigns/benchmarks/six_layer_reduced/` (how they were made, and how to make them
//! again: `docs/reduced-strand.md`, "The pinned six-layer check"). The test runs the stored
//! calibration through the held-out history (300 s of the paper case's hot spot at Hs 3.25 m,
//! Tp 11 s, a seed the calibration never saw) and checks, per contact class, both fretting
//! measures (the most damaged contact's damage rate, and the class mean) and the slip per
//! layer interface against the FE run, within the errors measured when the reference was made,
//! and against the reference's own reduced run (to 1e-6), so that any change of the response
//! shows.

use std::io::Read;
use std::path::{Path, PathBuf};

use moorfret_campaign::fatigue::FatigueSpec;
use moorfret_solver::damage::{sea_state_damage_inputs, TensionHistory};
use moorfret_solver::global::series::{LoadKind, LoadTable};
use moorfret_solver::strand::history::stiffness::straight_strand_stiffness;
use moorfret_solver::strand::history::{HistoryOptions, LoadSample};
use moorfret_solver::strand::profile::select_profile;
use moorfret_solver::strand::reduced::compare::compare_records;
use moorfret_solver::strand::reduced::{run_reduced, ReducedStrand};

/// Reduced / FE of a class's mean damage rate: the bounds measured when the reference was made
/// (0.608 to 3.53), rounded outwards.
const MEAN_RATIO: [f64; 2] = [0.6, 3.6];

/// Reduced / FE of a class's largest damage rate: measured 0.300 to 6.91.
const MAX_RATIO: [f64; 2] = [0.29, 7.0];

/// Largest relative difference, reduced against FE, of an interface's largest slip range
/// (measured: 11.7 %, interface 1).
const SLIP_RANGE_TOLERANCE: f64 = 0.12;

/// Largest relative difference of an interface's accumulated slip and count of cycles of at
/// least 1 µm, where the FE run counts any (measured: 10.5 % and 10.0 %, interface 4).
const CYCLES_TOLERANCE: f64 = 0.11;

fn reference_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/benchmarks/six_layer_reduced")
}

/// A relative difference that is 0 for two zeros.
fn relative(reference: f64, compared: f64) -> f64 {
    if reference == compared {
        0.0
    } else {
        (compared - reference).abs() / reference.abs().max(compared.abs())
    }
}

#[test]
fn the_reduced_six_layer_strand_stays_within_its_measured_error_of_the_fe_reference() {
    let dir = reference_dir();
    let mut text = Vec::new();
    flate2::read::GzDecoder::new(std::fs::File::open(dir.join("calibration.json.gz")).unwrap())
        .read_to_end(&mut text)
        .unwrap();
    let reduced = ReducedStrand::from_json(&text).unwrap();
    let profiles = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/data/strand_profiles.json"),
    )
    .unwrap();
    let strand = select_profile(&profiles, Some("paper_six_layer"))
        .unwrap()
        .validate()
        .unwrap();
    let table =
        LoadTable::parse(&std::fs::read_to_string(dir.join("load.csv")).unwrap(), 0).unwrap();
    assert_eq!(table.kind, LoadKind::Strain);
    let samples: Vec<LoadSample> = (0..table.time_s.len())
        .map(|i| LoadSample {
            time_s: table.time_s[i],
            strain: table.value[i],
            curvature_per_m: table.curvature_per_m[i],
        })
        .collect();
    let result = run_reduced(&reduced, &samples, &HistoryOptions::default()).unwrap();

    // damage as `moorfret strand compare` computes it for a strain history
    let ea_n = straight_strand_stiffness(&strand).simple_n;
    let tension: Vec<f64> = samples.iter().map(|s| s.strain * ea_n).collect();
    let dt_s = (samples[samples.len() - 1].time_s - samples[0].time_s) / (samples.len() - 1) as f64;
    let history = TensionHistory {
        tension_n: &tension,
        dt_s,
        run_in_samples: 0,
    };
    let config = FatigueSpec::default().fretting_config(&strand, ea_n);
    let inputs = sea_state_damage_inputs(&result.contacts, &history, &config).unwrap();

    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("compare.json")).unwrap()).unwrap();
    let classes = reference["classes"].as_array().unwrap();
    assert_eq!(classes.len(), inputs.classes.len());
    let (mut worst_mean, mut worst_max) = (0.0_f64, 0.0_f64);
    for row in classes {
        let interface = row["interface"].as_u64().unwrap() as usize;
        let position = row["position"].as_str().unwrap();
        let class = inputs
            .classes
            .iter()
            .find(|c| c.class.interface == interface && c.class.position.as_str() == position)
            .unwrap_or_else(|| panic!("class {interface} / {position}"));
        let pair = |field: &str| -> (f64, f64) {
            let v = row[field].as_array().unwrap();
            (v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
        };
        let (fe_mean, then_mean) = pair("damage_rate_mean_per_s");
        let (fe_max, then_max) = pair("damage_rate_max_per_s");
        let (now_mean, now_max) = (
            class.fretting_damage_rate_mean_per_s,
            class.fretting_damage_rate_max_per_s,
        );
        // the reduced response as the reference's own reduced run gave it
        assert!(
            relative(then_mean, now_mean) < 1e-6 && relative(then_max, now_max) < 1e-6,
            "class {interface} / {position}: mean {now_mean:e} (then {then_mean:e}), max \
             {now_max:e} (then {then_max:e})"
        );
        let (mean_ratio, max_ratio) = (now_mean / fe_mean, now_max / fe_max);
        worst_mean = worst_mean.max(mean_ratio.max(1.0 / mean_ratio));
        worst_max = worst_max.max(max_ratio.max(1.0 / max_ratio));
        assert!(
            (MEAN_RATIO[0]..=MEAN_RATIO[1]).contains(&mean_ratio),
            "class {interface} / {position}: mean {now_mean:e} against FE {fe_mean:e}"
        );
        assert!(
            (MAX_RATIO[0]..=MAX_RATIO[1]).contains(&max_ratio),
            "class {interface} / {position}: max {now_max:e} against FE {fe_max:e}"
        );
    }

    // slip per interface: the reduced run's statistics against the FE run's and its own then
    let now = compare_records(&result.contacts, &result.contacts, 1e-6, 0);
    let interfaces = reference["interfaces"].as_array().unwrap();
    assert_eq!(interfaces.len(), now.len());
    for (row, c) in interfaces.iter().zip(&now) {
        let stat = |side: &str, field: &str| row[side][field].as_f64().unwrap();
        let mine = &c.reference;
        for (field, value) in [
            ("max_slip_range_m", mine.max_slip_range_m),
            ("accumulated_slip_m", mine.accumulated_slip_m),
            ("cycles", mine.cycles),
        ] {
            assert!(
                relative(stat("compared", field), value) < 1e-6,
                "interface {}: {field} {value:e}, then {:e}",
                c.interface,
                stat("compared", field)
            );
        }
        let fe_range = stat("reference", "max_slip_range_m");
        assert!(
            relative(fe_range, mine.max_slip_range_m) <= SLIP_RANGE_TOLERANCE,
            "interface {}: largest slip range {:e} against FE {fe_range:e}",
            c.interface,
            mine.max_slip_range_m
        );
        if stat("reference", "cycles") > 0.0 {
            for (field, value) in [
                ("accumulated_slip_m", mine.accumulated_slip_m),
                ("cycles", mine.cycles),
            ] {
                let fe = stat("reference", field);
                assert!(
                    relative(fe, value) <= CYCLES_TOLERANCE,
                    "interface {}: {field} {value:e} against FE {fe:e}",
                    c.interface
                );
            }
        }
    }
    eprintln!(
        "largest factor between reduced and FE over {} classes: mean {worst_mean:.2}, max \
         {worst_max:.2}",
        classes.len()
    );
}
