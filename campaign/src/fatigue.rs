//! Fretting and fatigue settings of a campaign (`"fatigue"` in the campaign file, every field
//! optional) and the damage-input configuration a strand job derives from them and from the
//! strand profile (`docs/damage.md`, [`moorfret_solver::damage::sea_state_damage_inputs`]).
//!
//! What comes from where:
//! - Hertz geometry of each layer interface: the wire radii of the two layers and the angle
//!   between their tangents at a contact. At a crossing the two wire axes are radially aligned
//!   ([`moorfret_solver::strand::contacts`]), so both tangents lie in the same tangent plane of
//!   the strand cross-section, at the signed lay angles h·α of their layers from the strand axis
//!   (h = ±1 the hand, α = 0 for the straight core): the crossing angle is |h₂α₂ − h₁α₁|.
//!   Elastic constants and the friction coefficient are the strand model's, so that the
//!   indicators use the same contact as the finite-element run.
//! - Wire axial stress σ = T / A with A = EA / E (the rope's axial stiffness at the hot spot over
//!   the wire modulus): the stress of a straight wire at the strand strain ε = T / EA that the
//!   strand stage applies.
//! - T-N curves: the configured ones; by default the DNV-OS-E301 (2013, Ch.2 Sec.2 Table 6)
//!   spiral-rope curve on the nominal area πD²/4 of the hot spot's line type and, when the line
//!   type gives a minimum breaking load, the API RP 2SK spiral-strand curve on it. D is the line
//!   type's hydrodynamic diameter, taken as the rope's nominal diameter: an assumption, since
//!   a volume-equivalent diameter is somewhat smaller than the nominal one (the nominal stress
//!   range, hence the DNV damage, is then on the high side).
//! - Run-in: the start of each strand history is left out of every statistic (the paper's
//!   Fig. 22 shows a mean-slip drift over about the first 100 s). Each strand job detects where
//!   the slip of every slip monitor, less the part that follows the load (axial strain and
//!   curvature), stops drifting ([`RunInDetection`],
//!   `moorfret_solver::fretting::detect_set_run_in`) and stores it; the statistics leave out
//!   that run-in, or `run_in_s` when given (a fixed override). A history that never
//!   stabilises keeps every sample (transient slips are the larger ones, so this errs on the
//!   safe side) and says so in its job result.

use moorfret_solver::damage::{DamageInputsConfig, FrettingLaw, NamedTnCurve};
use moorfret_solver::fatigue::{rope_nominal_area_m2, ApiComponent, DnvComponent, TnCurve};
use moorfret_solver::fretting::life::{ContactStressLaw, StrainLife, WireSurface};
use moorfret_solver::fretting::{
    detect_set_run_in, BinEdges, CrossedCylinders, ElasticMaterial, ForceMeasure, FrettingParams,
    FrettingSnLaw, RegimeCriterion, RunInParams,
};
use moorfret_solver::mooring::spec::LineTypeSpec;
use moorfret_solver::strand::history::monitors::{MonitorChannel, MonitorQuantity, MonitorSeries};
use moorfret_solver::strand::profile::Strand;
use serde::{Deserialize, Serialize};

use crate::error::CampaignError;

/// Fretting measure names stored in `sea_state_class_damage_inputs`: the campaign's fretting
/// law (most damaged contact of a class, mean over its contacts), then the rope S-N law per
/// slip cycle beside it.
pub const FRETTING_MEASURES: [&str; 4] = [
    "fretting_max",
    "fretting_mean",
    "rope_tn_max",
    "rope_tn_mean",
];

/// Fretting and fatigue settings; every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FatigueSpec {
    /// Slip amplitude bin edges of the per-class cycle histograms (m), increasing.
    pub slip_amplitude_edges_m: Vec<f64>,
    /// Normal force bin edges of the per-class cycle histograms (N), increasing.
    pub normal_force_edges_n: Vec<f64>,
    /// Fretting regime criterion (default: Mindlin, no stick range).
    pub regime: RegimeCriterion,
    /// Normal force of a cycle that sizes its Hertz contact.
    pub force_measure: ForceMeasure,
    /// Fretting S-N law of `rope_tn_per_slip_cycle` (default: DNV spiral-rope curve on the
    /// wire stress range).
    pub sn_law: FrettingSnLaw,
    /// The law of the fretting measures: `contact_stress` (default) or
    /// `rope_tn_per_slip_cycle`.
    #[serde(skip_serializing_if = "is_default_law")]
    pub fretting_law: FrettingLaw,
    /// Wire surface of the contact-stress law: `galvanised` (default), `bright`, `sea_water`.
    #[serde(skip_serializing_if = "is_default_surface")]
    pub wire_surface: WireSurface,
    /// Critical distance L of the contact-stress law (m), in place of the surface's default.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub critical_distance_m: Option<f64>,
    /// T-N curves on the hot-spot tension; the defaults of the module doc when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tn_curves: Option<Vec<NamedTnCurve>>,
    /// Simulated time at the start of each strand history left out of the statistics (s): a
    /// fixed override of the detected run-in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run_in_s: Option<f64>,
    /// How the run-in is detected.
    #[serde(skip_serializing_if = "RunInDetection::is_default")]
    pub run_in_detection: RunInDetection,
}

fn is_default_law(law: &FrettingLaw) -> bool {
    *law == FrettingLaw::default()
}

fn is_default_surface(surface: &WireSurface) -> bool {
    *surface == WireSurface::default()
}

/// Settings of the run-in detection (`moorfret_solver::fretting::runin`): window means of
/// every slip monitor against the mean of the final `reference_fraction` of the history.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RunInDetection {
    /// Window length (s): several wave periods.
    pub window_s: f64,
    /// Fraction of the history, at its end, taken as the stabilised reference (0, 1).
    pub reference_fraction: f64,
    /// Band half-width around the reference mean, in reference standard deviations.
    pub tolerance_sigma: f64,
}

impl Default for RunInDetection {
    fn default() -> Self {
        Self {
            window_s: 50.0,
            reference_fraction: 0.25,
            tolerance_sigma: 0.25,
        }
    }
}

impl RunInDetection {
    /// Whether `self` is the default.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// The solver's parameters for strand load samples `load_interval_s` apart.
    pub fn params(&self, load_interval_s: f64) -> RunInParams {
        RunInParams {
            window_samples: ((self.window_s / load_interval_s).round() as usize).max(1),
            reference_fraction: self.reference_fraction,
            tolerance_sigma: self.tolerance_sigma,
        }
    }

    /// The run-in of a strand history's slip monitors against its load (strain and
    /// curvature), its samples `load_interval_s` apart, as a JSON record (`stabilised`,
    /// `end_s`, the monitors examined and unstable, the governing one, the worst drift over
    /// its band; `error` when the history is too short for the windows), with the first
    /// sample after the run-in when it stabilised.
    pub fn detect(
        &self,
        monitors: &MonitorSeries,
        load_interval_s: f64,
    ) -> (Option<usize>, serde_json::Value) {
        let slips: Vec<&MonitorChannel> = monitors
            .channels
            .iter()
            .filter(|c| c.quantity == MonitorQuantity::Slip && !c.values.is_empty())
            .collect();
        let set: Vec<&[f64]> = slips.iter().map(|c| c.values.as_slice()).collect();
        let loads = [
            monitors.strain.as_slice(),
            monitors.curvature_per_m.as_slice(),
        ];
        match detect_set_run_in(&set, &loads, &self.params(load_interval_s)) {
            Ok(r) => {
                let governing = r.governing.and_then(|k| slips.get(k)).map(|c| {
                    serde_json::json!({
                        "layer_interface": c.layer,
                        "group": format!("{:?}", c.group),
                    })
                });
                let end_s = r.end_index.map(|e| e as f64 * load_interval_s);
                (
                    r.end_index,
                    serde_json::json!({
                        "stabilised": r.end_index.is_some(),
                        "end_s": end_s,
                        "monitors": r.histories,
                        "unstable_monitors": r.unstable,
                        "governing_monitor": governing,
                        "worst_drift_ratio": r.worst_drift_ratio,
                    }),
                )
            }
            // too short a history for the windows: nothing detected
            Err(e) => (
                None,
                serde_json::json!({ "stabilised": false, "error": e.to_string() }),
            ),
        }
    }
}

impl Default for FatigueSpec {
    /// Slip edges from 0.5 µm to 1 mm and normal-force edges from 10 N to 100 kN, a few bins
    /// per decade: they span the µm-scale slips and the N to kN contact forces of the paper's
    /// strand results (Figs. 16-22).
    fn default() -> Self {
        let fretting = FrettingParams::default();
        Self {
            slip_amplitude_edges_m: vec![
                0.0, 0.5e-6, 1e-6, 2e-6, 5e-6, 1e-5, 2e-5, 5e-5, 1e-4, 1e-3,
            ],
            normal_force_edges_n: vec![0.0, 10.0, 30.0, 100.0, 300.0, 1e3, 3e3, 1e4, 1e5],
            regime: fretting.regime,
            force_measure: fretting.force_measure,
            sn_law: fretting.sn_law,
            fretting_law: FrettingLaw::default(),
            wire_surface: WireSurface::default(),
            critical_distance_m: None,
            tn_curves: None,
            run_in_s: None,
            run_in_detection: RunInDetection::default(),
        }
    }
}

fn invalid(field: &str, value: impl std::fmt::Display, reason: impl Into<String>) -> CampaignError {
    CampaignError::Invalid {
        field: field.to_owned(),
        value: value.to_string(),
        reason: reason.into(),
    }
}

impl FatigueSpec {
    /// Checks every value that needs neither the strand profile nor the global case, for a
    /// simulation of `duration_s` sampled by the strand every `load_interval_s`.
    pub fn validate(&self, duration_s: f64, load_interval_s: f64) -> Result<(), CampaignError> {
        for (field, edges) in [
            (
                "fatigue.slip_amplitude_edges_m",
                &self.slip_amplitude_edges_m,
            ),
            ("fatigue.normal_force_edges_n", &self.normal_force_edges_n),
        ] {
            BinEdges::new(edges.clone())
                .map_err(|e| invalid(field, format!("{edges:?}"), e.to_string()))?;
            // amplitudes and forces are magnitudes: a negative edge makes a bin no cycle
            // can fall in
            if let Some(e) = edges.iter().find(|e| **e < 0.0) {
                return Err(invalid(
                    field,
                    format!("{edges:?}"),
                    format!("has the negative edge {e}: the edges bound magnitudes, from 0 up"),
                ));
            }
        }
        let params = FrettingParams {
            regime: self.regime,
            force_measure: self.force_measure,
            sn_law: self.sn_law,
            ..FrettingParams::default()
        };
        params.validate().map_err(|e| {
            let value = format!("{:?} / {:?}", self.regime, self.sn_law);
            invalid("fatigue.regime / fatigue.sn_law", value, e.to_string())
        })?;
        self.contact_stress_law().validate().map_err(|e| {
            invalid(
                "fatigue.critical_distance_m",
                format!("{:?}", self.critical_distance_m),
                e.to_string(),
            )
        })?;
        let d = &self.run_in_detection;
        if !(d.window_s.is_finite() && d.window_s >= load_interval_s) {
            return Err(invalid(
                "fatigue.run_in_detection.window_s",
                d.window_s,
                "must be finite and at least strand.load_interval_s",
            ));
        }
        if !(d.reference_fraction > 0.0 && d.reference_fraction < 1.0) {
            return Err(invalid(
                "fatigue.run_in_detection.reference_fraction",
                d.reference_fraction,
                "must lie in (0, 1)",
            ));
        }
        if !(d.tolerance_sigma.is_finite() && d.tolerance_sigma > 0.0) {
            return Err(invalid(
                "fatigue.run_in_detection.tolerance_sigma",
                d.tolerance_sigma,
                "must be finite and > 0",
            ));
        }
        let (run_in, duration) = (self.run_in_s.unwrap_or(0.0), duration_s);
        if !(run_in.is_finite() && run_in >= 0.0) {
            return Err(invalid("fatigue.run_in_s", run_in, "must be >= 0"));
        }
        if run_in + 2.0 * load_interval_s > duration {
            return Err(invalid(
                "fatigue.run_in_s",
                run_in,
                format!(
                    "must leave at least two strand load intervals of \
                     simulation.duration_s = {duration} s"
                ),
            ));
        }
        let curves = self.tn_curves.as_deref().unwrap_or_default();
        for (i, c) in curves.iter().enumerate() {
            let field = format!("fatigue.tn_curves[{i}]");
            let taken = FRETTING_MEASURES.contains(&c.measure.as_str())
                || curves[..i].iter().any(|o| o.measure == c.measure);
            if c.measure.is_empty() || taken {
                return Err(invalid(
                    &format!("{field}.measure"),
                    &c.measure,
                    "must be a non-empty name, unique and not a fretting measure",
                ));
            }
            c.curve.validate().map_err(|e| {
                invalid(
                    &format!("{field}.curve"),
                    format!("{:?}", c.curve),
                    e.to_string(),
                )
            })?;
        }
        Ok(())
    }

    /// The contact-stress law of these settings.
    pub fn contact_stress_law(&self) -> ContactStressLaw {
        ContactStressLaw {
            surface: self.wire_surface,
            constants: self.critical_distance_m.map(|l| StrainLife {
                critical_distance_m: l,
                ..self.wire_surface.constants()
            }),
            ..ContactStressLaw::default()
        }
    }

    /// The fixed run-in in strand load samples, if `run_in_s` is given.
    pub fn fixed_run_in_samples(&self, load_interval_s: f64) -> Option<usize> {
        self.run_in_s
            .map(|r| (r / load_interval_s).round() as usize)
    }

    /// The damage-input configuration of a hot spot on `line_type` with axial stiffness
    /// `axial_stiffness_n` (N), for the strand model `strand`.
    pub fn damage_config(
        &self,
        strand: &Strand,
        line_type: &LineTypeSpec,
        axial_stiffness_n: f64,
    ) -> DamageInputsConfig {
        DamageInputsConfig {
            tn_curves: self
                .tn_curves
                .clone()
                .unwrap_or_else(|| default_tn_curves(line_type)),
            ..self.fretting_config(strand, axial_stiffness_n)
        }
    }

    /// The fretting part of [`Self::damage_config`]: the configured T-N curves only (none by
    /// default), for comparing strand runs without a line.
    pub fn fretting_config(&self, strand: &Strand, axial_stiffness_n: f64) -> DamageInputsConfig {
        DamageInputsConfig {
            slip_amplitude_edges_m: self.slip_amplitude_edges_m.clone(),
            normal_force_edges_n: self.normal_force_edges_n.clone(),
            fretting: FrettingParams {
                friction_coefficient: strand.friction_coefficient,
                regime: self.regime,
                force_measure: self.force_measure,
                sn_law: self.sn_law,
            },
            interfaces: interface_geometry(strand),
            metallic_area_m2: axial_stiffness_n / strand.young_modulus_pa,
            tn_curves: self.tn_curves.clone().unwrap_or_default(),
            law: self.fretting_law,
            contact_stress: self.contact_stress_law(),
        }
    }
}

/// The default T-N curves of a hot spot on `line_type` (module doc).
pub fn default_tn_curves(line_type: &LineTypeSpec) -> Vec<NamedTnCurve> {
    let mut curves = vec![NamedTnCurve {
        measure: "tn_dnv_spiral_rope".into(),
        curve: TnCurve::Dnv {
            component: DnvComponent::SpiralRope,
            nominal_area_m2: rope_nominal_area_m2(line_type.hydrodynamic_diameter_m),
        },
    }];
    if let Some(mbl) = line_type.minimum_breaking_load_n {
        curves.push(NamedTnCurve {
            measure: "tn_api_spiral_strand".into(),
            curve: TnCurve::Api {
                component: ApiComponent::SpiralStrandRope,
                reference_breaking_strength_n: mbl,
                // replaced by each sea state's mean load ratio
                mean_load_ratio: 0.0,
            },
        });
    }
    curves
}

/// Crossed-cylinder geometry of every layer interface (index 0: layer 1 on the core), with the
/// crossing angle |h₂α₂ − h₁α₁| of the module doc.
pub fn interface_geometry(strand: &Strand) -> Vec<CrossedCylinders> {
    let material = ElasticMaterial {
        youngs_modulus_pa: strand.young_modulus_pa,
        poisson_ratio: strand.poisson_ratio,
    };
    let mut inner = (strand.core_wire_radius_m, 0.0);
    strand
        .layers
        .iter()
        .map(|layer| {
            let signed = layer.hand.sign() * layer.lay_angle_rad;
            let pair = CrossedCylinders {
                radius_1_m: inner.0,
                radius_2_m: layer.wire_radius_m,
                crossing_angle_rad: (signed - inner.1).abs(),
                material_1: material,
                material_2: material,
            };
            inner = (layer.wire_radius_m, signed);
            pair
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use moorfret_solver::strand::contacts::{find_contacts, ContactSearchParameters};
    use moorfret_solver::strand::profile::profile_from_json;

    use super::*;

    fn benchmark() -> Strand {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../campaigns/benchmarks/strand_1_6_1.json"
        );
        let text = std::fs::read_to_string(path).unwrap();
        profile_from_json(&text).unwrap().validate().unwrap()
    }

    /// The closed-form crossing angle equals the angle between the wire tangents at every
    /// contact the geometric search finds (acos of a dot product: a few ulps of π).
    #[test]
    fn interface_crossing_angles_match_the_contact_search() {
        let strand = benchmark();
        let geometry = interface_geometry(&strand);
        assert_eq!(geometry.len(), 2);
        let set = find_contacts(&strand, &ContactSearchParameters::default()).unwrap();
        assert!(!set.contacts.is_empty());
        for c in &set.contacts {
            let g = &geometry[c.outer_layer];
            assert!(
                (g.crossing_angle_rad - c.crossing_angle_rad).abs() < 1e-12,
                "interface {}: {} vs {}",
                c.outer_layer,
                g.crossing_angle_rad,
                c.crossing_angle_rad
            );
        }
        // opposite hands, both 12°: 12° on the core, 24° between the layers
        assert!((geometry[0].crossing_angle_rad - 12f64.to_radians()).abs() < 1e-15);
        assert!((geometry[1].crossing_angle_rad - 24f64.to_radians()).abs() < 1e-15);
    }

    #[test]
    fn wire_stress_area_gives_the_straight_wire_stress_of_the_applied_strain() {
        let strand = benchmark();
        let line: LineTypeSpec = serde_json::from_value(serde_json::json!({
            "mass_kg_per_m": 16.5, "submerged_weight_n_per_m": 140.6,
            "axial_stiffness_n": 3.6e8, "bending_stiffness_nm2": 8e4,
            "hydrodynamic_diameter_m": 0.0604, "drag_normal": 1.2, "drag_tangential": 0.008,
            "added_mass_normal": 1.0, "added_mass_tangential": 0.0,
            "minimum_breaking_load_n": 3.2e6
        }))
        .unwrap();
        let config = FatigueSpec::default().damage_config(&strand, &line, 3.6e8);
        // σ = T / A = E T / EA = E ε
        let (t, ea) = (7.2e5, 3.6e8);
        let sigma = t / config.metallic_area_m2;
        assert!((sigma - strand.young_modulus_pa * t / ea).abs() <= 1e-15 * sigma);
        assert_eq!(
            config.fretting.friction_coefficient,
            strand.friction_coefficient
        );
        let names: Vec<_> = config
            .tn_curves
            .iter()
            .map(|c| c.measure.as_str())
            .collect();
        assert_eq!(names, ["tn_dnv_spiral_rope", "tn_api_spiral_strand"]);
    }
}
