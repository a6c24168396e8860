//! History runs on the 1+6+1 benchmark strand (the paper's Sec. 2.2) with the paper's
//! 'vs_analytical' regularisation (ε_N = 2e8 N/m, γ_e = 1e-7 m); slip onset of the outer helix near
//! κ_b ≈ 1.2e-2 1/m at ε = 1e-3 (campaigns/benchmarks/strand_1_6_1.json).

use std::f64::consts::PI;

use super::monitors::{MonitorChannel, MonitorQuantity};
use super::stiffness::{
    contact_compliant_stiffness_n, measure_axial_stiffness_n, samples_from_tension,
    straight_strand_stiffness, SlackTension,
};
use super::*;
use crate::strand::model::{EndKind, StrandModelParameters};
use crate::strand::profile::profile_from_json;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn model() -> StrandModel {
    benchmark_model(&StrandModelParameters::penalty_contact(
        2e8,
        1e-7,
        EndKind::PenaltyTies,
    ))
}

/// The benchmark strand under the contact-mechanics laws.
fn contact_mechanics_model() -> StrandModel {
    benchmark_model(&StrandModelParameters::contact_mechanics(
        EndKind::PenaltyTies,
    ))
}

fn benchmark_model(params: &StrandModelParameters) -> StrandModel {
    let strand = profile_from_json(BENCHMARK)
        .expect("benchmark profile parses")
        .validate()
        .expect("benchmark profile is valid");
    StrandModel::new(&strand, params).expect("benchmark model builds")
}

/// ε = 1e-3, κ = amplitude · sin(2π t / 10 s), `cycles` periods sampled every 0.5 s.
fn bending_cycles(amplitude: f64, cycles: usize) -> Vec<LoadSample> {
    (0..=20 * cycles)
        .map(|i| {
            let t = 0.5 * i as f64;
            LoadSample {
                time_s: t,
                strain: 1e-3,
                curvature_per_m: amplitude * (2.0 * PI * t / 10.0).sin(),
            }
        })
        .collect()
}

#[test]
fn bad_samples_are_refused_with_their_index() {
    let model = model();
    let options = HistoryOptions::default();
    let good = bending_cycles(1e-2, 1);
    let refused = |mutate: &dyn Fn(&mut Vec<LoadSample>)| {
        let mut h = good.clone();
        mutate(&mut h);
        match validate_samples(&model, &h, &options) {
            Err(HistoryError::InvalidSample { index, field, .. }) => (index, field),
            other => panic!("expected a refused sample, got {other:?}"),
        }
    };
    assert_eq!(refused(&|h| h[3].strain = f64::NAN), (3, "strain"));
    assert_eq!(refused(&|h| h[4].strain = -1e-4), (4, "strain"));
    assert_eq!(refused(&|h| h[5].time_s = h[4].time_s), (5, "time_s"));
    // 0.6 1/m at the 21.5 mm outer diameter: fibre strain 1e-3 + 6.45e-3 > 7e-3
    assert_eq!(
        refused(&|h| h[6].curvature_per_m = 0.6),
        (6, "curvature_per_m")
    );
    assert!(validate_samples(&model, &good, &options).is_ok());
    match samples_from_tension(
        &[0.0, 1.0],
        &[1e4, -5.0],
        &[0.0, 0.0],
        2e7,
        1,
        SlackTension::Refuse,
    ) {
        Err(HistoryError::InvalidSample { index, field, .. }) => {
            assert_eq!((index, field), (1, "tension_n"))
        }
        other => panic!("negative tension accepted: {other:?}"),
    }
    let bad_options = HistoryOptions {
        max_substep_strain: 0.0,
        ..options
    };
    assert!(matches!(
        run_history(&model, &good, &bad_options, &mut NoObserver),
        Err(HistoryError::InvalidOption {
            field: "max_substep_strain",
            ..
        })
    ));
    let bad_scale = HistoryOptions {
        turning_point_scale: [0.0, -1e-3],
        ..options
    };
    assert!(matches!(
        run_history(&model, &good, &bad_scale, &mut NoObserver),
        Err(HistoryError::InvalidOption {
            field: "turning_point_scale.curvature_per_m",
            ..
        })
    ));
}

/// EA measured on the model against the straight-strand estimates of
/// [`straight_strand_stiffness`] (simple E (A_core + Σ n A cos³β) and Costello-corrected); the
/// penalty end ties and the contact compliance make the model slightly softer, the tolerance is
/// the 3 % of the acceptance criterion.
#[test]
fn measured_axial_stiffness_is_the_straight_strand_estimate() {
    let model = model();
    let ea = measure_axial_stiffness_n(&model, 1e-3, &HistoryOptions::default()).unwrap();
    let estimate = straight_strand_stiffness(&model.strand);
    let e = (ea - estimate.corrected_n) / estimate.corrected_n;
    eprintln!(
        "EA = {ea:.5e} N, simple {:.5e} N, Costello-corrected {:.5e} N ({:+.2} %)",
        estimate.simple_n,
        estimate.corrected_n,
        100.0 * e
    );
    assert!(e.abs() < 0.03);
}

/// The inner three layers of the paper strand (core + 5 + 11 + 17 wires, model length one lay
/// length of the third layer) with periodic ends and the paper campaign's contact penalty
/// ε_N = 2e8 N/m: the interfaces carry hundreds of newtons per contact, and their penetration
/// shortens the helix radii enough to lower EA well below the rigid straight-strand estimate.
/// EA measured by the tension step against the estimate with the contacts' compliance
/// ([`contact_compliant_stiffness_n`]): within the 3 % of the acceptance criterion.
#[test]
fn measured_axial_stiffness_of_a_multilayer_strand_is_the_contact_compliant_estimate() {
    const PROFILES: &str = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../campaigns/data/strand_profiles.json"
    ));
    let mut profile = crate::strand::profile::profiles_from_json(PROFILES)
        .unwrap()
        .remove("paper_six_layer")
        .unwrap();
    profile.layers.as_mut().unwrap().truncate(3);
    profile.model_length_m = Some(0.2648);
    let strand = profile.validate().unwrap();
    let penalty = 2e8;
    let params = StrandModelParameters::penalty_contact(penalty, 1e-5, EndKind::Periodic);
    let model = StrandModel::new(&strand, &params).unwrap();
    let ea = measure_axial_stiffness_n(&model, 1e-3, &HistoryOptions::default()).unwrap();
    let rigid = straight_strand_stiffness(&model.strand).corrected_n;
    let compliant = contact_compliant_stiffness_n(&model, penalty);
    let e = (ea - compliant) / compliant;
    eprintln!(
        "EA = {ea:.5e} N; Costello-corrected, rigid contacts {rigid:.5e} N ({:+.2} %), with \
         the contact compliance {compliant:.5e} N ({:+.2} %)",
        100.0 * (ea / rigid - 1.0),
        100.0 * e
    );
    assert!(e.abs() < 0.03);
    // the compliance matters: the rigid estimate is more than 3 % off
    assert!(ea / rigid - 1.0 < -0.03);
}

/// Below the slip onset every contact sticks: the tangential gap stays within ±γ_e of the stick
/// law (range < 2 γ_e), the response is elastic and the slip returns to its value after a full
/// bending cycle. Above it (κ = 4e-2 1/m, over three times the onset), Coulomb sliding makes the
/// range exceed 2 γ_e and leaves a residual slip after the cycle (hysteresis).
#[test]
fn bending_cycles_are_reversible_in_stick_and_hysteretic_in_slip() {
    let model = model();
    let options = HistoryOptions::default();
    let outer: Vec<usize> = (0..model.contacts.len())
        .filter(|&c| {
            let b = model.mesh.contacts[c].nodes[1].0;
            model.strand.wires()[model.mesh.nodes[b].wire.0].layer == Some(1)
        })
        .collect();
    let residual_and_range = |amplitude: f64| {
        let h = bending_cycles(amplitude, 1);
        let r = run_history(&model, &h, &options, &mut NoObserver).unwrap();
        assert_eq!(r.contacts.len(), model.contacts.len());
        assert_eq!(r.monitors.time_s.len(), h.len());
        assert!(r.kept_samples.len() < h.len());
        // slip of every outer contact at t = 0 and after one period: monitors hold a ring
        let ring: Vec<&MonitorChannel> = r
            .monitors
            .channels
            .iter()
            .filter(|c| c.quantity == MonitorQuantity::Slip && c.layer == 1)
            .collect();
        assert!(!ring.is_empty());
        let residual = ring
            .iter()
            .map(|c| (c.values[h.len() - 1] - c.values[0]).abs())
            .fold(0.0, f64::max);
        // slip range over the cycle from the ring series (the rainflow gate of 1e-8 m hides
        // ripples below it) and the largest counted range of the outer contacts
        let ring_range = ring
            .iter()
            .map(|c| {
                let (lo, hi) = c
                    .values
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                        (l.min(v), h.max(v))
                    });
                hi - lo
            })
            .fold(0.0, f64::max);
        let counted = outer
            .iter()
            .flat_map(|&c| r.contacts[c].cycles.iter().map(|y| y.slip.range))
            .fold(0.0, f64::max);
        let range = ring_range.max(counted);
        (residual, range, r.stats)
    };
    let (res_stick, range_stick, stats) = residual_and_range(2e-3);
    let (res_slip, range_slip, _) = residual_and_range(4e-2);
    eprintln!(
        "stick: residual {res_stick:.3e} m, range {range_stick:.3e} m; slip: residual \
         {res_slip:.3e} m, range {range_slip:.3e} m; {stats:?}"
    );
    assert!(
        range_stick < 2e-7,
        "stick slip range {range_stick} above 2 γ_e"
    );
    assert!(res_stick < 1e-3 * range_stick.max(1e-12) + 1e-12);
    assert!(range_slip > 2e-7);
    assert!(res_slip > 1e-2 * range_slip);
}

/// Keeps the first checkpoint (as bytes) and stops the run after it if asked to.
struct KeepFirst {
    bytes: Option<Vec<u8>>,
    stop: bool,
}

impl HistoryObserver for KeepFirst {
    fn checkpoint(&mut self, checkpoint: &checkpoint::HistoryCheckpoint) {
        if self.bytes.is_none() {
            self.bytes = Some(checkpoint.to_bytes().unwrap());
        }
    }

    fn should_stop(&mut self) -> bool {
        self.stop && self.bytes.is_some()
    }
}

/// Runs `h` whole, then again until the observer stops it after the first checkpoint, which
/// must be written after `segment` segments; resumes from that checkpoint and checks that the
/// resumed run's records and monitors are the whole run's, to the bit. Returns the whole run,
/// the checkpoint and its bytes.
fn whole_and_resumed_runs_agree(
    model: &StrandModel,
    h: &[LoadSample],
    options: &HistoryOptions,
    segment: usize,
) -> (HistoryResult, checkpoint::HistoryCheckpoint, Vec<u8>) {
    let full = run_history(model, h, options, &mut NoObserver).unwrap();
    let mut stopper = KeepFirst {
        bytes: None,
        stop: true,
    };
    match run_history(model, h, options, &mut stopper) {
        Err(HistoryError::Stopped { segment: s, .. }) if s == segment => {}
        other => panic!(
            "expected a stop after segment {segment}, got {:?}",
            other.map(|r| r.stats)
        ),
    }
    let bytes = stopper.bytes.expect("a checkpoint was written");
    let cp = checkpoint::HistoryCheckpoint::from_bytes(&bytes).unwrap();
    let resumed = run_history_from(model, h, options, Some(&cp), &mut NoObserver).unwrap();
    assert_eq!(resumed.contacts, full.contacts);
    assert_eq!(resumed.monitors, full.monitors);
    // the initialisation's share of the counts: part of the totals, carried by the checkpoint
    let (init, total) = (full.stats.initialisation, &full.stats);
    assert_eq!(resumed.stats.initialisation, init);
    assert!(
        init.newton_steps >= total.initialisation_substeps,
        "{total:?}"
    );
    assert!(init.iterations > 0 && init.iterations < total.iterations);
    assert!(init.evaluations > init.iterations && init.evaluations < total.evaluations);
    assert!(init.linear.solves > 0 && init.linear.solves < total.linear.solves);
    assert!(init.linear.factorisations <= total.linear.factorisations);
    assert!(init.cutbacks <= total.cutbacks);
    (full, cp, bytes)
}

/// Under the contact-mechanics laws each sub-step starts from an earlier one's wire motion,
/// which a checkpoint does not keep: the uninterrupted run forgets it there too.
#[test]
fn a_run_with_the_segment_predictor_resumed_from_its_checkpoint_gives_identical_results() {
    let model = contact_mechanics_model();
    let options = HistoryOptions {
        checkpoint_interval_segments: 2,
        ..HistoryOptions::default()
    };
    let h = bending_cycles(3e-2, 2);
    let (full, _, _) = whole_and_resumed_runs_agree(&model, &h, &options, 2);
    assert!(full.kept_samples.len() >= 5);
}

#[test]
fn a_run_stopped_and_resumed_from_its_checkpoint_gives_identical_results() {
    let model = model();
    let options = HistoryOptions {
        checkpoint_interval_segments: 1,
        ..HistoryOptions::default()
    };
    let h = bending_cycles(3e-2, 1);
    let (full, cp, bytes) = whole_and_resumed_runs_agree(&model, &h, &options, 1);
    assert!(full.kept_samples.len() >= 3);
    // the bare bincode of a checkpoint (the form of the builds before the format header) is
    // refused, not misread
    assert!(matches!(
        checkpoint::HistoryCheckpoint::from_bytes(&bytes[8..]),
        Err(HistoryError::Checkpoint { .. })
    ));
    // a checkpoint of another history is refused
    let other = bending_cycles(3e-2, 2);
    assert!(matches!(
        run_history_from(&model, &other, &options, Some(&cp), &mut NoObserver),
        Err(HistoryError::Checkpoint { .. })
    ));
}

#[test]
fn outer_arc_monitors_sit_on_the_stretched_side_and_neutral_axis_monitors_on_the_axis() {
    use super::monitors::{contact_sites, default_channels, MonitorGroup, MonitorTarget};
    let model = model();
    let sites = contact_sites(&model);
    let channels = default_channels(&model, &sites);
    let length = model.strand.model_length_m;
    // within 20° of the target angle: about one element of the coarsest helix mesh
    let tolerance = PI / 9.0;
    let mut seen = [0; 2];
    for ch in &channels {
        let (s, c) = ch.theta_rad.sin_cos();
        match ch.group {
            MonitorGroup::OuterArc => {
                seen[0] += 1;
                // the stretched side θ ≈ +π/2, never the inner arc
                assert!(s > tolerance.cos(), "{ch:?}");
            }
            MonitorGroup::NeutralAxis => {
                seen[1] += 1;
                assert!(s.abs() < tolerance.sin() && c.abs() > 0.9, "{ch:?}");
            }
            MonitorGroup::Ring => continue,
        }
        assert!((0.0..=length).contains(&ch.z_m), "{ch:?}");
        if let MonitorTarget::Element(e) = ch.target {
            assert!(e < model.mesh.elements.len());
        }
    }
    // contacts (three quantities) of both interfaces and the elements of both helical layers
    assert_eq!(seen, [3 * 2 + 2, 3 * 2 + 2]);
    // the six-wire layer has a wire near either angle close to mid-length
    let layer1_element = channels
        .iter()
        .find(|ch| {
            ch.group == MonitorGroup::OuterArc
                && ch.layer == 0
                && ch.quantity == MonitorQuantity::WireAxialForce
        })
        .unwrap();
    assert!(
        (layer1_element.z_m - 0.5 * length).abs() < length / 6.0,
        "{layer1_element:?}"
    );
}

#[test]
fn strain_is_tension_over_axial_stiffness_at_every_stride_sample() {
    let time_s = [0.0, 0.1, 0.2, 0.3, 0.4];
    let tension_n = [3.6e5, 7.2e5, -1.0e3, 0.0, 3.6e6];
    let curvature_per_m = [0.01, 0.02, 0.03, 0.04, 0.05];
    let (load, slack) = samples_from_tension(
        &time_s,
        &tension_n,
        &curvature_per_m,
        3.6e8,
        2,
        SlackTension::AsZero,
    )
    .unwrap();
    let t: Vec<f64> = load.iter().map(|s| s.time_s).collect();
    assert_eq!(t, vec![0.0, 0.2, 0.4]);
    for (s, expected) in load.iter().zip([1e-3, 0.0, 1e-2]) {
        // one division: within an ulp of the quotient
        assert!(
            (s.strain - expected).abs() <= f64::EPSILON * expected,
            "{}",
            s.strain
        );
    }
    let k: Vec<f64> = load.iter().map(|s| s.curvature_per_m).collect();
    assert_eq!(k, vec![0.01, 0.03, 0.05]);
    assert_eq!(slack, 1);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let tension_n = [3.6e5, bad];
        match samples_from_tension(
            &[0.0, 0.1],
            &tension_n,
            &[0.0; 2],
            3.6e8,
            1,
            SlackTension::AsZero,
        ) {
            Err(HistoryError::InvalidSample { index, field, .. }) => {
                assert_eq!((index, field), (1, "tension_n"), "{bad}")
            }
            other => panic!("tension {bad} accepted: {other:?}"),
        }
    }
}

#[test]
fn a_segment_predictor_recovers_the_wire_motion_beyond_the_plane_sections() {
    use crate::beam::frame::FrameState;
    use crate::beam::rotation::exp_so3;
    use crate::strand::problem::SegmentPredictor;
    use nalgebra::Vector3;
    let model = model();
    let start = FrameState::reference(&model.frame);
    let from = SectionMotion {
        strain: 1e-3,
        curvature_per_m: 0.0,
    };
    let to = SectionMotion {
        strain: 1.2e-3,
        curvature_per_m: 1e-2,
    };
    // the end state: the plane-section motion from `from` to `to`, then a known wire motion
    let mut end = start.clone();
    let extra = |i: usize| {
        let a = i as f64;
        (
            Vector3::new(a.sin(), a.cos(), 0.5) * 1e-7,
            Vector3::new(a.cos(), 0.3, a.sin()) * 1e-5,
        )
    };
    for (i, x) in model.frame.reference_positions().iter().enumerate() {
        let (dx, dtheta) = extra(i);
        end.positions[i] += to.map(x) - from.map(x) + dx;
        end.rotations[i] = exp_so3(&dtheta)
            * to.rotation(x.z)
            * from.rotation(x.z).transpose()
            * start.rotations[i];
    }
    let weights = [1.0 / 5e-4, 1.0 / 5e-3];
    let p = SegmentPredictor::between(&model, &start, &end, from, to, weights);
    let (positions, rotations) = p.wire_motion();
    let mut free = 0;
    for (i, prescribed) in model.prescribed.iter().enumerate() {
        let (dx, dtheta) = extra(i);
        if *prescribed {
            assert_eq!(positions[i], Vector3::zeros());
            continue;
        }
        free += 1;
        // round-off of positions of centimetres and of unit rotations
        assert!(
            (positions[i] - dx).norm() < 1e-15,
            "node {i}: {}",
            positions[i]
        );
        assert!(
            (rotations[i] - dtheta).norm() < 1e-14,
            "node {i}: {}",
            rotations[i]
        );
    }
    assert!(free > 0);
    // the segment that repeats the change gets all of it, the way back its mirror image, a
    // change across it none
    let step = |s: f64, c: f64| SectionMotion {
        strain: to.strain + s,
        curvature_per_m: to.curvature_per_m + c,
    };
    assert!((p.share(&step(2e-4, 1e-2)) - 1.0).abs() < 1e-12);
    assert!((p.share(&from) + 1.0).abs() < 1e-12);
    assert!((p.share(&step(1e-4, 0.5e-2)) - 0.5).abs() < 1e-12);
    // never more than the earlier change
    assert_eq!(p.share(&step(6e-4, 3e-2)), 1.0);
    assert!(
        p.share(&step(
            1e-2 * weights[1] / weights[0],
            -2e-4 * weights[0] / weights[1]
        ))
        .abs()
            < 1e-12
    );
}

#[test]
fn the_segment_predictor_under_cattaneo_mindlin_saves_iterations_and_keeps_the_slips() {
    let model = contact_mechanics_model();
    assert!(model.predicts_from_last_segment());
    assert!(!self::model().predicts_from_last_segment());
    let h = bending_cycles(3e-2, 2);
    let run = |predictor: Option<bool>| {
        let options = HistoryOptions {
            segment_predictor: predictor,
            ..HistoryOptions::default()
        };
        run_history(&model, &h, &options, &mut NoObserver).unwrap()
    };
    let (with, without) = (run(None), run(Some(false)));
    let largest = largest_slip_range;
    let worst = largest_slip_range_difference(&with, &without);
    eprintln!(
        "largest slip range {:.4e} m (with) {:.4e} m (without); largest difference {worst:.3e} m; \
         Newton iterations {} against {}",
        largest(&with),
        largest(&without),
        with.stats.iterations,
        without.stats.iterations
    );
    // both converged to 0.01 N: the slips agree to a ten-thousandth of the largest
    assert!(largest(&without) > 1e-6);
    assert!(worst < 1e-4 * largest(&without), "{worst}");
    assert!(with.stats.iterations < without.stats.iterations);
}

/// The sliding stiffness of the Newton iteration matrix changes the path of the iterations,
/// not where they end: under Cattaneo–Mindlin the slips of a run with it agree with those of
/// the consistent tangent's run to a ten-thousandth of the largest (both converge every
/// sub-step to 0.01 N); under the regularised laws it is not used, and the runs agree to the bit.
#[test]
fn the_sliding_stiffness_keeps_the_slips_and_leaves_the_regularised_laws_alone() {
    // large enough for gross slip of the outer wires (24 µm slip ranges)
    let h = bending_cycles(0.06, 2);
    let run = |model: &StrandModel, sliding_stiffness: f64| {
        let options = HistoryOptions {
            sliding_stiffness,
            ..HistoryOptions::default()
        };
        run_history(model, &h, &options, &mut NoObserver).unwrap()
    };
    let cm = contact_mechanics_model();
    let (with, without) = (run(&cm, 0.1), run(&cm, 0.0));
    let largest = largest_slip_range(&without);
    let worst = largest_slip_range_difference(&with, &without);
    eprintln!(
        "largest slip range {largest:.4e} m; largest difference {worst:.3e} m; Newton \
         iterations {} with, {} without",
        with.stats.iterations, without.stats.iterations
    );
    assert!(largest > 1e-6);
    assert!(worst < 1e-4 * largest, "{worst}");
    let regularised = model();
    let (with, without) = (run(&regularised, 0.1), run(&regularised, 0.0));
    assert_eq!(with.contacts, without.contacts);
    assert_eq!(with.monitors, without.monitors);
    assert_eq!(with.stats.iterations, without.stats.iterations);
    // refused when negative or not finite, naming the field
    for bad in [-0.1, f64::NAN] {
        let options = HistoryOptions {
            sliding_stiffness: bad,
            ..HistoryOptions::default()
        };
        let err = run_history(&regularised, &h, &options, &mut NoObserver).unwrap_err();
        assert!(err.to_string().contains("sliding_stiffness"), "{err}");
    }
}

/// The largest slip range of any contact of a run (m).
fn largest_slip_range(r: &HistoryResult) -> f64 {
    r.contacts
        .iter()
        .map(|c| c.max_slip_range_m())
        .fold(0.0, f64::max)
}

/// The largest difference of a contact's largest slip range between two runs of one model (m).
fn largest_slip_range_difference(a: &HistoryResult, b: &HistoryResult) -> f64 {
    a.contacts
        .iter()
        .zip(&b.contacts)
        .map(|(x, y)| (x.max_slip_range_m() - y.max_slip_range_m()).abs())
        .fold(0.0, f64::max)
}
