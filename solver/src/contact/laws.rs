//! Contact laws and their parameters: normal law (linear penalty, Hertz for crossed cylinders, or
//! the line contact of cylinders along a generator), tangential law (elastic slip, Mindlin
//! compliance, or the Cattaneo–Mindlin law with memory) and Coulomb friction.
//!
//! Normal force (compression positive) from the penetration p = −g_N ≥ 0:
//!   penalty  f_N = ε_N p                  (the paper's Sec. 2.1; ε_N in N/m),
//!   Hertz    f_N = K_H p^{3/2}            (K_H from [`super::hertz::HertzModel`]),
//!   line     p = f_N/(π E* ℓ) [ln(4R₁/b) + ln(4R₂/b) − 1], b² = 4 f_N R/(π E* ℓ)
//!            (two cylinders of radii R₁, R₂ touching along a generator over a length ℓ,
//!            Johnson 1985 §5.3; [`super::hertz::LineContact`], inverted per evaluation).
//! Tangential stiffness before sliding, k_T, with the Coulomb limit |f_T| ≤ μ f_N:
//!   elastic slip  k_T = μ f_N / γ_e       (the paper's Sec. 2.1: slides once |g_T| = γ_e),
//!   Mindlin       k_T = 8 G* c(f_N)       (Mindlin 1949, initial stiffness; c ∝ f_N^{1/3}).
//! Both are elastic–perfectly-plastic in the tangential gap with this k_T: the Mindlin choice
//! gives the physical micro-slip stiffness, not the full Cattaneo–Mindlin hysteresis.
//!
//! Cattaneo–Mindlin (`TangentialLaw::CattaneoMindlin`, [`super::memory`]): the force–
//! displacement curve of a Hertz contact under a constant normal force P with micro-slip,
//! Q = μP [1 − (1 − δ/δ_s)^{3/2}], δ_s = 3μP/(16 G* c) (Johnson 1985 eq. 7.42, both bodies in
//! G*), its unloading and reloading branches by Masing's rule (Johnson §7.3; Mindlin &
//! Deresiewicz 1953) and Coulomb sliding at |Q| = μP, as a discrete Iwan model whose corners lie
//! on that curve (within 0.1 % of μP on the curves, 0.6 % on the loop energy). For a line contact the
//! initial stiffness 8 G* c is replaced by the Mindlin ratio of tangential to normal stiffness,
//! k_T0 = (4 G*/E*) k_N (exact for circular and elliptical Hertz contacts of equal elastic
//! constants to within the ellipse's correction; an approximation for the strip).

use serde::{Deserialize, Serialize};

use super::hertz::{
    contact_modulus, tangential_modulus, CrossedCylinders, ElasticMaterial, HertzModel, LineContact,
};

/// Normal contact law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum NormalLaw {
    /// Linear penalty f_N = ε_N (−g_N).
    Penalty {
        /// Penalty stiffness ε_N (N/m).
        stiffness_n_per_m: f64,
    },
    /// Hertz elliptical contact of crossed cylinders, f_N = K_H (−g_N)^{3/2}.
    Hertz,
    /// Two cylinders touching along a generator over the length `length_m` (Johnson 1985,
    /// §5.3): the approach of the axes p = f_N/(π E* ℓ) [ln(4R₁/b) + ln(4R₂/b) − 1].
    Line {
        /// Length of wire the contact stands for (m).
        length_m: f64,
    },
    /// The contact-mechanics family of a strand model: Hertz for crossed cylinders at the
    /// crossings (at their actual crossing angle), [`NormalLaw::Line`] over the tributary length
    /// for the line contacts of a helical layer on the core, which the strand model resolves per
    /// contact. A contact element given this law directly treats it as [`NormalLaw::Hertz`].
    ContactMechanics,
}

/// Tangential (stick) law before Coulomb sliding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case", deny_unknown_fields)]
pub enum TangentialLaw {
    /// Elastic slip γ_e: k_T = μ f_N / γ_e.
    ElasticSlip {
        /// Elastic slip γ_e (m).
        elastic_slip_m: f64,
    },
    /// Mindlin initial compliance: k_T = 8 G* c with c the Hertz equivalent contact radius.
    Mindlin,
    /// Cattaneo–Mindlin micro-slip with Masing unloading / reloading and Coulomb sliding, as an
    /// Iwan model whose elements' stretches are kept in the contact history (module docs,
    /// [`super::memory`]).
    CattaneoMindlin,
}

/// The contact laws a model is given: its regularisation. The friction coefficient and the
/// elastic constants are the wires' own, which the strand model adds
/// ([`ContactParameters::with_material`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactLaws {
    /// Normal law.
    pub normal: NormalLaw,
    /// Tangential law.
    pub tangential: TangentialLaw,
}

impl ContactLaws {
    /// The contact-mechanics family: Hertz (crossed cylinders, line contacts resolved by the
    /// strand model) and Cattaneo–Mindlin with memory. It has no regularisation parameter.
    pub fn contact_mechanics() -> Self {
        Self {
            normal: NormalLaw::ContactMechanics,
            tangential: TangentialLaw::CattaneoMindlin,
        }
    }
}

impl Default for ContactLaws {
    /// The paper's regularisation for comparison with the analytical solution (Sec. 2.2:
    /// ε_N = 2e5 N/mm, γ_e = 1e-4 mm).
    fn default() -> Self {
        let p = ContactParameters::default();
        Self {
            normal: p.normal,
            tangential: p.tangential,
        }
    }
}

/// Parameters shared by the contacts of a model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactParameters {
    /// Normal law.
    pub normal: NormalLaw,
    /// Tangential law.
    pub tangential: TangentialLaw,
    /// Coulomb friction coefficient μ.
    pub friction_coefficient: f64,
    /// Young's modulus of the wires (Pa), used by the Hertz and Mindlin laws.
    pub young_modulus_pa: f64,
    /// Poisson's ratio of the wires.
    pub poisson_ratio: f64,
}

impl ContactParameters {
    /// Whether the tangential law is Cattaneo–Mindlin's: a bank of Iwan elements per contact
    /// whose state remembers the load path, with a compliance that follows the normal force.
    /// The callers that treat that law apart (the calibration's design and modes, the history
    /// run's initialisation) ask this one question.
    pub fn is_cattaneo_mindlin(&self) -> bool {
        self.tangential == TangentialLaw::CattaneoMindlin
    }
}

impl Default for ContactParameters {
    /// The paper's regularisation for comparison with the analytical solution (Sec. 2.2:
    /// ε_N = 2e5 N/mm, γ_e = 1e-4 mm), steel wires, μ = 0.12 (the paper's Sec. 2.4).
    fn default() -> Self {
        Self {
            normal: NormalLaw::Penalty {
                stiffness_n_per_m: 2e8,
            },
            tangential: TangentialLaw::ElasticSlip {
                elastic_slip_m: 1e-7,
            },
            friction_coefficient: 0.12,
            young_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        }
    }
}

/// Errors of the contact element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactError {
    /// A parameter is out of its admissible range.
    #[error("contact parameter {field} = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Field name.
        field: &'static str,
        /// Offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// The two wire tangents are (nearly) parallel: the normal t₁ × t₂ is undefined.
    #[error("wire tangents are nearly parallel (sin of crossing angle {sin_angle:.3e}); the node-to-node normal t1 x t2 is undefined")]
    ParallelTangents {
        /// |t₁ × t₂|.
        sin_angle: f64,
    },
    /// The nodes lie in the plane of the tangents: the normal cannot be oriented from wire 1
    /// to wire 2.
    #[error("nodes are not separated along the normal ((x2 - x1)·n = {separation_m:.3e} m); cannot orient the contact normal")]
    UnorientedNormal {
        /// (x₂ − x₁)·(t₁ × t₂)/|t₁ × t₂|.
        separation_m: f64,
    },
}

impl ContactParameters {
    /// The parameters of contacts with `laws` between wires of friction coefficient μ, Young's
    /// modulus E (Pa) and Poisson's ratio ν.
    pub fn with_material(
        laws: ContactLaws,
        friction_coefficient: f64,
        young_modulus_pa: f64,
        poisson_ratio: f64,
    ) -> Self {
        Self {
            normal: laws.normal,
            tangential: laws.tangential,
            friction_coefficient,
            young_modulus_pa,
            poisson_ratio,
        }
    }

    /// Checks every field; the error names the field.
    pub fn validate(&self) -> Result<(), ContactError> {
        let bad = |field, value, reason| {
            Err(ContactError::InvalidParameter {
                field,
                value,
                reason,
            })
        };
        if !(self.friction_coefficient >= 0.0 && self.friction_coefficient.is_finite()) {
            return bad(
                "friction_coefficient",
                self.friction_coefficient,
                "must be finite and >= 0",
            );
        }
        if !(self.young_modulus_pa > 0.0 && self.young_modulus_pa.is_finite()) {
            return bad(
                "young_modulus_pa",
                self.young_modulus_pa,
                "must be finite and > 0",
            );
        }
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return bad("poisson_ratio", self.poisson_ratio, "must lie in (-1, 0.5)");
        }
        if let NormalLaw::Penalty { stiffness_n_per_m } = self.normal {
            if !(stiffness_n_per_m > 0.0 && stiffness_n_per_m.is_finite()) {
                return bad(
                    "normal.stiffness_n_per_m",
                    stiffness_n_per_m,
                    "must be finite and > 0",
                );
            }
        }
        if let NormalLaw::Line { length_m } = self.normal {
            if !(length_m > 0.0 && length_m.is_finite()) {
                return bad("normal.length_m", length_m, "must be finite and > 0");
            }
        }
        if let TangentialLaw::ElasticSlip { elastic_slip_m } = self.tangential {
            if !(elastic_slip_m > 0.0 && elastic_slip_m.is_finite()) {
                return bad(
                    "tangential.elastic_slip_m",
                    elastic_slip_m,
                    "must be finite and > 0",
                );
            }
        }
        Ok(())
    }
}

/// Normal law resolved for one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResolvedNormal {
    /// f_N = k p.
    Penalty(f64),
    /// f_N = K_H p^{3/2}.
    Hertz(f64),
    /// Line contact (f_N from p by inversion).
    Line(LineContact),
}

impl ResolvedNormal {
    /// f_N(p) and its derivative dF_N/dp for a penetration p > 0 (plain numbers).
    pub fn force_and_stiffness(&self, pen: f64) -> (f64, f64) {
        match *self {
            Self::Penalty(k) => (k * pen, k),
            Self::Hertz(k) => (k * pen.powf(1.5), 1.5 * k * pen.max(0.0).sqrt()),
            Self::Line(l) => l.force_and_stiffness(pen),
        }
    }
}

/// Tangential law resolved for one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResolvedTangential {
    /// k_T = μ f_N / γ_e; holds γ_e.
    ElasticSlip(f64),
    /// k_T = `coefficient` · f_N^{1/3} (= 8 G* c).
    Mindlin(f64),
    /// Cattaneo–Mindlin with memory, initial stiffness k_T0 = `coefficient` · f_N^{1/3}
    /// (= 8 G* c) at a Hertz point contact.
    CattaneoMindlinPoint(f64),
    /// Cattaneo–Mindlin with memory, initial stiffness k_T0 = `ratio` · k_N (the normal
    /// tangent stiffness) at a line contact; `ratio` = 4 G*/E*.
    CattaneoMindlinLine(f64),
}

/// The laws of one contact with every geometry-dependent constant computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedLaws {
    /// Normal law.
    pub normal: ResolvedNormal,
    /// Tangential law.
    pub tangential: ResolvedTangential,
    /// Friction coefficient μ.
    pub friction_coefficient: f64,
}

impl ResolvedLaws {
    /// Resolves `params` for wires of radii `r1`, `r2` (m) crossing at `angle_rad`.
    pub fn new(
        params: &ContactParameters,
        r1: f64,
        r2: f64,
        angle_rad: f64,
    ) -> Result<Self, ContactError> {
        params.validate()?;
        let (e, nu) = (params.young_modulus_pa, params.poisson_ratio);
        // The crossing folded into (0, π/2]; practically parallel wires (B/A > 1e8) make no
        // point contact.
        let hertz = || {
            let parallel = ContactError::ParallelTangents {
                sin_angle: angle_rad.sin().abs(),
            };
            let folded = angle_rad.rem_euclid(std::f64::consts::PI);
            let material = ElasticMaterial {
                youngs_modulus_pa: e,
                poisson_ratio: nu,
            };
            let angle = folded.min(std::f64::consts::PI - folded);
            let model = HertzModel::crossed_cylinders(&CrossedCylinders::of_one_material(
                r1, r2, angle, material,
            ))
            .map_err(|_| parallel.clone())?;
            if model.curvature_ratio() > 1e8 {
                return Err(parallel);
            }
            Ok(model)
        };
        let normal = match params.normal {
            NormalLaw::Penalty { stiffness_n_per_m } => ResolvedNormal::Penalty(stiffness_n_per_m),
            NormalLaw::Hertz | NormalLaw::ContactMechanics => {
                ResolvedNormal::Hertz(hertz()?.force_coefficient())
            }
            NormalLaw::Line { length_m } => ResolvedNormal::Line(LineContact::new(
                r1,
                r2,
                length_m,
                contact_modulus(e, nu, e, nu),
            )),
        };
        let tangential = match params.tangential {
            TangentialLaw::ElasticSlip { elastic_slip_m } => {
                ResolvedTangential::ElasticSlip(elastic_slip_m)
            }
            TangentialLaw::Mindlin => ResolvedTangential::Mindlin(
                8.0 * tangential_modulus(e, nu, e, nu) * hertz()?.radius_coefficient(),
            ),
            TangentialLaw::CattaneoMindlin => match normal {
                ResolvedNormal::Line(_) => ResolvedTangential::CattaneoMindlinLine(
                    4.0 * tangential_modulus(e, nu, e, nu) / contact_modulus(e, nu, e, nu),
                ),
                _ => ResolvedTangential::CattaneoMindlinPoint(
                    8.0 * tangential_modulus(e, nu, e, nu) * hertz()?.radius_coefficient(),
                ),
            },
        };
        Ok(Self {
            normal,
            tangential,
            friction_coefficient: params.friction_coefficient,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_penalty_is_rejected_naming_the_field() {
        let p = ContactParameters {
            normal: NormalLaw::Penalty {
                stiffness_n_per_m: -1.0,
            },
            ..Default::default()
        };
        match p.validate() {
            Err(ContactError::InvalidParameter { field, value, .. }) => {
                assert_eq!(field, "normal.stiffness_n_per_m");
                assert_eq!(value, -1.0);
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn parameters_round_trip_through_json() {
        let p = ContactParameters {
            normal: NormalLaw::Hertz,
            tangential: TangentialLaw::Mindlin,
            ..Default::default()
        };
        let s = serde_json::to_string(&p).unwrap();
        let q: ContactParameters = serde_json::from_str(&s).unwrap();
        assert_eq!(p, q);
        let txt = r#"{"normal":{"law":"penalty","stiffness_n_per_m":2e6},"tangential":{"law":"elastic_slip","elastic_slip_m":1e-5},"friction_coefficient":0.5,"young_modulus_pa":210e9,"poisson_ratio":0.3}"#;
        let r: ContactParameters = serde_json::from_str(txt).unwrap();
        assert_eq!(
            r.normal,
            NormalLaw::Penalty {
                stiffness_n_per_m: 2e6
            }
        );
    }
}
