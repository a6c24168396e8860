//! Verification of the strip-theory floater against hand formulas and the published OC4
//! DeepCwind values (Robertson et al. 2014, NREL/TP-5000-60601) quoted in
//! `campaigns/data/oc4_semi_floater.json`.

use moorfret_solver::floater::dynamics::{
    integrate, static_equilibrium, IntegratorParams, LinearMooring,
};
use moorfret_solver::floater::prescribed::{PrescribedMotion, COLUMNS};
use moorfret_solver::floater::{
    fairlead_body_points, BodyState, Floater, FloaterSpec, JacobianSteps,
};
use moorfret_solver::waves::{FluidKinematics, SeaKinematics, StillWater};
use nalgebra::{Matrix6, Vector3, Vector6};
use std::f64::consts::PI;

const OC4: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/oc4_semi_floater.json"
));
const G: f64 = 9.80665;
const RHO: f64 = 1025.0;

fn oc4_spec() -> FloaterSpec {
    FloaterSpec::from_json_str(OC4).unwrap()
}

fn oc4() -> Floater {
    Floater::from_spec(&oc4_spec()).unwrap()
}

/// Linear deep-water Airy wave along +x, kinematics evaluated up to the still water level
/// (linear theory: the free surface is taken at z = 0 for the wetted length).
struct DeepRegularWave {
    amplitude_m: f64,
    omega: f64,
    k: f64,
}

impl DeepRegularWave {
    fn new(height_m: f64, period_s: f64) -> Self {
        let omega = 2.0 * PI / period_s;
        Self {
            amplitude_m: 0.5 * height_m,
            omega,
            k: omega * omega / G,
        }
    }
}

impl SeaKinematics for DeepRegularWave {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        if x.z > 0.0 {
            return FluidKinematics::default();
        }
        let (a, w, k) = (self.amplitude_m, self.omega, self.k);
        let ph = k * x.x - w * t;
        let decay = (k * x.z).exp();
        FluidKinematics {
            velocity: Vector3::new(w * a * decay * ph.cos(), 0.0, w * a * decay * ph.sin()),
            acceleration: Vector3::new(
                w * w * a * decay * ph.sin(),
                0.0,
                -w * w * a * decay * ph.cos(),
            ),
            dynamic_pressure_pa: RHO * G * a * decay * ph.cos(),
        }
    }
    fn elevation(&self, _x: f64, _y: f64, _t: f64) -> f64 {
        0.0
    }
}

/// OC4 catenary moorings linearised about the undisplaced position (diagonal terms as commonly
/// quoted from Robertson et al. 2014; the surge–pitch coupling is neglected).
fn oc4_mooring(vertical_pretension_n: f64) -> LinearMooring {
    let stiffness = Matrix6::from_diagonal(&Vector6::new(
        7.08e4, 7.08e4, 1.91e4, 8.73e7, 8.73e7, 1.17e8,
    ));
    LinearMooring {
        stiffness,
        preload: Vector6::new(0.0, 0.0, -vertical_pretension_n, 0.0, 0.0, 0.0),
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b) / b
}

#[test]
fn oc4_displaced_volume_and_hydrostatic_stiffness_match_the_published_values() {
    let spec = oc4_spec();
    let f = oc4();
    let h = f.hydrostatics();
    let refs = spec.reference_values_for_checking.clone().unwrap();
    let e_v = rel(h.volume_m3, spec.displaced_volume_m3);
    let c = f.restoring_matrix();
    let e_c33 = rel(c[(2, 2)], refs.hydrostatic_heave_stiffness_n_per_m);
    let mp = f.mass_properties();
    let c55_no_gravity = c[(4, 4)] + mp.mass_kg * G * mp.centre_of_mass_m.z;
    let e_c55 = rel(
        c55_no_gravity,
        refs.hydrostatic_roll_pitch_stiffness_nm_per_rad_without_gravity_terms,
    );
    println!("V = {:.1} m3 ({:+.3} %), C33 = {:.4e} N/m ({:+.2} %), C55 w/o gravity = {:.4e} N m/rad ({:+.2} %)", h.volume_m3, 100.0 * e_v, c[(2, 2)], 100.0 * e_c33, c55_no_gravity, 100.0 * e_c55);
    // Geometry from the OC4 joints reproduces the WAMIT volume to 0.02 %.
    assert!(e_v.abs() < 5e-4, "volume error {e_v}");
    // Waterplane: three 12 m columns, the 6.5 m main column and the three cross braces cut
    // obliquely; −0.40 % against the quoted 3.836e6 N/m (WAMIT panel value).
    assert!(e_c33.abs() < 6e-3, "heave stiffness error {e_c33}");
    // ρg(∫x²dA + V z_B): a difference of two large terms, hence the looser bound.
    assert!(e_c55.abs() < 3e-2, "pitch stiffness error {e_c55}");
}

#[test]
fn neutral_body_in_still_water_at_rest_has_zero_load() {
    let mut spec = oc4_spec();
    spec.attached_masses.clear();
    let probe = Floater::from_spec(&spec).unwrap();
    let h = *probe.hydrostatics();
    // Mass equal to the displaced water, centre of mass on the vertical of the centre of buoyancy.
    spec.mass_kg = RHO * h.volume_m3;
    spec.centre_of_mass_m = [h.centre_of_buoyancy_m.x, h.centre_of_buoyancy_m.y, -10.0];
    let f = Floater::from_spec(&spec).unwrap();
    let loads = f.loads(&BodyState::at_rest(), &StillWater, 0.0, 0.0);
    let weight = spec.mass_kg * G;
    let total = loads.total();
    assert!(total.fixed_rows::<3>(0).norm() < 1e-9 * weight, "{total}");
    assert!(
        total.fixed_rows::<3>(3).norm() < 1e-9 * weight * 30.0,
        "{total}"
    );
    assert_eq!(loads.wave_inertia, Vector6::zeros());
    assert_eq!(loads.drag, Vector6::zeros());
}

#[test]
fn static_equilibrium_at_the_design_draft_balances_weight_buoyancy_and_pretension() {
    let f = oc4();
    let buoyancy = RHO * G * f.hydrostatics().volume_m3;
    let weight = f.mass_properties().mass_kg * G;
    // Vertical mooring pull that keeps the OC4 system at its 20 m draft.
    let pretension = buoyancy - weight;
    println!(
        "system mass {:.4e} kg, buoyancy {:.4e} N, implied vertical mooring pretension {:.4e} N",
        f.mass_properties().mass_kg,
        buoyancy,
        pretension
    );
    assert!(pretension > 1.5e6 && pretension < 2.3e6, "{pretension}");
    let (eq, iterations) = static_equilibrium(
        &f,
        &oc4_mooring(pretension),
        0.0,
        &BodyState::at_rest(),
        1e-12,
        20,
    )
    .unwrap();
    assert!(
        eq.position_m.z.abs() < 1e-4,
        "heave at equilibrium {}",
        eq.position_m.z
    );
    assert!(iterations <= 4, "{iterations} Newton iterations");
    // 100 kN more pull sinks the platform by ΔF / (ρgA_wp + K33) (linear waterplane).
    let extra = 1.0e5;
    let (eq2, _) = static_equilibrium(
        &f,
        &oc4_mooring(pretension + extra),
        0.0,
        &BodyState::at_rest(),
        1e-12,
        20,
    )
    .unwrap();
    let expected = -extra / (f.restoring_matrix()[(2, 2)] + 1.91e4);
    assert!(
        rel(eq2.position_m.z, expected).abs() < 1e-3,
        "{} vs {expected}",
        eq2.position_m.z
    );
}

#[test]
fn position_jacobian_equals_minus_the_linear_restoring_matrix() {
    let f = oc4();
    let jac = f.load_jacobians(&BodyState::at_rest(), &StillWater, 0.0, 0.0);
    let c = f.restoring_matrix();
    let scale = [
        c[(2, 2)],
        c[(2, 2)],
        c[(2, 2)],
        c[(3, 3)],
        c[(3, 3)],
        c[(3, 3)],
    ];
    for i in 0..6 {
        for j in 0..6 {
            let s = (scale[i] * scale[j]).sqrt();
            assert!(
                (jac.position[(i, j)] + c[(i, j)]).abs() < 1e-6 * s,
                "({i},{j}): {} vs {}",
                jac.position[(i, j)],
                -c[(i, j)]
            );
        }
    }
}

#[test]
fn velocity_jacobian_matches_central_differences_in_a_regular_wave() {
    let mut spec = oc4_spec();
    let mut b = [[0.0; 6]; 6];
    b[0][0] = 1.0e5;
    b[4][4] = 2.0e8;
    b[0][4] = -3.0e6;
    spec.linear_damping = Some(b);
    let f = Floater::from_spec(&spec).unwrap();
    let sea = DeepRegularWave::new(6.0, 10.0);
    let mut state = BodyState::at_rest();
    state.position_m = Vector3::new(1.5, -0.4, -0.3);
    state.rotation = moorfret_solver::beam::rotation::exp_so3(&Vector3::new(0.01, 0.04, -0.02));
    state.velocity_m_per_s = Vector3::new(0.6, -0.2, 0.3);
    state.angular_velocity_rad_per_s = Vector3::new(0.01, -0.03, 0.02);
    let t = 3.7;
    let jac = f.load_jacobians(&state, &sea, t, 5.0e5).velocity;
    let steps = [1e-6, 1e-6, 1e-6, 1e-8, 1e-8, 1e-8];
    for (j, h) in steps.iter().enumerate() {
        let shift = |sign: f64| {
            let mut s = state;
            if j < 3 {
                s.velocity_m_per_s[j] += sign * h;
            } else {
                s.angular_velocity_rad_per_s[j - 3] += sign * h;
            }
            f.net_forces(&s, &sea, t, 5.0e5)
        };
        let fd = (shift(1.0) - shift(-1.0)) / (2.0 * h);
        let err = (fd - jac.column(j)).norm();
        assert!(
            err < 1e-5 * jac.column(j).norm().max(1e3),
            "column {j}: fd {fd} vs analytic {}",
            jac.column(j)
        );
    }
}

/// One surface-piercing vertical cylinder from z = −depth to +5 m, bottom face exposed.
fn pile(d: f64, depth: f64, cd: f64, ca: f64) -> Floater {
    let area = PI * d * d / 4.0;
    let text = format!(
        r#"{{"mass_kg": 1.0e5, "centre_of_mass_m": [0, 0, -20], "inertia_about_com_kg_m2": {{"roll": 1e6, "pitch": 1e6, "yaw": 1e5}},
            "displaced_volume_m3": {vol}, "strip_length_m": 0.5,
            "members": [{{"name": "pile", "diameter_m": {d}, "from_m": [0, 0, -{depth}], "to_m": [0, 0, 5],
                          "drag_coefficient": {cd}, "added_mass_coefficient": {ca}, "end_pressure_areas_m2": [{area}, 0]}}]}}"#,
        vol = area * depth
    );
    Floater::from_spec(&FloaterSpec::from_json_str(&text).unwrap()).unwrap()
}

#[test]
fn maccamy_fuchs_scales_the_inertia_of_a_large_pile() {
    // D = 20 m in 8 s deep-water waves: ka = 0.63, C_M = 1.86 instead of 2.
    let (d, depth) = (20.0, 30.0);
    let sea = DeepRegularWave::new(2.0, 8.0);
    let plain = pile(d, depth, 0.0, 1.0);
    let corrected = pile(d, depth, 0.0, 1.0)
        .with_maccamy_fuchs(8.0, 1.0e4)
        .unwrap();
    let cm = moorfret_solver::floater::diffraction::inertia_coefficient(0.5 * sea.k * d);
    let t = 1.3;
    let a = plain
        .loads(&BodyState::at_rest(), &sea, t, 0.0)
        .wave_inertia[0];
    let b = corrected
        .loads(&BodyState::at_rest(), &sea, t, 0.0)
        .wave_inertia[0];
    println!("ka = {:.3}, C_M = {cm:.4}", 0.5 * sea.k * d);
    assert!(cm > 1.7 && cm < 1.95, "{cm}");
    assert!(
        (b - a * cm / 2.0).abs() < 1e-9 * a.abs(),
        "{b} vs {}",
        a * cm / 2.0
    );
}

#[test]
fn morison_force_on_a_fixed_vertical_cylinder_matches_the_hand_formula() {
    // One surface-piercing cylinder, D = 2 m, bottom at 30 m, Cd = 1, Ca = 1, bottom face exposed.
    let (d, depth, cd, ca) = (2.0, 30.0, 1.0, 1.0);
    let area = PI * d * d / 4.0;
    let f = pile(d, depth, cd, ca);
    let sea = DeepRegularWave::new(4.0, 9.0);
    let (a, w, k) = (sea.amplitude_m, sea.omega, sea.k);
    let decay1 = (1.0 - (-k * depth).exp()) / k; // ∫ e^{kz} dz over [−d, 0]
    let decay2 = (1.0 - (-2.0 * k * depth).exp()) / (2.0 * k); // ∫ e^{2kz} dz
    let zdecay1 = -1.0 / (k * k) + (-k * depth).exp() * (depth / k + 1.0 / (k * k)); // ∫ z e^{kz} dz
    let inertia_amp = RHO * (1.0 + ca) * area * w * w * a * decay1;
    let drag_amp = 0.5 * RHO * cd * d * w * w * a * a * decay2;
    let mut worst: f64 = 0.0;
    for n in 0..16 {
        let t = n as f64 * 9.0 / 16.0;
        let ph = -w * t;
        let loads = f.loads(&BodyState::at_rest(), &sea, t, 0.0);
        let fx_inertia = inertia_amp * ph.sin();
        let fx_drag = drag_amp * ph.cos().abs() * ph.cos();
        let my_inertia = RHO * (1.0 + ca) * area * w * w * a * zdecay1 * ph.sin();
        let fz_pressure = RHO * G * a * (-k * depth).exp() * ph.cos() * area;
        let errs = [
            (loads.wave_inertia[0] - fx_inertia) / inertia_amp,
            (loads.drag[0] - fx_drag) / drag_amp,
            (loads.wave_inertia[4] - my_inertia) / (inertia_amp * depth),
            (loads.wave_inertia[2] - fz_pressure) / (RHO * G * a * area),
        ];
        for e in errs {
            worst = worst.max(e.abs());
        }
    }
    println!("Morison on a fixed pile: worst relative error {worst:.2e} (inertia amplitude {inertia_amp:.4e} N, drag amplitude {drag_amp:.4e} N)");
    // Midpoint rule on 0.5 m strips: error ≈ (k Δz)²/24 ≈ 2e-4.
    assert!(worst < 1e-3, "{worst}");
}

#[test]
fn oc4_strip_theory_added_mass_against_the_low_frequency_potential_flow_values() {
    let spec = oc4_spec();
    let f = oc4();
    let a = f.added_mass_body();
    let r = spec
        .reference_values_for_checking
        .unwrap()
        .low_frequency_added_mass;
    let (e11, e33, e55) = (
        rel(a[(0, 0)], r.surge_sway_kg),
        rel(a[(2, 2)], r.heave_kg),
        rel(a[(4, 4)], r.roll_pitch_kg_m2),
    );
    println!(
        "A11 = {:.4e} ({:+.1} %), A33 = {:.4e} ({:+.1} %), A55 = {:.4e} ({:+.1} %)",
        a[(0, 0)],
        100.0 * e11,
        a[(2, 2)],
        100.0 * e33,
        a[(4, 4)],
        100.0 * e55
    );
    // Surge: the base columns' transverse Ca is set from this value (see the data file).
    assert!(e11.abs() < 5e-3, "{e11}");
    // Heave: disc added mass of the three heave plates plus the submerged pontoons: −1.6 %.
    assert!(e33.abs() < 3e-2, "{e33}");
    // Pitch: heave plates at the column radius dominate; strip theory gives −8 %.
    assert!(e55.abs() < 0.12, "{e55}");
    // Three-fold symmetry makes the horizontal added mass isotropic, up to the 5-digit rounding
    // of the pontoon coordinates (about 2e-6 here).
    assert!(
        (a[(0, 0)] - a[(1, 1)]).abs() < 1e-5 * a[(0, 0)],
        "surge and sway added mass differ: {} vs {}",
        a[(0, 0)],
        a[(1, 1)]
    );
}

/// Mean period between successive upward zero crossings of `x − mean`.
fn crossing_period(series: &[(f64, f64)], x_eq: f64) -> (f64, usize) {
    let mut ups = Vec::new();
    for w in series.windows(2) {
        let (t0, x0) = (w[0].0, w[0].1 - x_eq);
        let (t1, x1) = (w[1].0, w[1].1 - x_eq);
        if x0 < 0.0 && x1 >= 0.0 {
            ups.push(t0 + (t1 - t0) * (-x0) / (x1 - x0));
        }
    }
    let n = ups.len().saturating_sub(1);
    ((ups[ups.len() - 1] - ups[0]) / n as f64, n)
}

fn decay_period(dof: usize, offset: f64, duration_s: f64, dt: f64) -> (f64, f64) {
    let f = oc4();
    let buoyancy = RHO * G * f.hydrostatics().volume_m3;
    let pretension = buoyancy - f.mass_properties().mass_kg * G;
    let mooring = oc4_mooring(pretension);
    let (eq, _) = static_equilibrium(&f, &mooring, 0.0, &BodyState::at_rest(), 1e-12, 20).unwrap();
    let value = |s: &BodyState| {
        if dof < 3 {
            s.position_m[dof]
        } else {
            moorfret_solver::beam::rotation::log_so3(&s.rotation)[dof - 3]
        }
    };
    let x_eq = value(&eq);
    let mut start = eq;
    if dof < 3 {
        start.position_m[dof] += offset;
    } else {
        let mut th = Vector3::zeros();
        th[dof - 3] = offset;
        start.rotation = moorfret_solver::beam::rotation::exp_so3(&th) * eq.rotation;
    }
    let mut series = Vec::new();
    let params = IntegratorParams {
        time_step_s: dt,
        ..IntegratorParams::default()
    };
    let stats = integrate(
        &f,
        &mooring,
        &StillWater,
        0.0,
        &start,
        duration_s,
        &params,
        |t, s| series.push((t, value(s))),
    )
    .unwrap();
    assert!(stats.newton_iterations <= 4 * stats.steps, "{stats:?}");
    let (period, cycles) = crossing_period(&series, x_eq);
    assert!(cycles >= 2, "only {cycles} cycles");
    // Undamped estimate from the model's own matrices for the same DOF (uncoupled).
    let m = f.mass_matrix(&eq);
    let k = f.restoring_matrix() + mooring.stiffness;
    (period, 2.0 * PI * (m[(dof, dof)] / k[(dof, dof)]).sqrt())
}

#[test]
fn heave_free_decay_period_matches_the_oc4_value() {
    let (t, t_lin) = decay_period(2, 0.3, 70.0, 0.1);
    let reference = oc4_spec()
        .reference_values_for_checking
        .unwrap()
        .natural_periods_s_with_oc4_moorings
        .heave;
    println!(
        "heave: decay {t:.3} s, 2π√(M/K) {t_lin:.3} s, OC4 {reference} s ({:+.2} %)",
        100.0 * rel(t, reference)
    );
    assert!(
        rel(t, t_lin).abs() < 5e-3,
        "integrator period {t} vs {t_lin}"
    );
    assert!(rel(t, reference).abs() < 3e-2);
}

#[test]
fn pitch_free_decay_period_matches_the_oc4_value() {
    let (t, t_lin) = decay_period(4, 0.01, 110.0, 0.1);
    let reference = oc4_spec()
        .reference_values_for_checking
        .unwrap()
        .natural_periods_s_with_oc4_moorings
        .pitch;
    println!(
        "pitch: decay {t:.3} s, uncoupled 2π√(M/K) {t_lin:.3} s, OC4 {reference} s ({:+.2} %)",
        100.0 * rel(t, reference)
    );
    // The decay is the coupled surge–pitch mode (the rotation centre moves towards the centre of
    // mass), shorter than the uncoupled estimate; strip theory also gives 8.6 % less pitch added
    // mass than the potential-flow value, hence about −6 % against the OC4 period.
    assert!(rel(t, reference).abs() < 8e-2);
}

#[test]
fn surge_free_decay_period_matches_the_oc4_value() {
    let (t, t_lin) = decay_period(0, 2.0, 330.0, 0.25);
    let reference = oc4_spec()
        .reference_values_for_checking
        .unwrap()
        .natural_periods_s_with_oc4_moorings
        .surge;
    println!(
        "surge: decay {t:.3} s, uncoupled 2π√(M/K) {t_lin:.3} s, OC4 {reference} s ({:+.2} %)",
        100.0 * rel(t, reference)
    );
    assert!(rel(t, reference).abs() < 5e-2);
}

#[test]
fn rotor_thrust_acts_at_hub_height_along_x() {
    let f = oc4();
    let thrust = 5.0e5;
    let loads = f.loads(&BodyState::at_rest(), &StillWater, 0.0, thrust);
    assert_eq!(
        loads.wind,
        Vector6::new(thrust, 0.0, 0.0, 0.0, 90.0 * thrust, 0.0)
    );
    // Pitched by 5°, the hub moves forward and the moment arm shrinks to 90 cos 5°.
    let mut s = BodyState::at_rest();
    s.rotation =
        moorfret_solver::beam::rotation::exp_so3(&Vector3::new(0.0, 5f64.to_radians(), 0.0));
    let tilted = f.loads(&s, &StillWater, 0.0, thrust);
    assert!((tilted.wind[4] - 90.0 * 5f64.to_radians().cos() * thrust).abs() < 1e-6 * thrust);
}

#[test]
fn prescribed_motion_gives_fairlead_kinematics_consistent_with_its_positions() {
    let f = oc4();
    let w = 2.0 * PI / 14.0;
    let mut text = COLUMNS.join(",") + "\n";
    for k in 0..=2000 {
        let t = k as f64 * 0.05;
        let s = (w * t).sin();
        let c = (w * t).cos();
        text += &format!(
            "{t},{},{},{},{},{},{}\n",
            3.0 * s,
            0.5 * c,
            1.2 * s,
            0.03 * c,
            0.06 * s,
            0.02 * c
        );
    }
    let motion = PrescribedMotion::from_csv_str(&text).unwrap();
    let fairlead = fairlead_body_points(40.868, 14.0, &[-5.0])[0];
    let (t, h) = (47.3, 1e-3);
    let at = |t: f64| {
        let s = motion.sample(t).unwrap();
        f.point_kinematics(&s.state, &s.acceleration, &fairlead)
    };
    let (k, kp, km) = (at(t), at(t + h), at(t - h));
    let v_fd = (kp.position_m - km.position_m) / (2.0 * h);
    let a_fd = (kp.position_m - 2.0 * k.position_m + km.position_m) / (h * h);
    assert!(
        (k.velocity_m_per_s - v_fd).norm() < 1e-5 * k.velocity_m_per_s.norm(),
        "{} vs {v_fd}",
        k.velocity_m_per_s
    );
    assert!(
        (k.acceleration_m_per_s2 - a_fd).norm() < 1e-3 * k.acceleration_m_per_s2.norm(),
        "{} vs {a_fd}",
        k.acceleration_m_per_s2
    );
}

#[test]
fn wave_response_is_the_same_with_the_sea_independent_position_jacobian() {
    let full = oc4();
    let light = oc4().with_jacobian_steps(JacobianSteps {
        include_wave_terms: false,
        ..JacobianSteps::default()
    });
    let buoyancy = RHO * G * full.hydrostatics().volume_m3;
    let mooring = oc4_mooring(buoyancy - full.mass_properties().mass_kg * G);
    let sea = DeepRegularWave::new(6.0, 10.0);
    let params = IntegratorParams {
        time_step_s: 0.1,
        ..IntegratorParams::default()
    };
    let run = |f: &Floater| {
        let mut last = BodyState::at_rest();
        let mut heave_max: f64 = 0.0;
        let stats = integrate(
            f,
            &mooring,
            &sea,
            5.0e5,
            &BodyState::at_rest(),
            40.0,
            &params,
            |_, s| {
                last = *s;
                heave_max = heave_max.max(s.position_m.z.abs());
            },
        )
        .unwrap();
        (last, heave_max, stats)
    };
    let (a, heave_a, stats_a) = run(&full);
    let (b, _, stats_b) = run(&light);
    println!("full Jacobian {stats_a:?}; sea-independent Jacobian {stats_b:?}; max |heave| {heave_a:.3} m");
    assert!(
        (a.position_m - b.position_m).norm() < 1e-6,
        "{} vs {}",
        a.position_m,
        b.position_m
    );
    assert!((a.rotation - b.rotation).norm() < 1e-8);
    // A 6 m, 10 s wave: heave well below the wave amplitude (heave period 17 s), but not zero.
    assert!(heave_a > 0.1 && heave_a < 3.0, "{heave_a}");
    assert!(
        stats_b.newton_iterations <= 2 * stats_a.newton_iterations,
        "{stats_a:?} {stats_b:?}"
    );
}

#[test]
fn rotor_thrust_offsets_the_moored_platform_by_thrust_over_stiffness() {
    let f = oc4();
    let pretension = RHO * G * f.hydrostatics().volume_m3 - f.mass_properties().mass_kg * G;
    let mooring = oc4_mooring(pretension);
    let thrust = 5.0e5;
    let (eq0, _) = static_equilibrium(&f, &mooring, 0.0, &BodyState::at_rest(), 1e-12, 20).unwrap();
    let (eq, _) =
        static_equilibrium(&f, &mooring, thrust, &BodyState::at_rest(), 1e-12, 20).unwrap();
    // Only the mooring resists horizontally: x = T / K11 exactly.
    assert!(
        rel(eq.position_m.x, thrust / 7.08e4).abs() < 1e-9,
        "{}",
        eq.position_m.x
    );
    // Pitch: the thrust moment 90 T over the pitch stiffness (hydrostatic + mooring), to first
    // order in the angle.
    let pitch = moorfret_solver::beam::rotation::log_so3(&eq.rotation).y
        - moorfret_solver::beam::rotation::log_so3(&eq0.rotation).y;
    let linear = 90.0 * thrust / (f.restoring_matrix()[(4, 4)] + 8.73e7);
    println!(
        "thrust 500 kN: surge {:.3} m, pitch {:.3}° (linear {:.3}°)",
        eq.position_m.x,
        pitch.to_degrees(),
        linear.to_degrees()
    );
    assert!(rel(pitch, linear).abs() < 2e-2, "{pitch} vs {linear}");
}
