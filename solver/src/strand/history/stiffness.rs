//! Tension → strain: the strand's axial stiffness EA measured on the model itself by a tension
//! step (which EA a run uses, and its cache: `moorfret_campaign::stiffness`), and the
//! conversion of a tension history ε = T / EA.

use serde::{Deserialize, Serialize};

use super::{reference_problem, HistoryError, HistoryOptions, LoadSample};
use crate::linalg::{solve_load_path, NewtonStats, NewtonWorkspace};
use crate::strand::loading::SectionMotion;
use crate::strand::model::StrandModel;
use crate::strand::problem::section_force_n;

/// Axial stiffness EA = F / ε of `model` (N): the core and every wire driven to the axial strain
/// `strain` (κ = 0) in one Newton solve from the reference configuration, F the axial force
/// across the mid-length plane (`section_force_n`). The strand is nearly linear in tension
/// (Costello Ch. 2), so `strain` should be of the order of the service strains (1e-3). The
/// solve uses the initialisation's Newton settings and the threads of `options`.
pub fn measure_axial_stiffness_n(
    model: &StrandModel,
    strain: f64,
    options: &HistoryOptions,
) -> Result<f64, HistoryError> {
    let newton = &options.initialisation_newton();
    if !(strain > 0.0 && strain.is_finite()) {
        return Err(HistoryError::InvalidOption {
            field: "strain",
            value: strain,
            reason: "the measuring strain must be finite and > 0".into(),
        });
    }
    let mut problem = reference_problem(model, options.threads)?;
    problem.start_segment(SectionMotion {
        strain,
        curvature_per_m: 0.0,
    });
    let mut solver =
        model.linear_solver_threads(options.threads, options.preconditioner_precision)?;
    let mut ws = NewtonWorkspace::new(&model.pattern);
    let mut stats = NewtonStats::default();
    solve_load_path(
        &mut problem,
        0.0,
        1.0,
        &model.pattern,
        &mut solver,
        newton,
        &mut ws,
        &mut stats,
    )
    .map_err(|source| HistoryError::Step {
        stage: "axial stiffness measurement",
        sample: 0,
        time_s: 0.0,
        substep: 1,
        substeps: 1,
        from_strain: 0.0,
        from_curvature: 0.0,
        to_strain: strain,
        to_curvature: 0.0,
        source: Box::new(source),
    })?;
    let force = section_force_n(model, problem.state(), 0.5 * model.strand.model_length_m)?;
    Ok(force / strain)
}

/// What a negative tension sample means in [`samples_from_tension`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlackTension {
    /// Refused with its sample index: a strand cannot carry compression.
    Refuse,
    /// Taken as zero tension (a slack rope) and counted.
    AsZero,
}

/// Load samples from (t, T, κ) with ε = T / EA, at every `stride`-th sample (0 and 1: every
/// sample); a non-finite tension is refused with its sample index, a negative one as `slack`
/// says. Returns the samples and how many negative tensions were taken as zero.
pub fn samples_from_tension(
    time_s: &[f64],
    tension_n: &[f64],
    curvature_per_m: &[f64],
    axial_stiffness_n: f64,
    stride: usize,
    slack: SlackTension,
) -> Result<(Vec<LoadSample>, usize), HistoryError> {
    if !(axial_stiffness_n > 0.0 && axial_stiffness_n.is_finite()) {
        return Err(HistoryError::InvalidOption {
            field: "axial_stiffness_n",
            value: axial_stiffness_n,
            reason: "must be finite and > 0".into(),
        });
    }
    if time_s.len() != tension_n.len() || time_s.len() != curvature_per_m.len() {
        return Err(HistoryError::InvalidOption {
            field: "tension_n",
            value: tension_n.len() as f64,
            reason: format!(
                "time ({}), tension ({}) and curvature ({}) series differ in length",
                time_s.len(),
                tension_n.len(),
                curvature_per_m.len()
            ),
        });
    }
    let mut slack_samples = 0;
    let samples = (0..time_s.len())
        .step_by(stride.max(1))
        .map(|index| {
            let (t, tension) = (time_s[index], tension_n[index]);
            let refuse = |reason: &str| HistoryError::InvalidSample {
                index,
                time_s: t,
                field: "tension_n",
                value: tension,
                reason: reason.into(),
            };
            if !tension.is_finite() {
                return Err(refuse("must be finite"));
            }
            let carried = if tension >= 0.0 {
                tension
            } else if slack == SlackTension::AsZero {
                slack_samples += 1;
                0.0
            } else {
                return Err(refuse("must be ≥ 0 (a strand cannot carry compression)"));
            };
            Ok(LoadSample {
                time_s: t,
                strain: carried / axial_stiffness_n,
                curvature_per_m: curvature_per_m[index],
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((samples, slack_samples))
}

/// Straight-strand estimates of the axial stiffness of a multi-layer strand (N).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StraightStrandStiffness {
    /// E (A_core + Σ n A cos³β): wire tensions only.
    pub simple_n: f64,
    /// The same with Costello's wire bending and twisting terms, n N cos α per layer
    /// (Costello 1997, Ch. 3, see [`crate::strand::analytical`]).
    pub corrected_n: f64,
}

/// Axial stiffness of `strand` by Costello's theory applied layer by layer, with the
/// kinematics of this model: the core is imposed without Poisson contraction and the wires are
/// beams, so the helix radii do not change (Δr = 0) and every layer takes the strand strain ε:
/// ξ = ε sin²α, Δα = ξ cot α, Δκ = −2 sin α cos α Δα / r, Δτ = (1 − 2 sin²α) Δα / r,
/// T = EA ξ, G = EI Δκ, H = GJ Δτ, N = H κ − G τ; F = E A_core ε + Σ n (T sin α + N cos α),
/// with α = π/2 − β the helix angle.
pub fn straight_strand_stiffness(
    strand: &crate::strand::profile::Strand,
) -> StraightStrandStiffness {
    use std::f64::consts::PI;
    let e = strand.young_modulus_pa;
    let g = e / (2.0 * (1.0 + strand.poisson_ratio));
    let core = e * PI * strand.core_wire_radius_m.powi(2);
    let (mut simple, mut corrected) = (core, core);
    for l in &strand.layers {
        let (a, r) = (l.wire_radius_m, l.helix_radius_m);
        let alpha = 0.5 * PI - l.lay_angle_rad;
        let (sa, ca) = alpha.sin_cos();
        let area = PI * a * a;
        let inertia = 0.25 * PI * a.powi(4);
        // per unit strand strain
        let xi = sa * sa;
        let da = xi * ca / sa;
        let dkappa = -2.0 * sa * ca * da / r;
        let dtau = (1.0 - 2.0 * sa * sa) * da / r;
        let tension = e * area * xi;
        let shear = g * 2.0 * inertia * dtau * ca * ca / r - e * inertia * dkappa * sa * ca / r;
        let n = l.wires as f64;
        simple += n * tension * sa;
        corrected += n * (tension * sa + shear * ca);
    }
    StraightStrandStiffness {
        simple_n: simple,
        corrected_n: corrected,
    }
}

/// Axial stiffness of the straight-strand theory with the helix radii shortened by the contact
/// compliance of the model (N), for a normal law that is a penalty `normal_penalty_n_per_m`.
///
/// Costello's wire strain has a radial term, ξ = ε cos²β + (Δr/r) sin²β (Costello 1997, Ch. 2;
/// his Δr comes from the wires' Poisson contraction, which beam wires do not have). Here Δr is
/// the penetration of the contacts: a wire of tension T presses on the layer beneath with
/// T sin²β / r per unit wire length (helix curvature sin²β / r), i.e. n T sin²β / (r cos β) per
/// unit strand length for a layer of n wires; these radial loads pass inwards through every
/// interface below, so interface i carries Q_i = Σ_{j ≥ i} n_j T_j sin²β_j / (r_j cos β_j),
/// shared by its N_i contacts over the model length L: F_i = Q_i L / N_i, penetration
/// F_i / ε_N. Layer k's radius shrinks by the penetrations of interfaces 0..=k, and with
/// T_k = E A_k ξ_k the tensions follow from a linear system; F = E A_core ε + Σ n T cos β.
/// (Costello's bending and twisting terms change EA by 1e-4 here and are left out.)
pub fn contact_compliant_stiffness_n(model: &StrandModel, normal_penalty_n_per_m: f64) -> f64 {
    use std::f64::consts::PI;
    let strand = &model.strand;
    let layers = &strand.layers;
    let m = layers.len();
    let e = strand.young_modulus_pa;
    let mut contacts = vec![0usize; m];
    for site in crate::strand::history::monitors::contact_sites(model) {
        if site.interface < m {
            contacts[site.interface] += 1;
        }
    }
    // radial load per unit strand length of layer j per unit wire tension
    let radial: Vec<f64> = layers
        .iter()
        .map(|l| {
            let (s, c) = l.lay_angle_rad.sin_cos();
            l.wires as f64 * s * s / (l.helix_radius_m * c)
        })
        .collect();
    // penetration of interface i per unit load Q_i
    let compliance: Vec<f64> = contacts
        .iter()
        .map(|&n| {
            if n == 0 {
                0.0
            } else {
                strand.model_length_m / (n as f64 * normal_penalty_n_per_m)
            }
        })
        .collect();
    // T_k + E A_k sin²β_k / r_k Σ_{i ≤ k} compliance_i Σ_{j ≥ i} radial_j T_j = E A_k cos²β_k ε
    let mut a = nalgebra::DMatrix::<f64>::identity(m, m);
    let mut rhs = nalgebra::DVector::<f64>::zeros(m);
    for (k, l) in layers.iter().enumerate() {
        let (s, c) = l.lay_angle_rad.sin_cos();
        let ea = e * PI * l.wire_radius_m * l.wire_radius_m;
        rhs[k] = ea * c * c;
        for (i, comp) in compliance.iter().enumerate().take(k + 1) {
            for j in i..m {
                a[(k, j)] += ea * s * s / l.helix_radius_m * comp * radial[j];
            }
        }
    }
    let tension = a.lu().solve(&rhs).unwrap_or(rhs);
    e * PI * strand.core_wire_radius_m.powi(2)
        + layers
            .iter()
            .zip(tension.iter())
            .map(|(l, t)| l.wires as f64 * t * l.lay_angle_rad.cos())
            .sum::<f64>()
}
