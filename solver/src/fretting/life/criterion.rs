//! Life to crack initiation of one fretting cycle of one wire crossing.
//!
//! For a cycle with normal force P, tangential force amplitude Q and the wire's bulk stress
//! between σ_B,min and σ_B,max:
//!
//! 1. Contact patch: the Hertz ellipse of the two crossed wires ([`HertzModel`]), semi-axes
//!    a ≥ b, the slip taken along the major axis (the bisector of the acute angle between the
//!    wires; each wire's axis lies half the crossing angle off it). The ellipse's own stress
//!    field is used ([`EllipseHotSpot`]): the circle of equal area understates the stress at
//!    the hot spot of the strand's slender patches by about 40 % (tests,
//!    `docs/fretting-fatigue.md`).
//! 2. Regime (Cattaneo-Mindlin; for the ellipse Mindlin & Deresiewicz 1953, a similar stick
//!    ellipse): stick ratio c/a = (1 − Q/μP)^{1/3}; gross slip when Q
//!    reaches μP, stick when c/a ≥ [`STICK_RATIO_FOR_STICK`].
//! 3. Stress at the two extremes of the cycle, at the hot spot: the point at the critical
//!    distance's half, L/2, below the trailing edge of the contact (theory of critical
//!    distances, point method; Taylor 2007): Hamilton's normal part plus or minus the
//!    tangential part of the stick ratio c/a ([`super::field`]) (Hamilton's closed forms are the
//!    circle's, which the tabulated ellipse field reproduces), plus the wire's bulk stress
//!    along the slip direction (an assumption: in a crossing, the slip direction makes an angle
//!    with each wire's axis; taking them aligned is the severe case), its maximum at the
//!    extreme where the trailing edge is in tension.
//! 4. Critical plane: over the planes whose normal lies in the slip plane (x-z) and the plane
//!    normal to y, the largest Smith-Watson-Topper parameter σ_n,max Δε_n/2 and the largest
//!    Fatemi-Socie parameter Δγ/2 (1 + k σ_n,max/σ_y), elastic strains from the stresses.
//! 5. Life: the strain-life curves of [`StrainLife`]; the parameter the law names
//!    ([`CriticalPlane`]) gives the life, the other is reported beside it.
//!
//! Gross-slip cycles also carry the frictional (wear) energy 4 μ P δₐ, δₐ the slip amplitude.
//!
//! Units: N, m, Pa; lives in cycles.

use serde::{Deserialize, Serialize};

use super::field::{EllipseHotSpot, Stress};
use super::material::{StrainLife, WireSurface};
use crate::contact::hertz::HertzModel;
use crate::fretting::error::{non_negative, positive, FrettingError};
use crate::fretting::indicators::FrettingRegime;

/// Stick ratio c/a at and above which a cycle counts as stick (Q/μP ≤ 1 − 0.98³ ≈ 0.059).
pub const STICK_RATIO_FOR_STICK: f64 = 0.98;

/// Q/μP from which a cycle counts as gross slip (the Coulomb limit, to rounding).
pub const GROSS_SLIP_RATIO: f64 = 0.999;

/// Angular step of the critical-plane search (rad): 2°.
const PLANE_STEP_RAD: f64 = std::f64::consts::PI / 90.0;

/// Which critical-plane parameter gives the life.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "parameter", deny_unknown_fields)]
pub enum CriticalPlane {
    /// Smith-Watson-Topper (tensile cracking, the mode of high-strength steel wires).
    #[default]
    Swt,
    /// Fatemi-Socie with normal-stress sensitivity k (shear cracking).
    FatemiSocie {
        /// k (about 0.6-1 for steels; Fatemi & Socie 1988).
        k: f64,
    },
    /// The shorter of the two lives (SWT and Fatemi-Socie with k = 1).
    Governing,
}

/// The contact-stress fretting-fatigue law.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactStressLaw {
    /// Wire surface condition (selects the constants unless `constants` is given).
    pub surface: WireSurface,
    /// Explicit constants in place of the surface's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constants: Option<StrainLife>,
    /// Critical-plane parameter.
    #[serde(default)]
    pub critical_plane: CriticalPlane,
}

impl ContactStressLaw {
    /// The constants in force.
    pub fn material(&self) -> StrainLife {
        self.constants.unwrap_or_else(|| self.surface.constants())
    }

    /// Checks the constants and the parameter.
    pub fn validate(&self) -> Result<(), FrettingError> {
        let m = self.material();
        m.validate()?;
        if let CriticalPlane::FatemiSocie { k } = self.critical_plane {
            non_negative("critical_plane.k", k)?;
        }
        Ok(())
    }
}

/// The load of one cycle at one contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CycleLoad {
    /// Normal force P (N).
    pub normal_force_n: f64,
    /// Tangential force amplitude Q (N), half the range over the cycle.
    pub tangential_amplitude_n: f64,
    /// Slip amplitude δₐ (m), half the slip range.
    pub slip_amplitude_m: f64,
    /// Largest bulk stress of the wire over the cycle (Pa).
    pub bulk_max_pa: f64,
    /// Smallest bulk stress of the wire over the cycle (Pa).
    pub bulk_min_pa: f64,
}

/// What the law finds for one cycle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CycleLife {
    /// Regime.
    pub regime: FrettingRegime,
    /// Stick ratio c/a (0 in gross slip).
    pub stick_ratio: f64,
    /// Semi-axis a of the contact ellipse along the slip (m).
    pub contact_radius_m: f64,
    /// Peak pressure p₀ (Pa).
    pub peak_pressure_pa: f64,
    /// Largest SWT parameter over the planes (Pa).
    pub swt_pa: f64,
    /// Largest Fatemi-Socie parameter over the planes (k of the law, or 1).
    pub fatemi_socie: f64,
    /// Cycles to crack initiation under the law's parameter.
    pub cycles_to_initiation: f64,
    /// Frictional energy of a gross-slip cycle, 4 μ P δₐ (J); 0 otherwise.
    pub wear_energy_j: f64,
}

/// Evaluates one cycle; an open contact (P ≤ 0) has no fretting life to spend (∞). `shape` is
/// the hot-spot table of `model`'s ellipse (`EllipseHotSpot::shared(model.axis_ratio, ν)`),
/// looked up once per contact geometry by the caller, not per cycle.
pub fn cycle_life(
    model: &HertzModel,
    shape: &EllipseHotSpot,
    friction_coefficient: f64,
    law: &ContactStressLaw,
    load: &CycleLoad,
) -> Result<CycleLife, FrettingError> {
    positive("friction_coefficient", friction_coefficient)?;
    for (field, v) in [
        ("tangential_amplitude_n", load.tangential_amplitude_n),
        ("slip_amplitude_m", load.slip_amplitude_m),
        ("bulk_max_pa", load.bulk_max_pa),
        ("bulk_min_pa", load.bulk_min_pa),
    ] {
        if !v.is_finite() {
            return Err(FrettingError::InvalidParameter {
                field,
                value: v,
                reason: "must be finite",
            });
        }
    }
    let contact = model.contact(load.normal_force_n)?;
    let p = load.normal_force_n;
    if p <= 0.0 {
        return Ok(CycleLife {
            regime: FrettingRegime::Stick,
            stick_ratio: 1.0,
            contact_radius_m: 0.0,
            peak_pressure_pa: 0.0,
            swt_pa: 0.0,
            fatemi_socie: 0.0,
            cycles_to_initiation: f64::INFINITY,
            wear_energy_j: 0.0,
        });
    }
    let m = law.material();
    let mu = friction_coefficient;
    let ratio = (load.tangential_amplitude_n.abs() / (mu * p)).min(1.0);
    let (regime, stick_ratio) = if ratio >= GROSS_SLIP_RATIO {
        (FrettingRegime::GrossSlip, 0.0)
    } else {
        let s = (1.0 - ratio).cbrt();
        let regime = if s >= STICK_RATIO_FOR_STICK {
            FrettingRegime::Stick
        } else {
            FrettingRegime::PartialSlip
        };
        (regime, s)
    };
    let a = contact.semi_major_m;
    let p0 = contact.peak_pressure_pa;
    let eta = 0.5 * m.critical_distance_m / a;
    let normal = shape.normal(eta).scaled(p0);
    // The traction μp − μp₀(c/a)√(1 − ρ²) over the stick ellipse carries
    // Q = μP(1 − (c/a)³) by construction.
    let tangential = if ratio > 0.0 {
        shape.tangential(eta, stick_ratio).scaled(mu * p0)
    } else {
        Stress::default()
    };
    let mut high = normal.combine(1.0, tangential, 1.0);
    let mut low = normal.combine(1.0, tangential, -1.0);
    high.xx += load.bulk_max_pa.max(load.bulk_min_pa);
    low.xx += load.bulk_min_pa.min(load.bulk_max_pa);
    let (swt, fs_unit, fs_k) = critical_planes(&high, &low, &m, law.critical_plane);
    let swt_life = m.swt_life(swt);
    let cycles = match law.critical_plane {
        CriticalPlane::Swt => swt_life,
        CriticalPlane::FatemiSocie { .. } => m.fatemi_socie_life(fs_k),
        CriticalPlane::Governing => swt_life.min(m.fatemi_socie_life(fs_unit)),
    };
    let wear = if regime == FrettingRegime::GrossSlip {
        4.0 * mu * p * load.slip_amplitude_m.abs()
    } else {
        0.0
    };
    Ok(CycleLife {
        regime,
        stick_ratio,
        contact_radius_m: a,
        peak_pressure_pa: p0,
        swt_pa: swt,
        fatemi_socie: match law.critical_plane {
            CriticalPlane::FatemiSocie { .. } => fs_k,
            _ => fs_unit,
        },
        cycles_to_initiation: cycles,
        wear_energy_j: wear,
    })
}

/// Largest SWT (Pa), Fatemi-Socie with k = 1, and with the law's k, over the candidate planes.
fn critical_planes(
    high: &Stress,
    low: &Stress,
    m: &StrainLife,
    parameter: CriticalPlane,
) -> (f64, f64, f64) {
    let e = m.youngs_modulus_pa;
    let nu = m.poisson_ratio;
    let g = m.shear_modulus_pa();
    let k = match parameter {
        CriticalPlane::FatemiSocie { k } => k,
        _ => 1.0,
    };
    let (tr_h, tr_l) = (high.trace(), low.trace());
    let strain = |sn: f64, tr: f64| ((1.0 + nu) * sn - nu * tr) / e;
    let mut best = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut visit = |n: [f64; 3]| {
        let (th, tl) = (high.traction_on(n), low.traction_on(n));
        let sh = th[0] * n[0] + th[1] * n[1] + th[2] * n[2];
        let sl = tl[0] * n[0] + tl[1] * n[1] + tl[2] * n[2];
        let sn_max = sh.max(sl);
        let de_half = 0.5 * (strain(sh, tr_h) - strain(sl, tr_l)).abs();
        if sn_max > 0.0 {
            best.0 = best.0.max(sn_max * de_half);
        }
        // shear traction difference on the plane
        let d = [
            (th[0] - sh * n[0]) - (tl[0] - sl * n[0]),
            (th[1] - sh * n[1]) - (tl[1] - sl * n[1]),
            (th[2] - sh * n[2]) - (tl[2] - sl * n[2]),
        ];
        let dg_half = 0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / g;
        let boost = sn_max.max(0.0) / m.yield_strength_pa;
        best.1 = best.1.max(dg_half * (1.0 + boost));
        best.2 = best.2.max(dg_half * (1.0 + k * boost));
    };
    let planes = (std::f64::consts::PI / PLANE_STEP_RAD).round() as usize;
    for i in 0..planes {
        let th = i as f64 * PLANE_STEP_RAD;
        visit([th.cos(), 0.0, th.sin()]);
    }
    visit([0.0, 1.0, 0.0]);
    best
}
