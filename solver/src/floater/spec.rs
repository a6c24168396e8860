//! Serde description of a floater (JSON, SI units, units in field names), as in
//! `campaigns/data/oc4_semi_floater.json`, and its validation into resolved member geometry.
//!
//! Frame: body axes coincide with the global axes in the undisplaced position, origin at the
//! reference point (on the still water level, on the main column axis for the OC4 platform), z up.
//! A member is a circular cylinder given either by its two end points (`from_m`, `to_m`) or, for
//! vertical columns, by the polar position of its axis (`centre_radius_m`, `azimuth_deg`, measured
//! from +x towards +y) and its vertical extent (`z_from_m`, `z_to_m`). Entries without geometry
//! (descriptions only) are rejected by validation with the member's field path.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::error::FloaterError;

/// Principal moments of inertia about the centre of mass, body axes (kg m²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrincipalInertia {
    /// About x (kg m²).
    pub roll: f64,
    /// About y (kg m²).
    pub pitch: f64,
    /// About z (kg m²).
    pub yaw: f64,
}

/// A rigid mass carried by the floater (tower, rotor-nacelle assembly, ...).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AttachedMassSpec {
    /// Name, for messages.
    pub name: String,
    /// Mass (kg).
    pub mass_kg: f64,
    /// Centre of mass in body axes (m).
    pub centre_of_mass_m: [f64; 3],
    /// Principal inertia about its own centre of mass (kg m²); zero (point mass) when absent.
    #[serde(default)]
    pub inertia_about_com_kg_m2: Option<PrincipalInertia>,
    /// Free-text provenance.
    #[serde(default)]
    pub note: Option<String>,
}

/// One cylindrical member for strip theory and hydrostatics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MemberSpec {
    /// Name, for messages.
    pub name: String,
    /// Outer diameter (m).
    pub diameter_m: f64,
    /// First end point, body axes (m).
    #[serde(default)]
    pub from_m: Option<[f64; 3]>,
    /// Second end point, body axes (m).
    #[serde(default)]
    pub to_m: Option<[f64; 3]>,
    /// Horizontal distance of a vertical column's axis from the body z axis (m).
    #[serde(default)]
    pub centre_radius_m: Option<f64>,
    /// Azimuth of a vertical column's axis, from +x towards +y (deg).
    #[serde(default)]
    pub azimuth_deg: Option<f64>,
    /// Lower end of a vertical column (m).
    #[serde(default)]
    pub z_from_m: Option<f64>,
    /// Upper end of a vertical column (m).
    #[serde(default)]
    pub z_to_m: Option<f64>,
    /// Transverse quadratic drag coefficient Cd (on the diameter).
    pub drag_coefficient: f64,
    /// Transverse added-mass coefficient Ca (on the displaced volume); 1.0 (two-dimensional
    /// potential flow round a circle) when absent.
    #[serde(default)]
    pub added_mass_coefficient: Option<f64>,
    /// Axial quadratic drag coefficient on the end area πD²/4 (heave plates).
    #[serde(default)]
    pub axial_drag_coefficient: Option<f64>,
    /// Axial added-mass coefficient on the circular-disc added mass ρD³/3 (heave plates).
    #[serde(default)]
    pub axial_added_mass_coefficient: Option<f64>,
    /// Areas of the `from` and `to` end faces exposed to the wave dynamic pressure (m²); the
    /// pressure on the `from` face pushes along +axis, on the `to` face along −axis.
    #[serde(default)]
    pub end_pressure_areas_m2: Option<[f64; 2]>,
    /// Free-text description.
    #[serde(default)]
    pub note: Option<String>,
}

/// Low-frequency added mass quoted for checking.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceAddedMass {
    /// Surge and sway (kg).
    pub surge_sway_kg: f64,
    /// Heave (kg).
    pub heave_kg: f64,
    /// Roll and pitch about the reference point (kg m²).
    pub roll_pitch_kg_m2: f64,
}

/// Natural periods quoted for checking (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferencePeriods {
    /// Surge (s).
    pub surge: f64,
    /// Heave (s).
    pub heave: f64,
    /// Pitch (s).
    pub pitch: f64,
}

/// Published values the model is checked against (not used by the computation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceValues {
    /// ρ g A_wp (N/m).
    pub hydrostatic_heave_stiffness_n_per_m: f64,
    /// ρ g (I_wp + V z_B) (N m/rad).
    pub hydrostatic_roll_pitch_stiffness_nm_per_rad_without_gravity_terms: f64,
    /// Low-frequency added mass.
    pub low_frequency_added_mass: ReferenceAddedMass,
    /// Natural periods with the OC4 moorings.
    pub natural_periods_s_with_oc4_moorings: ReferencePeriods,
    /// Free-text provenance.
    #[serde(default)]
    pub note: Option<String>,
}

/// The floater description as read from JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloaterSpec {
    /// Free-text provenance.
    #[serde(rename = "_about", default)]
    pub about: Option<String>,
    /// Platform mass, ballast included (kg).
    pub mass_kg: f64,
    /// Platform centre of mass, body axes (m).
    pub centre_of_mass_m: [f64; 3],
    /// Platform principal inertia about its centre of mass (kg m²).
    pub inertia_about_com_kg_m2: PrincipalInertia,
    /// Displaced volume stated by the source (m³); checked against the member geometry.
    pub displaced_volume_m3: f64,
    /// Rigid masses carried by the platform (tower, rotor-nacelle assembly).
    #[serde(default)]
    pub attached_masses: Vec<AttachedMassSpec>,
    /// Hub height above the reference point, where the rotor thrust acts (m).
    #[serde(default)]
    pub hub_height_m: Option<f64>,
    /// Water density (kg/m³); 1025 when absent.
    #[serde(default)]
    pub water_density_kg_m3: Option<f64>,
    /// Acceleration of gravity (m/s²); 9.80665 when absent.
    #[serde(default)]
    pub gravity_m_per_s2: Option<f64>,
    /// Target strip length for strip theory (m); 1.0 when absent.
    #[serde(default)]
    pub strip_length_m: Option<f64>,
    /// Additional linear damping matrix about the reference point, body axes, rows/columns
    /// (surge, sway, heave, roll, pitch, yaw) in N s/m, N s, N m s/rad.
    #[serde(default)]
    pub linear_damping: Option<[[f64; 6]; 6]>,
    /// Cylindrical members.
    pub members: Vec<MemberSpec>,
    /// Published values for checking.
    #[serde(default)]
    pub reference_values_for_checking: Option<ReferenceValues>,
    /// How the source geometry was rotated.
    #[serde(default)]
    pub note_rotation: Option<String>,
}

/// A member with resolved, validated geometry and coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedMember {
    /// Name.
    pub name: String,
    /// Diameter (m).
    pub diameter_m: f64,
    /// First end, body axes (m).
    pub from_m: Vector3<f64>,
    /// Second end, body axes (m).
    pub to_m: Vector3<f64>,
    /// Transverse drag coefficient.
    pub drag_coefficient: f64,
    /// Transverse added-mass coefficient.
    pub added_mass_coefficient: f64,
    /// Axial drag coefficient.
    pub axial_drag_coefficient: f64,
    /// Axial added-mass coefficient.
    pub axial_added_mass_coefficient: f64,
    /// Exposed end areas (m²), `from` then `to`.
    pub end_pressure_areas_m2: [f64; 2],
}

impl FloaterSpec {
    /// Parses a JSON document (unknown fields are errors).
    pub fn from_json_str(text: &str) -> Result<Self, FloaterError> {
        serde_json::from_str(text).map_err(|e| FloaterError::Json {
            message: e.to_string(),
        })
    }

    /// Water density (kg/m³).
    pub(crate) fn water_density(&self) -> f64 {
        self.water_density_kg_m3.unwrap_or(1025.0)
    }

    /// Gravity (m/s²).
    pub fn gravity(&self) -> f64 {
        self.gravity_m_per_s2.unwrap_or(9.80665)
    }

    /// Strip length (m).
    pub(crate) fn strip_length(&self) -> f64 {
        self.strip_length_m.unwrap_or(1.0)
    }

    /// Checks every field and resolves the member geometry; errors name the field.
    pub(crate) fn resolve_members(&self) -> Result<Vec<ResolvedMember>, FloaterError> {
        positive("mass_kg", self.mass_kg)?;
        for (k, v) in self.centre_of_mass_m.iter().enumerate() {
            finite(&format!("centre_of_mass_m[{k}]"), *v)?;
        }
        let i = &self.inertia_about_com_kg_m2;
        positive("inertia_about_com_kg_m2.roll", i.roll)?;
        positive("inertia_about_com_kg_m2.pitch", i.pitch)?;
        positive("inertia_about_com_kg_m2.yaw", i.yaw)?;
        positive("displaced_volume_m3", self.displaced_volume_m3)?;
        positive("water_density_kg_m3", self.water_density())?;
        positive("gravity_m_per_s2", self.gravity())?;
        positive("strip_length_m", self.strip_length())?;
        if let Some(h) = self.hub_height_m {
            finite("hub_height_m", h)?;
        }
        if let Some(b) = &self.linear_damping {
            for (r, row) in b.iter().enumerate() {
                for (c, v) in row.iter().enumerate() {
                    finite(&format!("linear_damping[{r}][{c}]"), *v)?;
                }
            }
        }
        for (k, m) in self.attached_masses.iter().enumerate() {
            positive(&format!("attached_masses[{k}].mass_kg"), m.mass_kg)?;
            for (j, v) in m.centre_of_mass_m.iter().enumerate() {
                finite(&format!("attached_masses[{k}].centre_of_mass_m[{j}]"), *v)?;
            }
            if let Some(i) = &m.inertia_about_com_kg_m2 {
                for (name, v) in [("roll", i.roll), ("pitch", i.pitch), ("yaw", i.yaw)] {
                    non_negative(
                        &format!("attached_masses[{k}].inertia_about_com_kg_m2.{name}"),
                        v,
                    )?;
                }
            }
        }
        if self.members.is_empty() {
            return Err(FloaterError::field(
                "members",
                "[]",
                "at least one member is needed",
            ));
        }
        self.members
            .iter()
            .enumerate()
            .map(|(k, m)| resolve_member(k, m))
            .collect()
    }
}

fn resolve_member(k: usize, m: &MemberSpec) -> Result<ResolvedMember, FloaterError> {
    let path = |f: &str| format!("members[{k}].{f}");
    positive(&path("diameter_m"), m.diameter_m)?;
    non_negative(&path("drag_coefficient"), m.drag_coefficient)?;
    let ca = m.added_mass_coefficient.unwrap_or(1.0);
    non_negative(&path("added_mass_coefficient"), ca)?;
    let cd_ax = m.axial_drag_coefficient.unwrap_or(0.0);
    non_negative(&path("axial_drag_coefficient"), cd_ax)?;
    let ca_ax = m.axial_added_mass_coefficient.unwrap_or(0.0);
    non_negative(&path("axial_added_mass_coefficient"), ca_ax)?;
    let ends = m.end_pressure_areas_m2.unwrap_or([0.0, 0.0]);
    non_negative(&path("end_pressure_areas_m2[0]"), ends[0])?;
    non_negative(&path("end_pressure_areas_m2[1]"), ends[1])?;

    let column = (m.centre_radius_m, m.azimuth_deg, m.z_from_m, m.z_to_m);
    let (from, to) = match (m.from_m, m.to_m, column) {
        (Some(a), Some(b), (None, None, None, None)) => (Vector3::from(a), Vector3::from(b)),
        (None, None, (Some(r), Some(az), Some(z0), Some(z1))) => {
            non_negative(&path("centre_radius_m"), r)?;
            finite(&path("azimuth_deg"), az)?;
            let (s, c) = az.to_radians().sin_cos();
            (Vector3::new(r * c, r * s, z0), Vector3::new(r * c, r * s, z1))
        }
        _ => {
            return Err(FloaterError::field(
                path("from_m"),
                format!("{:?}", m.from_m),
                format!(
                    "member '{}' needs either from_m and to_m, or centre_radius_m, azimuth_deg, z_from_m and z_to_m (and not both)",
                    m.name
                ),
            ))
        }
    };
    for (j, v) in from.iter().chain(to.iter()).enumerate() {
        let f = if j < 3 {
            format!("from_m[{j}]")
        } else {
            format!("to_m[{}]", j - 3)
        };
        finite(&path(&f), *v)?;
    }
    let length = (to - from).norm();
    if length <= 1e-9 * m.diameter_m.max(1.0) {
        return Err(FloaterError::field(
            path("to_m"),
            format!("{:?}", to.as_slice()),
            "member has zero length",
        ));
    }
    Ok(ResolvedMember {
        name: m.name.clone(),
        diameter_m: m.diameter_m,
        from_m: from,
        to_m: to,
        drag_coefficient: m.drag_coefficient,
        added_mass_coefficient: ca,
        axial_drag_coefficient: cd_ax,
        axial_added_mass_coefficient: ca_ax,
        end_pressure_areas_m2: ends,
    })
}

fn finite(field: &str, v: f64) -> Result<(), FloaterError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(FloaterError::field(field, v, "must be finite"))
    }
}

fn positive(field: &str, v: f64) -> Result<(), FloaterError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(FloaterError::field(field, v, "must be > 0"))
    }
}

fn non_negative(field: &str, v: f64) -> Result<(), FloaterError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(FloaterError::field(field, v, "must be >= 0"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const OC4: &str = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../campaigns/data/oc4_semi_floater.json"
    ));

    #[test]
    fn oc4_file_loads_and_resolves_every_member() {
        let spec = FloaterSpec::from_json_str(OC4).unwrap();
        let members = spec.resolve_members().unwrap();
        assert_eq!(members.len(), spec.members.len());
        // Offset column 1 sits on +x after the file's 180° rotation.
        let col = members.iter().find(|m| m.name == "upper_column_1").unwrap();
        assert!((col.from_m - Vector3::new(28.868, 0.0, -14.0)).norm() < 1e-12);
    }

    #[test]
    fn unknown_field_is_rejected() {
        let text = OC4.replacen("\"mass_kg\"", "\"mass_kgs\": 1.0, \"mass_kg\"", 1);
        let err = FloaterSpec::from_json_str(&text).unwrap_err();
        assert!(
            matches!(&err, FloaterError::Json { message } if message.contains("mass_kgs")),
            "{err}"
        );
    }

    #[test]
    fn negative_diameter_error_names_the_member_field() {
        let mut spec = FloaterSpec::from_json_str(OC4).unwrap();
        spec.members[2].diameter_m = -1.0;
        let err = spec.resolve_members().unwrap_err();
        assert!(
            matches!(&err, FloaterError::InvalidField { field, .. } if field == "members[2].diameter_m"),
            "{err}"
        );
    }

    #[test]
    fn member_without_geometry_is_rejected_with_its_path() {
        let mut spec = FloaterSpec::from_json_str(OC4).unwrap();
        spec.members[1].from_m = None;
        spec.members[1].to_m = None;
        spec.members[1].centre_radius_m = None;
        let err = spec.resolve_members().unwrap_err();
        assert!(
            matches!(&err, FloaterError::InvalidField { field, .. } if field == "members[1].from_m"),
            "{err}"
        );
    }
}
