//! Tension → strain: the strand's axial stiffness EA measured on the model itself by a tension
//! step, cached per profile, and the conversion of a tension history ε = T / EA.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::{reference_problem, HistoryError, HistoryOptions, LoadSample};
use crate::linalg::{solve_load_path, NewtonStats, NewtonWorkspace};
use crate::strand::loading::SectionMotion;
use crate::strand::model::StrandModel;
use crate::strand::problem::section_force_n;

/// Axial stiffness EA = F / ε of `model` (N): the core and every wire driven to the axial strain
/// `strain` (κ = 0) in one Newton solve from the reference configuration, F the axial force
/// across the mid-length plane ([`section_force_n`]). The strand is nearly linear in tension
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
    let mut solver = model.linear_solver_threads(options.threads)?;
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

/// Measured axial stiffnesses by profile name (N), serialisable so that a campaign measures
/// each profile once.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxialStiffnessCache {
    /// EA by profile name (N).
    pub entries: BTreeMap<String, f64>,
}

impl AxialStiffnessCache {
    /// EA of profile `name`, measured on `model` at `strain` if not cached yet.
    pub fn get_or_measure(
        &mut self,
        name: &str,
        model: &StrandModel,
        strain: f64,
        options: &HistoryOptions,
    ) -> Result<f64, HistoryError> {
        if let Some(&ea) = self.entries.get(name) {
            return Ok(ea);
        }
        let ea = measure_axial_stiffness_n(model, strain, options)?;
        self.entries.insert(name.to_string(), ea);
        Ok(ea)
    }
}

/// Load samples from (t, T, κ) with ε = T / EA; a non-finite or negative tension is refused
/// with its sample index.
pub fn samples_from_tension(
    time_s: &[f64],
    tension_n: &[f64],
    curvature_per_m: &[f64],
    axial_stiffness_n: f64,
) -> Result<Vec<LoadSample>, HistoryError> {
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
    time_s
        .iter()
        .zip(tension_n)
        .zip(curvature_per_m)
        .enumerate()
        .map(|(index, ((&t, &tension), &k))| {
            if !(tension.is_finite() && tension >= 0.0) {
                return Err(HistoryError::InvalidSample {
                    index,
                    time_s: t,
                    field: "tension_n",
                    value: tension,
                    reason: "must be finite and ≥ 0 (a strand cannot carry compression)".into(),
                });
            }
            Ok(LoadSample {
                time_s: t,
                strain: tension / axial_stiffness_n,
                curvature_per_m: k,
            })
        })
        .collect()
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
