//! The reduced response's contact under the Cattaneo–Mindlin law: the one-dimensional Iwan
//! bank of the FE element ([`crate::contact::memory`]), loaded through the structure equation.
//!
//! Each contact keeps the elastic stretches eᵢ of the bank's Jenkins elements, whose
//! stiffnesses kᵢ = φᵢ k₀ and limits ℓᵢ = xᵢ δ_s follow the normal force through
//! k₀(f_N) = 8 G* c(f_N) (Hertz point contacts) or the line law's own (line contacts on the
//! core), and δ_s = 3 μ f_N / (2 k₀): the FE element's bank, with its fractions φᵢ, xᵢ
//! ([`crate::contact::memory::iwan_elements`]). A normal force that falls makes the elements
//! beyond their new limit slide, as in the FE element. The tangential force is
//! Q = Σ kᵢ eᵢ, its stick part s_e = Q / k with k = Σ kᵢ the bank's stiffness in stick, and the
//! irreversible slip s_p = s − s_e.
//!
//! The structure equation `s + g Q + r s_e = d` is, with c = g + r / k, `h(s) = s + c Q(s) = d`.
//! Along a monotone change of s every element that has not reached its limit stretches with s,
//! so h is piecewise linear with slope 1 + c K ≥ 1 (K the stiffness of the elements still
//! inside their limits): [`IwanContact::step`] solves it exactly by walking the elements' yield
//! points from the last state in the direction of d − h. Masing's rule and the memory of nested
//! loops come from each element's own stretch, as in the FE element.

use serde::{Deserialize, Serialize};

use crate::contact::laws::{ResolvedLaws, ResolvedNormal, ResolvedTangential};
use crate::contact::memory::{iwan_elements, IWAN_ELEMENTS};

/// The initial tangential stiffness k₀(f_N) of one contact (N/m) under the Cattaneo–Mindlin law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum InitialStiffness {
    /// A Hertz point contact: k₀ = `coefficient` · f_N^{1/3} (8 G* c, c ∝ f_N^{1/3}).
    Point {
        /// N^{2/3}/m.
        coefficient: f64,
    },
    /// A line contact of the line law ([`crate::contact::hertz::LineContact`]):
    /// k₀ = `coefficient` / (ln(`load_scale_n` / f_N) − 2) while f_N ≤ `load_scale_n` e⁻³,
    /// `coefficient` beyond (the law's linear continuation).
    Line {
        /// (4 G*/E*) π E* ℓ (N/m).
        coefficient: f64,
        /// C ℓ = 4π E* (R₁ + R₂) ℓ (N).
        load_scale_n: f64,
    },
}

impl InitialStiffness {
    /// The initial stiffness of a contact with the resolved `laws`, if its tangential law is
    /// Cattaneo–Mindlin's.
    pub fn of(laws: &ResolvedLaws) -> Option<Self> {
        match (laws.tangential, laws.normal) {
            (ResolvedTangential::CattaneoMindlinPoint(coefficient), _) => {
                Some(Self::Point { coefficient })
            }
            (ResolvedTangential::CattaneoMindlinLine(ratio), ResolvedNormal::Line(l)) => {
                Some(Self::Line {
                    coefficient: ratio * std::f64::consts::PI * l.e_star * l.length_m,
                    load_scale_n: l.c_n_per_m * l.length_m,
                })
            }
            _ => None,
        }
    }

    /// k₀ at normal force `f_n` (N/m; 0 for an open contact, `f_n` ≤ 0).
    #[inline]
    pub fn at(&self, f_n: f64) -> f64 {
        if f_n <= 0.0 {
            return 0.0;
        }
        match *self {
            Self::Point { coefficient } => coefficient * f_n.cbrt(),
            Self::Line {
                coefficient,
                load_scale_n,
            } => {
                let l = (load_scale_n / f_n).ln();
                if l > 3.0 {
                    coefficient / (l - 2.0)
                } else {
                    coefficient
                }
            }
        }
    }

    /// Finite and positive coefficients.
    pub(crate) fn is_valid(&self) -> bool {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        match *self {
            Self::Point { coefficient } => ok(coefficient),
            Self::Line {
                coefficient,
                load_scale_n,
            } => ok(coefficient) && ok(load_scale_n),
        }
    }
}

/// Relative slack of a limit within which an element counts as at its limit (round-off of
/// the walk).
const AT_LIMIT: f64 = 1e-12;

/// The bank's stiffness in stick over k₀, Σ φᵢ: the chord of its first segment, a hair below
/// the closed form's initial slope. The stick part of a slip is taken with it, so that a
/// contact in stick keeps its irreversible slip.
pub fn stick_fraction() -> f64 {
    static FRACTION: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *FRACTION.get_or_init(|| iwan_elements().iter().map(|e| e.stiffness_fraction).sum())
}

/// The structure compliance `c = g + r / k` of a contact with compliance `g`, stick ratio `r`
/// and initial stiffness `k0`, `k` the bank's stiffness in stick (0 for an open contact).
#[inline]
pub(crate) fn structure_compliance(g: f64, r: f64, k0: f64) -> f64 {
    if k0 > 0.0 {
        g + r / (stick_fraction() * k0)
    } else {
        0.0
    }
}

/// One contact's Iwan bank in the reduced response (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct IwanContact {
    /// Slip s (m).
    pub slip_m: f64,
    /// Elastic stretch of each element (m), weakest first.
    pub stretches: [f64; IWAN_ELEMENTS],
}

/// What a step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct IwanStep {
    /// Slip s (m).
    pub slip_m: f64,
    /// Tangential force Q (N).
    pub force_n: f64,
    /// Irreversible slip s − Q/k (m), k the bank's stiffness in stick.
    pub plastic_m: f64,
    /// ds_p/dd on the last segment of the walk: (1 − K/k)/(1 + c K), 0 in stick, 1 in gross
    /// slip.
    pub plastic_rate: f64,
    /// Whether the irreversible slip moved: an element slid at its limit, or was pulled back
    /// to a lower one.
    pub yielded: bool,
    /// The drive change that would make the first element yield, in either direction, from
    /// the state reached (m of drive; 0 if an element is at its limit).
    pub distance_m: f64,
}

impl IwanContact {
    /// The contact unloaded at slip `slip_m`.
    pub(crate) fn unloaded(slip_m: f64) -> Self {
        Self {
            slip_m,
            stretches: [0.0; IWAN_ELEMENTS],
        }
    }

    /// The tangential force at initial stiffness `k0` (N).
    fn force(&self, k0: f64) -> f64 {
        iwan_elements()
            .iter()
            .zip(&self.stretches)
            .map(|(e, s)| e.stiffness_fraction * k0 * s)
            .sum()
    }

    /// Advances the contact to drive `drive_m` at normal force `normal_n` with initial
    /// stiffness `k0` (> 0 when closed), compliance `g`, stick ratio `r` and friction
    /// coefficient `mu`. An open contact (`normal_n` ≤ 0) carries nothing and forgets its
    /// stretches: its slip follows the drive.
    pub(crate) fn step(
        &mut self,
        drive_m: f64,
        normal_n: f64,
        k0: f64,
        compliance_m_per_n: f64,
        stick_ratio: f64,
        mu: f64,
    ) -> IwanStep {
        let c = structure_compliance(compliance_m_per_n, stick_ratio, k0);
        self.step_with(drive_m, normal_n, k0, c, mu)
    }

    /// [`Self::step`] with the contact's structure compliance `c = g + r / k` given, `k` the
    /// bank's stiffness in stick ([`stick_fraction`] · k₀).
    pub(crate) fn step_with(
        &mut self,
        drive_m: f64,
        normal_n: f64,
        k0: f64,
        c: f64,
        mu: f64,
    ) -> IwanStep {
        if normal_n <= 0.0 || k0 <= 0.0 || mu <= 0.0 {
            let yielded = self.stretches.iter().any(|&s| s != 0.0) || drive_m != self.slip_m;
            *self = Self::unloaded(drive_m);
            return IwanStep {
                slip_m: drive_m,
                force_n: 0.0,
                plastic_m: drive_m,
                plastic_rate: 1.0,
                yielded,
                distance_m: 0.0,
            };
        }
        let elements = iwan_elements();
        let delta_s = 1.5 * mu * normal_n / k0;
        let full = stick_fraction() * k0;
        let limit = |i: usize| elements[i].yield_fraction * delta_s;
        let mut yielded = false;
        // a normal force that fell: the elements beyond their new limit slide to it
        for (i, s) in self.stretches.iter_mut().enumerate() {
            let l = limit(i);
            if s.abs() > l {
                *s = l.copysign(*s);
                yielded = true;
            }
        }
        let h = self.slip_m + c * self.force(k0);
        let delta = drive_m - h;
        let mut rate = 0.0;
        if delta != 0.0 {
            let dir = delta.signum();
            let mut remaining = delta.abs();
            // each element's travel in s to its limit in direction `dir`; those already there
            // slide from the start
            let travel: [f64; IWAN_ELEMENTS] = std::array::from_fn(|i| {
                let t = limit(i) - dir * self.stretches[i];
                if t <= AT_LIMIT * limit(i) {
                    0.0
                } else {
                    t
                }
            });
            let mut stiffness: f64 = (0..IWAN_ELEMENTS)
                .filter(|&i| travel[i] > 0.0)
                .map(|i| elements[i].stiffness_fraction * k0)
                .sum();
            let mut moved = 0.0;
            loop {
                let slope = 1.0 + c * stiffness;
                rate = if stiffness >= full * (1.0 - 1e-12) {
                    0.0
                } else {
                    (1.0 - stiffness / full) / slope
                };
                if rate > 0.0 {
                    yielded = true;
                }
                // the next element to reach its limit beyond `moved`
                let next = (0..IWAN_ELEMENTS)
                    .filter(|&i| travel[i] > moved)
                    .min_by(|&a, &b| travel[a].total_cmp(&travel[b]));
                match next {
                    Some(i) if slope * (travel[i] - moved) < remaining => {
                        remaining -= slope * (travel[i] - moved);
                        let reached = travel[i];
                        // every element of that travel yields there
                        for j in 0..IWAN_ELEMENTS {
                            if travel[j] > moved && travel[j] <= reached {
                                stiffness -= elements[j].stiffness_fraction * k0;
                            }
                        }
                        stiffness = stiffness.max(0.0);
                        moved = reached;
                    }
                    _ => {
                        moved += remaining / slope;
                        break;
                    }
                }
            }
            for (i, s) in self.stretches.iter_mut().enumerate() {
                *s = if travel[i] <= moved {
                    dir * limit(i)
                } else {
                    *s + dir * moved
                };
            }
            self.slip_m += dir * moved;
        }
        let force_n = self.force(k0);
        let distance_m = (0..IWAN_ELEMENTS)
            .map(|i| (limit(i) - self.stretches[i].abs()).max(0.0))
            .fold(f64::INFINITY, f64::min)
            * (1.0 + c * full);
        IwanStep {
            slip_m: self.slip_m,
            force_n,
            plastic_m: self.slip_m - force_n / full,
            plastic_rate: rate,
            yielded,
            distance_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::hertz::LineContact;

    const MU: f64 = 0.12;

    /// The Cattaneo–Mindlin virgin curve Q/μP = 1 − (1 − δ/δ_s)^{3/2}.
    fn virgin(delta: f64, delta_s: f64) -> f64 {
        let x = (delta / delta_s).min(1.0);
        1.0 - (1.0 - x).powf(1.5)
    }

    #[test]
    fn a_free_contact_follows_the_cattaneo_mindlin_curve_and_masing_loop() {
        // g = r = 0: the slip is the drive, the force the bank's; at the corners the bank is
        // the closed form (the chord interpolant), between them within 0.5 % of μP
        let (p, k0) = (300.0, 3.0e7);
        let delta_s = 1.5 * MU * p / k0;
        let mut c = IwanContact::unloaded(0.0);
        let mut worst = 0.0_f64;
        for k in 1..=200 {
            let d = 1.2 * delta_s * k as f64 / 200.0;
            let st = c.step(d, p, k0, 0.0, 0.0, MU);
            assert_eq!(st.slip_m, d);
            let err = (st.force_n / (MU * p) - virgin(d, delta_s)).abs();
            worst = worst.max(err);
        }
        assert!(worst < 5e-3, "virgin curve off by {worst} μP");
        // at gross slip the force is μP to round-off
        let st = c.step(2.0 * delta_s, p, k0, 0.0, 0.0, MU);
        assert!((st.force_n / (MU * p) - 1.0).abs() < 1e-12);
        assert_eq!(st.plastic_rate, 1.0);
        // unloading from gross slip: Masing's branch Q = μP − 2 μP q((δ* − δ)/(2δ_s))
        let top = 2.0 * delta_s;
        let mut worst = 0.0_f64;
        for k in 1..=200 {
            let d = top - 4.0 * delta_s * k as f64 / 200.0;
            let st = c.step(d, p, k0, 0.0, 0.0, MU);
            let exact = 1.0 - 2.0 * virgin(top - d, 2.0 * delta_s);
            worst = worst.max((st.force_n / (MU * p) - exact).abs());
        }
        assert!(worst < 1e-2, "unloading branch off by {worst} μP");
    }

    #[test]
    fn the_walk_solves_the_structure_equation_exactly() {
        // s + g Q + r Q/k₀ = d at every step, through loading, reversal, nested loops and a
        // normal force that rises and falls
        let (k0, g, r) = (2.0e7, 3.0e-8, 0.4);
        let mut c = IwanContact::unloaded(1e-6);
        let drives = [2e-6, 5e-6, 3e-6, 4e-6, 1e-7, -6e-6, 8e-6, 7.5e-6, 7.9e-6];
        let forces = [200.0, 220.0, 240.0, 180.0, 150.0, 260.0, 90.0, 95.0, 100.0];
        for (&d, &p) in drives.iter().zip(&forces) {
            let k = k0 * (p / 200.0_f64).cbrt();
            let st = c.step(d, p, k, g, r, MU);
            let full = stick_fraction() * k;
            let h = st.slip_m + g * st.force_n + r * st.force_n / full;
            assert!((h - d).abs() < 1e-15, "h = {h}, d = {d}");
            assert!(st.force_n.abs() <= MU * p * (1.0 + 1e-12));
            assert!((st.plastic_m - (st.slip_m - st.force_n / full)).abs() < 1e-18);
            // a step to the same drive moves nothing but round-off
            let before = c;
            let again = c.step(d, p, k, g, r, MU);
            assert!((c.slip_m - before.slip_m).abs() < 1e-18);
            for (a, b) in c.stretches.iter().zip(&before.stretches) {
                assert!((a - b).abs() < 1e-18);
            }
            assert!((again.force_n - st.force_n).abs() < 1e-9 * MU * p);
        }
    }

    #[test]
    fn the_plastic_rate_and_the_distance_to_yield_are_the_walks() {
        // at constant normal force: ds_p/dd on the last segment against a finite difference
        // of a further step the same way, and a stuck contact stays stuck within its distance
        let (p, k0, g, r) = (400.0, 3.0e7, 2.0e-8, 0.3);
        let mut c = IwanContact::unloaded(0.0);
        let mut previous = 0.0;
        for d in [1e-7, 1.5e-6, 2.9e-6, 2.0e-6, 1.0e-6, -3e-6, 1e-5, 9.9e-6] {
            let st = c.step(d, p, k0, g, r, MU);
            let dir = (d - previous).signum();
            previous = d;
            let eps = 1e-13;
            let mut probe = c;
            let next = probe.step(d + dir * eps, p, k0, g, r, MU);
            let rate = (next.plastic_m - st.plastic_m) / (dir * eps);
            if st.yielded {
                assert!(
                    (rate - st.plastic_rate).abs() < 1e-3,
                    "d = {d}: rate {rate} against {}",
                    st.plastic_rate
                );
            } else {
                assert!(rate.abs() < 1e-3, "stuck at d = {d}, yet ds_p/dd = {rate}");
            }
            if st.distance_m > 0.0 {
                for side in [-1.0, 1.0] {
                    let mut probe = c;
                    let moved = probe.step(d + side * 0.999 * st.distance_m, p, k0, g, r, MU);
                    assert!(!moved.yielded, "d = {d}: yielded within its distance");
                    assert!((moved.plastic_m - st.plastic_m).abs() < 1e-18);
                }
            }
        }
    }

    #[test]
    fn a_symmetric_loop_dissipates_the_mindlin_deresiewicz_energy() {
        // the Masing loop of the virgin curve F: W = 4 Q* δ* − 8 ∫₀^δ* F dδ; with
        // F = μP (1 − (1 − δ/δ_s)^{3/2}) and x* = δ*/δ_s = 1 − (1 − t)^{2/3}, t = Q*/μP:
        // W / (μP δ_s) = 4 t x* − 8 (x* − (2/5)(1 − (1 − x*)^{5/2})) (Mindlin & Deresiewicz 1953;
        // Johnson 1985, §7.4). The bank's loop within 1 % for Q* from 0.05 to 0.99 μP.
        let (p, k0) = (500.0, 4.0e7);
        let delta_s = 1.5 * MU * p / k0;
        for t in [0.05_f64, 0.2, 0.5, 0.9, 0.99] {
            let x = 1.0 - (1.0 - t).powf(2.0 / 3.0);
            let exact = 4.0 * t * x - 8.0 * (x - 0.4 * (1.0 - (1.0 - x).powf(2.5)));
            let amplitude = x * delta_s;
            let n = 4000;
            let mut c = IwanContact::unloaded(0.0);
            let mut step = |d: f64| {
                let st = c.step(d, p, k0, 0.0, 0.0, MU);
                (st.slip_m, st.force_n)
            };
            for k in 0..=n {
                step(amplitude * k as f64 / n as f64);
            }
            let mut last = step(amplitude);
            let mut work = 0.0;
            for k in 1..=4 * n {
                let f = k as f64 / n as f64;
                let d = if f <= 2.0 { 1.0 - f } else { f - 3.0 } * amplitude;
                let now = step(d);
                work += 0.5 * (now.1 + last.1) * (now.0 - last.0);
                last = now;
            }
            let work = -work / (MU * p * delta_s);
            assert!(
                (work / exact - 1.0).abs() < 0.01,
                "t = {t}: loop energy {work} against {exact} μP δ_s"
            );
        }
    }

    #[test]
    fn the_initial_stiffness_is_the_fe_elements() {
        let l = LineContact::new(2.5e-3, 2.3e-3, 4e-3, 1.15e11);
        let ratio = 0.8;
        let s = InitialStiffness::Line {
            coefficient: ratio * std::f64::consts::PI * l.e_star * l.length_m,
            load_scale_n: l.c_n_per_m * l.length_m,
        };
        for p in [5.0, 50.0, 500.0, 5000.0] {
            let pen = l.approach_m(p / l.length_m);
            let (f, k) = l.force_and_stiffness(pen);
            assert!((f / p - 1.0).abs() < 1e-6, "line law inverse: {f} vs {p}");
            assert!(
                (s.at(p) / (ratio * k) - 1.0).abs() < 1e-6,
                "k₀ {} vs {}",
                s.at(p),
                ratio * k
            );
        }
        let point = InitialStiffness::Point { coefficient: 2.0e6 };
        assert!((point.at(1000.0) - 2.0e7).abs() < 1e-6);
    }
}
