//! Verification of the strand geometry: profile validation, exact helices, contact detection and
//! counts, mesh counts, and Costello's analytical 1+6 strand in tension.

use std::f64::consts::PI;

use moorfret_solver::strand::analytical::{
    slip_onset_curvature, stick_force_variation, SimpleStrand,
};
use moorfret_solver::strand::contacts::{find_contacts, ContactKind, ContactSearchParameters};
use moorfret_solver::strand::mesh::{build_mesh, MeshParameters};
use moorfret_solver::strand::profile::{
    profile_from_json, profiles_from_json, ProfileError, Strand, StrandProfile,
};

const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));
const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

fn profile(name: &str) -> StrandProfile {
    profiles_from_json(PROFILES).unwrap().remove(name).unwrap()
}

fn strand(name: &str) -> Strand {
    profile(name).validate().unwrap()
}

fn derived() -> serde_json::Value {
    let v: serde_json::Value = serde_json::from_str(PROFILES).unwrap();
    v["paper_six_layer"]["_derived_for_checking"].clone()
}

#[test]
fn paper_profile_reproduces_its_lay_lengths_diameter_and_lateral_clearances() {
    let s = strand("paper_six_layer");
    let d = derived();
    assert!((s.outer_diameter_m() - d["outer_diameter_m"].as_f64().unwrap()).abs() < 1e-12);
    for (k, l) in s.layers.iter().enumerate() {
        // The file rounds lay lengths to 0.1 mm from lay angles given to 0.01°.
        let lay = d["lay_lengths_m"][k].as_f64().unwrap();
        assert!(
            (l.lay_length_m / lay - 1.0).abs() < 3e-4,
            "layer {k}: {} vs {lay}",
            l.lay_length_m
        );
        // Clearances are quoted to 0.01 mm.
        let c = d["min_lateral_clearance_m"][k].as_f64().unwrap();
        assert!(
            (l.lateral_clearance_m - c).abs() <= 5e-6,
            "layer {k}: {} vs {c}",
            l.lateral_clearance_m
        );
    }
}

#[test]
fn paper_strand_has_7269_trellis_contacts_as_the_crossing_count_predicts() {
    let s = strand("paper_six_layer");
    let c = find_contacts(&s, &ContactSearchParameters::default()).unwrap();
    let found: Vec<usize> = c.interfaces.iter().map(|i| i.contacts).collect();
    assert_eq!(found, vec![620, 562, 1036, 1484, 1903, 2284]);
    assert_eq!(c.count(ContactKind::Trellis), 7269);
    assert_eq!(c.count(ContactKind::SameHandCrossing), 0);
    let predicted: f64 = c
        .interfaces
        .iter()
        .filter(|i| i.kind == ContactKind::Trellis)
        .map(|i| i.predicted)
        .sum();
    let quoted = derived()["approx_trellis_contacts_over_model_length"]
        .as_f64()
        .unwrap();
    assert!(
        (predicted - quoted).abs() < 0.5,
        "predicted {predicted} vs {quoted}"
    );
    for i in c
        .interfaces
        .iter()
        .filter(|i| i.kind == ContactKind::Trellis)
    {
        // Each wire pair contributes floor or ceil of its share of the crossings.
        assert!((i.contacts as f64 - i.predicted).abs() < 1.0, "{i:?}");
    }
}

#[test]
fn contact_points_lie_on_both_helices_at_the_sum_of_the_radii() {
    for s in [
        strand("paper_six_layer"),
        profile_from_json(BENCHMARK).unwrap().validate().unwrap(),
    ] {
        let wires = s.wires();
        let c = find_contacts(&s, &ContactSearchParameters::default()).unwrap();
        for p in &c.contacts {
            let (a, b) = (&wires[p.inner.0], &wires[p.outer.0]);
            assert!((a.helix.position(p.z_m) - p.inner_position).norm() < 1e-15);
            assert!((b.helix.position(p.z_m) - p.outer_position).norm() < 1e-15);
            let seg = p.outer_position - p.inner_position;
            let gap = seg.norm() - (a.radius_m + b.radius_m);
            assert!(gap.abs() < 1e-15, "{p:?}: gap {gap:e}");
            // Common perpendicular: the points are the closest points of the two axes.
            let u = seg.normalize();
            assert!(u.dot(&a.helix.tangent(p.z_m)).abs() < 1e-12);
            assert!(u.dot(&b.helix.tangent(p.z_m)).abs() < 1e-12);
            assert!(p.z_m >= 0.0 && p.z_m < s.model_length_m);
        }
    }
}

#[test]
fn outer_helix_of_the_benchmark_crosses_the_six_wire_layer_18_times() {
    let s = profile_from_json(BENCHMARK).unwrap().validate().unwrap();
    let c = find_contacts(&s, &ContactSearchParameters::default()).unwrap();
    let trellis: Vec<_> = c
        .contacts
        .iter()
        .filter(|p| p.kind == ContactKind::Trellis)
        .collect();
    assert_eq!(trellis.len(), 18);
    // Opposite hands at 12°: crossing angle 24°.
    for p in &trellis {
        assert!(
            (p.crossing_angle_rad - 24f64.to_radians()).abs() < 1e-3,
            "{}",
            p.crossing_angle_rad.to_degrees()
        );
    }
    // The outer helix starts at the outer arc (θ = π/2) on top of inner wire 0.
    let first = trellis
        .iter()
        .min_by(|a, b| a.z_m.total_cmp(&b.z_m))
        .unwrap();
    assert!(first.z_m.abs() < 1e-15 && (first.theta_rad - 0.5 * PI).abs() < 1e-12);
    assert_eq!(c.count(ContactKind::CoreLine), 312);
}

#[test]
fn profile_validation_names_the_offending_field() {
    let base = profile("paper_six_layer");
    // Too many wires in the first layer: neighbours overlap.
    let mut p = base.clone();
    p.layers.as_mut().unwrap()[0].wires = Some(7);
    match p.validate() {
        Err(ProfileError::LateralOverlap {
            layer: 0,
            wires: 7,
            overlap_m,
            ..
        }) => assert!(overlap_m > 0.0),
        other => panic!("{other:?}"),
    }
    // Zero lay angle.
    let mut p = base.clone();
    p.layers.as_mut().unwrap()[3].lay_angle_deg = Some(0.0);
    match p.validate() {
        Err(ProfileError::InvalidValue { field, .. }) => {
            assert_eq!(field, "layers[3].lay_angle_deg")
        }
        other => panic!("{other:?}"),
    }
    // Missing layer field.
    let mut p = base.clone();
    p.layers.as_mut().unwrap()[2].wire_radius_m = None;
    assert_eq!(
        p.validate(),
        Err(ProfileError::MissingField {
            field: "layers[2].wire_radius_m".into()
        })
    );
    // Inconsistent radial stacking.
    let mut p = base.clone();
    p.layers.as_mut().unwrap()[1].helix_radius_m = Some(9.6e-3);
    match p.validate() {
        Err(ProfileError::Stacking {
            layer: 1,
            expected_m,
            ..
        }) => assert!((expected_m - 9.5e-3).abs() < 1e-12),
        other => panic!("{other:?}"),
    }
    // Omitted helix radius is computed from stacking; lay length may replace the angle.
    let mut p = base.clone();
    let l = &mut p.layers.as_mut().unwrap()[4];
    l.helix_radius_m = None;
    l.lay_angle_deg = None;
    l.lay_length_m = Some(0.4643);
    let s = p.validate().unwrap();
    assert!((s.layers[4].helix_radius_m - 23.3e-3).abs() < 1e-12);
    assert!((s.layers[4].lay_angle_rad.to_degrees() - 17.5).abs() < 0.01);
    // Unknown keys are rejected.
    assert!(matches!(
        profile_from_json(r#"{"core_wire_radius": 1e-3}"#),
        Err(ProfileError::Json { .. })
    ));
}

#[test]
fn seed_benchmark_wires_overlap_laterally_unless_the_overlap_is_accepted() {
    // Equal wires on R = 2r: the six helical wires overlap by ≈ 72 µm at 12°.
    match profile("benchmark_1_6_1").validate() {
        Err(ProfileError::LateralOverlap {
            layer: 0,
            wires: 6,
            overlap_m,
            ..
        }) => {
            assert!((overlap_m - 71.8e-6).abs() < 0.1e-6, "{overlap_m}")
        }
        other => panic!("{other:?}"),
    }
    let s = profile_from_json(BENCHMARK).unwrap().validate().unwrap();
    assert!(s.layers[0].lateral_clearance_m < 0.0);
    assert!(s.layers[1].lateral_clearance_m.is_infinite());
}

#[test]
fn mesh_puts_nodes_on_every_contact_and_keeps_elements_short() {
    let s = strand("paper_six_layer");
    let c = find_contacts(&s, &ContactSearchParameters::default()).unwrap();
    let params = MeshParameters::default();
    let m = build_mesh(&s, &c, &params).unwrap();
    assert_eq!(
        (
            m.stats.wires,
            m.stats.nodes,
            m.stats.elements,
            m.stats.contacts
        ),
        (121, 15353, 15232, 7889)
    );
    assert_eq!(m.stats.merged_points, 654);
    assert!(m.stats.max_element_length_m <= params.max_element_length_m);
    assert_eq!(m.elements.len(), m.nodes.len() - 121);
    for mc in &m.contacts {
        let p = &c.contacts[mc.id.0];
        assert_eq!(m.nodes[mc.nodes[0].0].wire, p.inner);
        assert_eq!(m.nodes[mc.nodes[1].0].wire, p.outer);
        assert!(mc.offset_m <= params.merge_tolerance_m);
    }
    let b = profile_from_json(BENCHMARK).unwrap().validate().unwrap();
    let cb = find_contacts(&b, &ContactSearchParameters::default()).unwrap();
    let mb = build_mesh(&b, &cb, &params).unwrap();
    assert_eq!(
        (
            mb.stats.nodes,
            mb.stats.elements,
            mb.stats.contacts,
            mb.stats.trellis_contacts
        ),
        (424, 416, 330, 18)
    );
}

#[test]
fn costello_simple_strand_in_tension_gives_the_published_forces() {
    // 1+6, r = 2.15 mm, 12°, E = 210 GPa, ν = 0.3, ε = 1e-3: F ≈ 19.95 kN, T₂ ≈ 2879 N
    // (`docs/verification.md`).
    let strand = SimpleStrand {
        core_radius_m: 2.15e-3,
        wire_radius_m: 2.15e-3,
        wires: 6,
        lay_angle_rad: 12f64.to_radians(),
        young_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };
    let r = strand.axial_response(1e-3);
    assert!(
        (r.wire_tension_n - 2879.0).abs() < 1.0,
        "T2 = {}",
        r.wire_tension_n
    );
    assert!(
        (r.strand_force_n - 19950.0).abs() < 5.0,
        "F = {}",
        r.strand_force_n
    );
    // Bending and twisting of the wires contribute a few newtons only.
    assert!(r.wire_shear_force_n.abs() < 5.0);
    // Without Poisson contraction the wire strain is ε cos²β exactly.
    let r0 = SimpleStrand {
        poisson_ratio: 0.0,
        ..strand
    }
    .axial_response(1e-3);
    assert!((r0.wire_strain - 1e-3 * 12f64.to_radians().cos().powi(2)).abs() < 1e-15);
    // Linear in the strain.
    let r2 = strand.axial_response(2e-3);
    assert!((r2.strand_force_n / r.strand_force_n - 2.0).abs() < 1e-12);
}

#[test]
fn benchmark_curvatures_bracket_the_slip_onset_of_the_outer_helix() {
    let b = profile_from_json(BENCHMARK).unwrap();
    let s = b.validate().unwrap();
    let outer = s.layers[1];
    let ea = 210e9 * PI * outer.wire_radius_m.powi(2);
    let strain = b.loading.as_ref().unwrap().axial_strain;
    let tension = ea * strain * outer.lay_angle_rad.cos().powi(2);
    let kb = slip_onset_curvature(0.5, outer.lay_angle_rad, tension, ea, outer.helix_radius_m);
    let curvatures = &b.loading.as_ref().unwrap().curvatures_per_m;
    assert!(curvatures[0] < kb && kb < curvatures[1], "kappa_b = {kb}");
    // At the onset the stick force variation at the neutral axis reaches μ sin β T.
    let df = stick_force_variation(ea, outer.lay_angle_rad, outer.helix_radius_m, kb, 0.5 * PI);
    assert!((df - 0.5 * outer.lay_angle_rad.sin() * tension).abs() < 1e-9 * df);
}
