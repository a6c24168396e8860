//! Chain element: a two-node tension-only bar (no bending, 3 DOF per node).
//!
//! With d = rⱼ − rᵢ, ℓ = |d|, e = d/ℓ and the engineering strain ε = ℓ/L − 1, the axial force
//! is N = EA max(ε, 0) (a slack chain carries no compression), smoothed near ε = 0 by
//! `super::loads::slack_axial_force`. Internal forces −N e at node i and +N e at node j;
//! tangent K = (N'(ε)/L) e eᵀ + (N/ℓ)(I − e eᵀ) in the pattern [K −K; −K K]. Mass, weight, Morison loads and seabed contact use nodal (trapezoidal)
//! quadrature, i.e. the lumped-mass discretisation usual for chain, with the bar direction as
//! the tangent.

use nalgebra::{Matrix3, Vector3};

use super::cable_element::{ElementContext, ElementValues};
use super::hydro::{morison, morison_force};
use super::loads::{
    slack_axial_force, LocalSystem, PointKinematics, PointLoad, SLACK_SMOOTHING_STRAIN,
};
use super::seabed::{seabed_energy, seabed_force, seabed_load};
use crate::waves::FluidKinematics;

/// Number of quadrature points (the nodes) of a bar.
pub const BAR_POINTS: usize = 2;

/// Residual of a bar alone: the residual of [`bar_system`] without its derivatives, by the
/// same operations in the same order.
pub(crate) fn bar_residual(
    ctx: &ElementContext<'_>,
    x: &ElementValues<2>,
    water: &[FluidKinematics],
) -> [Vector3<f64>; 2] {
    let sec = ctx.sec;
    let l = ctx.length_m;
    let mut r = [Vector3::zeros(); 2];
    let d = x.q[1] - x.q[0];
    if let Some(ax) = BarAxial::of(ctx, x, &d) {
        r[0] -= ax.e * ax.force;
        r[1] += ax.e * ax.force;
    }
    let w = 0.5 * l;
    for (node, water_at_node) in water.iter().take(2).enumerate() {
        if ctx.dynamic {
            r[node] += x.a[node] * (w * sec.mass_kg_per_m);
        }
        let k = PointKinematics {
            r: x.q[node],
            r_x: d / l,
            v: x.v[node],
            a: x.a[node],
        };
        let mut f = Vector3::new(0.0, 0.0, -sec.weight_n_per_m);
        f += seabed_force(sec, ctx.bed, ctx.depth_m, &k.r, &k.v);
        if ctx.dynamic {
            f += morison_force(sec, &k, water_at_node);
        }
        // The nodal rule: shape value 1 at its own node, 0 at the other.
        r[node] -= f * w;
    }
    r
}

/// Axial state of a bar of chord `d` = q_j − q_i (none for a bar of zero length): the
/// tension-only elastic law and the axial structural damping on ε̇ = e · (v_j − v_i) / L,
/// weighted by the slope φ of that law (φ = 1 taut, 0 slack) so that a slack chain resists no
/// compression.
struct BarAxial {
    /// Unit chord.
    e: Vector3<f64>,
    /// Chord length ℓ (m).
    len: f64,
    /// dN/dε of the elastic law (N).
    dforce: f64,
    /// Damping coefficient (N s; 0 in statics).
    c: f64,
    /// φ and dφ/dε.
    phi: f64,
    dphi: f64,
    /// Relative velocity v_j − v_i (m/s) and strain rate ε̇ (1/s).
    w_rel: Vector3<f64>,
    rate: f64,
    /// Axial force N (N).
    force: f64,
}

impl BarAxial {
    fn of(ctx: &ElementContext<'_>, x: &ElementValues<2>, d: &Vector3<f64>) -> Option<Self> {
        let (sec, l) = (ctx.sec, ctx.length_m);
        // zero or NaN length: no axial state
        let len = Some(d.norm()).filter(|&len| len > 0.0)?;
        let e = d / len;
        let (elastic, dforce, _) = slack_axial_force(sec.ea_n, len / l - 1.0);
        let c = ctx.axial_damping_n_s();
        let (phi, dphi) = slack_slope(len / l - 1.0);
        let w_rel = x.v[1] - x.v[0];
        let rate = e.dot(&w_rel) / l;
        let force = elastic + c * phi * rate;
        Some(Self {
            e,
            len,
            dforce,
            c,
            phi,
            dphi,
            w_rel,
            rate,
            force,
        })
    }
}

/// Residual M q̈ + f_int − f_ext and iteration matrix of a bar.
pub(crate) fn bar_system(
    ctx: &ElementContext<'_>,
    x: &ElementValues<2>,
    water: &[FluidKinematics],
) -> LocalSystem<2> {
    let sec = ctx.sec;
    let l = ctx.length_m;
    let mut out = LocalSystem::<2>::zero();
    let d = x.q[1] - x.q[0];
    if let Some(BarAxial {
        e,
        len,
        dforce,
        c,
        phi,
        dphi,
        w_rel,
        rate,
        force,
    }) = BarAxial::of(ctx, x, &d)
    {
        let eet = e * e.transpose();
        let p = Matrix3::identity() - eet;
        // ∂N/∂d = (N'(ε) + c ε̇ φ'(ε)) e / L + c φ P w / (L ℓ), ∂N/∂w = c φ e / L.
        let dn_dd = e * ((dforce + c * rate * dphi) / l) + p * w_rel * (c * phi / (l * len));
        let kb = e * dn_dd.transpose() + eet * (c * phi * ctx.coef.gamma_p / l) + p * (force / len);
        out.r[0] -= e * force;
        out.r[1] += e * force;
        out.k[0][0] += kb;
        out.k[1][1] += kb;
        out.k[0][1] -= kb;
        out.k[1][0] -= kb;
    }
    let w = 0.5 * l;
    let dn = [-1.0 / l, 1.0 / l];
    for (node, water_at_node) in water.iter().take(2).enumerate() {
        let n = if node == 0 { [1.0, 0.0] } else { [0.0, 1.0] };
        if ctx.dynamic {
            out.r[node] += x.a[node] * (w * sec.mass_kg_per_m);
            let m = w * sec.mass_kg_per_m * ctx.coef.beta_p;
            for i in 0..3 {
                out.k[node][node][(i, i)] += m;
            }
        }
        let k = PointKinematics {
            r: x.q[node],
            r_x: d / l,
            v: x.v[node],
            a: x.a[node],
        };
        let mut load = PointLoad::zero();
        load.f.z = -sec.weight_n_per_m;
        load.add(&seabed_load(sec, ctx.bed, ctx.depth_m, &k.r, &k.v));
        if ctx.dynamic {
            load.add(&morison(sec, &k, water_at_node));
        }
        out.add_point_load(&n, &dn, w, &load, &ctx.coef);
    }
    out
}

/// Slope φ = (dN/dε)/EA of the tension-only law and its derivative dφ/dε.
fn slack_slope(strain: f64) -> (f64, f64) {
    let e0 = SLACK_SMOOTHING_STRAIN;
    if strain <= -e0 {
        (0.0, 0.0)
    } else if strain < e0 {
        ((strain + e0) / (2.0 * e0), 1.0 / (2.0 * e0))
    } else {
        (1.0, 0.0)
    }
}

/// Axial force of a bar (N).
pub(crate) fn bar_tension(ea_n: f64, l: f64, q: &[Vector3<f64>; 2]) -> f64 {
    slack_axial_force(ea_n, (q[1] - q[0]).norm() / l - 1.0).0
}

/// Strain energy plus the potential of weight and seabed spring (J).
pub(crate) fn bar_potential(ctx: &ElementContext<'_>, q: &[Vector3<f64>; 2]) -> f64 {
    let sec = ctx.sec;
    let l = ctx.length_m;
    let mut e = l * slack_axial_force(sec.ea_n, (q[1] - q[0]).norm() / l - 1.0).2;
    for r in q {
        e += 0.5 * l * (sec.weight_n_per_m * r.z + seabed_energy(sec, ctx.depth_m, r));
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mooring::loads::Coefficients;
    use crate::mooring::section::Section;
    use crate::mooring::spec::{Environment, LineTypeSpec, SeabedSpec, SegmentSpec};

    fn chain() -> Section {
        let lt = LineTypeSpec {
            mass_kg_per_m: 114.9,
            submerged_weight_n_per_m: 980.4,
            axial_stiffness_n: 4.93e8,
            bending_stiffness_nm2: 0.0,
            bending_stiffness_min_nm2: None,
            torsional_stiffness_nm2: None,
            hydrodynamic_diameter_m: 0.1368,
            drag_normal: 2.4,
            drag_tangential: 1.15,
            added_mass_normal: 1.0,
            added_mass_tangential: 0.5,
            minimum_breaking_load_n: None,
        };
        let seg = SegmentSpec {
            name: "c".into(),
            line_type: "c".into(),
            length_m: 5.0,
            elements: 1,
            extra_mass_kg: None,
            extra_volume_m3: None,
        };
        let env = Environment {
            water_depth_m: 30.0,
            water_density_kg_m3: 1025.0,
            gravity_m_s2: 9.81,
            seabed: SeabedSpec::default(),
        };
        Section::new(&lt, &seg, &env)
    }

    #[test]
    fn bar_iteration_matrix_matches_central_differences_of_the_residual() {
        let sec = chain();
        let bed = SeabedSpec {
            friction_coefficient: 0.5,
            ..Default::default()
        };
        let coef = Coefficients {
            axial_damping_ratio: 0.5,
            beta_p: 900.0,
            gamma_p: 30.0,
        };
        let ctx = ElementContext {
            sec: &sec,
            length_m: 5.0,
            bed: &bed,
            depth_m: 30.0,
            coef,
            dynamic: true,
        };
        let water = [FluidKinematics {
            velocity: Vector3::new(0.5, -0.2, 0.1),
            acceleration: Vector3::new(0.2, 0.1, -0.3),
            dynamic_pressure_pa: 0.0,
        }; 2];
        let x0 = ElementValues {
            q: [
                Vector3::new(0.0, 0.0, -29.0),
                Vector3::new(4.0, 1.0, -30.001 - 3.0 * 0.0),
            ],
            v: [
                Vector3::new(0.1, 0.2, -0.1),
                Vector3::new(0.02, -0.05, 0.03),
            ],
            a: [Vector3::new(0.3, 0.0, 0.1), Vector3::new(-0.2, 0.1, 0.0)],
        };
        // Stretch it: put node 1 at 5.01 m from node 0.
        let mut x0 = x0;
        let d = (x0.q[1] - x0.q[0]).normalize() * 5.01;
        x0.q[1] = x0.q[0] + d;
        let sys = bar_system(&ctx, &x0, &water);
        let h = 1e-7;
        let mut worst: f64 = 0.0;
        for b in 0..2 {
            for j in 0..3 {
                let mut xp = x0;
                let mut xm = x0;
                xp.q[b][j] += h;
                xm.q[b][j] -= h;
                xp.v[b][j] += coef.gamma_p * h;
                xm.v[b][j] -= coef.gamma_p * h;
                xp.a[b][j] += coef.beta_p * h;
                xm.a[b][j] -= coef.beta_p * h;
                let rp = bar_system(&ctx, &xp, &water);
                let rm = bar_system(&ctx, &xm, &water);
                for a in 0..2 {
                    let col = (rp.r[a] - rm.r[a]) / (2.0 * h);
                    worst = worst.max((col - sys.k[a][b].column(j)).norm());
                }
            }
        }
        let scale = sec.ea_n / 5.0;
        assert!(worst < 1e-7 * scale, "worst column error {worst:e}");
        // The residual-only kernel gives the system's residual, by the same operations; in
        // statics too, and for a slack bar (no axial force).
        assert_eq!(bar_residual(&ctx, &x0, &water), sys.r);
        let statics = ElementContext {
            dynamic: false,
            ..ctx
        };
        assert_eq!(
            bar_residual(&statics, &x0, &water),
            bar_system(&statics, &x0, &water).r
        );
        let mut slack = x0;
        slack.q[1] = x0.q[0] + d * 0.9;
        assert_eq!(
            bar_residual(&ctx, &slack, &water),
            bar_system(&ctx, &slack, &water).r
        );
    }

    #[test]
    fn axial_damping_adds_c_times_strain_rate_when_taut_and_nothing_when_slack() {
        let sec = chain();
        let bed = SeabedSpec::default();
        let ctx = ElementContext {
            sec: &sec,
            length_m: 5.0,
            bed: &bed,
            depth_m: 30.0,
            coef: Coefficients {
                axial_damping_ratio: 0.5,
                ..Coefficients::default()
            },
            dynamic: true,
        };
        let c = sec.axial_damping_n_s(5.0, 0.5);
        // c = ζ L √(EA m): ζ at the two-mass axial frequency ω = (2/L) √(EA/m) is c ω / (2 EA).
        let omega = 2.0 / 5.0 * (sec.ea_n / sec.mass_kg_per_m).sqrt();
        assert!((c * omega / (2.0 * sec.ea_n) - 0.5).abs() < 1e-12);
        let run = |len: f64| {
            let x = ElementValues {
                q: [Vector3::new(0.0, 0.0, -10.0), Vector3::new(len, 0.0, -10.0)],
                v: [Vector3::zeros(), Vector3::new(0.2, 0.0, 0.0)],
                a: [Vector3::zeros(); 2],
            };
            let still = ElementValues {
                v: [Vector3::zeros(); 2],
                ..x
            };
            let water = [FluidKinematics::default(); 2];
            (bar_system(&ctx, &x, &water).r[1] - bar_system(&ctx, &still, &water).r[1]).x
        };
        // Taut: ε̇ = 0.2 / 5 per second; the drag of the moving node is also in the difference,
        // so compare with the lumped drag removed: the node moves along the bar (tangential).
        let drag = 0.5 * 5.0 * sec.drag_tangential_kg_per_m2 * 0.2 * 0.2;
        let taut = run(5.01);
        assert!(
            (taut - (c * 0.2 / 5.0 + drag)).abs() < 1e-6 * c * 0.04,
            "{taut}"
        );
        let slack = run(4.9);
        assert!((slack - drag).abs() < 1e-9, "{slack}");
    }

    #[test]
    fn compressed_bar_carries_no_force() {
        let sec = chain();
        let bed = SeabedSpec::default();
        let ctx = ElementContext {
            sec: &sec,
            length_m: 5.0,
            bed: &bed,
            depth_m: 30.0,
            coef: Coefficients::default(),
            dynamic: false,
        };
        let q = [Vector3::new(0.0, 0.0, -10.0), Vector3::new(4.0, 0.0, -10.0)];
        assert_eq!(bar_tension(sec.ea_n, 5.0, &q), 0.0);
        let x = ElementValues {
            q,
            v: [Vector3::zeros(); 2],
            a: [Vector3::zeros(); 2],
        };
        let sys = bar_system(&ctx, &x, &[FluidKinematics::default(); 2]);
        // Only the lumped weight remains: each node carries half of w L.
        assert!((sys.r[0].z - 0.5 * 5.0 * sec.weight_n_per_m).abs() < 1e-9);
        assert!(sys.r[0].x.abs() < 1e-12);
    }
}
