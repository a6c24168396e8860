//! Input description of a mooring line: line types (section properties), segments from the
//! fairlead to the anchor, the site (depth, water, seabed) and the end points.
//!
//! These serde structures use `deny_unknown_fields` and carry units in their names, so the
//! campaign layer can embed them directly. [`LineSpec::validate`] rejects non-physical input
//! with the path of the offending field (`segments[1].length_m must be > 0`).
//!
//! A line type with `bending_stiffness_nm2 > 0` is a wire rope (Hermite cable elements); with
//! zero bending stiffness it is a chain (tension-only bars).

use std::collections::BTreeMap;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::error::LineError;
use crate::text::Num;

/// Most elements of one segment (the paper's line has 84 in all).
pub(crate) const MAX_SEGMENT_ELEMENTS: usize = 10_000;

/// Section properties of one line type (a chain grade or a rope construction).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineTypeSpec {
    /// Mass in air per unit unstretched length (kg/m).
    pub mass_kg_per_m: f64,
    /// Submerged weight per unit unstretched length (N/m).
    pub submerged_weight_n_per_m: f64,
    /// Axial stiffness EA (N).
    pub axial_stiffness_n: f64,
    /// Bending stiffness EI (N m²); zero makes the type a chain.
    pub bending_stiffness_nm2: f64,
    /// Lower bound of a tension/curvature-dependent bending stiffness (N m²); informative only,
    /// the line model uses the constant `bending_stiffness_nm2` (wires stuck).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bending_stiffness_min_nm2: Option<f64>,
    /// Torsional stiffness (N m²); informative only, torsion is not modelled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torsional_stiffness_nm2: Option<f64>,
    /// Hydrodynamic (volume-equivalent) diameter (m), used for drag and added mass.
    pub hydrodynamic_diameter_m: f64,
    /// Normal drag coefficient, on the projected area D per unit length.
    pub drag_normal: f64,
    /// Tangential drag coefficient, on the same reference area D per unit length.
    pub drag_tangential: f64,
    /// Normal added-mass coefficient.
    pub added_mass_normal: f64,
    /// Tangential added-mass coefficient.
    pub added_mass_tangential: f64,
    /// Minimum breaking load (N); informative only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub minimum_breaking_load_n: Option<f64>,
}

/// One homogeneous segment of a line, listed from the fairlead to the anchor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Free name, for messages and outputs.
    pub name: String,
    /// Key into [`LineSpec::line_types`].
    #[serde(rename = "type")]
    pub line_type: String,
    /// Unstretched length (m).
    pub length_m: f64,
    /// Number of finite elements (equal lengths).
    pub elements: usize,
    /// Extra (clump) mass distributed uniformly over the segment (kg).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extra_mass_kg: Option<f64>,
    /// Volume of water displaced by the extra mass (m³): its submerged weight is
    /// (m − ρ_w V) g. Absent, the extra mass is steel (V = m / 7850 kg/m³). A MoorDyn point's
    /// mass and volume map onto `extra_mass_kg` and this.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extra_volume_m3: Option<f64>,
}

impl SegmentSpec {
    /// Submerged weight of the extra mass (N): (m − ρ_w V) g, V = m / ρ_steel when the
    /// volume is not given; negative for a buoy.
    pub(crate) fn extra_submerged_weight_n(&self, env: &Environment) -> f64 {
        let mass_kg = self.extra_mass_kg.unwrap_or(0.0);
        let volume_m3 = self
            .extra_volume_m3
            .unwrap_or(mass_kg / super::catenary::STEEL_DENSITY_KG_M3);
        (mass_kg - env.water_density_kg_m3 * volume_m3) * env.gravity_m_s2
    }
}

/// A mooring line: its line types and its segments from the fairlead to the anchor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineSpec {
    /// Line types by name.
    pub line_types: BTreeMap<String, LineTypeSpec>,
    /// Segments, fairlead first.
    pub segments: Vec<SegmentSpec>,
}

/// Seabed contact: penalty spring and damper normal to the flat seabed, optional regularised
/// Coulomb friction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeabedSpec {
    /// Normal penalty stiffness per unit line length (N/m per m = N/m²).
    pub normal_stiffness_n_per_m2: f64,
    /// Normal damping as a fraction of the critical damping of the line mass on the penalty
    /// spring, c = 2 ζ √(k m) (N s/m²).
    #[serde(default = "default_seabed_damping_ratio")]
    pub damping_ratio: f64,
    /// Coulomb friction coefficient (0 = frictionless).
    #[serde(default)]
    pub friction_coefficient: f64,
    /// Sliding speed (m/s) below which friction is regularised (linear in the speed).
    #[serde(default = "default_friction_velocity")]
    pub friction_velocity_m_s: f64,
}

fn default_seabed_damping_ratio() -> f64 {
    0.2
}

fn default_friction_velocity() -> f64 {
    0.01
}

impl Default for SeabedSpec {
    fn default() -> Self {
        SeabedSpec {
            normal_stiffness_n_per_m2: 1.0e6,
            damping_ratio: default_seabed_damping_ratio(),
            friction_coefficient: 0.0,
            friction_velocity_m_s: default_friction_velocity(),
        }
    }
}

/// Site data the line needs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Environment {
    /// Water depth (m); the seabed is the plane z = -depth.
    pub water_depth_m: f64,
    /// Sea water density (kg/m³).
    #[serde(default = "default_water_density")]
    pub water_density_kg_m3: f64,
    /// Gravitational acceleration (m/s²).
    #[serde(default = "default_gravity")]
    pub gravity_m_s2: f64,
    /// Seabed contact.
    #[serde(default)]
    pub seabed: SeabedSpec,
}

/// Sea water density when a file omits it (kg/m³).
pub(crate) fn default_water_density() -> f64 {
    1025.0
}

/// Standard gravity (m/s²) when a file omits it.
pub(crate) fn default_gravity() -> f64 {
    9.80665
}

/// End points of a line in the global frame (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineEnds {
    /// Fairlead position at the start of the analysis (m).
    pub fairlead_m: Vector3<f64>,
    /// Fixed anchor position (m).
    pub anchor_m: Vector3<f64>,
}

fn positive(field: String, v: f64) -> Result<(), LineError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(LineError::invalid(field, Num(v), "must be > 0"))
    }
}

fn non_negative(field: String, v: f64) -> Result<(), LineError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(LineError::invalid(field, Num(v), "must be >= 0"))
    }
}

impl LineTypeSpec {
    /// True when the type has bending stiffness (wire rope, Hermite cable elements).
    pub fn is_rope(&self) -> bool {
        self.bending_stiffness_nm2 > 0.0
    }

    fn validate(&self, path: &str) -> Result<(), LineError> {
        positive(format!("{path}.mass_kg_per_m"), self.mass_kg_per_m)?;
        non_negative(
            format!("{path}.submerged_weight_n_per_m"),
            self.submerged_weight_n_per_m,
        )?;
        positive(format!("{path}.axial_stiffness_n"), self.axial_stiffness_n)?;
        non_negative(
            format!("{path}.bending_stiffness_nm2"),
            self.bending_stiffness_nm2,
        )?;
        positive(
            format!("{path}.hydrodynamic_diameter_m"),
            self.hydrodynamic_diameter_m,
        )?;
        non_negative(format!("{path}.drag_normal"), self.drag_normal)?;
        non_negative(format!("{path}.drag_tangential"), self.drag_tangential)?;
        non_negative(format!("{path}.added_mass_normal"), self.added_mass_normal)?;
        non_negative(
            format!("{path}.added_mass_tangential"),
            self.added_mass_tangential,
        )?;
        Ok(())
    }
}

impl LineSpec {
    /// Checks every field; the error names the first offending one.
    pub fn validate(&self) -> Result<(), LineError> {
        for (name, t) in &self.line_types {
            t.validate(&format!("line_types.{name}"))?;
        }
        if self.segments.is_empty() {
            return Err(LineError::invalid(
                "segments",
                0,
                "must hold at least one segment",
            ));
        }
        for (i, s) in self.segments.iter().enumerate() {
            let path = format!("segments[{i}]");
            if !self.line_types.contains_key(&s.line_type) {
                return Err(LineError::invalid(
                    format!("{path}.type"),
                    &s.line_type,
                    "must name one of line_types",
                ));
            }
            positive(format!("{path}.length_m"), s.length_m)?;
            if s.elements == 0 || s.elements > MAX_SEGMENT_ELEMENTS {
                return Err(LineError::invalid(
                    format!("{path}.elements"),
                    s.elements,
                    &format!("must be from 1 to {MAX_SEGMENT_ELEMENTS}"),
                ));
            }
            if let Some(m) = s.extra_mass_kg {
                non_negative(format!("{path}.extra_mass_kg"), m)?;
            }
            if let Some(v) = s.extra_volume_m3 {
                non_negative(format!("{path}.extra_volume_m3"), v)?;
                if s.extra_mass_kg.is_none() {
                    return Err(LineError::invalid(
                        format!("{path}.extra_volume_m3"),
                        v,
                        "needs extra_mass_kg (the mass of the body that displaces it)",
                    ));
                }
            }
        }
        Ok(())
    }

    /// Total unstretched length (m).
    pub fn length_m(&self) -> f64 {
        self.segments.iter().map(|s| s.length_m).sum()
    }
}

impl Environment {
    /// Checks every field; the error names the first offending one.
    pub fn validate(&self) -> Result<(), LineError> {
        positive("water_depth_m".into(), self.water_depth_m)?;
        positive("water_density_kg_m3".into(), self.water_density_kg_m3)?;
        positive("gravity_m_s2".into(), self.gravity_m_s2)?;
        non_negative(
            "seabed.normal_stiffness_n_per_m2".into(),
            self.seabed.normal_stiffness_n_per_m2,
        )?;
        non_negative("seabed.damping_ratio".into(), self.seabed.damping_ratio)?;
        non_negative(
            "seabed.friction_coefficient".into(),
            self.seabed.friction_coefficient,
        )?;
        positive(
            "seabed.friction_velocity_m_s".into(),
            self.seabed.friction_velocity_m_s,
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rope() -> LineTypeSpec {
        LineTypeSpec {
            mass_kg_per_m: 16.5,
            submerged_weight_n_per_m: 140.6,
            axial_stiffness_n: 3.6e8,
            bending_stiffness_nm2: 8.0e4,
            bending_stiffness_min_nm2: None,
            torsional_stiffness_nm2: None,
            hydrodynamic_diameter_m: 0.0604,
            drag_normal: 1.2,
            drag_tangential: 0.008,
            added_mass_normal: 1.0,
            added_mass_tangential: 0.0,
            minimum_breaking_load_n: None,
        }
    }

    fn spec() -> LineSpec {
        LineSpec {
            line_types: [("rope".to_string(), rope())].into_iter().collect(),
            segments: vec![
                SegmentSpec {
                    name: "a".into(),
                    line_type: "rope".into(),
                    length_m: 10.0,
                    elements: 2,
                    extra_mass_kg: None,
                    extra_volume_m3: None,
                },
                SegmentSpec {
                    name: "b".into(),
                    line_type: "rope".into(),
                    length_m: 20.0,
                    elements: 4,
                    extra_mass_kg: Some(100.0),
                    extra_volume_m3: None,
                },
            ],
        }
    }

    #[test]
    fn valid_spec_passes_and_sums_length() {
        let s = spec();
        assert_eq!(s.validate(), Ok(()));
        assert_eq!(s.length_m(), 30.0);
    }

    /// A clump of given volume weighs (m − ρV) g in water; without a volume it is steel; the
    /// section carries the weight per metre of its segment.
    #[test]
    fn extra_mass_weighs_its_mass_less_its_displaced_water() {
        let env: Environment = serde_json::from_str(r#"{"water_depth_m": 100.0}"#).unwrap();
        let mut s = spec();
        let steel = s.segments[1].extra_submerged_weight_n(&env);
        let expected_steel = 100.0 * 9.80665 * (1.0 - 1025.0 / 7850.0);
        assert!((steel - expected_steel).abs() < 1e-12 * expected_steel);
        s.segments[1].extra_volume_m3 = Some(0.2);
        let buoy = s.segments[1].extra_submerged_weight_n(&env);
        assert!((buoy - (100.0 - 1025.0 * 0.2) * 9.80665).abs() < 1e-9);
        assert!(buoy < 0.0, "a 100 kg body of 0.2 m³ floats");
        let with_volume = super::super::section::Section::new(&rope(), &s.segments[1], &env);
        let bare = super::super::section::Section::new(&rope(), &s.segments[0], &env);
        assert!((with_volume.weight_n_per_m - (bare.weight_n_per_m + buoy / 20.0)).abs() < 1e-9);
        assert_eq!(with_volume.mass_kg_per_m, bare.mass_kg_per_m + 100.0 / 20.0);
        s.segments[1].extra_volume_m3 = Some(-1.0);
        let msg = s.validate().unwrap_err().to_string();
        assert!(
            msg.starts_with("segments[1].extra_volume_m3 must be >= 0"),
            "{msg}"
        );
        s.segments[0].extra_volume_m3 = Some(1.0);
        let msg = s.validate().unwrap_err().to_string();
        assert!(msg.starts_with("segments[0].extra_volume_m3"), "{msg}");
    }

    #[test]
    fn zero_segment_length_is_rejected_with_its_path() {
        let mut s = spec();
        s.segments[1].length_m = 0.0;
        let msg = s.validate().unwrap_err().to_string();
        assert_eq!(msg, "segments[1].length_m must be > 0 (got 0)");
    }

    #[test]
    fn unknown_type_and_negative_stiffness_are_rejected() {
        let mut s = spec();
        s.segments[0].line_type = "wire".into();
        assert!(s
            .validate()
            .unwrap_err()
            .to_string()
            .starts_with("segments[0].type"));
        let mut s = spec();
        s.line_types.get_mut("rope").unwrap().axial_stiffness_n = -1.0;
        let msg = s.validate().unwrap_err().to_string();
        assert!(
            msg.starts_with("line_types.rope.axial_stiffness_n must be > 0"),
            "{msg}"
        );
    }

    #[test]
    fn unknown_json_fields_are_rejected() {
        let json = r#"{"name":"a","type":"rope","length_m":1.0,"elements":1,"colour":"red"}"#;
        assert!(serde_json::from_str::<SegmentSpec>(json).is_err());
    }
}
