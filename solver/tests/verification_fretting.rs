//! Verification of the fretting statistics across modules: rainflow invariants on long seeded
//! random histories (batch vs streaming, count conservation, bounds, invariance to non-reversal
//! points, checkpoint / resume), and the chain contact history → slip cycles → histogram →
//! Hertz / Mindlin regime against the closed-form circular contact.

use moorfret_solver::fretting::rainflow::{count_cycles, total_count, Cycle, RainflowOptions};
use moorfret_solver::fretting::reversals::extract_reversals;
use moorfret_solver::fretting::streaming::StreamingRainflow;
use moorfret_solver::fretting::{
    evaluate_cycle, BinEdges, ContactCycleAccumulator, ContactSample, CrossedCylinders,
    CycleHistogram, ElasticMaterial, ForceMeasure, FrettingParams, FrettingRegime, HertzModel,
    SlipCycle, WireStress,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A history of `n` samples mixing white noise, a random walk and coarse quantisation (which
/// creates flat stretches and repeated values).
fn random_history(seed: u64, n: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let kind = seed % 3;
    let mut walk = 0.0;
    (0..n)
        .map(|_| {
            let u: f64 = rng.gen_range(-1.0..1.0);
            match kind {
                0 => u,
                1 => {
                    walk += u;
                    walk
                }
                _ => (4.0 * u).round() * 0.25,
            }
        })
        .collect()
}

fn stream_all(history: &[f64], gate: f64) -> Vec<Cycle> {
    let mut s = StreamingRainflow::<()>::new(gate).unwrap();
    let mut out = Vec::new();
    for &x in history {
        s.push(x, &mut out).unwrap();
    }
    s.finish(&mut out);
    out
}

fn config() -> Config {
    Config {
        cases: 48,
        rng_seed: RngSeed::Fixed(0x6d6f_6f72),
        failure_persistence: None,
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn streaming_count_equals_batch_count(seed in any::<u64>(), n in 0usize..20_000, gate in prop_oneof![Just(0.0), 0.0..0.3f64]) {
        let h = random_history(seed, n);
        let options = RainflowOptions { hysteresis_gate: gate, repeating: false };
        let batch = count_cycles(&h, &options).unwrap();
        let streamed = stream_all(&h, gate);
        prop_assert_eq!(streamed, batch);
    }

    #[test]
    fn total_count_is_half_the_number_of_ranges(seed in any::<u64>(), n in 1usize..5_000, gate in 0.0..0.2f64) {
        let h = random_history(seed, n);
        let reversals = extract_reversals(&h, gate).unwrap().len();
        let cycles = count_cycles(&h, &RainflowOptions { hysteresis_gate: gate, repeating: false }).unwrap();
        prop_assert_eq!(total_count(&cycles), (reversals as f64 - 1.0) / 2.0);
    }

    #[test]
    fn no_range_exceeds_the_range_of_the_history(seed in any::<u64>(), n in 1usize..5_000, repeating in any::<bool>()) {
        let h = random_history(seed, n);
        let span = h.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - h.iter().cloned().fold(f64::INFINITY, f64::min);
        let cycles = count_cycles(&h, &RainflowOptions { hysteresis_gate: 0.0, repeating }).unwrap();
        for c in &cycles {
            prop_assert!(c.range <= span);
            prop_assert!(c.count == 0.5 || c.count == 1.0);
            prop_assert!(!repeating || c.count == 1.0);
        }
    }

    #[test]
    fn inserting_non_reversal_points_changes_nothing_but_indices(seed in any::<u64>(), n in 2usize..3_000) {
        let h = random_history(seed, n);
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xabcd);
        let mut dense = Vec::with_capacity(3 * n);
        for w in h.windows(2) {
            dense.push(w[0]);
            // Points strictly between two samples, in order, never beyond either end.
            let k = rng.gen_range(0..3);
            let mut ts: Vec<f64> = (0..k).map(|_| rng.gen_range(0.05..0.95)).collect();
            ts.sort_by(f64::total_cmp);
            dense.extend(ts.iter().map(|t| w[0] + t * (w[1] - w[0])));
        }
        dense.push(h[n - 1]);
        let o = RainflowOptions::default();
        let key = |c: &[Cycle]| c.iter().map(|c| (c.range, c.mean, c.count)).collect::<Vec<_>>();
        prop_assert_eq!(key(&count_cycles(&dense, &o).unwrap()), key(&count_cycles(&h, &o).unwrap()));
    }

    #[test]
    fn repeating_count_is_invariant_to_rotation(seed in any::<u64>(), n in 2usize..2_000, shift in 0usize..2_000) {
        let h = random_history(seed, n);
        let mut rotated = h.clone();
        rotated.rotate_left(shift % n);
        let o = RainflowOptions { hysteresis_gate: 0.0, repeating: true };
        let mut a: Vec<(f64, f64)> = count_cycles(&h, &o).unwrap().iter().map(|c| (c.range, c.mean)).collect();
        let mut b: Vec<(f64, f64)> = count_cycles(&rotated, &o).unwrap().iter().map(|c| (c.range, c.mean)).collect();
        a.sort_by(|x, y| x.partial_cmp(y).unwrap());
        b.sort_by(|x, y| x.partial_cmp(y).unwrap());
        prop_assert_eq!(a, b);
    }

    #[test]
    fn checkpointed_stream_resumes_bit_for_bit(seed in any::<u64>(), n in 1usize..6_000, cut in 0usize..6_000) {
        let h = random_history(seed, n);
        let cut = cut % n;
        let mut s = StreamingRainflow::<()>::new(0.0).unwrap();
        let mut out = Vec::new();
        for &x in &h[..cut] {
            s.push(x, &mut out).unwrap();
        }
        let json = serde_json::to_string(&s).unwrap();
        let mut resumed: StreamingRainflow<()> = serde_json::from_str(&json).unwrap();
        prop_assert_eq!(&resumed, &s);
        for &x in &h[cut..] {
            resumed.push(x, &mut out).unwrap();
        }
        resumed.finish(&mut out);
        let uninterrupted = stream_all(&h, 0.0);
        prop_assert_eq!(out.len(), uninterrupted.len());
        for (a, b) in out.iter().zip(&uninterrupted) {
            prop_assert_eq!(a.range.to_bits(), b.range.to_bits());
            prop_assert_eq!(a.mean.to_bits(), b.mean.to_bits());
            prop_assert_eq!((a.count, a.start_index, a.end_index), (b.count, b.start_index, b.end_index));
        }
    }
}

fn contact_history(seed: u64, n: usize) -> Vec<ContactSample> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.05;
            ContactSample {
                slip_m: 2e-6 * t.sin() + 5e-7 * rng.gen_range(-1.0..1.0),
                normal_force_n: 800.0 + 100.0 * (0.3 * t).sin() + rng.gen_range(-5.0..5.0),
                tangential_force_n: 60.0 * t.cos() + rng.gen_range(-2.0..2.0),
            }
        })
        .collect()
}

#[test]
fn contact_accumulator_checkpoint_resumes_bit_for_bit() {
    let h = contact_history(7, 20_000);
    let run = |cut: Option<usize>| -> Vec<SlipCycle> {
        let mut acc = ContactCycleAccumulator::new(1e-8).unwrap();
        let mut out = Vec::new();
        for (i, s) in h.iter().enumerate() {
            if Some(i) == cut {
                let json = serde_json::to_vec(&acc).unwrap();
                acc = serde_json::from_slice(&json).unwrap();
            }
            acc.push(*s, &mut out).unwrap();
        }
        acc.finish(&mut out);
        out
    };
    let whole = run(None);
    assert!(whole.len() > 1000);
    for cut in [1, 777, 12_345] {
        let resumed = run(Some(cut));
        assert_eq!(resumed.len(), whole.len());
        for (a, b) in resumed.iter().zip(&whole) {
            // Bit-for-bit: compare the serialised bit patterns of every float.
            let bits = |c: &SlipCycle| {
                [
                    c.slip.range,
                    c.slip.mean,
                    c.normal_force_n.mean,
                    c.normal_force_n.max,
                    c.tangential_force_n.mean,
                ]
                .map(f64::to_bits)
            };
            assert_eq!(bits(a), bits(b));
            assert_eq!(a, b);
        }
    }
}

#[test]
fn contact_history_to_regimes_follows_the_mindlin_limit_of_the_circular_contact() {
    // Equal perpendicular steel wires (r = 2.3 mm) under f_N = 600 N, μ = 0.12: circular Hertz
    // contact a = (3PR/4E*)^(1/3) and Mindlin gross-slip amplitude δ* = 3μP(2 − ν)/(8Ga)
    // (Johnson 1985, eqs. 4.22 and 7.42). Fifty slip cycles at 0.5 δ* then fifty at 2 δ*.
    let m = ElasticMaterial::default();
    let (r, p, mu) = (2.3e-3, 600.0, 0.12);
    let model = HertzModel::crossed_cylinders(&CrossedCylinders {
        radius_1_m: r,
        radius_2_m: r,
        crossing_angle_rad: std::f64::consts::FRAC_PI_2,
        material_1: m,
        material_2: m,
    })
    .unwrap();
    let e_star = m.youngs_modulus_pa / (2.0 * (1.0 - m.poisson_ratio.powi(2)));
    let a = (3.0 * p * r / (4.0 * e_star)).cbrt();
    let delta_star = 3.0 * mu * p * (2.0 - m.poisson_ratio) / (8.0 * m.shear_modulus_pa() * a);
    let per = 32;
    let mut acc = ContactCycleAccumulator::new(0.0).unwrap();
    let mut cycles = Vec::new();
    for k in 0..100 * per {
        let amp = if k < 50 * per {
            0.5 * delta_star
        } else {
            2.0 * delta_star
        };
        let phase = std::f64::consts::TAU * (k % per) as f64 / per as f64;
        let sample = ContactSample {
            slip_m: amp * phase.sin(),
            normal_force_n: p,
            tangential_force_n: 40.0 * phase.sin(),
        };
        acc.push(sample, &mut cycles).unwrap();
    }
    acc.finish(&mut cycles);
    let slip_edges = BinEdges::geometric(0.1 * delta_star, 10.0 * delta_star, 20).unwrap();
    let force_edges = BinEdges::uniform(0.0, 1000.0, 10).unwrap();
    let mut hist = CycleHistogram::new(slip_edges, force_edges, ForceMeasure::Mean);
    let params = FrettingParams {
        friction_coefficient: mu,
        ..FrettingParams::default()
    };
    let (mut partial, mut gross) = (0.0, 0.0);
    for c in &cycles {
        hist.add_cycle(c);
        let ind = evaluate_cycle(&model, &params, c, &WireStress::default()).unwrap();
        assert!((ind.gross_slip_amplitude_m / delta_star - 1.0).abs() < 1e-12);
        assert!((ind.contact.semi_major_m / a - 1.0).abs() < 1e-12);
        match ind.regime {
            FrettingRegime::PartialSlip => partial += c.slip.count,
            FrettingRegime::GrossSlip => gross += c.slip.count,
            FrettingRegime::Stick => panic!("Mindlin default has no stick range"),
        }
    }
    // Reversals: the start, 100 peaks, 100 valleys and the last sample → 100.5 cycles. Partial
    // slip: the start half cycle plus 99 half cycles between the small extremes (50), and the
    // final half cycle from the last valley to the last sample, amplitude 0.62 δ* (0.5). Gross
    // slip: the range from the last small valley to the first large peak (amplitude 1.25 δ*)
    // and every large range (50).
    assert_eq!(partial, 50.5);
    assert_eq!(gross, 50.0);
    assert!(
        (hist.total() - total_count(&cycles.iter().map(|c| c.slip).collect::<Vec<_>>())).abs()
            < 1e-12
    );
    assert_eq!(hist.out_of_range(), 0.0);
}
