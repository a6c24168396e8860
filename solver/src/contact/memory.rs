//! The Cattaneo–Mindlin tangential law with memory, as a discrete Iwan model in the element's
//! two-dimensional tangential gap.
//!
//! One dimension, constant normal force P (Johnson 1985, §7.2-7.3; Mindlin & Deresiewicz 1953):
//! - virgin loading: Q = μP q(δ/δ_s), q(x) = 1 − (1 − x)^{3/2}, δ_s = 3μP/(2 k₀), k₀ = 8 G* c
//!   the initial stiffness (Johnson eq. 7.42: δ_s = 3μP/(16 G* c));
//! - after a reversal at (δ*, Q*), Masing's rule: the branch is the virgin curve scaled by two
//!   from the reversal point, with the memory of nested loops;
//! - gross sliding at |Q| = μP (Coulomb).
//!
//! Iwan (1967) showed that a parallel bank of elastic–perfectly-plastic (Jenkins) elements, each
//! a spring in series with a Coulomb slider, follows Masing's rule and its memory exactly: each
//! element remembers its own last sliding, so no reversal has to be detected. Its virgin curve
//! is Σᵢ kᵢ min(δ, dᵢ), piecewise linear with corners at the yield displacements dᵢ. Here the
//! corners are put on the Cattaneo–Mindlin curve: xᵢ = dᵢ/δ_s = sin²(π yᵢ/2), yᵢ = x₀^{1−i/N},
//! i = 1..N, N = [`IWAN_ELEMENTS`], x₀ = 0.05 (fine near the origin for small loops and near
//! x = 1 where q has its square-root end), and the stiffnesses are the differences of the
//! chords' slopes, kᵢ = (2k₀/3)(sᵢ − sᵢ₊₁), sᵢ = (q(xᵢ) − q(xᵢ₋₁))/(xᵢ − xᵢ₋₁), s_{N+1} = 0.
//! The model is then the chord interpolant of the virgin curve, exact at the corners; its last
//! element yields at δ_s exactly, where the contact slides as a whole. Against the closed form
//! (checked in `tests/verification_cattaneo_mindlin.rs`): the virgin curve within 0.2 % of the
//! force, the energy of a symmetric loop within 0.9 % for 0.05 μP ≤ Q* ≤ μP (a loop below the
//! first corner, Q* < 0.07 μP, dissipates nothing: its exact energy is below 1.3e-5 of the
//! energy of a loop at Q* = μP).
//!
//! In the tangent plane each element keeps its elastic stretch eᵢ (a vector); a step of the
//! trial gap moves every stretch by the same increment, and each element is returned radially
//! to its own limit, |kᵢ eᵢ| ≤ fᵢ = kᵢ dᵢ: the two-dimensional Iwan model, whose elements are
//! each the elastic-slip law of [`super::laws`]. The element's stored elastic gap is the stretch
//! of the last element N (the one that yields at δ_s): it changes by sliding only when the
//! contact slides as a whole, so the element's Coulomb sliding is the gross slip. The other
//! N − 1 stretches are the memory kept here, each by its components on (t₁₍ₙ₎, t₂₍ₙ₎).
//!
//! Varying normal force: every kᵢ follows k₀ (∝ P^{1/3} at a Hertz contact) and every dᵢ
//! follows δ_s (∝ P^{2/3}), while the stretches are kept; a P that falls makes the elements at
//! their limit slide. This is exact only when P is constant: it neglects Mindlin & Deresiewicz's
//! dependence on the path of (P, Q), the frozen slip annuli of an earlier, larger P.
//!
//! The tangent: the force is evaluated in plain numbers with its derivatives with respect to
//! the trial gap, the current tangents t₁, t₂ (through which the stored stretches are mapped),
//! the normal force and k₀, and those derivatives are carried into the element's dual numbers
//! (exact, [`super::scalar`]).

use std::sync::OnceLock;

use nalgebra::{Matrix3, Vector3};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::scalar::{Scalar, V3};

/// Jenkins elements of the Iwan model.
pub const IWAN_ELEMENTS: usize = 40;

/// Stretches kept in the memory: every element's but the last one's (the element's elastic gap).
const KEPT: usize = IWAN_ELEMENTS - 1;

/// x₀ of the corners' grading (module docs).
const GRADING_START: f64 = 0.05;

/// The stretches of the Iwan elements 1..N−1 at the last accepted step (all zero for the other
/// laws, on a contact that never slid, and after a separation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentialMemory {
    /// Elastic stretch of each element by its components on (t₁₍ₙ₎, t₂₍ₙ₎) (m), weakest
    /// element first.
    pub stretches: [[f64; 2]; KEPT],
}

impl Default for TangentialMemory {
    fn default() -> Self {
        Self {
            stretches: [[0.0; 2]; KEPT],
        }
    }
}

impl TangentialMemory {
    /// Whether every stretch is zero (nothing to keep).
    pub fn is_empty(&self) -> bool {
        self.stretches.iter().all(|s| s[0] == 0.0 && s[1] == 0.0)
    }
}

/// Stored as the list of stretches, empty when every stretch is zero (the other laws' contacts
/// then cost a length in a checkpoint); self-describing and binary forms alike.
impl Serialize for TangentialMemory {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Stored<'a> {
            stretches: &'a [[f64; 2]],
        }
        let stretches: &[[f64; 2]] = if self.is_empty() {
            &[]
        } else {
            &self.stretches
        };
        Stored { stretches }.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for TangentialMemory {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        struct Stored {
            stretches: Vec<[f64; 2]>,
        }
        let stored = Stored::deserialize(deserializer)?;
        let mut memory = Self::default();
        if stored.stretches.is_empty() {
            return Ok(memory);
        }
        if stored.stretches.len() != KEPT {
            return Err(D::Error::custom(format!(
                "tangential_memory.stretches: {} entries, expected {KEPT} (or none)",
                stored.stretches.len()
            )));
        }
        if stored.stretches.iter().flatten().any(|v| !v.is_finite()) {
            return Err(D::Error::custom(
                "tangential_memory.stretches: a stretch is not a finite number",
            ));
        }
        memory.stretches.copy_from_slice(&stored.stretches);
        Ok(memory)
    }
}

/// One Jenkins element in units of the contact: stiffness over the initial stiffness k₀ and
/// yield displacement over δ_s.
#[derive(Clone, Copy, Debug)]
pub struct IwanElement {
    /// kᵢ / k₀.
    pub stiffness_fraction: f64,
    /// dᵢ / δ_s.
    pub yield_fraction: f64,
}

/// The Iwan elements of the Cattaneo–Mindlin curve (module docs), weakest first.
pub fn iwan_elements() -> &'static [IwanElement; IWAN_ELEMENTS] {
    static ELEMENTS: OnceLock<[IwanElement; IWAN_ELEMENTS]> = OnceLock::new();
    ELEMENTS.get_or_init(|| {
        let q = |x: f64| 1.0 - (1.0 - x).powf(1.5);
        let n = IWAN_ELEMENTS as f64;
        let corner = |i: usize| {
            if i == IWAN_ELEMENTS {
                1.0
            } else {
                let y = GRADING_START.powf(1.0 - i as f64 / n);
                (0.5 * std::f64::consts::PI * y).sin().powi(2)
            }
        };
        let mut slopes = [0.0; IWAN_ELEMENTS + 1];
        let mut previous = 0.0;
        for (i, slope) in slopes.iter_mut().take(IWAN_ELEMENTS).enumerate() {
            let x = corner(i + 1);
            *slope = (q(x) - q(previous)) / (x - previous);
            previous = x;
        }
        std::array::from_fn(|i| IwanElement {
            // q is in units of μP over δ_s: μP/δ_s = 2k₀/3
            stiffness_fraction: 2.0 / 3.0 * (slopes[i] - slopes[i + 1]),
            yield_fraction: corner(i + 1),
        })
    })
}

/// A trial evaluation of the law.
pub(crate) struct Trial<S> {
    /// Tangential force.
    pub force: V3<S>,
    /// Gross sliding (the last element slides).
    pub slip: bool,
    /// Trial stretches of elements 1..N−1 after the return, in the current frame.
    pub stretches: [Vector3<f64>; KEPT],
    /// Stretch of element N after the return: the elastic gap to keep (m).
    pub elastic: Vector3<f64>,
    /// ∂f/∂g at fixed tangents, normal force and k₀: the elements' stiffnesses, each sliding
    /// one's only across its sliding direction (symmetric, positive semi-definite), for
    /// preconditioning.
    pub jacobian: Matrix3<f64>,
}

/// `m (v − v₀)` with `v` carrying derivatives and `m`, `v₀` plain.
fn linear<S: Scalar>(m: &Matrix3<f64>, v: &V3<S>, v0: &Vector3<f64>) -> V3<S> {
    let dv: [S; 3] = std::array::from_fn(|j| v.c[j] + (-v0[j]));
    let row = |i: usize| dv[0] * m[(i, 0)] + dv[1] * m[(i, 1)] + dv[2] * m[(i, 2)];
    V3::new(row(0), row(1), row(2))
}

/// The Cattaneo–Mindlin force at the trial elastic gap `g` (the stretch of the last element),
/// from the accepted `memory` and elastic gap components `elastic` on (t₁₍ₙ₎, t₂₍ₙ₎), mapped
/// with the current tangents `t1`, `t2`; normal force `p`, initial stiffness `k0`, friction
/// coefficient `mu`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate<S: Scalar>(
    memory: &TangentialMemory,
    elastic: [f64; 2],
    g: &V3<S>,
    t1: &V3<S>,
    t2: &V3<S>,
    p: S,
    k0: S,
    mu: f64,
) -> Trial<S> {
    let zero = S::cst(0.0);
    let none = [Vector3::zeros(); KEPT];
    if mu <= 0.0 {
        return Trial {
            force: V3::new(zero, zero, zero),
            slip: g.norm().val() > 0.0,
            stretches: none,
            elastic: Vector3::zeros(),
            jacobian: Matrix3::zeros(),
        };
    }
    let (gv, t1v, t2v) = (g.val(), t1.val(), t2.val());
    let (pv, k0v) = (p.val(), k0.val());
    let delta_s = 1.5 * mu * pv / k0v;
    // Sums over the elements of the force and of its derivatives: with respect to the trial
    // gap (a), to t₁ and t₂ through each stretch's offset from the gap (b1, b2), to P and to k₀.
    let mut force = Vector3::zeros();
    let (mut a, mut b1, mut b2) = (Matrix3::zeros(), Matrix3::zeros(), Matrix3::zeros());
    let (mut d_p, mut d_k0) = (Vector3::zeros(), Vector3::zeros());
    let mut stretches = none;
    let mut elastic_out = Vector3::zeros();
    let mut slip = false;
    for (i, element) in iwan_elements().iter().enumerate() {
        // the stretch's offset from the gap, (eᵢ − e_N) on (t₁, t₂)
        let offset = match memory.stretches.get(i) {
            Some(s) => [s[0] - elastic[0], s[1] - elastic[1]],
            None => [0.0, 0.0],
        };
        let trial = gv + t1v * offset[0] + t2v * offset[1];
        let k = element.stiffness_fraction * k0v;
        // fᵢ = kᵢ dᵢ = kᵢ/k₀ · xᵢ · k₀ δ_s = (3/2) kᵢ/k₀ · xᵢ · μP (independent of k₀)
        let limit = element.stiffness_fraction * element.yield_fraction * k0v * delta_s;
        let norm = trial.norm();
        let (f, jacobian, kept) = if k * norm <= limit {
            d_k0 += trial * element.stiffness_fraction;
            (trial * k, Matrix3::identity() * k, trial)
        } else {
            let dir = trial / norm;
            d_p += dir * (1.5 * element.stiffness_fraction * element.yield_fraction * mu);
            if i == IWAN_ELEMENTS - 1 {
                slip = true;
            }
            (
                dir * limit,
                (Matrix3::identity() - dir * dir.transpose()) * (limit / norm),
                dir * (limit / k),
            )
        };
        force += f;
        a += jacobian;
        b1 += jacobian * offset[0];
        b2 += jacobian * offset[1];
        if i < KEPT {
            stretches[i] = kept;
        } else {
            elastic_out = kept;
        }
    }
    let lifted =
        V3::cst(&force) + linear(&a, g, &gv) + linear(&b1, t1, &t1v) + linear(&b2, t2, &t2v);
    let scalar_part = |v: &Vector3<f64>, s: S, s0: f64| {
        let ds = s + (-s0);
        V3::new(ds * v[0], ds * v[1], ds * v[2])
    };
    let force = lifted + scalar_part(&d_p, p, pv) + scalar_part(&d_k0, k0, k0v);
    Trial {
        force,
        slip,
        stretches,
        elastic: elastic_out,
        jacobian: a,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Iwan curve of the elements: Σ kᵢ min(x, xᵢ) in units of μP (k₀ = 3/2 in these
    /// units).
    fn iwan_curve(x: f64) -> f64 {
        iwan_elements()
            .iter()
            .map(|e| 1.5 * e.stiffness_fraction * x.min(e.yield_fraction))
            .sum()
    }

    #[test]
    fn elements_interpolate_the_virgin_curve_at_their_corners() {
        let elements = iwan_elements();
        assert!(elements.iter().all(|e| e.stiffness_fraction > 0.0));
        assert!(elements
            .windows(2)
            .all(|w| w[0].yield_fraction < w[1].yield_fraction));
        assert_eq!(elements[IWAN_ELEMENTS - 1].yield_fraction, 1.0);
        for e in elements {
            let exact = 1.0 - (1.0 - e.yield_fraction).powf(1.5);
            assert!((iwan_curve(e.yield_fraction) - exact).abs() < 1e-12);
        }
        // the whole μP at δ_s, and the initial stiffness the chord's below k₀ by < 0.2 %
        assert!((iwan_curve(1.0) - 1.0).abs() < 1e-12);
        let k: f64 = elements.iter().map(|e| e.stiffness_fraction).sum();
        assert!(k < 1.0 && k > 0.998, "initial stiffness {k} k0");
    }

    #[test]
    fn a_memory_round_trips_and_a_wrong_one_is_refused_naming_the_field() {
        let mut m = TangentialMemory::default();
        m.stretches[3] = [1e-7, -2e-7];
        let s = serde_json::to_string(&m).unwrap();
        assert_eq!(serde_json::from_str::<TangentialMemory>(&s).unwrap(), m);
        let b = bincode::serialize(&m).unwrap();
        assert_eq!(bincode::deserialize::<TangentialMemory>(&b).unwrap(), m);
        // an empty memory is an empty list: a length in the binary form
        let empty = TangentialMemory::default();
        assert_eq!(
            serde_json::to_string(&empty).unwrap(),
            r#"{"stretches":[]}"#
        );
        let b = bincode::serialize(&empty).unwrap();
        assert_eq!(b.len(), 8);
        assert_eq!(bincode::deserialize::<TangentialMemory>(&b).unwrap(), empty);
        let short = r#"{"stretches":[[0,0]]}"#;
        let err = serde_json::from_str::<TangentialMemory>(short).unwrap_err();
        assert!(
            err.to_string().contains("tangential_memory.stretches"),
            "{err}"
        );
    }

    /// The preconditioner's ∂f/∂g of a bank in partial slip, loaded along t₁ and then turned
    /// across it: central differences of the force at fixed tangents, P and k₀; symmetric, and
    /// not the isotropic stiffness of the sticking elements (the sliding ones resist across
    /// their sliding direction).
    #[test]
    fn the_preconditioner_jacobian_is_the_force_derivative_in_partial_slip() {
        let (mu, p, k0) = (0.3, 100.0, 3e7);
        let delta_s = 1.5 * mu * p / k0;
        let (t1, t2) = (Vector3::x(), Vector3::y());
        let at = |m: &TangentialMemory, e: [f64; 2], g: Vector3<f64>| {
            evaluate::<f64>(m, e, &V3::cst(&g), &V3::cst(&t1), &V3::cst(&t2), p, k0, mu)
        };
        let virgin = TangentialMemory::default();
        let loaded = at(&virgin, [0.0, 0.0], Vector3::new(0.6 * delta_s, 0.0, 0.0));
        let mut memory = TangentialMemory::default();
        for (kept, s) in memory.stretches.iter_mut().zip(&loaded.stretches) {
            *kept = [s.x, s.y];
        }
        let elastic = [loaded.elastic.x, loaded.elastic.y];
        let g = loaded.elastic + Vector3::new(0.1, 0.25, 0.0) * delta_s;
        let trial = at(&memory, elastic, g);
        assert!(!trial.slip);
        let j = trial.jacobian;
        let h = 1e-7 * delta_s;
        for c in 0..3 {
            let mut e = Vector3::zeros();
            e[c] = h;
            let fd = (at(&memory, elastic, g + e).force.val()
                - at(&memory, elastic, g - e).force.val())
                / (2.0 * h);
            let err = (j.column(c) - fd).norm();
            assert!(
                err <= 1e-6 * j.norm(),
                "column {c}: {} against {fd}",
                j.column(c)
            );
        }
        assert!((j - j.transpose()).norm() <= 1e-12 * j.norm());
        // the sum of the sticking elements' stiffnesses (a sliding one's stretch is at its
        // limit, a sticking one's within it)
        let stretches = trial
            .stretches
            .iter()
            .chain(std::iter::once(&trial.elastic));
        let sticking: f64 = iwan_elements()
            .iter()
            .zip(stretches)
            .filter(|(e, s)| s.norm() < e.yield_fraction * delta_s * (1.0 - 1e-9))
            .map(|(e, _)| e.stiffness_fraction * k0)
            .sum();
        assert!(sticking > 0.0);
        let isotropic = Matrix3::identity() * sticking;
        assert!(
            (j - isotropic).norm() > 0.05 * j.norm(),
            "{j} against {isotropic}"
        );
    }
}
