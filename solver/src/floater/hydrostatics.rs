//! Hydrostatics from the member geometry: submerged volume and centre of buoyancy in any pose,
//! waterplane properties and the linear restoring matrix of the undisplaced body.
//!
//! Buoyancy is taken on the still water level z = 0 (the wave dynamic pressure enters through the
//! Froude–Krylov terms of the strip theory). For a cylinder of radius R whose axis (unit e, e_z ≥ 0)
//! meets z = 0 at axial distance L from its lower end, with the cut crossing only the side wall,
//! the submerged part is exact in closed form: with g = ẑ − e_z e (|g| = sin of the tilt),
//!
//! ```text
//! V = πR² L,   s_B = L/2 + R²|g|²/(8 e_z² L) along the axis,   ρ_B = −R² g /(4 e_z L) across it,
//! ```
//!
//! which carries the waterplane second moment πR⁴/4 and hence the metacentric restoring. Other
//! partial cases (the surface cutting an end face, near-horizontal members at the surface) are
//! integrated numerically over the cross-section (Gauss–Legendre in radius and angle).
//!
//! Linear restoring (about the reference point, F = −C ξ with ξ = (translation, small spatial
//! rotation)): C33 = ρgA_wp, C34 = ρgA_wp y_f, C35 = −ρgA_wp x_f, C44 = ρg(∫y² dA + V z_B) − m g z_G,
//! C55 = ρg(∫x² dA + V z_B) − m g z_G, C45 = −ρg∫xy dA, C46 = −ρgV x_B + m g x_G,
//! C56 = −ρgV y_B + m g y_G (e.g. WAMIT User Manual, §3.1 hydrostatic coefficients).

use nalgebra::{Matrix6, Vector3};

/// Below this vertical axis component a member is treated as horizontal.
const HORIZONTAL_EZ: f64 = 1e-9;
/// Gauss–Legendre points for the numerical cross-section integration (radius, angle).
const RADIAL_POINTS: usize = 12;
const ANGULAR_POINTS: usize = 48;

/// Submerged volume and its centroid.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Buoyancy {
    /// Submerged volume (m³).
    pub volume_m3: f64,
    /// Centre of buoyancy, global axes (m); meaningless when the volume is zero.
    pub centre_m: Vector3<f64>,
}

impl Buoyancy {
    /// Adds another submerged part.
    pub fn add(&mut self, other: &Buoyancy) {
        let v = self.volume_m3 + other.volume_m3;
        if v > 0.0 {
            self.centre_m = (self.centre_m * self.volume_m3 + other.centre_m * other.volume_m3) / v;
        }
        self.volume_m3 = v;
    }
}

/// Submerged part (below z = 0) of the solid circular cylinder with axis end points `a`, `b`
/// (global, m) and radius `radius_m`.
pub(crate) fn submerged_cylinder(a: &Vector3<f64>, b: &Vector3<f64>, radius_m: f64) -> Buoyancy {
    let (a, b) = if b.z >= a.z { (*a, *b) } else { (*b, *a) };
    let len = (b - a).norm();
    let e = (b - a) / len;
    let g = Vector3::z() - e * e.z;
    let gn = g.norm();
    let area = std::f64::consts::PI * radius_m * radius_m;
    let zmin = a.z - radius_m * gn;
    let zmax = b.z + radius_m * gn;
    if zmax <= 0.0 {
        return Buoyancy {
            volume_m3: area * len,
            centre_m: 0.5 * (a + b),
        };
    }
    if zmin >= 0.0 {
        return Buoyancy::default();
    }
    if e.z > HORIZONTAL_EZ {
        let l = -a.z / e.z;
        let spread = radius_m * gn / e.z;
        if l - spread >= 0.0 && l + spread <= len {
            let r2 = radius_m * radius_m;
            let s_b = 0.5 * l + r2 * gn * gn / (8.0 * e.z * e.z * l);
            let rho_b = -g * (r2 / (4.0 * e.z * l));
            return Buoyancy {
                volume_m3: area * l,
                centre_m: a + e * s_b + rho_b,
            };
        }
    }
    integrate_cross_section(&a, &e, &g, len, radius_m)
}

/// Numerical integration of the submerged axial length over the cross-section.
fn integrate_cross_section(
    a: &Vector3<f64>,
    e: &Vector3<f64>,
    g: &Vector3<f64>,
    len: f64,
    radius: f64,
) -> Buoyancy {
    // Orthonormal cross-section basis (p, q) ⟂ e.
    let seed = if e.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let p = (seed - e * e.dot(&seed)).normalize();
    let q = e.cross(&p);
    let (xr, wr) = gauss_legendre_unit(RADIAL_POINTS);
    let mut vol = 0.0;
    let mut first = Vector3::zeros();
    let dphi = 2.0 * std::f64::consts::PI / ANGULAR_POINTS as f64;
    for (xi, wi) in xr.iter().zip(wr.iter()) {
        let r = 0.5 * radius * (1.0 + xi);
        let wr_area = 0.5 * radius * wi * r * dphi;
        for k in 0..ANGULAR_POINTS {
            let phi = (k as f64 + 0.5) * dphi;
            let rho = p * (r * phi.cos()) + q * (r * phi.sin());
            let z0 = a.z + g.dot(&rho);
            // Submerged axial interval [s0, s1] ⊂ [0, len] where z0 + s e_z ≤ 0.
            let (s0, s1) = if e.z > HORIZONTAL_EZ {
                (0.0, (-z0 / e.z).clamp(0.0, len))
            } else if z0 <= 0.0 {
                (0.0, len)
            } else {
                (0.0, 0.0)
            };
            let l = s1 - s0;
            if l > 0.0 {
                vol += wr_area * l;
                first += (rho * l + e * (0.5 * (s1 * s1 - s0 * s0))) * wr_area;
            }
        }
    }
    if vol <= 0.0 {
        return Buoyancy::default();
    }
    Buoyancy {
        volume_m3: vol,
        centre_m: a + first / vol,
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on the Legendre recurrence).
fn gauss_legendre_unit(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-15 {
                break;
            }
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

/// Waterplane and displacement of the undisplaced body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HydrostaticProperties {
    /// Displaced volume (m³).
    pub volume_m3: f64,
    /// Centre of buoyancy relative to the reference point (m).
    pub centre_of_buoyancy_m: Vector3<f64>,
    /// Waterplane area (m²).
    pub waterplane_area_m2: f64,
    /// Waterplane centroid (x_f, y_f) (m).
    pub waterplane_centroid_m: [f64; 2],
    /// ∫x² dA, ∫y² dA, ∫xy dA over the waterplane about the reference point (m⁴).
    pub waterplane_moments_m4: [f64; 3],
}

/// One member's section by the plane z = 0: an ellipse of area πR²/e_z centred where the axis
/// crosses; returns (area, centroid x, y, ∫x², ∫y², ∫xy) in the undisplaced pose.
pub(crate) fn waterplane_section(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    radius: f64,
) -> Option<[f64; 6]> {
    let (a, b) = if b.z >= a.z { (*a, *b) } else { (*b, *a) };
    if !(a.z < 0.0 && b.z > 0.0) {
        return None;
    }
    let e = (b - a).normalize();
    let c = a + e * (-a.z / e.z);
    let area = std::f64::consts::PI * radius * radius / e.z;
    // Ellipse: semi-axis R across the horizontal projection of e, R/e_z along it.
    let h = Vector3::new(e.x, e.y, 0.0);
    let (u, long) = if h.norm() > 1e-12 {
        (h.normalize(), radius / e.z)
    } else {
        (Vector3::x(), radius)
    };
    let v = Vector3::new(-u.y, u.x, 0.0);
    let (iu, iv) = (area * long * long / 4.0, area * radius * radius / 4.0);
    // Central second moments in (x, y) from those along u (long axis) and v.
    let ixx = iu * u.x * u.x + iv * v.x * v.x;
    let iyy = iu * u.y * u.y + iv * v.y * v.y;
    let ixy = iu * u.x * u.y + iv * v.x * v.y;
    Some([
        area,
        c.x,
        c.y,
        ixx + area * c.x * c.x,
        iyy + area * c.y * c.y,
        ixy + area * c.x * c.y,
    ])
}

impl HydrostaticProperties {
    /// Linear restoring matrix about the reference point for a body of mass `mass_kg` with centre
    /// of mass `com_m`, including the gravity terms (see the module equations).
    pub fn restoring_matrix(
        &self,
        rho: f64,
        g: f64,
        mass_kg: f64,
        com_m: &Vector3<f64>,
    ) -> Matrix6<f64> {
        let rg = rho * g;
        let a = self.waterplane_area_m2;
        let [xf, yf] = self.waterplane_centroid_m;
        let [ixx, iyy, ixy] = self.waterplane_moments_m4;
        let v = self.volume_m3;
        let cb = self.centre_of_buoyancy_m;
        let mg = mass_kg * g;
        let mut c = Matrix6::zeros();
        c[(2, 2)] = rg * a;
        c[(2, 3)] = rg * a * yf;
        c[(3, 2)] = c[(2, 3)];
        c[(2, 4)] = -rg * a * xf;
        c[(4, 2)] = c[(2, 4)];
        c[(3, 3)] = rg * (iyy + v * cb.z) - mg * com_m.z;
        c[(4, 4)] = rg * (ixx + v * cb.z) - mg * com_m.z;
        c[(3, 4)] = -rg * ixy;
        c[(4, 3)] = c[(3, 4)];
        c[(3, 5)] = -rg * v * cb.x + mg * com_m.x;
        c[(4, 5)] = -rg * v * cb.y + mg * com_m.y;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::rotation::exp_so3;

    #[test]
    fn tilted_cylinder_closed_form_matches_numerical_integration() {
        let r = 6.0;
        let rot = exp_so3(&Vector3::new(0.12, -0.07, 0.0));
        let a = rot * Vector3::new(28.0, 3.0, -14.0);
        let b = rot * Vector3::new(28.0, 3.0, 12.0);
        let closed = submerged_cylinder(&a, &b, r);
        let e = (b - a).normalize();
        let g = Vector3::z() - e * e.z;
        let num = integrate_cross_section(&a, &e, &g, (b - a).norm(), r);
        assert!(
            (closed.volume_m3 - num.volume_m3).abs() < 1e-3 * closed.volume_m3,
            "{} {}",
            closed.volume_m3,
            num.volume_m3
        );
        assert!(
            (closed.centre_m - num.centre_m).norm() < 5e-3,
            "{} {}",
            closed.centre_m,
            num.centre_m
        );
    }

    #[test]
    fn fully_submerged_and_dry_cylinders_are_exact() {
        let full = submerged_cylinder(
            &Vector3::new(0.0, 0.0, -17.0),
            &Vector3::new(10.0, 0.0, -17.0),
            0.8,
        );
        assert!((full.volume_m3 - std::f64::consts::PI * 0.64 * 10.0).abs() < 1e-12);
        assert!((full.centre_m - Vector3::new(5.0, 0.0, -17.0)).norm() < 1e-12);
        let dry = submerged_cylinder(
            &Vector3::new(0.0, 0.0, 10.0),
            &Vector3::new(10.0, 0.0, 10.0),
            0.8,
        );
        assert_eq!(dry.volume_m3, 0.0);
    }

    #[test]
    fn half_submerged_horizontal_cylinder_has_the_semicircle_centroid() {
        let r = 1.0;
        let half = submerged_cylinder(
            &Vector3::new(0.0, 0.0, 0.0),
            &Vector3::new(0.0, 5.0, 0.0),
            r,
        );
        let exact_v = 0.5 * std::f64::consts::PI * r * r * 5.0;
        assert!(
            (half.volume_m3 - exact_v).abs() < 2e-3 * exact_v,
            "{}",
            half.volume_m3
        );
        let exact_z = -4.0 * r / (3.0 * std::f64::consts::PI);
        assert!(
            (half.centre_m.z - exact_z).abs() < 5e-3,
            "{}",
            half.centre_m.z
        );
    }
}
