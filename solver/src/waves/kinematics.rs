//! Linear (Airy) wave kinematics in finite depth, summed over a set of wave components, with
//! Wheeler stretching.
//!
//! Each component n has angular frequency ωₙ, wavenumber kₙ (from the dispersion relation) and a
//! complex amplitude aₙ; its phase at horizontal position x and time t is
//! θₙ = ωₙ t − kₙ (x cos β + y sin β) for propagation heading β (from +x towards +y), and
//!
//! η   = Σ Re(aₙ e^{iθₙ})
//! u_h = Σ ωₙ  C(kₙ, s) Re(aₙ e^{iθₙ})         w   = Σ ωₙ  S(kₙ, s) Im(aₙ e^{iθₙ})
//! a_h = −Σ ωₙ² C(kₙ, s) Im(aₙ e^{iθₙ})        a_z = Σ ωₙ² S(kₙ, s) Re(aₙ e^{iθₙ})
//! p_d = ρ Σ (ωₙ²/kₙ) C(kₙ, s) Re(aₙ e^{iθₙ})   (= ρ g a cosh(ks)/cosh(kd) cos θ)
//!
//! with C = cosh(k s)/sinh(k d), S = sinh(k s)/sinh(k d), evaluated in the overflow-free form
//! C, S = (e^{k(s−d)} ± e^{−k(s+d)}) / (1 − e^{−2kd}). The horizontal vectors are u_h and a_h
//! along (cos β, sin β). The accelerations are the local (∂/∂t) ones of linear theory.
//!
//! Wheeler stretching maps the wetted column [−d, η] onto [−d, 0]: the profiles are evaluated at
//! z' = (z − η) d/(d + η), i.e. at s = z' + d = (z + d) d/(d + η). Above the instantaneous surface
//! (z > η) the point is dry and every quantity is zero.
//!
//! Units: m, s, rad, Pa; z up, still water at z = 0, seabed at z = −d.

use nalgebra::{Complex, Vector3};

use super::sea::FluidKinematics;

/// One linear wave component: η = Re(amplitude · e^{i(ω t − k x_β)}).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveComponent {
    /// Angular frequency ω (rad/s).
    pub omega_rad_s: f64,
    /// Wavenumber k (rad/m), satisfying ω² = g k tanh(k d).
    pub wavenumber_rad_m: f64,
    /// Complex amplitude (m): modulus is the amplitude, argument the phase at x = 0, t = 0.
    pub amplitude_m: Complex<f64>,
}

/// Depth profiles (C, S) = (cosh(k s), sinh(k s)) / sinh(k d) at height s above the seabed.
#[inline]
pub(crate) fn depth_profiles(k: f64, s: f64, depth_m: f64) -> (f64, f64) {
    let denom = -(-2.0 * k * depth_m).exp_m1();
    let up = (k * (s - depth_m)).exp();
    let down = (-k * (s + depth_m)).exp();
    ((up + down) / denom, (up - down) / denom)
}

/// Wheeler-stretched height above the seabed s = (z + d) d/(d + η), or `None` when the point is
/// dry (z > η) or the trough reaches the seabed.
#[inline]
pub(crate) fn stretched_height(z: f64, eta: f64, depth_m: f64) -> Option<f64> {
    if z > eta || depth_m + eta <= 0.0 {
        None
    } else {
        Some((z + depth_m) * depth_m / (depth_m + eta))
    }
}

/// A set of linear components in water of given depth and density, travelling along one heading.
#[derive(Debug, Clone, PartialEq)]
pub struct AiryField {
    components: Vec<WaveComponent>,
    /// Per-component constants of the direct summation (see [`SummationTerm`]).
    terms: Vec<SummationTerm>,
    depth_m: f64,
    heading_rad: f64,
    direction: (f64, f64),
    water_density_kg_m3: f64,
}

impl AiryField {
    /// Field of `components` (already validated) in depth `depth_m`, heading `heading_rad`.
    pub(crate) fn new(
        components: Vec<WaveComponent>,
        depth_m: f64,
        heading_rad: f64,
        water_density_kg_m3: f64,
    ) -> Self {
        let terms = components
            .iter()
            .map(|c| SummationTerm::new(c, depth_m))
            .collect();
        Self {
            components,
            terms,
            depth_m,
            heading_rad,
            direction: (heading_rad.cos(), heading_rad.sin()),
            water_density_kg_m3,
        }
    }

    /// The wave components.
    pub fn components(&self) -> &[WaveComponent] {
        &self.components
    }
    /// Water depth (m).
    pub fn depth_m(&self) -> f64 {
        self.depth_m
    }
    /// Propagation heading β (rad, from +x towards +y).
    pub fn heading_rad(&self) -> f64 {
        self.heading_rad
    }
    /// Unit propagation direction (cos β, sin β).
    pub fn direction(&self) -> (f64, f64) {
        self.direction
    }
    /// Water density (kg/m³).
    pub fn water_density_kg_m3(&self) -> f64 {
        self.water_density_kg_m3
    }

    /// Distance along the propagation direction, x_β = x cos β + y sin β (m).
    #[inline]
    pub fn along(&self, x: f64, y: f64) -> f64 {
        x * self.direction.0 + y * self.direction.1
    }

    /// Complex phasor aₙ e^{iθₙ} of component `c` at x_β, t.
    #[inline]
    fn phasor(c: &WaveComponent, x_beta: f64, t: f64) -> Complex<f64> {
        let (s, co) = (c.omega_rad_s * t - c.wavenumber_rad_m * x_beta).sin_cos();
        c.amplitude_m * Complex::new(co, s)
    }

    /// Surface elevation η (m) at (x, y), time t, by direct summation.
    pub fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        let xb = self.along(x, y);
        self.components
            .iter()
            .map(|c| Self::phasor(c, xb, t).re)
            .sum()
    }

    /// Kinematics at point `p` and time `t` by direct summation, with Wheeler stretching.
    pub fn kinematics(&self, p: &Vector3<f64>, t: f64) -> FluidKinematics {
        PHASORS.with(|buffer| {
            let mut phasors = buffer.borrow_mut();
            self.kinematics_with(p, t, &mut phasors)
        })
    }

    /// [`AiryField::kinematics`] with a scratch buffer for the phasors. Each component costs
    /// one `sin_cos` (its phasor, shared by η and the kinematics) and one `exp` (the depth
    /// profiles, with e^{−k(s+d)} = e^{−2kd} / e^{k(s−d)} and 1/(1 − e^{−2kd}) precomputed).
    fn kinematics_with(
        &self,
        p: &Vector3<f64>,
        t: f64,
        phasors: &mut Vec<Complex<f64>>,
    ) -> FluidKinematics {
        let xb = self.along(p.x, p.y);
        phasors.clear();
        let mut eta = 0.0;
        for c in &self.components {
            let e = Self::phasor(c, xb, t);
            eta += e.re;
            phasors.push(e);
        }
        let Some(s) = stretched_height(p.z, eta, self.depth_m) else {
            return FluidKinematics::default();
        };
        let (mut uh, mut w, mut ah, mut az, mut pd) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let lift = s - self.depth_m;
        for (term, e) in self.terms.iter().zip(phasors.iter()) {
            let up = (term.k * lift).exp();
            // e^{−2kd} / e^{k(s−d)} unless that quotient could lose range (very short waves).
            let down = if up > 1e-100 {
                term.exp_m2kd / up
            } else {
                (-term.k * (s + self.depth_m)).exp()
            };
            let cp = (up + down) * term.inv_denom;
            let sp = (up - down) * term.inv_denom;
            uh += term.omega * cp * e.re;
            w += term.omega * sp * e.im;
            ah -= term.omega2 * cp * e.im;
            az += term.omega2 * sp * e.re;
            pd += term.omega2_over_k * cp * e.re;
        }
        let (cx, cy) = self.direction;
        FluidKinematics {
            velocity: Vector3::new(uh * cx, uh * cy, w),
            acceleration: Vector3::new(ah * cx, ah * cy, az),
            dynamic_pressure_pa: self.water_density_kg_m3 * pd,
        }
    }
}

/// Constants of one component in the direct summation of [`AiryField::kinematics`].
#[derive(Debug, Clone, Copy, PartialEq)]
struct SummationTerm {
    k: f64,
    omega: f64,
    omega2: f64,
    omega2_over_k: f64,
    /// e^{−2kd}.
    exp_m2kd: f64,
    /// 1 / (1 − e^{−2kd}).
    inv_denom: f64,
}

impl SummationTerm {
    fn new(c: &WaveComponent, depth_m: f64) -> Self {
        let k = c.wavenumber_rad_m;
        let om = c.omega_rad_s;
        SummationTerm {
            k,
            omega: om,
            omega2: om * om,
            omega2_over_k: om * om / k,
            exp_m2kd: (-2.0 * k * depth_m).exp(),
            inv_denom: 1.0 / -(-2.0 * k * depth_m).exp_m1(),
        }
    }
}

thread_local! {
    /// Scratch phasors of [`AiryField::kinematics`] (grows to the component count once).
    static PHASORS: std::cell::RefCell<Vec<Complex<f64>>> = const { std::cell::RefCell::new(Vec::new()) };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::dispersion::{wavenumber, GRAVITY};

    fn single(a: f64, period: f64, depth: f64) -> AiryField {
        let omega = 2.0 * std::f64::consts::PI / period;
        let k = wavenumber(omega, depth).unwrap();
        AiryField::new(
            vec![WaveComponent {
                omega_rad_s: omega,
                wavenumber_rad_m: k,
                amplitude_m: Complex::new(a, 0.0),
            }],
            depth,
            0.0,
            1025.0,
        )
    }

    #[test]
    fn profiles_match_hyperbolic_functions() {
        let (k, d) = (0.05, 80.0);
        for &s in &[0.0, 10.0, 40.0, 80.0, 85.0] {
            let (c, sp) = depth_profiles(k, s, d);
            assert!((c - (k * s).cosh() / (k * d).sinh()).abs() < 1e-13 * c);
            if s > 0.0 {
                assert!((sp - (k * s).sinh() / (k * d).sinh()).abs() < 1e-13 * sp);
            }
        }
    }

    #[test]
    fn crest_kinematics_match_airy_closed_form() {
        // Under a crest at x = 0, t = 0 (θ = 0): u = ω a cosh(k s)/sinh(k d), w = 0,
        // a_x = 0, a_z = ω² a sinh(ks)/sinh(kd), p = ρ g a cosh(ks)/cosh(kd) (s from Wheeler).
        let (a, period, depth) = (1.5, 9.0, 50.0);
        let f = single(a, period, depth);
        let c = f.components()[0];
        let (om, k) = (c.omega_rad_s, c.wavenumber_rad_m);
        let z = -12.0;
        let kin = f.kinematics(&Vector3::new(0.0, 0.0, z), 0.0);
        let s = (z + depth) * depth / (depth + a);
        let u = om * a * (k * s).cosh() / (k * depth).sinh();
        let az = om * om * a * (k * s).sinh() / (k * depth).sinh();
        let p = 1025.0 * GRAVITY * a * (k * s).cosh() / (k * depth).cosh();
        assert!((kin.velocity.x - u).abs() < 1e-12 * u);
        assert!(kin.velocity.z.abs() < 1e-12 * u);
        assert!(kin.acceleration.x.abs() < 1e-12 * az);
        assert!((kin.acceleration.z - az).abs() < 1e-12 * az);
        assert!((kin.dynamic_pressure_pa - p).abs() < 1e-10 * p);
    }

    #[test]
    fn acceleration_is_time_derivative_of_velocity_at_fixed_stretched_depth() {
        // Below the trough and with zero amplitude change in s, check ∂u/∂t by central
        // differences on a field evaluated at the same stretched height (small amplitude).
        let f = single(1e-8, 7.0, 30.0);
        let p = Vector3::new(3.0, 0.0, -10.0);
        let (t, h) = (1.3, 1e-4);
        let du = (f.kinematics(&p, t + h).velocity - f.kinematics(&p, t - h).velocity) / (2.0 * h);
        let a = f.kinematics(&p, t).acceleration;
        assert!((du - a).norm() < 1e-7 * a.norm());
    }

    #[test]
    fn points_above_the_surface_are_dry() {
        let f = single(1.0, 8.0, 40.0);
        let kin = f.kinematics(&Vector3::new(0.0, 0.0, 1.01), 0.0);
        assert_eq!(kin, FluidKinematics::default());
        let wet = f.kinematics(&Vector3::new(0.0, 0.0, 0.99), 0.0);
        assert!(wet.velocity.x > 0.0);
    }

    #[test]
    fn wheeler_stretching_puts_surface_values_at_the_crest() {
        // At z = η the stretched height is d, where the profile C equals coth(kd).
        let f = single(2.0, 10.0, 60.0);
        let c = f.components()[0];
        let kin = f.kinematics(&Vector3::new(0.0, 0.0, 2.0), 0.0);
        let u_surface = c.omega_rad_s * 2.0 / (c.wavenumber_rad_m * 60.0).tanh();
        assert!((kin.velocity.x - u_surface).abs() < 1e-12 * u_surface);
    }
}
