//! The strand FE model on the 1+6+1 benchmark of the seed's Sec. 2.2 (DESIGN §6): the 1+6
//! strand in tension against Costello's simple straight strand, and the outer helix of the
//! 1+6+1 strand in bending against the stick and friction-limited slip solutions.

use moorfret_solver::contact::{ContactParameters, NormalLaw, TangentialLaw};
use moorfret_solver::strand::analytical::SimpleStrand;
use moorfret_solver::strand::driver::{run_case, StrandRunParameters};
use moorfret_solver::strand::model::{StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::{profile_from_json, Strand};

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn benchmark(layers: usize) -> Strand {
    let mut profile = profile_from_json(BENCHMARK).expect("benchmark profile parses");
    if let Some(l) = profile.layers.as_mut() {
        l.truncate(layers);
    }
    profile.validate().expect("benchmark profile is valid")
}

/// The seed's 'vs_analytical' regularisation: ε_N = 2e5 N/mm, γ_e = 1e-4 mm.
fn vs_analytical() -> StrandModelParameters {
    StrandModelParameters {
        contact: ContactParameters {
            normal: NormalLaw::Penalty {
                stiffness_n_per_m: 2e8,
            },
            tangential: TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-7,
            },
            ..ContactParameters::default()
        },
        ..StrandModelParameters::default()
    }
}

#[test]
fn one_plus_six_strand_in_tension_matches_costello() {
    let strand = benchmark(1);
    let model = StrandModel::new(&strand, &vs_analytical()).unwrap();
    let result = run_case(&model, 1e-3, 0.0, &StrandRunParameters::default()).unwrap();
    let layer = &strand.layers[0];
    let costello = SimpleStrand {
        core_radius_m: strand.core_wire_radius_m,
        wire_radius_m: layer.wire_radius_m,
        wires: layer.wires,
        lay_angle_rad: layer.lay_angle_rad,
        young_modulus_pa: strand.young_modulus_pa,
        poisson_ratio: strand.poisson_ratio,
    }
    .axial_response(1e-3);
    // mean helical wire tension at mid-length
    let mid = 0.5 * strand.model_length_m;
    let helical: Vec<f64> = result
        .element_forces
        .iter()
        .filter(|f| f.wire.0 > 0 && (f.z_m - mid).abs() < 0.02)
        .map(|f| f.axial_force_n)
        .collect();
    let wire_tension = helical.iter().sum::<f64>() / helical.len() as f64;
    let e_wire = (wire_tension - costello.wire_tension_n) / costello.wire_tension_n;
    let e_strand = (result.strand_force_n - costello.strand_force_n) / costello.strand_force_n;
    eprintln!(
        "1+6 tension: wire {wire_tension:.1} N vs {:.1} N ({:+.3} %), strand {:.1} N vs {:.1} N ({:+.3} %), {:?}",
        costello.wire_tension_n,
        100.0 * e_wire,
        result.strand_force_n,
        costello.strand_force_n,
        100.0 * e_strand,
        result.stats.step_iterations
    );
    assert!(e_wire.abs() < 0.02);
    assert!(e_strand.abs() < 0.02);
}
