//! Strand profile: the serde description of a spiral strand (core wire and helical layers) and
//! its validation into resolved [`Strand`] geometry.
//!
//! Format (SI, as `campaigns/data/strand_profiles.json`): material (`young_modulus_pa`,
//! `poisson_ratio`, `friction_coefficient`), `core_wire_radius_m`, `model_length_m`, and per
//! layer, innermost first: `wires`, `wire_radius_m`, the helix radius `helix_radius_m` (optional:
//! computed from radial stacking when omitted), the lay angle `lay_angle_deg` or the lay length
//! `lay_length_m` (one of them), `hand` (`right` = Z, `left` = S) and an optional `phase_deg`
//! (angular position of wire 0 at z = 0, default 90° = outer arc). Keys starting with `_` are
//! comments and are ignored by [`profiles_from_json`].
//!
//! Geometry: wire i of layer k follows the helix θ(z) = φₖ + 2π i/nₖ + hₖ z tan βₖ / Rₖ
//! (`super::helix`; θ = π/2 is the outer arc) with hₖ = +1 (right hand) or −1 (left hand); lay
//! length Lₖ = 2π Rₖ / tan βₖ. Layers stack radially in contact, Rₖ = Rₖ₋₁ + rₖ₋₁ + rₖ with R₀ = 0,
//! r₀ the core radius (as the paper's strand is built, `docs/paper-campaign.md`): at a trellis
//! crossing the two axes are radially aligned, so this is exact for crossed helices. Lateral
//! clearance inside a layer is the exact minimum distance between the axes of neighbouring wires
//! minus 2r (`super::clearance`); a negative value is an overlap.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::clearance::lateral_clearance;
use super::helix::Hand;

/// Tolerance on the radial stacking Rₖ = Rₖ₋₁ + rₖ₋₁ + rₖ (m).
pub(crate) const STACKING_TOLERANCE_M: f64 = 1e-6;

/// One layer as written in a profile file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerSpec {
    /// Number of wires in the layer.
    pub wires: Option<usize>,
    /// Wire radius (m).
    pub wire_radius_m: Option<f64>,
    /// Helix radius of the wire axes (m); computed from radial stacking when omitted.
    pub helix_radius_m: Option<f64>,
    /// Lay angle from the strand axis (deg); alternatively `lay_length_m`.
    pub lay_angle_deg: Option<f64>,
    /// Lay length (pitch) (m); alternatively `lay_angle_deg`.
    pub lay_length_m: Option<f64>,
    /// Hand of lay.
    pub hand: Option<Hand>,
    /// Angular position of wire 0 at z = 0 (deg, default 90 = outer arc).
    pub phase_deg: Option<f64>,
}

/// Extra per-case settings some profile entries carry (the benchmark's load and regularisation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileLoading {
    /// Imposed axial strain of the core.
    pub axial_strain: f64,
    /// Imposed curvatures (1/m), applied one after the other.
    pub curvatures_per_m: Vec<f64>,
}

/// A contact regularisation set (the paper's Sec. 2.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Regularisation {
    /// Normal penalty ε_N (N/m).
    pub normal_penalty_n_per_m: f64,
    /// Elastic slip γ_e (m).
    pub elastic_slip_m: f64,
}

/// A strand profile as written in a file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrandProfile {
    /// Young's modulus of the wires (Pa).
    pub young_modulus_pa: Option<f64>,
    /// Poisson's ratio of the wires.
    pub poisson_ratio: Option<f64>,
    /// Coulomb friction coefficient between wires.
    pub friction_coefficient: Option<f64>,
    /// Core wire radius (m).
    pub core_wire_radius_m: Option<f64>,
    /// Length of the modelled strand portion (m).
    pub model_length_m: Option<f64>,
    /// Layers, innermost first.
    pub layers: Option<Vec<LayerSpec>>,
    /// Lateral overlap of neighbouring wires accepted without error (m, default 0). Same-layer
    /// contact is not modelled (the paper's Sec. 2.1); the paper's 1+6+1 benchmark, with equal
    /// wires on R = 2r, overlaps by about 72 µm and needs it.
    #[serde(default)]
    pub lateral_overlap_tolerance_m: Option<f64>,
    /// Load case carried with the profile (benchmark entries).
    #[serde(default)]
    pub loading: Option<ProfileLoading>,
    /// Named regularisation sets carried with the profile (benchmark entries).
    #[serde(default)]
    pub regularisation: Option<BTreeMap<String, Regularisation>>,
}

/// A validated helical layer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Number of wires.
    pub wires: usize,
    /// Wire radius r (m).
    pub wire_radius_m: f64,
    /// Helix radius R (m).
    pub helix_radius_m: f64,
    /// Lay angle β from the strand axis (rad).
    pub lay_angle_rad: f64,
    /// Lay length 2π R / tan β (m).
    pub lay_length_m: f64,
    /// Hand of lay.
    pub hand: Hand,
    /// Angular position of wire 0 at z = 0 (rad).
    pub phase_rad: f64,
    /// Minimum surface gap between neighbouring wires of the layer (m); +∞ for one wire,
    /// negative for an accepted overlap.
    pub lateral_clearance_m: f64,
}

/// Validated strand geometry and material.
#[derive(Clone, Debug, PartialEq)]
pub struct Strand {
    /// Young's modulus (Pa).
    pub young_modulus_pa: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Friction coefficient.
    pub friction_coefficient: f64,
    /// Core wire radius (m).
    pub core_wire_radius_m: f64,
    /// Model length (m).
    pub model_length_m: f64,
    /// Helical layers, innermost first.
    pub layers: Vec<Layer>,
}

/// Profile errors; each names the offending field or layer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// The document is not valid JSON for a profile.
    #[error("strand profile JSON: {message}")]
    Json {
        /// Parser message.
        message: String,
    },
    /// No profile of that name.
    #[error("no strand profile named '{name}' (the file has: {})", known.join(", "))]
    UnknownProfile {
        /// Requested name.
        name: String,
        /// The names the file has.
        known: Vec<String>,
    },
    /// A name was given for a file of one profile.
    #[error(
        "the file holds one profile, not named profiles: '{name}' cannot be chosen (give no name)"
    )]
    SingleProfile {
        /// Requested name.
        name: String,
    },
    /// No name was given for a file of named profiles.
    #[error("the file holds named profiles ({}): give the name of one", known.join(", "))]
    NameNeeded {
        /// The names the file has.
        known: Vec<String>,
    },
    /// A required field is missing.
    #[error("{field} is missing")]
    MissingField {
        /// Field path, e.g. `layers[1].wire_radius_m`.
        field: String,
    },
    /// A field has an inadmissible value.
    #[error("{field} = {value} is invalid: {reason}")]
    InvalidValue {
        /// Field path.
        field: String,
        /// Value.
        value: f64,
        /// Why.
        reason: &'static str,
    },
    /// Layers do not stack radially in contact.
    #[error("layers[{layer}].helix_radius_m = {given_m} m but radial stacking gives {expected_m} m (R_k = R_k-1 + r_k-1 + r_k)")]
    Stacking {
        /// Layer index (0 = first helical layer).
        layer: usize,
        /// Given helix radius (m).
        given_m: f64,
        /// Stacked value (m).
        expected_m: f64,
    },
    /// Neighbouring wires of a layer overlap.
    #[error("layers[{layer}]: {wires} wires of radius {wire_radius_m} m on radius {helix_radius_m} m overlap by {overlap_m:.3e} m")]
    LateralOverlap {
        /// Layer index.
        layer: usize,
        /// Wire count.
        wires: usize,
        /// Wire radius (m).
        wire_radius_m: f64,
        /// Helix radius (m).
        helix_radius_m: f64,
        /// Overlap, −clearance (m).
        overlap_m: f64,
    },
    /// Lay angle and lay length both given and inconsistent.
    #[error("layers[{layer}]: lay_angle_deg = {lay_angle_deg} and lay_length_m = {lay_length_m} disagree")]
    ConflictingLay {
        /// Layer index.
        layer: usize,
        /// Given angle (deg).
        lay_angle_deg: f64,
        /// Given length (m).
        lay_length_m: f64,
    },
}

fn positive(field: impl Into<String>, v: Option<f64>) -> Result<f64, ProfileError> {
    let field = field.into();
    let v = v.ok_or_else(|| ProfileError::MissingField {
        field: field.clone(),
    })?;
    if !(v > 0.0 && v.is_finite()) {
        return Err(ProfileError::InvalidValue {
            field,
            value: v,
            reason: "must be finite and > 0",
        });
    }
    Ok(v)
}

impl StrandProfile {
    /// Validates the profile and resolves every layer.
    pub fn validate(&self) -> Result<Strand, ProfileError> {
        let young_modulus_pa = positive("young_modulus_pa", self.young_modulus_pa)?;
        let poisson_ratio = self.poisson_ratio.ok_or(ProfileError::MissingField {
            field: "poisson_ratio".into(),
        })?;
        if !(poisson_ratio > -1.0 && poisson_ratio < 0.5) {
            return Err(ProfileError::InvalidValue {
                field: "poisson_ratio".into(),
                value: poisson_ratio,
                reason: "must lie in (-1, 0.5)",
            });
        }
        let friction_coefficient = self
            .friction_coefficient
            .ok_or(ProfileError::MissingField {
                field: "friction_coefficient".into(),
            })?;
        if !(friction_coefficient >= 0.0 && friction_coefficient.is_finite()) {
            return Err(ProfileError::InvalidValue {
                field: "friction_coefficient".into(),
                value: friction_coefficient,
                reason: "must be finite and >= 0",
            });
        }
        let core = positive("core_wire_radius_m", self.core_wire_radius_m)?;
        let model_length_m = positive("model_length_m", self.model_length_m)?;
        let specs = self.layers.as_ref().ok_or(ProfileError::MissingField {
            field: "layers".into(),
        })?;
        let overlap_tolerance = self.lateral_overlap_tolerance_m.unwrap_or(0.0);
        if !(overlap_tolerance >= 0.0 && overlap_tolerance.is_finite()) {
            return Err(ProfileError::InvalidValue {
                field: "lateral_overlap_tolerance_m".into(),
                value: overlap_tolerance,
                reason: "must be finite and >= 0",
            });
        }
        let mut layers = Vec::with_capacity(specs.len());
        let (mut prev_radius, mut prev_wire) = (0.0, core);
        for (k, spec) in specs.iter().enumerate() {
            let f = |name: &str| format!("layers[{k}].{name}");
            let wires = spec
                .wires
                .ok_or_else(|| ProfileError::MissingField { field: f("wires") })?;
            if wires < 1 {
                return Err(ProfileError::InvalidValue {
                    field: f("wires"),
                    value: wires as f64,
                    reason: "must be >= 1",
                });
            }
            let r = positive(f("wire_radius_m"), spec.wire_radius_m)?;
            let stacked = prev_radius + prev_wire + r;
            let helix_radius_m = match spec.helix_radius_m {
                None => stacked,
                Some(given) => {
                    let given = positive(f("helix_radius_m"), Some(given))?;
                    if (given - stacked).abs() > STACKING_TOLERANCE_M {
                        return Err(ProfileError::Stacking {
                            layer: k,
                            given_m: given,
                            expected_m: stacked,
                        });
                    }
                    given
                }
            };
            let lay_angle_rad = match (spec.lay_angle_deg, spec.lay_length_m) {
                (None, None) => {
                    return Err(ProfileError::MissingField {
                        field: f("lay_angle_deg"),
                    })
                }
                (Some(deg), len) => {
                    if !(deg > 0.0 && deg < 90.0) {
                        return Err(ProfileError::InvalidValue {
                            field: f("lay_angle_deg"),
                            value: deg,
                            reason: "must lie in (0, 90)",
                        });
                    }
                    let beta = deg.to_radians();
                    if let Some(len) = len {
                        let from_len = (2.0 * PI * helix_radius_m / len).atan();
                        if len.is_nan() || len <= 0.0 || (from_len - beta).abs() > 1e-3 * beta {
                            return Err(ProfileError::ConflictingLay {
                                layer: k,
                                lay_angle_deg: deg,
                                lay_length_m: len,
                            });
                        }
                    }
                    beta
                }
                (None, Some(len)) => {
                    let len = positive(f("lay_length_m"), Some(len))?;
                    (2.0 * PI * helix_radius_m / len).atan()
                }
            };
            let hand = spec
                .hand
                .ok_or_else(|| ProfileError::MissingField { field: f("hand") })?;
            let phase_rad = spec.phase_deg.unwrap_or(90.0).to_radians();
            if !phase_rad.is_finite() {
                return Err(ProfileError::InvalidValue {
                    field: f("phase_deg"),
                    value: phase_rad,
                    reason: "must be finite",
                });
            }
            let lateral_clearance_m = lateral_clearance(wires, r, helix_radius_m, lay_angle_rad);
            if lateral_clearance_m < -overlap_tolerance {
                return Err(ProfileError::LateralOverlap {
                    layer: k,
                    wires,
                    wire_radius_m: r,
                    helix_radius_m,
                    overlap_m: -lateral_clearance_m,
                });
            }
            layers.push(Layer {
                wires,
                wire_radius_m: r,
                helix_radius_m,
                lay_angle_rad,
                lay_length_m: 2.0 * PI * helix_radius_m / lay_angle_rad.tan(),
                hand,
                phase_rad,
                lateral_clearance_m,
            });
            prev_radius = helix_radius_m;
            prev_wire = r;
        }
        Ok(Strand {
            young_modulus_pa,
            poisson_ratio,
            friction_coefficient,
            core_wire_radius_m: core,
            model_length_m,
            layers,
        })
    }
}

fn strip_comments(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(map) => {
            map.retain(|k, _| !k.starts_with('_'));
            map.values_mut().for_each(strip_comments);
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(strip_comments),
        _ => {}
    }
}

/// Parses a profile library (name → profile); keys starting with `_` are comments.
pub fn profiles_from_json(text: &str) -> Result<BTreeMap<String, StrandProfile>, ProfileError> {
    let mut v: serde_json::Value = serde_json::from_str(text).map_err(|e| ProfileError::Json {
        message: e.to_string(),
    })?;
    strip_comments(&mut v);
    serde_json::from_value(v).map_err(|e| ProfileError::Json {
        message: e.to_string(),
    })
}

/// Parses one profile (keys starting with `_` are comments).
pub fn profile_from_json(text: &str) -> Result<StrandProfile, ProfileError> {
    let mut v: serde_json::Value = serde_json::from_str(text).map_err(|e| ProfileError::Json {
        message: e.to_string(),
    })?;
    strip_comments(&mut v);
    serde_json::from_value(v).map_err(|e| ProfileError::Json {
        message: e.to_string(),
    })
}

/// The profile of a profile file: the file's one profile, or, with `name`, the profile of that
/// name in a file of named profiles.
pub fn select_profile(text: &str, name: Option<&str>) -> Result<StrandProfile, ProfileError> {
    let Some(name) = name else {
        return profile_from_json(text).map_err(|e| match profiles_from_json(text) {
            Ok(named) => ProfileError::NameNeeded {
                known: named.into_keys().collect(),
            },
            Err(_) => e,
        });
    };
    let mut profiles = match profiles_from_json(text) {
        Ok(p) => p,
        Err(e) => {
            return Err(if profile_from_json(text).is_ok() {
                ProfileError::SingleProfile {
                    name: name.to_owned(),
                }
            } else {
                e
            })
        }
    };
    profiles
        .remove(name)
        .ok_or_else(|| ProfileError::UnknownProfile {
            name: name.to_owned(),
            known: profiles.into_keys().collect(),
        })
}

impl Strand {
    /// Total number of wires (core included).
    pub fn wire_count(&self) -> usize {
        1 + self.layers.iter().map(|l| l.wires).sum::<usize>()
    }

    /// Outer diameter 2 (R_last + r_last) (m).
    pub fn outer_diameter_m(&self) -> f64 {
        self.layers
            .last()
            .map_or(2.0 * self.core_wire_radius_m, |l| {
                2.0 * (l.helix_radius_m + l.wire_radius_m)
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SINGLE: &str = include_str!("../../../campaigns/benchmarks/strand_1_6_1.json");
    const NAMED: &str = include_str!("../../../campaigns/data/strand_profiles.json");

    #[test]
    fn a_name_is_given_exactly_when_the_file_holds_named_profiles() {
        assert!(select_profile(SINGLE, None).is_ok());
        assert!(select_profile(NAMED, Some("benchmark_1_6_1")).is_ok());
        let e = select_profile(SINGLE, Some("x")).unwrap_err().to_string();
        assert!(e.starts_with("the file holds one profile"), "{e}");
        let e = select_profile(NAMED, None).unwrap_err().to_string();
        assert!(
            e.starts_with("the file holds named profiles (") && e.contains("paper_six_layer"),
            "{e}"
        );
        let e = select_profile(NAMED, Some("x")).unwrap_err().to_string();
        assert!(e.starts_with("no strand profile named 'x'"), "{e}");
    }
}
