//! Stress field under a circular Hertz contact carrying a tangential traction.
//!
//! Frame: the contact is centred at the origin of the surface z = 0 of an elastic half-space,
//! z points into the body, the tangential traction acts in +x; stresses are tension-positive.
//! A Hertz pressure p = p₀ √(1 − r²/a²) pushes on the body; the tangential traction is
//!
//! - gross slip (sliding): q = μ p over the whole circle;
//! - partial slip (Cattaneo 1938, Mindlin 1949; Johnson 1985 §7.2): the same, less the stick-zone
//!   correction μ p₀ (c/a) √(1 − r²/c²) over the stick circle of radius c, with
//!   c/a = (1 − Q/μP)^{1/3}.
//!
//! Under cyclic tangential load ±Q* at constant P the traction at each extreme of the cycle is
//! the monotonic one, mirrored (Mindlin & Deresiewicz 1953; Johnson §7.3), so the two extreme
//! states of a cycle are σ_N ± σ_T(c).
//!
//! Both parts in closed form (Hamilton 1983, Proc. IMechE 197C: the normal part,
//! [`hertz_normal_stress`], and the tangential part, [`hamilton_tangential_stress`]; Johnson eqs.
//! 3.41-3.46 on the surface and the axis). The Boussinesq and Cerruti point-force solutions
//! (Johnson 1985 §3.3), integrated over the tractions by nested double-exponential quadrature
//! in polar coordinates centred under the field point ([`traction_stress`]), check them in the
//! tests and give the stresses of the elliptical patch, against which the equivalent circle's
//! error is measured.
//!
//! Units: any consistent set (the module works in p₀ and a units); stresses as [`Stress`].

use std::f64::consts::PI;
use std::sync::OnceLock;

/// Symmetric stress tensor (Pa, or per unit pressure in the nondimensional routines).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Stress {
    /// σ_xx.
    pub xx: f64,
    /// σ_yy.
    pub yy: f64,
    /// σ_zz.
    pub zz: f64,
    /// τ_xy.
    pub xy: f64,
    /// τ_xz.
    pub xz: f64,
    /// τ_yz.
    pub yz: f64,
}

impl Stress {
    /// Componentwise a·self + b·other.
    pub fn combine(self, a: f64, other: Stress, b: f64) -> Stress {
        Stress {
            xx: a * self.xx + b * other.xx,
            yy: a * self.yy + b * other.yy,
            zz: a * self.zz + b * other.zz,
            xy: a * self.xy + b * other.xy,
            xz: a * self.xz + b * other.xz,
            yz: a * self.yz + b * other.yz,
        }
    }

    /// Scaled copy.
    pub fn scaled(self, s: f64) -> Stress {
        self.combine(s, Stress::default(), 0.0)
    }

    /// Trace σ_xx + σ_yy + σ_zz.
    pub fn trace(&self) -> f64 {
        self.xx + self.yy + self.zz
    }

    /// Traction vector σ·n.
    pub fn traction_on(&self, n: [f64; 3]) -> [f64; 3] {
        [
            self.xx * n[0] + self.xy * n[1] + self.xz * n[2],
            self.xy * n[0] + self.yy * n[1] + self.yz * n[2],
            self.xz * n[0] + self.yz * n[1] + self.zz * n[2],
        ]
    }

    fn add_scaled(&mut self, w: f64, s: &Stress) {
        self.xx += w * s.xx;
        self.yy += w * s.yy;
        self.zz += w * s.zz;
        self.xy += w * s.xy;
        self.xz += w * s.xz;
        self.yz += w * s.yz;
    }
}

/// Stress of the Hertz pressure p₀ √(1 − r²/a²) on a circle of radius a at (x, y, z), z ≥ 0,
/// for Poisson's ratio `nu` (Hamilton 1983, normal-load part; the axis r = 0 by its limit,
/// Johnson eq. 3.46).
pub fn hertz_normal_stress(p0: f64, a: f64, nu: f64, x: f64, y: f64, z: f64) -> Stress {
    let k = p0 / a; // 3P/(2πa³)
    let r2 = x * x + y * y;
    let z = z.max(0.0);
    if r2 < 1e-20 * a * a {
        let z2 = z * z;
        let radial = (1.0 + nu) * (z * (a / z.max(1e-300 * a)).atan() - a)
            + a.powi(3) / (2.0 * (a * a + z2));
        return Stress {
            xx: k * radial,
            yy: k * radial,
            zz: -k * a.powi(3) / (a * a + z2),
            ..Default::default()
        };
    }
    let a2 = a * a;
    let big_a = r2 + z * z - a2;
    let s = (big_a * big_a + 4.0 * a2 * z * z).sqrt();
    let m = (0.5 * (s + big_a)).max(0.0).sqrt();
    let n = (0.5 * (s - big_a)).max(0.0).sqrt();
    let phi = if m > 0.0 { (a / m).atan() } else { 0.5 * PI };
    let g = m * m - n * n + z * m - a * n;
    let h = 2.0 * m * n + a * m + z * n;
    let (x2, y2) = (x * x, y * y);
    let common = (1.0 - nu) * n * z * z
        - (1.0 - 2.0 * nu) / 3.0 * (n * s + 2.0 * big_a * n + a2 * a)
        - nu * m * z * a;
    // a z M / S vanishes with z; S > 0 off the contact edge circle.
    let mzs = if s > 0.0 { m * z * a / s } else { 0.0 };
    let xx = k
        * ((1.0 + nu) * z * phi
            + ((y2 - x2) / r2 * common - n * (x2 + 2.0 * nu * y2) - mzs * x2) / r2);
    let yy = k
        * ((1.0 + nu) * z * phi
            + ((x2 - y2) / r2 * common - n * (y2 + 2.0 * nu * x2) - mzs * y2) / r2);
    let zz = k * (-n + mzs);
    let r4 = r2 * r2;
    let xy = k
        * (x * y * (1.0 - 2.0 * nu) / r4
            * (-n * r2 + 2.0 / 3.0 * n * (s + 2.0 * big_a) - z * (z * n + a * m)
                + 2.0 / 3.0 * a2 * a)
            + x * y * z / r4 * (-a * m * r2 / s.max(1e-300) - z * n + a * m));
    let gh = g * g + h * h;
    let shear = |c: f64| {
        if s > 0.0 && gh > 0.0 {
            -k * z * (c * n / s - c * z * h / gh)
        } else {
            0.0
        }
    };
    Stress {
        xx,
        yy,
        zz,
        xy,
        xz: shear(x),
        yz: shear(y),
    }
}

/// Stress at (x, y, z), z > 0, of a unit normal point force pressing on the surface at the
/// origin (Boussinesq; Johnson 1985 eq. 3.(20)), per newton.
pub fn boussinesq_kernel(nu: f64, x: f64, y: f64, z: f64) -> Stress {
    let r2 = x * x + y * y;
    let rho2 = r2 + z * z;
    let rho = rho2.sqrt();
    let rho3 = rho2 * rho;
    let rho5 = rho3 * rho2;
    let c = 1.0 / (2.0 * PI);
    let t = 1.0 - 2.0 * nu;
    // (1 − z/ρ)/r² = 1/(ρ(ρ + z)): no cancellation near the axis.
    let f = 1.0 / (rho * (rho + z));
    // Direction cosines squared in the surface plane; on the axis, their mean (axisymmetry).
    let (cx2, cy2, cxy) = if r2 > 0.0 {
        (x * x / r2, y * y / r2, x * y / r2)
    } else {
        (0.5, 0.5, 0.0)
    };
    Stress {
        xx: c * (t * (f * (cx2 - cy2) + z * cy2 / rho3) - 3.0 * z * x * x / rho5),
        yy: c * (t * (f * (cy2 - cx2) + z * cx2 / rho3) - 3.0 * z * y * y / rho5),
        zz: -3.0 * c * z.powi(3) / rho5,
        xy: c * (t * (2.0 * f * cxy - z * cxy / rho3) - 3.0 * x * y * z / rho5),
        xz: -3.0 * c * x * z * z / rho5,
        yz: -3.0 * c * y * z * z / rho5,
    }
}

/// Stress at (x, y, z), z > 0, of a unit tangential point force acting in +x on the surface at
/// the origin (Cerruti; Johnson 1985 eq. 3.(22)), per newton.
pub fn cerruti_kernel(nu: f64, x: f64, y: f64, z: f64) -> Stress {
    let rho2 = x * x + y * y + z * z;
    let rho = rho2.sqrt();
    let rho3 = rho2 * rho;
    let rho5 = rho3 * rho2;
    let rz = rho + z;
    let rz2 = rz * rz;
    let rz3 = rz2 * rz;
    let c = 1.0 / (2.0 * PI);
    let t = 1.0 - 2.0 * nu;
    let (x2, y2) = (x * x, y * y);
    Stress {
        xx: c
            * (-3.0 * x * x2 / rho5
                + t * (x / rho3 - 3.0 * x / (rho * rz2)
                    + x * x2 / (rho3 * rz2)
                    + 2.0 * x * x2 / (rho2 * rz3))),
        yy: c
            * (-3.0 * x * y2 / rho5
                + t * (x / rho3 - x / (rho * rz2)
                    + x * y2 / (rho3 * rz2)
                    + 2.0 * x * y2 / (rho2 * rz3))),
        zz: -3.0 * c * x * z * z / rho5,
        xy: c
            * (-3.0 * x2 * y / rho5
                + t * (-y / (rho * rz2) + x2 * y / (rho3 * rz2) + 2.0 * x2 * y / (rho2 * rz3))),
        xz: -3.0 * c * x2 * z / rho5,
        yz: -3.0 * c * x * y * z / rho5,
    }
}

/// Which point-force solution a traction integral uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// Normal pressure (Boussinesq).
    Normal,
    /// Tangential traction in +x (Cerruti).
    Tangential,
}

/// Double-exponential (tanh-sinh) nodes and weights on (−1, 1): (1 − x, 1 + x, w), with the
/// distances to the ends kept exact so that end singularities are resolved.
fn tanh_sinh(level: u32) -> &'static [(f64, f64, f64)] {
    static RULES: [OnceLock<Vec<(f64, f64, f64)>>; 4] = [
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
    ];
    let level = level.min(3) as usize;
    RULES[level].get_or_init(|| {
        let h = 1.0 / f64::from(1u32 << (level + 2));
        let t_max = 3.2;
        let n = (t_max / h).ceil() as i64;
        (-n..=n)
            .map(|k| {
                let t = k as f64 * h;
                let u = 0.5 * PI * t.sinh();
                let e = (-2.0 * u.abs()).exp();
                // 1 − tanh|u| = 2e/(1 + e)
                let small = 2.0 * e / (1.0 + e);
                let (one_minus, one_plus) = if u >= 0.0 {
                    (small, 2.0 - small)
                } else {
                    (2.0 - small, small)
                };
                let w = h * 0.5 * PI * t.cosh() / u.cosh().powi(2);
                (one_minus, one_plus, w)
            })
            .filter(|&(_, _, w)| w > 1e-300)
            .collect()
    })
}

/// Stress at (x₀, y₀, z₀), z₀ > 0, of a Hertz-shaped traction t₀ √(1 − (x/ra)² − (y/rb)²) on the
/// ellipse of semi-axes `ra` (along x) and `rb`, normal (`Kernel::Normal`, pressure t₀) or
/// tangential in +x (`Kernel::Tangential`), by nested tanh-sinh quadrature in polar coordinates
/// centred under the field point. `level` 0-3 halves the step each time (2 is ample: tests).
pub fn traction_stress(
    kernel: Kernel,
    nu: f64,
    t0: f64,
    ra: f64,
    rb: f64,
    point: [f64; 3],
    level: u32,
) -> Stress {
    let [x0, y0, z0] = point;
    let rule = tanh_sinh(level);
    let mut total = Stress::default();
    // Polar angle ranges: all of (−π, π]; rays that miss the ellipse contribute nothing. Split
    // at the tangent directions when the point lies outside (or on) the ellipse, so that each
    // sub-range's integrand is smooth inside and singular only at its ends.
    let inside = (x0 / ra).powi(2) + (y0 / rb).powi(2) < 1.0;
    let ranges: Vec<(f64, f64)> = if inside {
        vec![(-PI, PI)]
    } else {
        let base = y0.atan2(x0) + PI; // direction towards the centre
        let (lo, hi) = tangent_half_width(x0, y0, ra, rb);
        vec![(base - hi, base + lo)]
    };
    for (p_lo, p_hi) in ranges {
        let half = 0.5 * (p_hi - p_lo);
        for &(om, _, w) in rule {
            let phi = p_lo + half * om;
            let (s, c) = phi.sin_cos();
            let Some((r1, r2)) = ray_ellipse(x0, y0, c, s, ra, rb) else {
                continue;
            };
            let rhalf = 0.5 * (r2 - r1);
            if rhalf <= 0.0 {
                continue;
            }
            let mut ray = Stress::default();
            for &(rm, rp, wr) in rule {
                // ρ measured from both ends exactly
                let rho = if rm < rp {
                    r1 + rhalf * rm
                } else {
                    r2 - rhalf * rp
                };
                let (px, py) = (x0 + rho * c, y0 + rho * s);
                let f2 = 1.0 - (px / ra).powi(2) - (py / rb).powi(2);
                if f2 <= 0.0 {
                    continue;
                }
                let amp = t0 * f2.sqrt();
                let (dx, dy) = (x0 - px, y0 - py);
                let k = match kernel {
                    Kernel::Normal => boussinesq_kernel(nu, dx, dy, z0),
                    Kernel::Tangential => cerruti_kernel(nu, dx, dy, z0),
                };
                ray.add_scaled(wr * rhalf * rho * amp, &k);
            }
            total.add_scaled(w * half, &ray);
        }
    }
    total
}

/// Entry and exit distances along the ray (x₀, y₀) + ρ (c, s), ρ ≥ 0, through the ellipse.
fn ray_ellipse(x0: f64, y0: f64, c: f64, s: f64, ra: f64, rb: f64) -> Option<(f64, f64)> {
    let qa = (c / ra).powi(2) + (s / rb).powi(2);
    let qb = 2.0 * (x0 * c / (ra * ra) + y0 * s / (rb * rb));
    let qc = (x0 / ra).powi(2) + (y0 / rb).powi(2) - 1.0;
    let disc = qb * qb - 4.0 * qa * qc;
    if disc <= 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    // numerically stable roots
    let q = -0.5 * (qb + qb.signum() * sq);
    let (mut t1, mut t2) = if q != 0.0 {
        (q / qa, qc / q)
    } else {
        (0.0, 0.0)
    };
    if t1 > t2 {
        std::mem::swap(&mut t1, &mut t2);
    }
    if t2 <= 0.0 {
        return None;
    }
    Some((t1.max(0.0), t2))
}

/// Half-widths (towards +angle, towards −angle) of the cone of directions from an outside point
/// towards the ellipse, measured from the direction to the centre; found by bisection on the
/// ray-hit predicate (robust for a point on the boundary too).
fn tangent_half_width(x0: f64, y0: f64, ra: f64, rb: f64) -> (f64, f64) {
    let base = y0.atan2(x0) + PI;
    let hits = |d: f64| {
        let (s, c) = (base + d).sin_cos();
        ray_ellipse(x0, y0, c, s, ra, rb).is_some_and(|(a, b)| b - a > 0.0)
    };
    let edge = |sign: f64| {
        let (mut lo, mut hi) = (0.0, 0.5 * PI);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if hits(sign * mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    };
    (edge(1.0), edge(-1.0))
}

/// Stress per unit q₀ of the tangential traction q₀ √(1 − r²/a²) in +x on the circle of radius
/// a, at (x, y, z), z ≥ 0 (Hamilton 1983, tangential part, written in units of a).
///
/// The closed form has 1/r⁴ terms that lose precision within about 1e-4 a of the axis; there
/// the field is taken at r = 1e-3 a off the axis along x (its limit to 1e-6).
pub fn hamilton_tangential_stress(a: f64, nu: f64, x: f64, y: f64, z: f64) -> Stress {
    let (mut x, y, z) = (x / a, y / a, (z / a).max(0.0));
    let mut r2 = x * x + y * y;
    if r2 < 1e-6 {
        x = if x < 0.0 { -1e-3 } else { 1e-3 };
        r2 = x * x + y * y;
    }
    let r4 = r2 * r2;
    let big_a = r2 + z * z - 1.0;
    let s = (big_a * big_a + 4.0 * z * z).sqrt();
    let m = (0.5 * (s + big_a)).max(0.0).sqrt();
    let n = (0.5 * (s - big_a)).max(0.0).sqrt();
    let phi = if m > 0.0 { (1.0 / m).atan() } else { 0.5 * PI };
    let (x2, y2, z2) = (x * x, y * y, z * z);
    // Terms in 1/S multiply M or N, which vanish with S on the edge circle.
    let inv_s = if s > 0.0 { 1.0 / s } else { 0.0 };
    let t = 1.0 - 2.0 * nu;
    let fx = 1.5 - 2.0 * x2 / r2;
    let hx = 0.5 - 2.0 * x2 / r2;
    let hy = 0.5 - 2.0 * y2 / r2;
    let xx = -x * (nu / 4.0 + 1.0) * phi
        + x * m / r4
            * (fx * (nu * s - 2.0 * nu * big_a + z2) + x2 * z2 * inv_s + 7.0 * nu * r2 / 4.0
                - 2.0 * nu * x2
                + r2)
        + x * z * n / r4
            * (fx * (-s * t / 6.0 - big_a * t / 3.0 - (z2 + 3.0) / 2.0) + x2 * inv_s
                - nu * r2 / 4.0
                - 7.0 * r2 / 4.0)
        + 4.0 * x * z / (3.0 * r4) * fx * t;
    let yy = -3.0 * nu * x * phi / 4.0
        + x * m / r4
            * (hy * (nu * (s - 2.0 * big_a + r2) + z2) + y2 * z2 * inv_s + 3.0 * nu * r2 / 4.0)
        + x * z * n / r4
            * (hy * (-s * t / 6.0 - big_a * t / 3.0 - z2 / 2.0 - 1.5) + y2 * inv_s
                - 3.0 * nu * r2 / 4.0
                - r2 / 4.0)
        + 4.0 * x * z / (3.0 * r4) * hy * t;
    let zz = x * z * n / (2.0 * r2) * (1.0 - (r2 + z2 + 1.0) * inv_s);
    let xy = (y / 2.0) * (nu / 2.0 - 1.0) * phi
        + y * m / r4
            * (x2 * z2 * inv_s
                + nu * ((s - 2.0 * big_a) * hx - 2.0 * x2 + r2 / 4.0)
                + r2 / 2.0
                + z2 * hx)
        + y * z * n / r4
            * (hx * ((2.0 * nu - 1.0) * (s / 6.0 + big_a / 3.0) - z2 / 2.0 - 1.5 - r2 / 2.0)
                + nu * r2 / 4.0
                + x2 * inv_s
                - y2 / 2.0
                - 1.5 * x2)
        + 4.0 * y * z / (3.0 * r4) * hx * t;
    let yz = x * y * z / (2.0 * r4)
        * (m * (0.5 + (z2 / 2.0 - 1.5 - r2 / 2.0) * inv_s)
            + (z * n / 2.0) * (-3.0 + (5.0 + z2 + r2) * inv_s));
    let xz = 1.5 * z * phi
        + z * m / r2 * (1.0 + x2 / r2 - x2 * inv_s)
        + n / r2 * (-0.75 * (s + 2.0 * big_a) + z2 - 0.75 - r2 / 4.0 + (z2 / 2.0) * hx);
    Stress {
        xx,
        yy,
        zz,
        xy,
        xz,
        yz,
    }
}

/// Tangential stress per unit μp₀ of a Cattaneo-Mindlin traction with stick ratio s = c/a
/// (s = 0: sliding) at (x, y, z): T(x/a) − s T(x/c), T the sliding field of
/// [`hamilton_tangential_stress`].
pub fn partial_slip_tangential_stress(
    a: f64,
    stick_ratio: f64,
    nu: f64,
    x: f64,
    y: f64,
    z: f64,
) -> Stress {
    let full = hamilton_tangential_stress(a, nu, x, y, z);
    if stick_ratio <= 0.0 {
        return full;
    }
    let stick = hamilton_tangential_stress(stick_ratio * a, nu, x, y, z);
    full.combine(1.0, stick, -stick_ratio)
}

/// The stresses at the hot spots of one elliptical Hertz contact shape, per unit peak pressure,
/// tabulated once per shape: the contact is the ellipse of semi-axes a (along the slip, x) and
/// b = k a, the hot spot lies at depth η a below the trailing end of the slip axis, (−a, 0, ηa).
///
/// - normal part N(η): the Hertz pressure integrated by [`traction_stress`];
/// - tangential part T(ξ, ζ): the unit Hertz-shaped traction in +x on the ellipse of semi-axes
///   (1, k), at (−ξ, 0, ζ), ξ ≥ 1. The partial-slip field (stick ellipse of the same shape,
///   scaled by s = c/a: Mindlin & Deresiewicz 1953) is T(1, η) − s T(1/s, η/s).
///
/// Bilinear in (ln η) and in (u = 1/ξ clustered towards 1, ln ζ); the tests bound the
/// interpolation error against the direct integration.
#[derive(Debug, Clone)]
pub struct EllipseHotSpot {
    axis_ratio: f64,
    nu: f64,
    ln_depth: Vec<f64>,
    normal: Vec<Stress>,
    u: Vec<f64>,
    tangential: Vec<Stress>,
}

impl EllipseHotSpot {
    /// Smallest and largest tabulated depth over semi-axis.
    pub const DEPTH_RANGE: (f64, f64) = (1e-3, 30.0);
    const DEPTHS: usize = 46;
    const U_POINTS: usize = 25;
    const LEVEL: u32 = 2;

    /// Tabulates the shape of axis ratio `axis_ratio` = b/a ∈ (0, 1] (slip along a) for
    /// Poisson's ratio `nu`; a ratio above 1 means slip along the minor axis.
    pub fn new(axis_ratio: f64, nu: f64) -> Self {
        let (lo, hi) = Self::DEPTH_RANGE;
        let ln_depth: Vec<f64> = (0..Self::DEPTHS)
            .map(|i| lo.ln() + (hi / lo).ln() * i as f64 / (Self::DEPTHS - 1) as f64)
            .collect();
        // u = 1 − (1 − t)²: dense near u = 1, where the stick ellipse's edge nears the point.
        let u: Vec<f64> = (0..Self::U_POINTS)
            .map(|j| {
                let t = j as f64 / (Self::U_POINTS - 1) as f64;
                1.0 - (1.0 - t) * (1.0 - t)
            })
            .collect();
        let k = axis_ratio;
        let normal = ln_depth
            .iter()
            .map(|&le| {
                traction_stress(
                    Kernel::Normal,
                    nu,
                    1.0,
                    1.0,
                    k,
                    [-1.0, 0.0, le.exp()],
                    Self::LEVEL,
                )
            })
            .collect();
        let mut tangential = Vec::with_capacity(u.len() * ln_depth.len());
        for &uj in &u {
            for &le in &ln_depth {
                tangential.push(if uj <= 0.0 {
                    Stress::default()
                } else {
                    traction_stress(
                        Kernel::Tangential,
                        nu,
                        1.0,
                        1.0,
                        k,
                        [-1.0 / uj, 0.0, le.exp()],
                        Self::LEVEL,
                    )
                });
            }
        }
        Self {
            axis_ratio,
            nu,
            ln_depth,
            normal,
            u,
            tangential,
        }
    }

    /// The shared table of a shape (built on first use, then kept for the process).
    pub fn shared(axis_ratio: f64, nu: f64) -> std::sync::Arc<EllipseHotSpot> {
        use std::sync::{Arc, Mutex};
        static TABLES: OnceLock<Mutex<Vec<Arc<EllipseHotSpot>>>> = OnceLock::new();
        let tables = TABLES.get_or_init(|| Mutex::new(Vec::new()));
        let mut guard = match tables.lock() {
            Ok(g) => g,
            Err(poisoned) => poisoned.into_inner(),
        };
        if let Some(t) = guard
            .iter()
            .find(|t| t.axis_ratio == axis_ratio && t.nu == nu)
        {
            return Arc::clone(t);
        }
        let table = Arc::new(EllipseHotSpot::new(axis_ratio, nu));
        guard.push(Arc::clone(&table));
        table
    }

    /// Axis ratio b/a of the shape.
    pub fn axis_ratio(&self) -> f64 {
        self.axis_ratio
    }

    /// Normal part per unit p₀ at depth `eta`·a below the trailing end.
    pub fn normal(&self, eta: f64) -> Stress {
        let (i, f) = bracket(&self.ln_depth, Self::clamp_depth(eta).ln());
        self.normal[i].combine(1.0 - f, self.normal[i + 1], f)
    }

    /// Tangential part per unit μp₀ at depth `eta`·a below the trailing end, stick ratio s.
    pub fn tangential(&self, eta: f64, stick_ratio: f64) -> Stress {
        let full = self.unit_traction(1.0, eta);
        if stick_ratio <= 0.0 {
            return full;
        }
        let s = stick_ratio.min(1.0);
        full.combine(1.0, self.unit_traction(s, eta / s), -s)
    }

    /// T(1/u, ζ).
    fn unit_traction(&self, u: f64, zeta: f64) -> Stress {
        let n = self.ln_depth.len();
        let (i, fi) = bracket(&self.u, u.clamp(0.0, 1.0));
        let (j, fj) = bracket(&self.ln_depth, Self::clamp_depth(zeta).ln());
        let v = |ii: usize, jj: usize| self.tangential[ii * n + jj];
        let lower = v(i, j).combine(1.0 - fj, v(i, j + 1), fj);
        let upper = v(i + 1, j).combine(1.0 - fj, v(i + 1, j + 1), fj);
        lower.combine(1.0 - fi, upper, fi)
    }

    fn clamp_depth(x: f64) -> f64 {
        x.clamp(Self::DEPTH_RANGE.0, Self::DEPTH_RANGE.1)
    }
}

/// Index i and fraction f with grid[i] + f (grid[i+1] − grid[i]) = x, for a sorted grid.
fn bracket(grid: &[f64], x: f64) -> (usize, f64) {
    let last = grid.len() - 2;
    let i = grid
        .partition_point(|&g| g <= x)
        .saturating_sub(1)
        .min(last);
    let f = ((x - grid[i]) / (grid[i + 1] - grid[i])).clamp(0.0, 1.0);
    (i, f)
}
