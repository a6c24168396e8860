//! Cross-section and material of a beam element: the stiffnesses EA, GA_s, EI and GJ that the
//! local Timoshenko law of the corotational element needs.
//!
//! Local axes: x along the element, y and z the principal axes of the section. `inertia_y_m4`
//! resists bending about y (curvature in the x-z plane), `inertia_z_m4` bending about z. The
//! transverse shear areas are A_s = k A with Cowper's shear coefficient k (Cowper, "The shear
//! coefficient in Timoshenko's beam theory", J. Appl. Mech. 33, 1966, Table 1):
//! k = 6(1+ν)/(7+6ν) for a solid circle (≈ 0.886 at ν = 0.3, 0.9 in the ν → 0.5 limit commonly
//! quoted for steel wires), k = 10(1+ν)/(12+11ν) for a solid rectangle. Units: m, m², m⁴, Pa.

use thiserror::Error;

/// A section property that is not strictly positive and finite.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("beam section: {field} = {value} must be finite and > 0")]
pub struct SectionError {
    /// Name of the offending field.
    pub field: &'static str,
    /// Its value.
    pub value: f64,
}

/// Elastic properties of a prismatic beam section (immutable model data).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamSection {
    /// Young's modulus E (Pa).
    pub young_pa: f64,
    /// Shear modulus G (Pa).
    pub shear_modulus_pa: f64,
    /// Area A (m²).
    pub area_m2: f64,
    /// Shear area for transverse shear along local y, k_y A (m²).
    pub shear_area_y_m2: f64,
    /// Shear area for transverse shear along local z, k_z A (m²).
    pub shear_area_z_m2: f64,
    /// Second moment of area about local y (m⁴).
    pub inertia_y_m4: f64,
    /// Second moment of area about local z (m⁴).
    pub inertia_z_m4: f64,
    /// Saint-Venant torsion constant J (m⁴).
    pub torsion_m4: f64,
}

impl BeamSection {
    /// Solid circular section of radius `radius_m` (a wire) with Cowper's shear coefficient.
    pub fn circle(radius_m: f64, young_pa: f64, poisson: f64) -> Result<Self, SectionError> {
        positive("radius_m", radius_m)?;
        let area = std::f64::consts::PI * radius_m * radius_m;
        let inertia = 0.25 * area * radius_m * radius_m;
        let k = 6.0 * (1.0 + poisson) / (7.0 + 6.0 * poisson);
        Self {
            young_pa,
            shear_modulus_pa: young_pa / (2.0 * (1.0 + poisson)),
            area_m2: area,
            shear_area_y_m2: k * area,
            shear_area_z_m2: k * area,
            inertia_y_m4: inertia,
            inertia_z_m4: inertia,
            torsion_m4: 2.0 * inertia,
        }
        .validated()
    }

    /// Solid rectangle `width_m` (along local y) × `height_m` (along local z), with Cowper's
    /// shear coefficient and the Saint-Venant torsion constant of the rectangle (series of
    /// Timoshenko & Goodier, Theory of Elasticity, §109, five terms).
    pub fn rectangle(
        width_m: f64,
        height_m: f64,
        young_pa: f64,
        poisson: f64,
    ) -> Result<Self, SectionError> {
        positive("width_m", width_m)?;
        positive("height_m", height_m)?;
        let area = width_m * height_m;
        let k = 10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson);
        let (a, b) = if width_m >= height_m {
            (width_m, height_m)
        } else {
            (height_m, width_m)
        };
        // J = a b³ [1/3 − (64/π⁵)(b/a) Σ_{n odd} tanh(nπa/2b)/n⁵]
        let series: f64 = (0..5)
            .map(|i| {
                let n = (2 * i + 1) as f64;
                (n * std::f64::consts::PI * a / (2.0 * b)).tanh() / n.powi(5)
            })
            .sum();
        let torsion =
            a * b.powi(3) * (1.0 / 3.0 - 64.0 / std::f64::consts::PI.powi(5) * (b / a) * series);
        Self {
            young_pa,
            shear_modulus_pa: young_pa / (2.0 * (1.0 + poisson)),
            area_m2: area,
            shear_area_y_m2: k * area,
            shear_area_z_m2: k * area,
            inertia_y_m4: width_m * height_m.powi(3) / 12.0,
            inertia_z_m4: height_m * width_m.powi(3) / 12.0,
            torsion_m4: torsion,
        }
        .validated()
    }

    /// Checks that every property is finite and strictly positive.
    pub fn validated(self) -> Result<Self, SectionError> {
        positive("young_pa", self.young_pa)?;
        positive("shear_modulus_pa", self.shear_modulus_pa)?;
        positive("area_m2", self.area_m2)?;
        positive("shear_area_y_m2", self.shear_area_y_m2)?;
        positive("shear_area_z_m2", self.shear_area_z_m2)?;
        positive("inertia_y_m4", self.inertia_y_m4)?;
        positive("inertia_z_m4", self.inertia_z_m4)?;
        positive("torsion_m4", self.torsion_m4)?;
        Ok(self)
    }
}

fn positive(field: &'static str, value: f64) -> Result<(), SectionError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SectionError { field, value })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_has_polar_torsion_and_cowper_coefficient() {
        let s = BeamSection::circle(2.3e-3, 210e9, 0.3).unwrap();
        let a = std::f64::consts::PI * 2.3e-3_f64.powi(2);
        assert!((s.area_m2 - a).abs() < 1e-18);
        assert!((s.torsion_m4 - 2.0 * s.inertia_y_m4).abs() < 1e-24);
        assert!((s.shear_area_y_m2 / a - 7.8 / 8.8).abs() < 1e-12);
    }

    #[test]
    fn square_torsion_constant_matches_tabulated_value() {
        // Timoshenko & Goodier tabulate k1 = 0.141 for a/b = 1: J = 0.1406 a⁴.
        let s = BeamSection::rectangle(1.0, 1.0, 1e7, 0.0).unwrap();
        assert!((s.torsion_m4 - 0.1406).abs() < 2e-4, "{}", s.torsion_m4);
    }

    #[test]
    fn negative_radius_is_rejected_with_its_value() {
        let e = BeamSection::circle(-1.0, 210e9, 0.3).unwrap_err();
        assert_eq!(e.field, "radius_m");
        assert_eq!(e.value, -1.0);
    }
}
