//! Section properties of a line segment, resolved from its line type, the extra mass and the
//! site, in the per-unit-length form the element kernels use.
//!
//! Hydrodynamic coefficients follow Morison's equation per unit length of line:
//! drag f = ½ ρ D C_d |u| u on the normal and tangential relative velocities (both on the
//! projected area D, the reference of the DNV-OS-E301 coefficient tables), added mass
//! ρ A C_a and Froude–Krylov plus diffraction ρ A (1 + C_a,n) on the normal water acceleration,
//! with A = π D² / 4.
//!
//! Extra (clump) mass is spread over its segment: it adds mass and its submerged weight
//! (m − ρ_w V) g, with V its displaced volume when given and m / ρ_steel (steel) otherwise; its
//! own drag and added mass are neglected.

use super::catenary::STEEL_DENSITY_KG_M3;
use super::spec::{Environment, LineTypeSpec, SegmentSpec};

/// How a segment is discretised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SectionKind {
    /// Wire rope: C¹ Hermite cable elements with axial and bending stiffness.
    Rope,
    /// Chain: tension-only bars.
    Chain,
}

/// Per-unit-length properties of one segment (all per metre of unstretched line).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Element family.
    pub kind: SectionKind,
    /// Structural mass including extra mass (kg/m).
    pub mass_kg_per_m: f64,
    /// Submerged weight including extra mass (N/m).
    pub weight_n_per_m: f64,
    /// Axial stiffness EA (N).
    pub ea_n: f64,
    /// Bending stiffness EI (N m²).
    pub ei_nm2: f64,
    /// ½ ρ D C_d,n (kg/m²): normal drag per unit length is this × |u_n| u_n.
    pub drag_normal_kg_per_m2: f64,
    /// ½ ρ D C_d,t (kg/m²).
    pub drag_tangential_kg_per_m2: f64,
    /// ρ A C_a,n (kg/m).
    pub added_mass_normal_kg_per_m: f64,
    /// ρ A C_a,t (kg/m).
    pub added_mass_tangential_kg_per_m: f64,
    /// ρ A (1 + C_a,n) (kg/m): inertia force per unit normal water acceleration.
    pub froude_krylov_kg_per_m: f64,
    /// Seabed penalty stiffness (N/m²).
    pub seabed_stiffness_n_per_m2: f64,
    /// Seabed damping 2 ζ √(k (m + m_a,n)) (N s/m²).
    pub seabed_damping_n_s_per_m2: f64,
}

impl Section {
    /// Axial damping coefficient c = ζ L √(EA m) (N s) of an element of length `length_m`
    /// whose two-mass axial mode ω = (2/L) √(EA/m) has the damping ratio ζ = `ratio`
    /// (stiffness-proportional damping: ζ = c ω / (2 EA)).
    pub(crate) fn axial_damping_n_s(&self, length_m: f64, ratio: f64) -> f64 {
        ratio * length_m * (self.ea_n * self.mass_kg_per_m).sqrt()
    }
}

impl Section {
    /// Resolves the section of `segment` made of `line_type` at the given site.
    pub fn new(line_type: &LineTypeSpec, segment: &SegmentSpec, env: &Environment) -> Section {
        let rho = env.water_density_kg_m3;
        let d = line_type.hydrodynamic_diameter_m;
        let area = std::f64::consts::PI * d * d / 4.0;
        let extra_per_m = segment.extra_mass_kg.unwrap_or(0.0) / segment.length_m;
        let extra_weight_per_m = match segment.extra_volume_m3 {
            Some(_) => segment.extra_submerged_weight_n(env) / segment.length_m,
            // Kept in this form for steel: the results of cases without a volume are unchanged
            // to the bit.
            None => extra_per_m * env.gravity_m_s2 * (1.0 - rho / STEEL_DENSITY_KG_M3),
        };
        let mass = line_type.mass_kg_per_m + extra_per_m;
        let added_n = rho * area * line_type.added_mass_normal;
        let k = env.seabed.normal_stiffness_n_per_m2;
        Section {
            kind: if line_type.is_rope() {
                SectionKind::Rope
            } else {
                SectionKind::Chain
            },
            mass_kg_per_m: mass,
            weight_n_per_m: line_type.submerged_weight_n_per_m + extra_weight_per_m,
            ea_n: line_type.axial_stiffness_n,
            ei_nm2: line_type.bending_stiffness_nm2,
            drag_normal_kg_per_m2: 0.5 * rho * d * line_type.drag_normal,
            drag_tangential_kg_per_m2: 0.5 * rho * d * line_type.drag_tangential,
            added_mass_normal_kg_per_m: added_n,
            added_mass_tangential_kg_per_m: rho * area * line_type.added_mass_tangential,
            froude_krylov_kg_per_m: rho * area * (1.0 + line_type.added_mass_normal),
            seabed_stiffness_n_per_m2: k,
            seabed_damping_n_s_per_m2: 2.0
                * env.seabed.damping_ratio
                * (k * (mass + added_n)).sqrt(),
        }
    }
}
