//! Strand section resultants from the wire forces and the bending-stiffness bounds they are
//! checked against.
//!
//! Resultants: the force and moment carried across the plane z = z_cut of the reference
//! configuration, summed over the wire elements spanning it, each taken at the element end
//! beyond the plane (an element carries no distributed load, its contacts act at nodes), with
//! moments about the current strand axis point of that section, c(z_cut)
//! (`super::loading::SectionMotion::axis_point`): M = Σ (x_b − c) × f_b + m_b.
//!
//! Bounds (Papailiou 1997, IEEE Trans. Power Delivery 12(4), Eqs. 1-2): with every wire free to
//! slide, each bends about its own axis, EI_min = E I_core + Σ n E I cos β; with every wire
//! stuck, the plane-section (stick) force EA cos²β R κ sin θ of each helical wire adds its
//! lever arm, EI_max = EI_min + Σ_wires E A cos³β (R sin θ)², θ the wire's angle from the
//! neutral axis in the section considered; Σ sin²θ = n/2 for n ≥ 3 equally spaced wires, the
//! familiar Σ n E A R² cos³β / 2. Units: N, m.

use nalgebra::Vector3;

use super::loading::SectionMotion;
use super::model::StrandModel;
use super::profile::Strand;
use crate::beam::corotational::Vector12;
use crate::beam::frame::{FrameError, FrameState};

/// Force and moment carried across a section (N, N m), global axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionResultants {
    /// Force (N).
    pub force_n: Vector3<f64>,
    /// Moment about the strand axis point of the section (N m).
    pub moment_n_m: Vector3<f64>,
}

/// Resultants across the reference plane `z_m` (module docs).
pub fn section_resultants(
    model: &StrandModel,
    state: &FrameState,
    motion: &SectionMotion,
    z_m: f64,
) -> Result<SectionResultants, FrameError> {
    let centre = motion.axis_point(z_m);
    let reference = model.frame.reference_positions();
    let mut fe = Vector12::zeros();
    let (mut force, mut moment) = (Vector3::zeros(), Vector3::zeros());
    for (e, el) in model.frame.elements().iter().enumerate() {
        let [a, b] = el.nodes;
        if !(reference[a.0].z <= z_m && reference[b.0].z > z_m) {
            continue;
        }
        el.beam
            .internal_force(
                &state.positions[a.0],
                &state.positions[b.0],
                &state.rotations[a.0],
                &state.rotations[b.0],
                &mut fe,
            )
            .map_err(|source| FrameError::Element { element: e, source })?;
        let f = Vector3::new(fe[6], fe[7], fe[8]);
        let m = Vector3::new(fe[9], fe[10], fe[11]);
        force += f;
        moment += (state.positions[b.0] - centre).cross(&f) + m;
    }
    Ok(SectionResultants {
        force_n: force,
        moment_n_m: moment,
    })
}

/// Bending stiffness bounds of a strand (N m²), module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BendingStiffnessBounds {
    /// All wires sliding: E I_core + Σ n E I cos β.
    pub min_n_m2: f64,
    /// All wires stuck: EI_min + Σ_wires E A cos³β (R sin θ)².
    pub max_n_m2: f64,
}

/// EI_min and EI_max of `strand` in the section at reference axial coordinate `z_m`.
pub fn bending_stiffness_bounds(strand: &Strand, z_m: f64) -> BendingStiffnessBounds {
    use std::f64::consts::PI;
    let e = strand.young_modulus_pa;
    let inertia = |r: f64| 0.25 * PI * r.powi(4);
    let mut min = e * inertia(strand.core_wire_radius_m);
    let mut extra = 0.0;
    for w in strand.wires().iter().filter(|w| w.layer.is_some()) {
        let c = w.helix.lay_angle_rad.cos();
        let area = PI * w.radius_m.powi(2);
        let lever = w.helix.radius_m * w.helix.angle(z_m).sin();
        min += e * inertia(w.radius_m) * c;
        extra += e * area * lever * lever * c.powi(3);
    }
    BendingStiffnessBounds {
        min_n_m2: min,
        max_n_m2: min + extra,
    }
}
