//! Wire-rope element: the gradient-deficient ANCF cable element (Gerstmayr & Shabana 2006),
//! a C¹ cubic Hermite interpolation of position r(x) from the nodal positions and gradients
//! (see [`super::hermite`]).
//!
//! Strain energy per element, x the unstretched arc length:
//!
//! U = ½ ∫ EA (|r'| − 1)² dx + ½ ∫ EI |r''|² dx.
//!
//! The axial force is N = EA (|r'| − 1) (engineering strain of the interpolated gradient,
//! integrated with 3-point Gauss). Unlike chain, the rope element also carries compression
//! (reported as negative tension), as line codes do for lines with bending stiffness: the
//! axial term is what keeps the nodal gradients at unit length, and a tension-only law lets
//! them drift when the rope goes slack (folded shapes of a few centimetres radius). Bending uses |r''|², which equals the curvature squared up to
//! terms of the order of the axial strain (≤ 0.3 % for steel rope); it makes the bending
//! stiffness the constant Euler–Bernoulli matrix EI ∫ N''ᵀ N'' dx. The reported curvature is the
//! exact one of the interpolation, κ = |r' × r''| / |r'|³.
//!
//! Inertia: consistent mass matrix μ ∫ Nᵀ N dx (μ including distributed extra mass) and
//! orientation-dependent added mass at the Gauss points; weight, Morison loads and seabed contact
//! at the Gauss points.

use nalgebra::{Matrix3, Vector3};

use super::hermite::{bending_integrals, hermite, mass_integrals, GAUSS3};
use super::hydro::{morison, morison_force};
use super::loads::{Coefficients, LocalSystem, PointKinematics, PointLoad};
use super::seabed::{seabed_energy, seabed_force, seabed_load};
use super::section::Section;
use super::spec::SeabedSpec;
use crate::waves::FluidKinematics;

/// Number of quadrature points of a cable element.
pub(crate) const CABLE_POINTS: usize = 3;

/// What an element kernel needs besides its nodal values.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ElementContext<'a> {
    /// Section of the element.
    pub sec: &'a Section,
    /// Unstretched length (m).
    pub length_m: f64,
    /// Seabed.
    pub bed: &'a SeabedSpec,
    /// Water depth (m).
    pub depth_m: f64,
    /// Integrator coefficients.
    pub coef: Coefficients,
    /// Whether inertia and hydrodynamic loads are included (false in statics).
    pub dynamic: bool,
}

impl ElementContext<'_> {
    /// Coefficient c (N s) of the axial structural damping on the strain rate; 0 in statics.
    pub(crate) fn axial_damping_n_s(&self) -> f64 {
        if self.dynamic {
            self.sec
                .axial_damping_n_s(self.length_m, self.coef.axial_damping_ratio)
        } else {
            0.0
        }
    }
}

/// Axial state of a cable element at a Gauss point.
struct CableAxial {
    /// |r'|.
    stretch: f64,
    /// Unit tangent t = r' / |r'|.
    t: Vector3<f64>,
    /// ṙ'.
    v_x: Vector3<f64>,
    /// Axial force N = EA (|r'| − 1) + c t · ṙ' (N).
    force: f64,
}

impl CableAxial {
    /// At the point with gradient `r_x` and shape derivatives `dn`, nodal rates `v`, damping
    /// coefficient `c`.
    fn at(sec: &Section, c: f64, r_x: &Vector3<f64>, dn: &[f64; 4], v: &[Vector3<f64>; 4]) -> Self {
        let stretch = r_x.norm();
        let t = r_x / stretch;
        let v_x = dn
            .iter()
            .zip(v)
            .fold(Vector3::zeros(), |acc, (d, v)| acc + v * *d);
        let force = sec.ea_n * (stretch - 1.0) + c * t.dot(&v_x);
        Self {
            stretch,
            t,
            v_x,
            force,
        }
    }
}

/// Nodal values of an element with `NC` vector coefficients.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ElementValues<const NC: usize> {
    /// Positions and gradients (m and −).
    pub q: [Vector3<f64>; NC],
    /// Their rates.
    pub v: [Vector3<f64>; NC],
    /// Their second rates.
    pub a: [Vector3<f64>; NC],
}

/// Residual of a cable element alone (modified Newton iterations reuse an earlier
/// factorisation): the residual of [`cable_system`] without its derivatives, by the same
/// operations in the same order.
pub(crate) fn cable_residual(
    ctx: &ElementContext<'_>,
    x: &ElementValues<4>,
    water: &[FluidKinematics; CABLE_POINTS],
) -> [Vector3<f64>; 4] {
    let sec = ctx.sec;
    let l = ctx.length_m;
    let mut r = [Vector3::zeros(); 4];
    add_scalar_product(&mut r, &bending_integrals(l), sec.ei_nm2, &x.q);
    if ctx.dynamic {
        add_scalar_product(&mut r, &mass_integrals(l), sec.mass_kg_per_m, &x.a);
    }
    let c = ctx.axial_damping_n_s();
    for (g, &(xi, wg)) in GAUSS3.iter().enumerate() {
        let s = hermite(xi, l);
        let w = wg * l;
        let k = PointKinematics::interpolate(&s.n, &s.dn, &x.q, &x.v, &x.a);
        let CableAxial { t, force, .. } = CableAxial::at(sec, c, &k.r_x, &s.dn, &x.v);
        for (ra, dna) in r.iter_mut().zip(&s.dn) {
            *ra += t * (w * force * dna);
        }
        let mut f = Vector3::new(0.0, 0.0, -sec.weight_n_per_m);
        f += seabed_force(sec, ctx.bed, ctx.depth_m, &k.r, &k.v);
        if ctx.dynamic {
            f += morison_force(sec, &k, &water[g]);
        }
        for (ra, na) in r.iter_mut().zip(&s.n) {
            *ra -= f * (w * na);
        }
    }
    r
}

/// r += s C x for a constant coefficient matrix C (the residual part of
/// [`LocalSystem::add_scalar_matrix`]).
fn add_scalar_product(r: &mut [Vector3<f64>; 4], c: &[[f64; 4]; 4], s: f64, x: &[Vector3<f64>; 4]) {
    for (ra, row) in r.iter_mut().zip(c) {
        for (&cab, xb) in row.iter().zip(x) {
            *ra += xb * (s * cab);
        }
    }
}

/// Residual M q̈ + f_int − f_ext and iteration matrix of a cable element.
pub(crate) fn cable_system(
    ctx: &ElementContext<'_>,
    x: &ElementValues<4>,
    water: &[FluidKinematics; CABLE_POINTS],
) -> LocalSystem<4> {
    let sec = ctx.sec;
    let l = ctx.length_m;
    let mut out = LocalSystem::<4>::zero();
    out.add_scalar_matrix(&bending_integrals(l), sec.ei_nm2, &x.q, 1.0);
    if ctx.dynamic {
        out.add_scalar_matrix(&mass_integrals(l), sec.mass_kg_per_m, &x.a, ctx.coef.beta_p);
    }
    // Axial structural damping on the strain rate ε̇ = t · ṙ' (dynamics only).
    let c = ctx.axial_damping_n_s();
    for (g, &(xi, wg)) in GAUSS3.iter().enumerate() {
        let s = hermite(xi, l);
        let w = wg * l;
        let k = PointKinematics::interpolate(&s.n, &s.dn, &x.q, &x.v, &x.a);
        let CableAxial {
            stretch,
            t,
            v_x,
            force,
        } = CableAxial::at(sec, c, &k.r_x, &s.dn, &x.v);
        let dforce = sec.ea_n;
        for a in 0..4 {
            out.r[a] += t * (w * force * s.dn[a]);
        }
        let ttt = t * t.transpose();
        let p = Matrix3::identity() - ttt;
        // ∂N/∂r' = EA t + c P ṙ' / |r'|, ∂N/∂ṙ' = c t.
        let dn_drx = t * dforce + p * v_x * (c / stretch);
        let kt =
            (t * dn_drx.transpose() + ttt * (c * ctx.coef.gamma_p)) * w + p * (w * force / stretch);
        for a in 0..4 {
            for b in 0..4 {
                out.k[a][b] += kt * (s.dn[a] * s.dn[b]);
            }
        }
        // External loads.
        let mut load = PointLoad::zero();
        load.f.z = -sec.weight_n_per_m;
        load.add(&seabed_load(sec, ctx.bed, ctx.depth_m, &k.r, &k.v));
        if ctx.dynamic {
            load.add(&morison(sec, &k, &water[g]));
        }
        out.add_point_load(&s.n, &s.dn, w, &load, &ctx.coef);
    }
    out
}

/// Position, gradient and second derivative at ξ.
pub(crate) fn cable_point(q: &[Vector3<f64>; 4], l: f64, xi: f64) -> [Vector3<f64>; 3] {
    let s = hermite(xi, l);
    let mut r = [Vector3::zeros(); 3];
    for (a, qa) in q.iter().enumerate() {
        r[0] += qa * s.n[a];
        r[1] += qa * s.dn[a];
        r[2] += qa * s.ddn[a];
    }
    r
}

/// Axial force EA (|r'| − 1) (N) and curvature |r' × r''| / |r'|³ (1/m) at ξ.
pub(crate) fn cable_tension_curvature(
    sec: &Section,
    q: &[Vector3<f64>; 4],
    l: f64,
    xi: f64,
) -> (f64, f64) {
    let [_, rx, rxx] = cable_point(q, l, xi);
    let stretch = rx.norm();
    let curvature = if stretch > 0.0 {
        rx.cross(&rxx).norm() / stretch.powi(3)
    } else {
        0.0
    };
    (sec.ea_n * (stretch - 1.0), curvature)
}

/// Strain energy plus the potential of weight and seabed spring (J).
pub(crate) fn cable_potential(ctx: &ElementContext<'_>, q: &[Vector3<f64>; 4]) -> f64 {
    let sec = ctx.sec;
    let l = ctx.length_m;
    let b = bending_integrals(l);
    let mut e = 0.0;
    for i in 0..4 {
        for j in 0..4 {
            e += 0.5 * sec.ei_nm2 * b[i][j] * q[i].dot(&q[j]);
        }
    }
    for &(xi, wg) in GAUSS3.iter() {
        let [r, rx, _] = cable_point(q, l, xi);
        let w = wg * l;
        e += w
            * (0.5 * sec.ea_n * (rx.norm() - 1.0).powi(2)
                + sec.weight_n_per_m * r.z
                + seabed_energy(sec, ctx.depth_m, &r));
    }
    e
}

/// Kinetic energy of the structural mass (J).
pub(crate) fn cable_kinetic(sec: &Section, l: f64, v: &[Vector3<f64>; 4]) -> f64 {
    let m = mass_integrals(l);
    let mut e = 0.0;
    for i in 0..4 {
        for j in 0..4 {
            e += 0.5 * sec.mass_kg_per_m * m[i][j] * v[i].dot(&v[j]);
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mooring::spec::{Environment, LineTypeSpec, SegmentSpec};

    pub(crate) fn rope_section(extra_kg: f64) -> Section {
        let lt = LineTypeSpec {
            mass_kg_per_m: 16.5,
            submerged_weight_n_per_m: 140.6,
            axial_stiffness_n: 3.6e8,
            bending_stiffness_nm2: 8.0e4,
            bending_stiffness_min_nm2: None,
            torsional_stiffness_nm2: None,
            hydrodynamic_diameter_m: 0.0604,
            drag_normal: 1.2,
            drag_tangential: 0.2,
            added_mass_normal: 1.0,
            added_mass_tangential: 0.3,
            minimum_breaking_load_n: None,
        };
        let seg = SegmentSpec {
            name: "r".into(),
            line_type: "r".into(),
            length_m: 2.0,
            elements: 1,
            extra_mass_kg: Some(extra_kg),
            extra_volume_m3: None,
        };
        let env = Environment {
            water_depth_m: 50.0,
            water_density_kg_m3: 1025.0,
            gravity_m_s2: 9.81,
            seabed: SeabedSpec {
                friction_coefficient: 0.3,
                ..Default::default()
            },
        };
        Section::new(&lt, &seg, &env)
    }

    fn values() -> ElementValues<4> {
        // A bent, stretched element partly below the seabed (z = −50), moving.
        ElementValues {
            q: [
                Vector3::new(0.0, 0.0, -49.9),
                Vector3::new(0.8, 0.1, -0.6),
                Vector3::new(1.5, 0.4, -50.1),
                Vector3::new(0.75, 0.3, 0.6),
            ],
            v: [
                Vector3::new(0.1, 0.0, 0.2),
                Vector3::new(0.01, 0.02, 0.0),
                Vector3::new(-0.3, 0.1, 0.05),
                Vector3::new(0.0, -0.03, 0.01),
            ],
            a: [
                Vector3::new(0.5, 0.1, -0.2),
                Vector3::new(0.0, 0.1, 0.0),
                Vector3::new(0.2, -0.4, 0.3),
                Vector3::new(0.05, 0.0, -0.02),
            ],
        }
    }

    #[test]
    fn cable_iteration_matrix_matches_central_differences_of_the_residual() {
        let sec = rope_section(50.0);
        let bed = SeabedSpec {
            friction_coefficient: 0.3,
            ..Default::default()
        };
        let coef = Coefficients {
            axial_damping_ratio: 0.5,
            beta_p: 400.0,
            gamma_p: 25.0,
        };
        let ctx = ElementContext {
            sec: &sec,
            length_m: 2.0,
            bed: &bed,
            depth_m: 50.0,
            coef,
            dynamic: true,
        };
        let water = [FluidKinematics {
            velocity: Vector3::new(0.8, 0.1, -0.2),
            acceleration: Vector3::new(0.3, 0.0, 0.4),
            dynamic_pressure_pa: 0.0,
        }; 3];
        let x0 = values();
        let sys = cable_system(&ctx, &x0, &water);
        let h = 1e-7;
        let mut worst: f64 = 0.0;
        for b in 0..4 {
            for j in 0..3 {
                // Perturb q and, consistently with the integrator, v and a.
                let mut xp = x0;
                let mut xm = x0;
                xp.q[b][j] += h;
                xm.q[b][j] -= h;
                xp.v[b][j] += coef.gamma_p * h;
                xm.v[b][j] -= coef.gamma_p * h;
                xp.a[b][j] += coef.beta_p * h;
                xm.a[b][j] -= coef.beta_p * h;
                let rp = cable_system(&ctx, &xp, &water);
                let rm = cable_system(&ctx, &xm, &water);
                for a in 0..4 {
                    let col = (rp.r[a] - rm.r[a]) / (2.0 * h);
                    let exact = sys.k[a][b].column(j);
                    worst = worst.max((col - exact).norm());
                }
            }
        }
        let scale = sec.ea_n / 2.0;
        assert!(
            worst < 1e-6 * scale,
            "worst column error {worst:e} vs scale {scale:e}"
        );
        // The residual-only kernel gives the system's residual, by the same operations; in
        // statics too.
        assert_eq!(cable_residual(&ctx, &x0, &water), sys.r);
        let statics = ElementContext {
            dynamic: false,
            ..ctx
        };
        assert_eq!(
            cable_residual(&statics, &x0, &water),
            cable_system(&statics, &x0, &water).r
        );
    }

    #[test]
    fn cable_residual_is_the_gradient_of_its_potential_in_statics() {
        let sec = rope_section(0.0);
        let bed = SeabedSpec::default();
        let ctx = ElementContext {
            sec: &sec,
            length_m: 2.0,
            bed: &bed,
            depth_m: 50.0,
            coef: Coefficients::default(),
            dynamic: false,
        };
        // At rest: the seabed damper is not part of the potential.
        let mut x0 = values();
        x0.v = [Vector3::zeros(); 4];
        let sys = cable_system(&ctx, &x0, &[FluidKinematics::default(); 3]);
        let h = 1e-6;
        for b in 0..4 {
            for j in 0..3 {
                let mut qp = x0.q;
                let mut qm = x0.q;
                qp[b][j] += h;
                qm[b][j] -= h;
                let de = (cable_potential(&ctx, &qp) - cable_potential(&ctx, &qm)) / (2.0 * h);
                let err = (de - sys.r[b][j]).abs();
                assert!(
                    err < 1e-7 * sys.r[b][j].abs().max(1e4),
                    "coefficient {b},{j}: {de} vs {}",
                    sys.r[b][j]
                );
            }
        }
    }

    #[test]
    fn circular_arc_curvature_converges_at_second_order_and_stretch_gives_tension() {
        let sec = rope_section(0.0);
        // An arc of radius R interpolated by one element with exact end tangents: the midpoint
        // curvature error of the cubic is O(φ²) in the subtended angle φ = L/R.
        let rad = 5.0;
        let error = |l: f64| {
            let phi = l / rad;
            let q = [
                Vector3::new(rad, 0.0, 0.0),
                Vector3::new(0.0, 1.0, 0.0),
                Vector3::new(rad * phi.cos(), rad * phi.sin(), 0.0),
                Vector3::new(-phi.sin(), phi.cos(), 0.0),
            ];
            let (_, k) = cable_tension_curvature(&sec, &q, l, 0.5);
            (k * rad - 1.0).abs()
        };
        let (e1, e2) = (error(1.0), error(0.5));
        assert!(e1 < 0.2f64.powi(2) / 20.0, "error {e1}");
        assert!((e1 / e2 - 4.0).abs() < 0.1, "ratio {}", e1 / e2);
        let eps = 1e-3;
        let q = [
            Vector3::zeros(),
            Vector3::new(1.0 + eps, 0.0, 0.0),
            Vector3::new(2.0 * (1.0 + eps), 0.0, 0.0),
            Vector3::new(1.0 + eps, 0.0, 0.0),
        ];
        let (t, k) = cable_tension_curvature(&sec, &q, 2.0, 0.3);
        assert!((t - sec.ea_n * eps).abs() < 1e-6 * sec.ea_n * eps);
        assert_eq!(k, 0.0);
    }
}
