//! Runs one loading case of the strand model (tension ε, then curvature κ at constant ε) with the
//! Newton driver ([`crate::linalg::solve_load_path`], sparse LU) and extracts the monitors:
//! axial force of every wire element, contact forces, status and slip, strand axial force.
//!
//! Stage 1 drives λ from 0 to 1 (ε), stage 2 from 1 to 2 (κ), each with its own first load
//! increment; cut-backs and growth follow [`NewtonParams`]. Errors carry the stage and the
//! driver's step / iteration / residual data.

use std::time::Instant;

use super::contacts::ContactKind;
use super::loading::{LoadPath, SectionMotion};
use super::model::StrandModel;
use super::problem::{section_force_n, StrandProblem};
use super::wires::WireId;
use crate::beam::frame::{FrameError, FrameState};
use crate::contact::ContactStatus;
use crate::linalg::{
    solve_load_path, LinalgError, NewtonError, NewtonParams, NewtonStats, NewtonWorkspace,
};

/// Errors of a strand run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StrandRunError {
    /// Symbolic analysis of the pattern failed.
    #[error(transparent)]
    Linear(#[from] LinalgError),
    /// Newton failed in a stage (1 = tension, 2 = bending).
    #[error("stage {stage} (strain {strain}, curvature {curvature_per_m} 1/m): {source}")]
    Newton {
        /// Stage.
        stage: usize,
        /// Target strain.
        strain: f64,
        /// Target curvature (1/m).
        curvature_per_m: f64,
        /// Driver error (step, iteration, residual, load factor).
        source: NewtonError<FrameError>,
    },
    /// An element could not be evaluated while extracting results.
    #[error(transparent)]
    Frame(#[from] FrameError),
}

/// Run parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrandRunParameters {
    /// Newton settings (increments as fractions of a stage).
    pub newton: NewtonParams,
    /// First increment of the tension stage.
    pub tension_increment: f64,
    /// First increment of the bending stage.
    pub bending_increment: f64,
}

impl Default for StrandRunParameters {
    fn default() -> Self {
        Self {
            newton: NewtonParams {
                max_iterations: 60,
                easy_iterations: 8,
                relative_tolerance: 1e-6,
                energy_tolerance: 1e-16,
                max_load_increment: 1.0,
                // backtracking breaks the two-cycles of full Newton steps in which slip directions
                // turn (1+6+1 strand at κ = 1 1/m: one step instead of ~1 500)
                line_search_trials: 8,
                ..NewtonParams::default()
            },
            // from the reference state, where the contacts carry only the interference force,
            // larger first increments fail six times before 1/64 converges (1+6+1 benchmark)
            tension_increment: 1.0 / 64.0,
            bending_increment: 1.0,
        }
    }
}

/// Axial force of one wire element.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ElementForce {
    /// Wire.
    pub wire: WireId,
    /// Arc length of the element midpoint along the reference helix (m).
    pub arc_length_m: f64,
    /// Reference axial coordinate of the midpoint (m).
    pub z_m: f64,
    /// Angular position of the midpoint, wrapped to (−π, π] (rad).
    pub theta_rad: f64,
    /// Axial force N (N), tension positive.
    pub axial_force_n: f64,
}

/// Result of one contact.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ContactResult {
    /// Reference z of the contact (m).
    pub z_m: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Tangential force magnitude (N).
    pub tangential_force_n: f64,
    /// Magnitude of the total relative tangential displacement (m).
    pub slip_m: f64,
    /// Status.
    pub status: ContactStatus,
}

/// Result of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    /// Imposed strain.
    pub strain: f64,
    /// Imposed curvature (1/m).
    pub curvature_per_m: f64,
    /// Newton work counts (both stages).
    pub stats: NewtonStats,
    /// Wall time of the tension stage (s).
    pub tension_time_s: f64,
    /// Wall time of the bending stage (s).
    pub bending_time_s: f64,
    /// Axial force of every wire element, mesh element order.
    pub element_forces: Vec<ElementForce>,
    /// Contacts, mesh contact order.
    pub contacts: Vec<ContactResult>,
    /// Axial force across the mid-length plane (N), all wires.
    pub strand_force_n: f64,
    /// Departure from plane-section motion at every trellis contact, mesh contact order.
    pub trellis_departures: Vec<PlaneSectionDeparture>,
}

/// Displacements, relative to the rigid plane-section motion of the strand
/// ([`SectionMotion::map`]), of the material points of one trellis contact, projected on the
/// outer wire's current tangent (m). The stick solution of the outer helix assumes all of them
/// zero; `outer_axis_m` is what its axial force follows. Points: the outer wire's axis node,
/// the contact points on the outer and inner wire surfaces (±r along the reference normal,
/// carried by the node rotations), and the inner wire's point on the opposite side (towards the
/// core).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PlaneSectionDeparture {
    /// Angular position of the outer wire at the contact (rad, unwrapped).
    pub theta_rad: f64,
    /// Outer wire axis.
    pub outer_axis_m: f64,
    /// Outer wire contact point.
    pub outer_point_m: f64,
    /// Inner wire contact point (its side facing the outer wire).
    pub inner_top_m: f64,
    /// Inner wire axis.
    pub inner_axis_m: f64,
    /// Inner wire point on the core side.
    pub inner_bottom_m: f64,
}

/// Departures from plane-section motion of every trellis contact of `model` in `state` under
/// the section motion `motion`.
pub fn plane_section_departures(
    model: &StrandModel,
    state: &FrameState,
    motion: &SectionMotion,
) -> Vec<PlaneSectionDeparture> {
    let wires = model.strand.wires();
    model
        .mesh
        .contacts
        .iter()
        .filter(|mc| mc.kind == ContactKind::Trellis)
        .map(|mc| {
            let [a, b] = mc.nodes;
            let (na, nb) = (&model.mesh.nodes[a.0], &model.mesh.nodes[b.0]);
            let n0 = (nb.position - na.position).normalize();
            let (ra, rb) = (wires[na.wire.0].radius_m, wires[nb.wire.0].radius_m);
            let t2 = motion.rotation(nb.z_m) * nb.tangent;
            let along = |current: nalgebra::Vector3<f64>, reference: nalgebra::Vector3<f64>| {
                (current - motion.map(&reference)).dot(&t2)
            };
            let (xa, xb) = (state.positions[a.0], state.positions[b.0]);
            let (la, lb) = (state.rotations[a.0], state.rotations[b.0]);
            PlaneSectionDeparture {
                theta_rad: wires[nb.wire.0].helix.angle(nb.z_m),
                outer_axis_m: along(xb, nb.position),
                outer_point_m: along(xb - lb * n0 * rb, nb.position - n0 * rb),
                inner_top_m: along(xa + la * n0 * ra, na.position + n0 * ra),
                inner_axis_m: along(xa, na.position),
                inner_bottom_m: along(xa - la * n0 * ra, na.position - n0 * ra),
            }
        })
        .collect()
}

fn wrap(theta: f64) -> f64 {
    let t = theta.rem_euclid(2.0 * std::f64::consts::PI);
    if t > std::f64::consts::PI {
        t - 2.0 * std::f64::consts::PI
    } else {
        t
    }
}

/// Solves one case: ε = `strain`, then κ = `curvature_per_m` (skipped if 0).
pub fn run_case(
    model: &StrandModel,
    strain: f64,
    curvature_per_m: f64,
    params: &StrandRunParameters,
) -> Result<CaseResult, StrandRunError> {
    let path = LoadPath {
        strain,
        curvature_per_m,
    };
    let mut problem = StrandProblem::new(model, path);
    let mut solver = model.linear_solver()?;
    let mut ws = NewtonWorkspace::new(&model.pattern);
    let mut stats = NewtonStats::default();
    let stage_err = |stage, source| StrandRunError::Newton {
        stage,
        strain,
        curvature_per_m,
        source,
    };
    let t0 = Instant::now();
    let np = NewtonParams {
        initial_load_increment: params.tension_increment,
        ..params.newton
    };
    solve_load_path(
        &mut problem,
        0.0,
        1.0,
        &model.pattern,
        &mut solver,
        &np,
        &mut ws,
        &mut stats,
    )
    .map_err(|e| stage_err(1, e))?;
    let tension_time_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    if curvature_per_m != 0.0 {
        let np = NewtonParams {
            initial_load_increment: params.bending_increment,
            ..params.newton
        };
        solve_load_path(
            &mut problem,
            1.0,
            2.0,
            &model.pattern,
            &mut solver,
            &np,
            &mut ws,
            &mut stats,
        )
        .map_err(|e| stage_err(2, e))?;
    }
    let bending_time_s = t1.elapsed().as_secs_f64();

    let state = problem.state();
    let wires = model.strand.wires();
    let mut element_forces = Vec::with_capacity(model.frame.elements().len());
    for (e, (el, me)) in model
        .frame
        .elements()
        .iter()
        .zip(&model.mesh.elements)
        .enumerate()
    {
        let [a, b] = el.nodes;
        let lf = el
            .beam
            .local_forces(
                &state.positions[a.0],
                &state.positions[b.0],
                &state.rotations[a.0],
                &state.rotations[b.0],
            )
            .map_err(|source| FrameError::Element { element: e, source })?;
        let helix = &wires[me.wire.0].helix;
        let z = 0.5 * (model.mesh.nodes[a.0].z_m + model.mesh.nodes[b.0].z_m);
        element_forces.push(ElementForce {
            wire: me.wire,
            arc_length_m: helix.arc_length(z),
            z_m: z,
            theta_rad: wrap(helix.angle(z)),
            axial_force_n: lf.axial_n,
        });
    }
    let contacts = model
        .mesh
        .contacts
        .iter()
        .zip(problem.histories())
        .map(|(mc, h)| {
            let z = model.mesh.nodes[mc.nodes[1].0].z_m;
            let resp = problem.responses()[mc.id.0];
            ContactResult {
                z_m: z,
                normal_force_n: resp.map_or(0.0, |r| r.normal_force_n),
                tangential_force_n: resp.map_or(0.0, |r| r.tangential_force_n),
                slip_m: resp.map_or(0.0, |r| r.total_slip.norm()),
                status: h.status,
            }
        })
        .collect();
    let strand_force_n = section_force_n(model, state, 0.5 * model.strand.model_length_m)?;
    let trellis_departures = plane_section_departures(model, state, &problem.motion());
    Ok(CaseResult {
        strain,
        curvature_per_m,
        stats,
        tension_time_s,
        bending_time_s,
        element_forces,
        contacts,
        strand_force_n,
        trellis_departures,
    })
}
