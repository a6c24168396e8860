//! Tests of [`super::sea_state_damage_inputs`] against values computed by hand.

use std::f64::consts::{FRAC_PI_2, PI};

use super::*;
use crate::contact::hertz::ElasticMaterial;
use crate::fatigue::{ApiComponent, DnvComponent};
use crate::fretting::cycles::{ForceStats, SlipCycle};
use crate::fretting::indicators::RegimeCriterion;
use crate::fretting::rainflow::Cycle;
use crate::fretting::record::AngularPosition;

fn wires() -> CrossedCylinders {
    let m = ElasticMaterial::default();
    CrossedCylinders {
        radius_1_m: 2.3e-3,
        radius_2_m: 2.3e-3,
        crossing_angle_rad: FRAC_PI_2,
        material_1: m,
        material_2: m,
    }
}

fn config() -> DamageInputsConfig {
    DamageInputsConfig {
        slip_amplitude_edges_m: vec![0.0, 2e-6, 4e-6],
        normal_force_edges_n: vec![0.0, 1000.0],
        fretting: FrettingParams {
            regime: RegimeCriterion::Amplitude {
                stick_below_m: 0.5e-6,
                gross_from_m: 2e-6,
            },
            ..FrettingParams::default()
        },
        interfaces: vec![wires(), wires()],
        metallic_area_m2: 0.01,
        tn_curves: vec![
            NamedTnCurve {
                measure: "tn_dnv_spiral_rope".into(),
                curve: TnCurve::Dnv {
                    component: DnvComponent::SpiralRope,
                    nominal_area_m2: 0.01,
                },
            },
            NamedTnCurve {
                measure: "tn_api_spiral_strand".into(),
                curve: TnCurve::Api {
                    component: ApiComponent::SpiralStrandRope,
                    reference_breaking_strength_n: 1e7,
                    mean_load_ratio: 0.5,
                },
            },
        ],
        law: FrettingLaw::RopeTnPerSlipCycle,
        contact_stress: ContactStressLaw::default(),
    }
}

fn cycle(start: usize, end: usize, count: f64, amplitude: f64, normal: f64) -> SlipCycle {
    SlipCycle {
        slip: Cycle {
            range: 2.0 * amplitude,
            mean: 0.0,
            count,
            start_index: start,
            end_index: end,
        },
        normal_force_n: ForceStats {
            min: normal,
            max: normal,
            mean: normal,
        },
        tangential_force_n: ForceStats {
            min: -30.0,
            max: 30.0,
            mean: 0.0,
        },
    }
}

fn record(interface: usize, theta_rad: f64, cycles: Vec<SlipCycle>) -> ContactRecord {
    ContactRecord {
        interface,
        theta_rad,
        z_m: 0.0,
        max_normal_force_n: 400.0,
        cycles,
    }
}

/// Sample 0 is run-in; then 1 MN and 2 MN alternate (σ = T / 0.01 m² = 100 and 200 MPa).
fn tension() -> Vec<f64> {
    let mut t = vec![1.5e6];
    t.extend((0..10).map(|k| if k % 2 == 0 { 1e6 } else { 2e6 }));
    t
}

fn records() -> Vec<ContactRecord> {
    vec![
        // Neutral axis, interface 0: a run-in half cycle (dropped) and a partial-slip cycle.
        record(
            0,
            0.1,
            vec![cycle(0, 1, 0.5, 4e-6, 400.0), cycle(2, 4, 1.0, 1e-6, 400.0)],
        ),
        // Same class: a gross-slip half cycle.
        record(0, PI - 0.2, vec![cycle(5, 6, 0.5, 3e-6, 400.0)]),
        // Outer arc, interface 1: a stick cycle.
        record(1, FRAC_PI_2, vec![cycle(3, 7, 1.0, 0.2e-6, 300.0)]),
    ]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn class_inputs_match_hand_computed_values() {
    let t = tension();
    let history = TensionHistory {
        tension_n: &t,
        dt_s: 1.0,
        run_in_samples: 1,
    };
    let out = sea_state_damage_inputs(&records(), &history, &config()).unwrap();
    // 11 samples, 1 of run-in: T_eff = 9 s, 400 per hour per cycle.
    assert_eq!(out.effective_duration_s, 9.0);
    assert_eq!(out.classes.len(), 2);
    let (na, oa) = (&out.classes[0], &out.classes[1]);
    assert_eq!(
        na.class,
        ContactClass {
            interface: 0,
            position: AngularPosition::NeutralAxis
        }
    );
    assert_eq!(oa.class.position, AngularPosition::OuterArc);
    assert_eq!((na.contacts, oa.contacts), (2, 1));
    // Histograms per hour: amplitudes 1 µm (bin 0, 1 cycle) and 3 µm (bin 1, ½ cycle).
    assert!(rel(na.cycles_per_hour.count(0, 0), 400.0) < 1e-14);
    assert!(rel(na.cycles_per_hour.count(1, 0), 200.0) < 1e-14);
    assert!(rel(na.cycles_per_hour.total(), 600.0) < 1e-14);
    assert!(rel(oa.cycles_per_hour.count(0, 0), 400.0) < 1e-14);
    // Regimes: thresholds 0.5 µm / 2 µm.
    let r = na.regime_cycles_per_hour;
    assert_eq!(r.stick, 0.0);
    assert!(rel(r.partial_slip, 400.0) < 1e-14);
    assert!(rel(r.gross_slip, 200.0) < 1e-14);
    assert!(rel(oa.regime_cycles_per_hour.stick, 400.0) < 1e-14);
    // Every counted window holds 1 MN and 2 MN: wire stress range 100 MPa, N = 1.7e17 / 100^4.8.
    let n = 1.7e17 / 100f64.powf(4.8);
    assert!(rel(na.fretting_damage_rate_max_per_s, 1.0 / n / 9.0) < 1e-12);
    assert!(rel(na.fretting_damage_rate_mean_per_s, 0.75 / n / 9.0) < 1e-12);
    assert!(rel(oa.fretting_damage_rate_max_per_s, 1.0 / n / 9.0) < 1e-12);
    // Ruiz: τ = 30 N / (πab at 400 N), largest δ = 3 µm, σ_max = 200 MPa.
    let contact = HertzModel::crossed_cylinders(&wires())
        .unwrap()
        .contact(400.0)
        .unwrap();
    let f1 = 30.0 / contact.area_m2() * 3e-6;
    assert!(rel(na.ruiz_f1_max, f1) < 1e-12);
    assert!(rel(na.ruiz_f2_max, 200e6 * f1) < 1e-12);
    assert!(rel(na.peak_pressure_max_pa, contact.peak_pressure_pa) < 1e-14);
    assert_eq!(na.slip_amplitude_max_m, 3e-6);
}

#[test]
fn tension_damage_follows_the_curves_on_the_effective_series() {
    let t = tension();
    let history = TensionHistory {
        tension_n: &t,
        dt_s: 1.0,
        run_in_samples: 1,
    };
    let out = sea_state_damage_inputs(&records(), &history, &config()).unwrap();
    // Ten alternating samples: nine half cycles of 1 MN.
    let dnv = &out.tension[0];
    assert_eq!(dnv.measure, "tn_dnv_spiral_rope");
    assert_eq!(dnv.cycles, 4.5);
    let s_mpa: f64 = 1e6 / 0.01 * 1e-6;
    assert!(rel(dnv.damage, 4.5 * s_mpa.powf(4.8) / 1.7e17) < 1e-12);
    assert!(rel(dnv.damage_rate_per_s, dnv.damage / 9.0) < 1e-14);
    // API spiral strand at this sea state's Lm = 1.5 MN / 10 MN = 0.15, R = 0.1.
    let api = &out.tension[1];
    assert!(rel(api.mean_tension_n, 1.5e6) < 1e-14);
    let k = 10f64.powf(3.25 - 3.43 * 0.15);
    assert!(rel(api.damage, 4.5 / (k * 0.1f64.powf(-5.05))) < 1e-12);
    assert!(matches!(api.curve, TnCurve::Api { mean_load_ratio, .. }
        if (mean_load_ratio - 0.15).abs() < 1e-15));
}

#[test]
fn inconsistent_inputs_name_the_field() {
    let t = tension();
    let history = TensionHistory {
        tension_n: &t,
        dt_s: 1.0,
        run_in_samples: 1,
    };
    let field_of = |e: DamageInputsError| match e {
        DamageInputsError::InvalidInput { field, .. } => field,
        other => panic!("unexpected {other}"),
    };
    let unknown = vec![record(2, 0.0, vec![])];
    let e = sea_state_damage_inputs(&unknown, &history, &config()).unwrap_err();
    assert_eq!(field_of(e), "records[0].interface");
    let beyond = vec![record(0, 0.0, vec![cycle(3, 11, 1.0, 1e-6, 400.0)])];
    let e = sea_state_damage_inputs(&beyond, &history, &config()).unwrap_err();
    assert_eq!(field_of(e), "records[0].cycles[0]");
    let mut nan = t.clone();
    nan[4] = f64::NAN;
    let bad = TensionHistory {
        tension_n: &nan,
        ..history
    };
    let e = sea_state_damage_inputs(&records(), &bad, &config()).unwrap_err();
    assert_eq!(field_of(e), "tension_n[4]");
    let long_run_in = TensionHistory {
        run_in_samples: 10,
        ..history
    };
    let e = sea_state_damage_inputs(&records(), &long_run_in, &config()).unwrap_err();
    assert_eq!(field_of(e), "tension_n");
    let mut cfg = config();
    cfg.slip_amplitude_edges_m = vec![1.0];
    assert!(matches!(
        sea_state_damage_inputs(&records(), &history, &cfg),
        Err(DamageInputsError::Fretting(_))
    ));
}

#[test]
fn range_extrema_agree_with_a_direct_scan() {
    let x: Vec<f64> = (0..37).map(|i| ((i * 7919) % 31) as f64 - 15.0).collect();
    let table = RangeExtrema::new(&x);
    for lo in 0..x.len() {
        for hi in lo..x.len() {
            let w = &x[lo..=hi];
            let min = w.iter().copied().fold(f64::INFINITY, f64::min);
            let max = w.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            assert_eq!(table.query(lo, hi), (min, max), "{lo}..={hi}");
        }
    }
}
