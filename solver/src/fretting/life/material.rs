//! Strain-life constants of rope wire and the critical distance of the theory of critical
//! distances, per surface condition.
//!
//! Strain-life (Basquin-Coffin-Manson) under uniaxial loading:
//!
//! ```text
//! Δε/2 = σ'f/E (2N)^b + ε'f (2N)^c
//! ```
//!
//! and the two critical-plane forms built on it: Smith-Watson-Topper (1970)
//! `σ_n,max Δε_n/2 = σ'f²/E (2N)^{2b} + σ'f ε'f (2N)^{b+c}` and Fatemi-Socie (1988)
//! `Δγ/2 (1 + k σ_n,max/σ_y) = τ'f/G (2N)^{b} + γ'f (2N)^{c}` with the von Mises estimates
//! τ'f = σ'f/√3, γ'f = √3 ε'f (Socie & Marquis 2000, §4).
//!
//! The critical distance of the theory of critical distances (Taylor 2007) is
//! L = (1/π)(ΔK_th/Δσ₀)², ΔK_th the long-crack threshold and Δσ₀ the plain fatigue limit. Neither
//! was found measured on rope wire, so L is a constant of its own here, with a stated default.
//!
//! Where each constant comes from is stated on [`WireSurface::constants`] and in
//! `docs/fretting-fatigue.md`.

use serde::{Deserialize, Serialize};

use crate::fretting::error::{positive, FrettingError};

/// Surface condition of the wires, which selects the constants.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WireSurface {
    /// Bright (ungalvanised) cold-drawn wire in air.
    Bright,
    /// Galvanised cold-drawn wire in air (the usual mooring spiral strand).
    #[default]
    Galvanised,
    /// Free corrosion in sea water (no cathodic protection, sheathing or blocking compound).
    SeaWater,
}

impl WireSurface {
    /// Stable lower-case name.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Bright => "bright",
            Self::Galvanised => "galvanised",
            Self::SeaWater => "sea_water",
        }
    }

    /// The constants of this condition; see [`StrainLife::cold_drawn_wire`].
    pub fn constants(self) -> StrainLife {
        StrainLife::cold_drawn_wire(self)
    }
}

/// Strain-life and threshold constants of one wire material and surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrainLife {
    /// Young's modulus E (Pa).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Fatigue strength coefficient σ'f (Pa).
    pub strength_coefficient_pa: f64,
    /// Fatigue strength exponent b (< 0).
    pub strength_exponent: f64,
    /// Fatigue ductility coefficient ε'f.
    pub ductility_coefficient: f64,
    /// Fatigue ductility exponent c (< 0).
    pub ductility_exponent: f64,
    /// Cyclic yield strength σ_y (Pa), for the Fatemi-Socie normal-stress term.
    pub yield_strength_pa: f64,
    /// Critical distance L of the theory of critical distances (m); the stresses are taken at
    /// L/2 below the surface (point method).
    pub critical_distance_m: f64,
    /// Factor dividing every predicted life (≥ 1): the environment's knock-down where the data
    /// give it on life rather than on the constants.
    pub life_factor: f64,
}

impl StrainLife {
    /// Constants of cold-drawn eutectoid rope wire of tensile strength S_u = 1770 MPa (the
    /// usual grade of mooring spiral strand), per surface. Sources and status:
    ///
    /// - E = 209 GPa and yield 0.81 S_u: the cold-drawn prestressing wire of Toribio et al.
    ///   (ICF13, 2013, Table 1: E 209 GPa, σ_Y 1480 MPa, S_u 1820 MPa).
    /// - σ'f, b, ε'f, c: Bäumel & Seeger's uniform material law for steels from S_u
    ///   (Bäumel & Seeger 1990, *Materials Data for Cyclic Loading*, Suppl. 1):
    ///   σ'f = 1.5 S_u, b = −0.087, ε'f = 0.59 ψ, ψ = 1.375 − 125 S_u/E, c = −0.58; estimated
    ///   from S_u as Cruzado et al. (2013, Int. J. Fatigue 55) did for their wires. In the
    ///   high-cycle range of fretting the elastic term (σ'f, b) governs.
    /// - L = 20 µm: an assumption (no ΔK_th or fatigue limit of rope wire was found); the
    ///   sensitivity of lives to it is in `docs/fretting-fatigue.md`.
    /// - Galvanised: the bright constants. Galvanised wire keeps its fatigue strength while
    ///   only the zinc corrodes (Nakamura & Suzumura 2009, J. Constr. Steel Res. 65).
    /// - Sea water (free corrosion): lives divided by 3, by analogy with the free-corrosion
    ///   S-N curves of steel in DNV-RP-C203; no factor measured on rope wire was found.
    pub fn cold_drawn_wire(surface: WireSurface) -> Self {
        let su = 1770e6;
        let e = 209e9;
        let psi = 1.375 - 125.0 * su / e;
        let bright = Self {
            youngs_modulus_pa: e,
            poisson_ratio: 0.3,
            strength_coefficient_pa: 1.5 * su,
            strength_exponent: -0.087,
            ductility_coefficient: 0.59 * psi,
            ductility_exponent: -0.58,
            yield_strength_pa: 1480.0 / 1820.0 * su,
            critical_distance_m: 20e-6,
            life_factor: 1.0,
        };
        match surface {
            WireSurface::Bright | WireSurface::Galvanised => bright,
            WireSurface::SeaWater => Self {
                life_factor: 3.0,
                ..bright
            },
        }
    }

    /// Checks every constant.
    pub fn validate(&self) -> Result<(), FrettingError> {
        positive("youngs_modulus_pa", self.youngs_modulus_pa)?;
        positive("strength_coefficient_pa", self.strength_coefficient_pa)?;
        positive("ductility_coefficient", self.ductility_coefficient)?;
        positive("yield_strength_pa", self.yield_strength_pa)?;
        positive("critical_distance_m", self.critical_distance_m)?;
        if !(self.life_factor.is_finite() && self.life_factor >= 1.0) {
            return Err(FrettingError::InvalidParameter {
                field: "life_factor",
                value: self.life_factor,
                reason: "must be finite and >= 1",
            });
        }
        if !(self.poisson_ratio > 0.0 && self.poisson_ratio < 0.5) {
            return Err(FrettingError::InvalidParameter {
                field: "poisson_ratio",
                value: self.poisson_ratio,
                reason: "must lie in (0, 0.5)",
            });
        }
        for (field, value) in [
            ("strength_exponent", self.strength_exponent),
            ("ductility_exponent", self.ductility_exponent),
        ] {
            if !(value.is_finite() && value < 0.0 && value > -1.5) {
                return Err(FrettingError::InvalidParameter {
                    field,
                    value,
                    reason: "must lie in (-1.5, 0)",
                });
            }
        }
        Ok(())
    }

    /// Shear modulus G = E/(2(1 + ν)) (Pa).
    pub fn shear_modulus_pa(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Cycles N with SWT(N) = `swt_pa` (σ_n,max Δε/2 in Pa); ∞ for a non-positive parameter.
    pub fn swt_life(&self, swt_pa: f64) -> f64 {
        if swt_pa.is_nan() || swt_pa <= 0.0 {
            return f64::INFINITY;
        }
        let (sf, b, ef, c, e) = self.constants();
        let curve = |two_n: f64| sf * sf / e * two_n.powf(2.0 * b) + sf * ef * two_n.powf(b + c);
        solve_decreasing(curve, swt_pa) / self.life_factor
    }

    /// Cycles N with FS(N) = `fs` (Δγ/2 (1 + k σ_n,max/σ_y), dimensionless); ∞ when ≤ 0.
    pub fn fatemi_socie_life(&self, fs: f64) -> f64 {
        if fs.is_nan() || fs <= 0.0 {
            return f64::INFINITY;
        }
        let (sf, b, ef, c, _) = self.constants();
        let g = self.shear_modulus_pa();
        let (tf, gf) = (sf / 3f64.sqrt(), 3f64.sqrt() * ef);
        let curve = |two_n: f64| tf / g * two_n.powf(b) + gf * two_n.powf(c);
        solve_decreasing(curve, fs) / self.life_factor
    }

    fn constants(&self) -> (f64, f64, f64, f64, f64) {
        (
            self.strength_coefficient_pa,
            self.strength_exponent,
            self.ductility_coefficient,
            self.ductility_exponent,
            self.youngs_modulus_pa,
        )
    }
}

/// N with curve(2N) = target for a curve decreasing in 2N; bisection on log(2N) over
/// [1, 1e30] reversals: N = 0.5 when the target exceeds the curve at one reversal, ∞ beyond
/// 1e30 reversals.
fn solve_decreasing(curve: impl Fn(f64) -> f64, target: f64) -> f64 {
    let (mut lo, mut hi) = (0.0_f64, 30.0_f64);
    if curve(1.0) <= target {
        return 0.5;
    }
    if curve(10f64.powf(hi)) >= target {
        return f64::INFINITY;
    }
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if curve(10f64.powf(mid)) > target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-10 {
            break;
        }
    }
    0.5 * 10f64.powf(0.5 * (lo + hi))
}
