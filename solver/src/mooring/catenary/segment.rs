//! One uniform stretch of a multi-segment mooring line ([`LineSegment`]: length, submerged
//! weight, axial stiffness, clump at its anchor-side end), the extra-mass bookkeeping that builds
//! its weight ([`submerged_weight_n`]) and the physical constants that bookkeeping uses.
//!
//! The segment is the input shared by the multi-segment solver and its shooting integration;
//! it lives apart from both so that neither depends on the other for it.

/// Standard acceleration of gravity (m/s²), ISO 80000-3.
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;
/// Density of carbon steel (kg/m³), the usual design value (DNV-OS-E301 uses 7850 kg/m³).
pub const STEEL_DENSITY_KG_M3: f64 = 7850.0;
/// Density of sea water (kg/m³), as in the paper case's line data.
pub const SEAWATER_DENSITY_KG_M3: f64 = 1025.0;

/// A uniform stretch of mooring line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSegment {
    /// Unstretched length (m).
    pub length_m: f64,
    /// Submerged weight per unit unstretched length, extra masses included (N/m).
    pub weight_n_per_m: f64,
    /// Axial stiffness EA (N).
    pub axial_stiffness_n: f64,
    /// Submerged weight of a clump hung at the anchor-side end of this segment (N), 0 if none.
    pub clump_weight_n: f64,
}

impl LineSegment {
    /// A segment without clump.
    pub fn new(length_m: f64, weight_n_per_m: f64, axial_stiffness_n: f64) -> Self {
        Self {
            length_m,
            weight_n_per_m,
            axial_stiffness_n,
            clump_weight_n: 0.0,
        }
    }

    /// Adds a mass spread uniformly over the segment: w += m g (1 − ρ_water/ρ_material) / L.
    pub fn with_distributed_extra_mass(
        mut self,
        mass_kg: f64,
        material_density_kg_m3: f64,
        water_density_kg_m3: f64,
    ) -> Self {
        self.weight_n_per_m +=
            submerged_weight_n(mass_kg, material_density_kg_m3, water_density_kg_m3)
                / self.length_m;
        self
    }

    /// Hangs a clump of the given submerged weight (N) at the anchor-side end.
    pub fn with_clump_weight(mut self, clump_weight_n: f64) -> Self {
        self.clump_weight_n = clump_weight_n;
        self
    }
}

/// Submerged weight m g (1 − ρ_water/ρ_material) of a solid mass (N).
pub fn submerged_weight_n(
    mass_kg: f64,
    material_density_kg_m3: f64,
    water_density_kg_m3: f64,
) -> f64 {
    mass_kg * STANDARD_GRAVITY_M_S2 * (1.0 - water_density_kg_m3 / material_density_kg_m3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extra_mass_adds_its_submerged_weight_per_metre() {
        let seg = LineSegment::new(40.0, 140.6, 3.6e8).with_distributed_extra_mass(
            2000.0,
            STEEL_DENSITY_KG_M3,
            SEAWATER_DENSITY_KG_M3,
        );
        // 2000 kg × 9.80665 m/s² × (1 − 1025/7850) / 40 m = 426.31 N/m.
        let expected = 140.6 + 2000.0 * 9.80665 * (1.0 - 1025.0 / 7850.0) / 40.0;
        assert!((seg.weight_n_per_m - expected).abs() < 1e-12);
        assert!((seg.weight_n_per_m - 566.91).abs() < 0.01);
    }
}
