//! The Cattaneo–Mindlin tangential law with memory, in the element's two-dimensional tangential
//! gap.
//!
//! One dimension, constant normal force P (Johnson 1985, §7.2-7.3; Mindlin & Deresiewicz 1953):
//! - virgin loading: Q = μP [1 − (1 − δ/δ_s)^{3/2}], δ_s = 3μP/(2 k₀), k₀ = 8 G* c the initial
//!   stiffness (Johnson eq. 7.42: δ_s = 3μP/(16 G* c));
//! - after a reversal at (δ*, Q*), Masing's rule: the branch is the virgin curve scaled by two
//!   from the reversal point, Q = Q* − 2μP [1 − (1 − (δ* − δ)/(2δ_s))^{3/2}] on unloading;
//! - gross sliding at |Q| = μP (Coulomb).
//!
//! In the tangent plane the displacement δ is the element's elastic tangential gap g (micro-slip
//! included; the Coulomb part is sliding) and the reversal points are vectors. The branch from
//! the newest reversal point (g_k, Q_k) is
//!   Q = Q_k + κ μP [1 − (1 − s/(κ δ_s))^{3/2}] (g − g_k)/s,  s = |g − g_k|,
//! with κ = 1 on the virgin curve (g₀ = 0, Q₀ = 0) and κ = 2 after a reversal, written
//! Q = Q_k + (μP/δ_s) F(x) (g − g_k), x = s/(κ δ_s), F(x) = (1 + y + y²)/(1 + y), y = (1 − x)^{1/2},
//! which is smooth at s = 0 (F(0) = 3/2: initial stiffness k₀ in every direction).
//! - Reversal: the trial gap moves back towards the current branch's origin,
//!   (g − g_n)·(g_n − g_k) < 0 with g_n the last accepted gap: (g_n, Q(g_n)) is pushed. In two
//!   dimensions the two branches differ off the line of the branch: the forces of the branch
//!   continued and of the branch reversed are blended (C¹ smoothstep) over the steps whose
//!   cosine with the way back lies within ±[`REVERSAL_BAND`], so that the force is continuous
//!   (in one dimension the cosine is ±1 and one branch is taken exactly); the memory kept is
//!   that of the branch of larger weight.
//! - Memory (Masing's rule for nested loops): a branch that reaches the reversal point before
//!   its own (the mirror point −g₁ for the first branch, whose previous branch is the symmetric
//!   virgin curve) rejoins the branch it interrupted: both points are popped. At most
//!   [`MEMORY_DEPTH`] points are kept; a deeper nesting forgets the oldest.
//! - Gross sliding: when |Q| > μP (or s ≥ κ δ_s) the force is returned to μP Q/|Q| and the
//!   memory is wiped out (Coulomb sliding erases it): the gap is put back on the virgin curve's
//!   end, g = δ_s Q/|Q|, the rest of the trial gap is sliding.
//!
//! Varying normal force: the branch is evaluated with the current P (and so the current contact
//! radius and δ_s ∝ P^{2/3}) while the stored reversal forces Q_k stay fixed; a P that falls
//! below |Q_k|/μ makes the contact slide. This is the exact solution only when P is constant. It
//! neglects Mindlin & Deresiewicz's dependence on the path of (P, Q) between two reversals: the
//! frozen slip annuli of an earlier, larger P, the extra stiffness of a P that grows faster than
//! |Q|/μ (no slip at all), and the memory of P at a reversal point.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::scalar::{Scalar, V3};

/// Reversal points kept in a contact's memory.
pub const MEMORY_DEPTH: usize = 4;

/// Half-width, in the cosine of the angle between the step and the way back to the newest
/// reversal point, of the band over which the continued and the reversed branch are blended.
pub const REVERSAL_BAND: f64 = 0.2;

/// The reversal points of the Cattaneo–Mindlin law at the last accepted step (empty for the
/// other laws and on the virgin curve).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TangentialMemory {
    /// Reversal points, oldest first: elastic tangential gap (m) and tangential force (N), each
    /// by its components on (t₁₍ₙ₎, t₂₍ₙ₎): [g₁, g₂, Q₁, Q₂].
    pub reversals: [[f64; 4]; MEMORY_DEPTH],
    /// How many of them are held.
    pub count: u8,
}

/// A trial evaluation of the law.
pub(crate) struct Trial<S> {
    /// Tangential force.
    pub force: V3<S>,
    /// Gross sliding.
    pub slip: bool,
    /// Reversal points (gap, force) in the current frame, oldest first.
    pub points: [(Vector3<f64>, Vector3<f64>); MEMORY_DEPTH],
    /// How many.
    pub count: usize,
    /// Elastic gap to keep (m).
    pub elastic: Vector3<f64>,
    /// Tangent stiffness of the current branch along its direction (N/m), for preconditioning.
    pub stiffness: f64,
}

fn map<S: Scalar>(t1: &V3<S>, t2: &V3<S>, a: f64, b: f64) -> V3<S> {
    t1.scalef(a) + t2.scalef(b)
}

/// Force of the branch from (`gk`, `qk`) with scale `kappa` at the gap `g`; also x = s/(κ δ_s)
/// (the branch has reached its end when x ≥ 1).
fn branch<S: Scalar>(
    g: &V3<S>,
    gk: &V3<S>,
    qk: &V3<S>,
    kappa: f64,
    limit: S,
    delta_s: S,
) -> (V3<S>, f64) {
    let w = *g - *gk;
    if w.norm().val() == 0.0 {
        // F(0) = 3/2; the derivative of s is undefined here but multiplies w = 0.
        return (*qk + w.scale(limit / delta_s * 1.5), 0.0);
    }
    let s = w.norm();
    let x = s / (delta_s * kappa);
    if x.val() >= 1.0 {
        return (*qk + w.scale(limit * kappa / s), x.val());
    }
    let y = (S::cst(1.0) - x).sqrt();
    let f = (y + y * y + 1.0) / (y + 1.0);
    (*qk + w.scale(limit / delta_s * f), x.val())
}

/// The Cattaneo–Mindlin force at the trial elastic gap `g`, from the accepted `memory` and gap
/// `previous` (both mapped with the current t₁, t₂), normal force `p`, initial stiffness `k0`
/// and friction coefficient `mu`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate<S: Scalar>(
    memory: &TangentialMemory,
    previous: &V3<S>,
    g: &V3<S>,
    t1: &V3<S>,
    t2: &V3<S>,
    p: S,
    k0: S,
    mu: f64,
) -> Trial<S> {
    let zero = S::cst(0.0);
    let empty = [(Vector3::zeros(), Vector3::zeros()); MEMORY_DEPTH];
    if mu <= 0.0 {
        return Trial {
            force: V3::new(zero, zero, zero),
            slip: g.norm().val() > 0.0,
            points: empty,
            count: 0,
            elastic: Vector3::zeros(),
            stiffness: 0.0,
        };
    }
    let limit = p * mu;
    let delta_s = limit * 1.5 / k0;
    let origin = V3::new(zero, zero, zero);
    let mut stack = [(origin, origin); MEMORY_DEPTH];
    let count = (memory.count as usize).min(MEMORY_DEPTH);
    for (slot, r) in stack.iter_mut().zip(&memory.reversals).take(count) {
        *slot = (map(t1, t2, r[0], r[1]), map(t1, t2, r[2], r[3]));
    }
    let top = |stack: &[(V3<S>, V3<S>); MEMORY_DEPTH], count: usize| {
        if count == 0 {
            (origin, origin, 1.0)
        } else {
            (stack[count - 1].0, stack[count - 1].1, 2.0)
        }
    };
    // Reversal: the trial gap heads back towards the current branch's origin. The branch
    // without (A) and with (B) the reversal are blended over a band of step directions nearly
    // perpendicular to the branch, |cos| < REVERSAL_BAND, so that the force stays continuous in
    // two dimensions (in one, cos = ±1 and one branch is taken exactly).
    let (gk, qk, kappa) = top(&stack, count);
    let back = *previous - gk;
    let step = *g - *previous;
    let (bn, sn) = (back.norm().val(), step.norm().val());
    let cosine = if bn > 0.0 && sn > 0.0 {
        Some(step.dot(&back) / (step.norm() * back.norm()))
    } else {
        None
    };
    let weight = cosine.map(|c| {
        if c.val() <= -REVERSAL_BAND {
            S::cst(1.0)
        } else if c.val() >= REVERSAL_BAND {
            S::cst(0.0)
        } else {
            // smoothstep from 0 at c = +band to 1 at c = −band (C¹)
            let t = (S::cst(REVERSAL_BAND) - c) / S::cst(2.0 * REVERSAL_BAND);
            t * t * (S::cst(3.0) - t * 2.0)
        }
    });
    let follow = |mut stack: [(V3<S>, V3<S>); MEMORY_DEPTH], mut count: usize| {
        // Memory: a branch reaching the reversal point before its own rejoins the earlier one.
        while count > 0 {
            let gk = stack[count - 1].0.val();
            let gp = if count >= 2 {
                stack[count - 2].0.val()
            } else {
                -gk
            };
            let span = gp - gk;
            let w = g.val() - gk;
            if span.norm() > 0.0 && w.dot(&span) > 0.0 && w.norm() >= span.norm() {
                count -= count.min(2);
            } else {
                break;
            }
        }
        let (gk, qk, kappa) = top(&stack, count);
        let (q, x) = branch(g, &gk, &qk, kappa, limit, delta_s);
        stack
            .iter_mut()
            .skip(count)
            .for_each(|e| *e = (origin, origin));
        (stack, count, q, x)
    };
    let continued = match weight {
        Some(w) if w.val() >= 1.0 => None,
        _ => Some(follow(stack, count)),
    };
    let reversed = match weight {
        Some(w) if w.val() > 0.0 => {
            let (q_prev, _) = branch(previous, &gk, &qk, kappa, limit, delta_s);
            let (mut pushed, mut n) = (stack, count);
            if n == MEMORY_DEPTH {
                pushed.copy_within(1.., 0);
                n -= 1;
            }
            pushed[n] = (*previous, q_prev);
            Some(follow(pushed, n + 1))
        }
        _ => None,
    };
    let (stack, count, q, x) = match (continued, reversed, weight) {
        (Some(a), None, _) => a,
        (None, Some(b), _) => b,
        (Some(a), Some(b), Some(w)) => {
            let q = a.2 + (b.2 - a.2).scale(w);
            let x = a.3 + (b.3 - a.3) * w.val();
            if w.val() >= 0.5 {
                (b.0, b.1, q, x)
            } else {
                (a.0, a.1, q, x)
            }
        }
        _ => unreachable!("one branch at least is followed"),
    };
    let mut points = empty;
    for (out, (a, b)) in points.iter_mut().zip(&stack).take(count) {
        *out = (a.val(), b.val());
    }
    let qn = q.norm();
    if x >= 1.0 || qn.val() > limit.val() {
        let dir = q.val() / qn.val();
        return Trial {
            force: q.scale(limit / qn),
            slip: true,
            points: empty,
            count: 0,
            elastic: dir * delta_s.val(),
            stiffness: 0.0,
        };
    }
    Trial {
        force: q,
        slip: false,
        points,
        count,
        elastic: g.val(),
        stiffness: k0.val() * (1.0 - x).max(0.0).sqrt(),
    }
}
