//! The case description of one global run: site, sea state, timing, floater, mooring layout,
//! hot spots and wind, as read from a case JSON file (serde, `deny_unknown_fields`, units in the
//! field names).
//!
//! File paths in the case (floater description, prescribed motion table) are kept as written;
//! the caller resolves them relative to the case file and passes the parsed content to
//! [`super::system::GlobalModel::new`], so this module never touches the file system.
//!
//! Layout convention (seed, Sec. 3.1 and Table 1): line `i` leaves its fairlead on a circle of
//! radius `fairlead_radius_m` around the body z axis, `fairlead_depth_m` below the still water
//! level, at azimuth φᵢ (deg, from +x towards +y); its anchor lies on the seabed at the
//! horizontal distance `anchor_horizontal_distance_m` from the fairlead, radially outwards along
//! φᵢ. Arc lengths are measured from the fairlead.
//!
//! [`CaseSpec::validate`] checks every field before anything runs; errors carry the field path,
//! e.g. `mooring.segments[1].length_m must be > 0 (got -3)`.

use std::collections::BTreeMap;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::error::GlobalError;
use crate::mooring::spec::{
    default_gravity, default_water_density, Environment, LineEnds, LineSpec, LineTypeSpec,
    SeabedSpec, SegmentSpec,
};
use crate::text::Num;
use crate::waves::spectrum::PeakEnhancement;
use crate::waves::RealisationParams;

/// A whole global-stage case.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    /// Free-text provenance.
    #[serde(rename = "_about", default, skip_serializing_if = "Option::is_none")]
    pub about: Option<String>,
    /// Case name, used in outputs.
    pub name: String,
    /// Water depth, density and seabed.
    pub site: SiteSpec,
    /// Irregular sea state; absent (or `hs_m: 0`) means calm water, no waves.
    #[serde(default, skip_serializing_if = "SeaStateSpec::is_calm")]
    pub sea_state: SeaStateSpec,
    /// Time integration and output settings.
    pub timing: TimingSpec,
    /// Floater model or prescribed motion.
    pub floater: FloaterSource,
    /// Line types, segments and layout.
    pub mooring: MooringSpec,
    /// Points along the lines where T(t) and κ(t) are recorded.
    pub hot_spots: Vec<HotSpotSpec>,
    /// Steady rotor thrust.
    pub wind: WindSpec,
}

/// Site data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SiteSpec {
    /// Water depth (m).
    pub water_depth_m: f64,
    /// Sea water density (kg/m³).
    #[serde(default = "default_water_density")]
    pub water_density_kg_m3: f64,
    /// Gravitational acceleration (m/s²).
    #[serde(default = "default_gravity")]
    pub gravity_m_s2: f64,
    /// Seabed contact of the lines.
    #[serde(default)]
    pub seabed: SeabedSpec,
}

/// JONSWAP peak enhancement: a number, or `"dnv"` for the DNV-RP-C205 default from Tp/√Hs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum GammaSpec {
    /// γ given.
    Value(f64),
    /// `"dnv"`.
    Rule(String),
}

/// Irregular sea state. `hs_m: 0` (or no `sea_state` at all) is calm water: no waves, the other
/// fields unused.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeaStateSpec {
    /// Significant wave height (m); 0 for calm water.
    pub hs_m: f64,
    /// Peak period (s); required when `hs_m > 0`.
    #[serde(default)]
    pub tp_s: f64,
    /// Peak enhancement factor γ or `"dnv"` (DNV-RP-C205 from Tp/√Hs, the default).
    #[serde(default = "dnv_gamma")]
    pub gamma: GammaSpec,
    /// Seed of the random realisation.
    #[serde(default)]
    pub seed: u64,
    /// Wave heading (deg, from +x towards +y).
    #[serde(default)]
    pub heading_deg: f64,
}

fn dnv_gamma() -> GammaSpec {
    GammaSpec::Rule("dnv".into())
}

impl Default for SeaStateSpec {
    /// Calm water.
    fn default() -> Self {
        Self {
            hs_m: 0.0,
            tp_s: 0.0,
            gamma: dnv_gamma(),
            seed: 0,
            heading_deg: 0.0,
        }
    }
}

impl SeaStateSpec {
    /// True for calm water (no waves).
    pub fn is_calm(&self) -> bool {
        self.hs_m == 0.0
    }
}

/// Time integration and output settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimingSpec {
    /// Start-up time discarded from the outputs (s); the paper uses 50 s.
    pub transient_s: f64,
    /// Recorded duration after the transient (s); the paper uses 1000 s.
    pub duration_s: f64,
    /// Time step of the implicit integration (s).
    pub time_step_s: f64,
    /// Sampling interval of the output series (s).
    pub output_interval_s: f64,
    /// Time over which the wave loads are ramped up from zero (s), within the transient.
    #[serde(default = "default_ramp")]
    pub wave_ramp_s: f64,
    /// Spectral radius ρ∞ of the generalised-α method; the line integrator's default (0, the
    /// most dissipative) when omitted.
    #[serde(default = "default_rho")]
    pub spectral_radius: f64,
}

fn default_ramp() -> f64 {
    20.0
}

fn default_rho() -> f64 {
    crate::mooring::dynamics::DynamicParams::default().spectral_radius
}

/// Where the floater motion comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum FloaterSource {
    /// A rigid body with strip-theory hydrodynamics described by a floater JSON file.
    RigidBody {
        /// Path of the floater description, relative to the case file.
        spec_path: String,
    },
    /// A 6-DOF motion table (`time_s,surge_m,…,yaw_rad`). Simulation time is the table's
    /// time: the statics take the pose at t = 0 and the table must cover t = 0 to
    /// `transient_s + duration_s`.
    PrescribedMotion {
        /// Path of the CSV table, relative to the case file.
        csv_path: String,
    },
}

/// One line of the layout.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineLayoutSpec {
    /// Line number used by hot spots and outputs.
    pub id: u32,
    /// Azimuth of the fairlead (deg, from +x towards +y).
    pub fairlead_azimuth_deg: f64,
}

/// Mooring system: one line make-up shared by all lines, and the layout.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MooringSpec {
    /// Line types by name.
    pub line_types: BTreeMap<String, LineTypeSpec>,
    /// Segments from the fairlead to the anchor.
    pub segments: Vec<SegmentSpec>,
    /// Fairlead radius from the body z axis (m); 0 puts every fairlead on the axis.
    pub fairlead_radius_m: f64,
    /// Fairlead depth below the still water level (m).
    pub fairlead_depth_m: f64,
    /// Horizontal distance from fairlead to anchor (m).
    pub anchor_horizontal_distance_m: f64,
    /// The lines.
    pub lines: Vec<LineLayoutSpec>,
}

/// A hot spot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HotSpotSpec {
    /// Line id.
    pub line: u32,
    /// Arc length from the fairlead (m).
    pub arc_length_m: f64,
}

/// Rotor thrust: the NREL 5 MW table (or a given one) scaled, at the wind speed of the sea state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindSpec {
    /// Hub wind speed: `{"FullyDevelopedSea": {...}}`, `{"Table": {...}}`
    /// ([`crate::waves::WindLaw`]), or absent together with `wind_speed_m_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<crate::waves::WindLaw>,
    /// Hub wind speed given directly (m/s); overrides `law`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind_speed_m_s: Option<f64>,
    /// Thrust table; the built-in NREL 5 MW table when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thrust_table: Option<ThrustTableSpec>,
    /// Scale of the thrust (0.72 for the paper's 3.6 MW turbine).
    #[serde(default = "one")]
    pub thrust_scale: f64,
}

fn one() -> f64 {
    1.0
}

/// Thrust versus hub wind speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThrustTableSpec {
    /// Wind speeds (m/s), increasing.
    pub wind_m_s: Vec<f64>,
    /// Thrust (kN).
    pub thrust_kn: Vec<f64>,
}

/// Most time steps a run may take (10⁸: about 116 days at the paper's 0.1 s).
const MAX_STEPS: f64 = 1e8;

fn invalid(field: impl Into<String>, value: impl std::fmt::Display, reason: &str) -> GlobalError {
    GlobalError::InvalidCase {
        field: field.into(),
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

fn positive(field: &str, v: f64) -> Result<(), GlobalError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, Num(v), "must be > 0"))
    }
}

fn non_negative(field: &str, v: f64) -> Result<(), GlobalError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, Num(v), "must be >= 0"))
    }
}

/// Re-roots a line-model field error under `prefix`.
fn line_field(prefix: &str, e: crate::mooring::LineError) -> GlobalError {
    match e {
        crate::mooring::LineError::InvalidInput {
            field,
            value,
            reason,
        } => GlobalError::InvalidCase {
            field: format!("{prefix}.{field}"),
            value,
            reason,
        },
        other => GlobalError::Line {
            line: 0,
            source: Box::new(other),
        },
    }
}

impl CaseSpec {
    /// Parses a case JSON document.
    pub fn from_json_str(text: &str) -> Result<Self, GlobalError> {
        serde_json::from_str(text).map_err(|e| GlobalError::CaseJson {
            message: e.to_string(),
        })
    }

    /// Checks every field; the error names the first offending one by its path.
    pub fn validate(&self) -> Result<(), GlobalError> {
        positive("site.water_depth_m", self.site.water_depth_m)?;
        self.environment()
            .validate()
            .map_err(|e| line_field("site", e))?;
        let s = &self.sea_state;
        non_negative("sea_state.hs_m", s.hs_m)?;
        if !s.is_calm() {
            if !(s.hs_m * s.hs_m).is_normal() {
                return Err(invalid(
                    "sea_state.hs_m",
                    s.hs_m,
                    "must be 0 (calm water) or above 1.5e-154 m (Hs² underflows)",
                ));
            }
            if !(s.tp_s.is_finite() && s.tp_s > 0.0) {
                return Err(invalid(
                    "sea_state.tp_s",
                    s.tp_s,
                    "must be > 0 when sea_state.hs_m > 0",
                ));
            }
            if !s.heading_deg.is_finite() {
                return Err(invalid(
                    "sea_state.heading_deg",
                    s.heading_deg,
                    "must be finite",
                ));
            }
            self.peak_enhancement()?;
        }
        let t = &self.timing;
        non_negative("timing.transient_s", t.transient_s)?;
        positive("timing.duration_s", t.duration_s)?;
        positive("timing.time_step_s", t.time_step_s)?;
        positive("timing.output_interval_s", t.output_interval_s)?;
        non_negative("timing.wave_ramp_s", t.wave_ramp_s)?;
        if t.time_step_s > t.output_interval_s + 1e-12 {
            return Err(invalid(
                "timing.time_step_s",
                t.time_step_s,
                "must not exceed timing.output_interval_s",
            ));
        }
        let steps = (t.transient_s + t.duration_s) / t.time_step_s;
        if steps > MAX_STEPS {
            return Err(invalid(
                "timing.duration_s",
                Num(t.duration_s),
                &format!(
                    "with timing.transient_s and timing.time_step_s gives {} steps, more than {}",
                    Num(steps.floor()),
                    Num(MAX_STEPS)
                ),
            ));
        }
        if !(0.0..=1.0).contains(&t.spectral_radius) {
            return Err(invalid(
                "timing.spectral_radius",
                t.spectral_radius,
                "must be in [0, 1]",
            ));
        }
        let m = &self.mooring;
        self.line_spec()
            .validate()
            .map_err(|e| line_field("mooring", e))?;
        non_negative("mooring.fairlead_radius_m", m.fairlead_radius_m)?;
        non_negative("mooring.fairlead_depth_m", m.fairlead_depth_m)?;
        if m.fairlead_depth_m >= self.site.water_depth_m {
            return Err(invalid(
                "mooring.fairlead_depth_m",
                m.fairlead_depth_m,
                "must be less than site.water_depth_m",
            ));
        }
        positive(
            "mooring.anchor_horizontal_distance_m",
            m.anchor_horizontal_distance_m,
        )?;
        let length = self.line_spec().length_m();
        let reach = m
            .anchor_horizontal_distance_m
            .hypot(self.site.water_depth_m - m.fairlead_depth_m);
        if reach >= length {
            return Err(invalid(
                "mooring.anchor_horizontal_distance_m",
                m.anchor_horizontal_distance_m,
                &format!(
                    "puts the anchor out of reach: the fairlead-anchor distance {reach:.1} m must \
                     be less than the line length {length:.1} m"
                ),
            ));
        }
        if m.lines.is_empty() {
            return Err(invalid("mooring.lines", 0, "must hold at least one line"));
        }
        for (i, l) in m.lines.iter().enumerate() {
            if !l.fairlead_azimuth_deg.is_finite() {
                return Err(invalid(
                    format!("mooring.lines[{i}].fairlead_azimuth_deg"),
                    l.fairlead_azimuth_deg,
                    "must be finite",
                ));
            }
            if m.lines[..i].iter().any(|o| o.id == l.id) {
                return Err(invalid(
                    format!("mooring.lines[{i}].id"),
                    l.id,
                    "must be unique",
                ));
            }
        }
        for (i, h) in self.hot_spots.iter().enumerate() {
            if !m.lines.iter().any(|l| l.id == h.line) {
                return Err(invalid(
                    format!("hot_spots[{i}].line"),
                    h.line,
                    "must name a line id of mooring.lines",
                ));
            }
            if !(h.arc_length_m.is_finite() && (0.0..=length).contains(&h.arc_length_m)) {
                return Err(invalid(
                    format!("hot_spots[{i}].arc_length_m"),
                    h.arc_length_m,
                    &format!("must be in [0, {length}] m"),
                ));
            }
        }
        let w = &self.wind;
        positive("wind.thrust_scale", w.thrust_scale)?;
        if let Some(u) = w.wind_speed_m_s {
            non_negative("wind.wind_speed_m_s", u)?;
        }
        if let Some(tab) = &w.thrust_table {
            if tab.wind_m_s.len() != tab.thrust_kn.len() || tab.wind_m_s.len() < 2 {
                return Err(invalid(
                    "wind.thrust_table.thrust_kn",
                    format!("{} values", tab.thrust_kn.len()),
                    "must have as many values as wind_m_s, at least two",
                ));
            }
        }
        Ok(())
    }

    /// Site data for the line models.
    pub fn environment(&self) -> Environment {
        Environment {
            water_depth_m: self.site.water_depth_m,
            water_density_kg_m3: self.site.water_density_kg_m3,
            gravity_m_s2: self.site.gravity_m_s2,
            seabed: self.site.seabed.clone(),
        }
    }

    /// The line make-up shared by all lines.
    pub fn line_spec(&self) -> LineSpec {
        LineSpec {
            line_types: self.mooring.line_types.clone(),
            segments: self.mooring.segments.clone(),
        }
    }

    /// The settings of the sea's realisation over the whole run (transient and record), with
    /// the components above `cut_off_rad_s` dropped.
    pub fn realisation_params(&self, cut_off_rad_s: Option<f64>) -> RealisationParams {
        let s = &self.sea_state;
        RealisationParams {
            duration_s: self.timing.transient_s + self.timing.duration_s,
            seed: s.seed,
            heading_rad: s.heading_deg.to_radians(),
            depth_m: self.site.water_depth_m,
            water_density_kg_m3: self.site.water_density_kg_m3,
            cut_off_rad_s,
            ..RealisationParams::default()
        }
    }

    /// JONSWAP peak enhancement.
    pub fn peak_enhancement(&self) -> Result<PeakEnhancement, GlobalError> {
        match &self.sea_state.gamma {
            GammaSpec::Value(g) if g.is_finite() && (1.0..=7.0).contains(g) => {
                Ok(PeakEnhancement::Given(*g))
            }
            GammaSpec::Value(g) => Err(invalid("sea_state.gamma", g, "must be in [1, 7]")),
            GammaSpec::Rule(r) if r.eq_ignore_ascii_case("dnv") => Ok(PeakEnhancement::DnvDefault),
            GammaSpec::Rule(r) => Err(invalid("sea_state.gamma", r, "must be a number or \"dnv\"")),
        }
    }

    /// Fairlead of line `k` in body axes (reference point on the still water level).
    pub(crate) fn fairlead_body_point(&self, k: usize) -> Vector3<f64> {
        let m = &self.mooring;
        let (s, c) = m.lines[k].fairlead_azimuth_deg.to_radians().sin_cos();
        Vector3::new(
            m.fairlead_radius_m * c,
            m.fairlead_radius_m * s,
            -m.fairlead_depth_m,
        )
    }

    /// Anchor of line `k` (global, m).
    pub fn anchor(&self, k: usize) -> Vector3<f64> {
        let m = &self.mooring;
        let (s, c) = m.lines[k].fairlead_azimuth_deg.to_radians().sin_cos();
        let r = m.fairlead_radius_m + m.anchor_horizontal_distance_m;
        Vector3::new(r * c, r * s, -self.site.water_depth_m)
    }

    /// Ends of line `k` for the undisplaced floater.
    pub fn line_ends(&self, k: usize) -> LineEnds {
        LineEnds {
            fairlead_m: self.fairlead_body_point(k),
            anchor_m: self.anchor(k),
        }
    }

    /// Index of the line with id `id`.
    pub fn line_index(&self, id: u32) -> Option<usize> {
        self.mooring.lines.iter().position(|l| l.id == id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper_case() -> CaseSpec {
        let text = include_str!("../../../campaigns/paper_case.json");
        CaseSpec::from_json_str(text).unwrap()
    }

    #[test]
    fn paper_case_file_parses_and_validates() {
        let c = paper_case();
        assert_eq!(c.validate(), Ok(()));
        assert_eq!(c.mooring.lines.len(), 6);
        assert_eq!(c.line_spec().length_m(), 572.0);
        assert_eq!(c.sea_state.hs_m, 8.75);
        assert_eq!(c.peak_enhancement(), Ok(PeakEnhancement::Given(1.3)));
    }

    #[test]
    fn non_physical_input_names_the_field() {
        let mut c = paper_case();
        c.sea_state.tp_s = 0.0;
        let e = c.validate().unwrap_err().to_string();
        assert!(e.starts_with("sea_state.tp_s must be > 0"), "{e}");
        let mut c = paper_case();
        c.timing.duration_s = 1e300;
        let e = c.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("timing.duration_s with timing.transient_s and timing.time_step_s gives")
                && e.ends_with("(got 1e300)"),
            "{e}"
        );
        let mut c = paper_case();
        c.mooring.segments[1].length_m = -3.0;
        let e = c.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("mooring.segments[1].length_m must be > 0"),
            "{e}"
        );
        let mut c = paper_case();
        c.mooring.anchor_horizontal_distance_m = 600.0;
        let e = c.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("mooring.anchor_horizontal_distance_m puts the anchor out of reach"),
            "{e}"
        );
        let mut c = paper_case();
        c.hot_spots[0].line = 9;
        let e = c.validate().unwrap_err().to_string();
        assert!(e.starts_with("hot_spots[0].line"), "{e}");
    }

    #[test]
    fn gamma_accepts_dnv_and_rejects_other_words() {
        let mut c = paper_case();
        c.sea_state.gamma = GammaSpec::Rule("dnv".into());
        assert_eq!(c.peak_enhancement(), Ok(PeakEnhancement::DnvDefault));
        c.sea_state.gamma = GammaSpec::Rule("high".into());
        assert!(c
            .validate()
            .unwrap_err()
            .to_string()
            .starts_with("sea_state.gamma"));
    }

    /// One default per setting: the paper case with every setting that equals its default
    /// left out resolves to the same case as the file that writes them all.
    #[test]
    fn omitted_settings_resolve_to_the_written_defaults() {
        let full: serde_json::Value =
            serde_json::from_str(include_str!("../../../campaigns/paper_case.json")).unwrap();
        let mut minimal = full.clone();
        for (section, key) in [
            ("site", "water_density_kg_m3"),
            ("site", "gravity_m_s2"),
            ("site", "seabed"),
            ("sea_state", "heading_deg"),
            ("timing", "wave_ramp_s"),
            ("timing", "spectral_radius"),
        ] {
            let removed = minimal[section].as_object_mut().unwrap().remove(key);
            assert!(removed.is_some(), "{section}.{key} is in the full case");
        }
        let parse = |v: &serde_json::Value| CaseSpec::from_json_str(&v.to_string()).unwrap();
        assert_eq!(parse(&minimal), parse(&full));
        // The line integrator, the mooring site and the case agree on their shared defaults.
        let minimal = parse(&minimal);
        assert_eq!(
            minimal.timing.spectral_radius,
            crate::mooring::dynamics::DynamicParams::default().spectral_radius
        );
        let site: Environment = serde_json::from_str(r#"{"water_depth_m": 100.0}"#).unwrap();
        assert_eq!(site, minimal.environment());
        // Calm water: no sea_state at all, or only hs_m = 0.
        let mut calm = full.clone();
        calm.as_object_mut().unwrap().remove("sea_state");
        let mut zero = full;
        zero["sea_state"] = serde_json::json!({"hs_m": 0.0});
        assert_eq!(parse(&calm).sea_state, parse(&zero).sea_state);
        assert!(parse(&calm).sea_state.is_calm());
    }

    #[test]
    fn unknown_fields_are_rejected() {
        let text = include_str!("../../../campaigns/paper_case.json").replacen(
            "\"name\"",
            "\"colour\": 1, \"name\"",
            1,
        );
        assert!(CaseSpec::from_json_str(&text).is_err());
    }

    #[test]
    fn anchors_lie_radially_outside_the_fairleads_on_the_seabed() {
        let c = paper_case();
        for k in 0..c.mooring.lines.len() {
            let e = c.line_ends(k);
            let d = e.anchor_m - e.fairlead_m;
            assert!((d.xy().norm() - c.mooring.anchor_horizontal_distance_m).abs() < 1e-9);
            assert!((e.anchor_m.z + c.site.water_depth_m).abs() < 1e-12);
            assert!(d.xy().dot(&e.fairlead_m.xy()) > 0.0);
        }
    }
}
