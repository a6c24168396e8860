//! Cylindrical members and their strip-theory (Morison) loads.
//!
//! Each member is cut into strips of about the spec's strip length. On the wetted part of a
//! strip (below the free-surface elevation η(x, y, t), sampled once per member where its axis
//! crosses the still water level), of volume V = πD²/4 · ℓ_wet, with
//! unit axis e, normal projector P = I − e eᵀ, fluid velocity u and acceleration u̇ from
//! [`SeaKinematics`] at the wetted centre and body velocity v_p there:
//!
//! ```text
//! f = ρ V (1 + C_a) P u̇  +  ½ ρ C_d D ℓ_wet |P u_r| P u_r,      u_r = u − v_p
//!                        −  C_a ρ V P a_p                     (added mass, in the mass matrix)
//! ```
//!
//! i.e. Froude–Krylov plus diffraction through (1 + C_a) (long-wave limit of the MacCamy–Fuchs
//! solution; the correction for D/λ is not applied), added mass on the normal relative
//! acceleration and quadratic drag on the normal relative velocity (e.g. DNV-RP-C205 §6.2).
//! Members with axial coefficients (heave plates) also get, at their mid-point,
//! f_ax = e [A_ax (e·u̇) + ½ ρ C_d,ax (πD²/4) |e·u_r| (e·u_r)] − A_ax e eᵀ a_p with the circular-disc
//! added mass A_ax = C_a,ax ρ D³/3 (DNV-RP-H103 Table A-2), and the wave dynamic pressure acts on
//! the exposed end faces (force p·A_end along +e on the `from` face, −e on the `to` face).
//!
//! The added mass is constant in body axes: it is evaluated once, for the undisplaced body in
//! still water, and rotated with the body; its centripetal terms are neglected.

use nalgebra::{Matrix3, Matrix6, Vector3};

use super::body::{add_point_block, BodyState, Wrench};
use super::spec::ResolvedMember;
use crate::waves::SeaKinematics;

/// Index of a member in its floater.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MemberId(pub usize);

/// A cylindrical member in body axes with its strip discretisation.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// Name.
    pub name: String,
    /// Diameter (m).
    pub diameter_m: f64,
    /// First end, body axes (m).
    pub from_m: Vector3<f64>,
    /// Second end, body axes (m).
    pub to_m: Vector3<f64>,
    /// Transverse drag coefficient.
    pub drag_coefficient: f64,
    /// Transverse added-mass coefficient.
    pub added_mass_coefficient: f64,
    /// Axial drag coefficient (on πD²/4).
    pub axial_drag_coefficient: f64,
    /// Axial added-mass coefficient (on ρD³/3).
    pub axial_added_mass_coefficient: f64,
    /// Exposed end areas (m²), `from` then `to`.
    pub end_pressure_areas_m2: [f64; 2],
    /// Number of strips.
    pub strips: usize,
    /// Factor on the transverse Froude–Krylov + diffraction term (1, or the MacCamy–Fuchs
    /// ratio C_M(ka)/2 of [`super::diffraction`]).
    pub inertia_factor: f64,
}

/// Wetted part of one strip in the current pose.
struct WetStrip {
    centre: Vector3<f64>,
    length_m: f64,
}

impl Member {
    /// Builds the member from validated input, with strips no longer than `strip_length_m`.
    pub fn new(r: &ResolvedMember, strip_length_m: f64) -> Self {
        let len = (r.to_m - r.from_m).norm();
        Self {
            name: r.name.clone(),
            diameter_m: r.diameter_m,
            from_m: r.from_m,
            to_m: r.to_m,
            drag_coefficient: r.drag_coefficient,
            added_mass_coefficient: r.added_mass_coefficient,
            axial_drag_coefficient: r.axial_drag_coefficient,
            axial_added_mass_coefficient: r.axial_added_mass_coefficient,
            end_pressure_areas_m2: r.end_pressure_areas_m2,
            strips: ((len / strip_length_m).ceil() as usize).max(1),
            inertia_factor: 1.0,
        }
    }

    /// Length (m).
    pub fn length_m(&self) -> f64 {
        (self.to_m - self.from_m).norm()
    }

    /// Cross-section area πD²/4 (m²).
    pub(crate) fn section_area_m2(&self) -> f64 {
        0.25 * std::f64::consts::PI * self.diameter_m * self.diameter_m
    }

    /// Axial (heave-plate) added mass C_a,ax ρ D³/3 (kg).
    pub(crate) fn axial_added_mass_kg(&self, rho: f64) -> f64 {
        self.axial_added_mass_coefficient * rho * self.diameter_m.powi(3) / 3.0
    }

    /// End points in global axes for the pose.
    pub(crate) fn global_ends(&self, state: &BodyState) -> (Vector3<f64>, Vector3<f64>) {
        (
            state.point_position(&self.from_m),
            state.point_position(&self.to_m),
        )
    }

    /// Free-surface elevation seen by the member: sampled once, where its axis crosses the still
    /// water level (or at its end nearest to it), which is exact for vertical members and saves
    /// one sea evaluation per strip.
    fn member_elevation<S: SeaKinematics + ?Sized>(
        a: &Vector3<f64>,
        b: &Vector3<f64>,
        sea: &S,
        t: f64,
    ) -> f64 {
        let p = if (a.z <= 0.0) != (b.z <= 0.0) {
            a + (b - a) * (a.z / (a.z - b.z))
        } else if a.z.abs() < b.z.abs() {
            *a
        } else {
            *b
        };
        sea.elevation(p.x, p.y, t)
    }

    /// Wetted part of strip `k` between global end points `a`, `b` below the elevation `eta`.
    fn wet_strip(
        &self,
        k: usize,
        a: &Vector3<f64>,
        b: &Vector3<f64>,
        eta: f64,
    ) -> Option<WetStrip> {
        let n = self.strips as f64;
        let p0 = a + (b - a) * (k as f64 / n);
        let p1 = a + (b - a) * ((k + 1) as f64 / n);
        let (z0, z1) = (p0.z - eta, p1.z - eta);
        let (t0, t1) = if z0 <= 0.0 && z1 <= 0.0 {
            (0.0, 1.0)
        } else if z0 > 0.0 && z1 > 0.0 {
            return None;
        } else {
            let tc = z0 / (z0 - z1);
            if z0 <= 0.0 {
                (0.0, tc)
            } else {
                (tc, 1.0)
            }
        };
        let length_m = (t1 - t0) * (p1 - p0).norm();
        if length_m <= 0.0 {
            return None;
        }
        Some(WetStrip {
            centre: p0 + (p1 - p0) * (0.5 * (t0 + t1)),
            length_m,
        })
    }

    /// Adds the member's hydrodynamic loads about the reference point: Froude–Krylov,
    /// diffraction, axial inertia and end pressures to `inertia`, quadratic drag to `drag` (the
    /// added-mass reaction is in the mass matrix), and, when given, the derivative of the drag
    /// with respect to the generalised velocity ν to `velocity_jacobian`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add_hydrodynamic_loads<S: SeaKinematics + ?Sized>(
        &self,
        state: &BodyState,
        sea: &S,
        t: f64,
        rho: f64,
        inertia: &mut Wrench,
        drag: &mut Wrench,
        mut velocity_jacobian: Option<&mut Matrix6<f64>>,
    ) {
        let (a, b) = self.global_ends(state);
        let e = (b - a) / (b - a).norm();
        let proj = Matrix3::identity() - e * e.transpose();
        let area = self.section_area_m2();
        let eta = Self::member_elevation(&a, &b, sea, t);
        for k in 0..self.strips {
            let Some(strip) = self.wet_strip(k, &a, &b, eta) else {
                continue;
            };
            let r = strip.centre - state.position_m;
            let fluid = sea.kinematics(&strip.centre, t);
            let u_rel = fluid.velocity - state.velocity_at(&strip.centre);
            let un = proj * u_rel;
            let volume = area * strip.length_m;
            let f_inertia = (proj * fluid.acceleration)
                * (rho * volume * (1.0 + self.added_mass_coefficient) * self.inertia_factor);
            let cd = 0.5 * rho * self.drag_coefficient * self.diameter_m * strip.length_m;
            let speed = un.norm();
            inertia.add_at(&f_inertia, &r);
            drag.add_at(&(un * (cd * speed)), &r);
            if let Some(jac) = velocity_jacobian.as_deref_mut() {
                if speed > 0.0 {
                    // d(|Pu| Pu)/du = |Pu| P + Pu (Pu)ᵀ/|Pu| ; du/dν = −[I, −r̂]
                    let d = (proj * speed + un * un.transpose() / speed) * cd;
                    add_point_block(jac, &d, &r, -1.0);
                }
            }
        }
        self.add_axial_loads(
            state,
            sea,
            t,
            rho,
            (&a, &b, &e),
            (inertia, drag),
            velocity_jacobian,
        );
    }

    #[allow(clippy::too_many_arguments)]
    fn add_axial_loads<S: SeaKinematics + ?Sized>(
        &self,
        state: &BodyState,
        sea: &S,
        t: f64,
        rho: f64,
        (a, b, e): (&Vector3<f64>, &Vector3<f64>, &Vector3<f64>),
        (inertia, drag): (&mut Wrench, &mut Wrench),
        velocity_jacobian: Option<&mut Matrix6<f64>>,
    ) {
        for (point, area, sign) in [
            (a, self.end_pressure_areas_m2[0], 1.0),
            (b, self.end_pressure_areas_m2[1], -1.0),
        ] {
            if area > 0.0 && point.z <= sea.elevation(point.x, point.y, t) {
                let p = sea.kinematics(point, t).dynamic_pressure_pa;
                inertia.add_at(&(e * (sign * p * area)), &(point - state.position_m));
            }
        }
        if self.axial_drag_coefficient == 0.0 && self.axial_added_mass_coefficient == 0.0 {
            return;
        }
        let mid = 0.5 * (a + b);
        if mid.z > sea.elevation(mid.x, mid.y, t) {
            return;
        }
        let r = mid - state.position_m;
        let fluid = sea.kinematics(&mid, t);
        let u_ax = e.dot(&(fluid.velocity - state.velocity_at(&mid)));
        let cd = 0.5 * rho * self.axial_drag_coefficient * self.section_area_m2();
        inertia.add_at(
            &(e * (self.axial_added_mass_kg(rho) * e.dot(&fluid.acceleration))),
            &r,
        );
        drag.add_at(&(e * (cd * u_ax.abs() * u_ax)), &r);
        if let Some(jac) = velocity_jacobian {
            let d = e * e.transpose() * (2.0 * cd * u_ax.abs());
            add_point_block(jac, &d, &r, -1.0);
        }
    }

    /// Adds the member's added-mass matrix (about the reference point, body axes, undisplaced
    /// body in still water) to `m`.
    pub(crate) fn add_added_mass(&self, rho: f64, m: &mut Matrix6<f64>) {
        let rest = BodyState::at_rest();
        let (a, b) = (self.from_m, self.to_m);
        let e = (b - a) / (b - a).norm();
        let proj = Matrix3::identity() - e * e.transpose();
        for k in 0..self.strips {
            let Some(strip) = self.wet_strip(k, &a, &b, 0.0) else {
                continue;
            };
            let mass = self.added_mass_coefficient * rho * self.section_area_m2() * strip.length_m;
            add_point_block(m, &(proj * mass), &(strip.centre - rest.position_m), 1.0);
        }
        let mid = 0.5 * (a + b);
        if self.axial_added_mass_coefficient > 0.0 && mid.z <= 0.0 {
            add_point_block(
                m,
                &(e * e.transpose() * self.axial_added_mass_kg(rho)),
                &mid,
                1.0,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pile(from_z: f64, to_z: f64, ca_axial: f64) -> Member {
        let r = ResolvedMember {
            name: "pile".into(),
            diameter_m: 2.0,
            from_m: Vector3::new(3.0, 0.0, from_z),
            to_m: Vector3::new(3.0, 0.0, to_z),
            drag_coefficient: 1.0,
            added_mass_coefficient: 1.0,
            axial_drag_coefficient: 0.0,
            axial_added_mass_coefficient: ca_axial,
            end_pressure_areas_m2: [0.0, 0.0],
        };
        Member::new(&r, 1.0)
    }

    #[test]
    fn added_mass_counts_only_the_wetted_length_of_a_surface_piercing_member() {
        // 15 m long, the still water level in the middle of a strip: 10.5 m wetted.
        let rho = 1025.0;
        let m = pile(-10.5, 4.5, 0.0);
        let mut a = Matrix6::zeros();
        m.add_added_mass(rho, &mut a);
        let expected = rho * std::f64::consts::PI * 10.5;
        assert!((a[(0, 0)] - expected).abs() < 1e-9 * expected);
        assert!((a[(1, 1)] - expected).abs() < 1e-9 * expected);
        assert_eq!(a[(2, 2)], 0.0);
        // Yaw: the lever of 3 m to the body axis.
        assert!((a[(5, 5)] - 9.0 * expected).abs() < 1e-9 * expected);
    }

    #[test]
    fn heave_plate_added_mass_is_the_circular_disc_value() {
        let rho = 1025.0;
        let m = pile(-20.0, -14.0, 1.0);
        let mut a = Matrix6::zeros();
        m.add_added_mass(rho, &mut a);
        let disc = rho * 8.0 / 3.0;
        assert!((a[(2, 2)] - disc).abs() < 1e-12 * disc);
        // Pitch: the disc at 3 m from the axis, plus the six 1 m strips at z = −19.5 … −14.5
        // (Σ z² = 6·17² + 17.5).
        let strips = a[(0, 0)] / 6.0 * (6.0 * 17.0 * 17.0 + 17.5);
        assert!((a[(4, 4)] - (9.0 * disc + strips)).abs() < 1e-9 * a[(4, 4)]);
    }
}
