//! Single homogeneous elastic catenary with seabed contact and seabed friction, solved in closed
//! form for the fairlead tensions (Jonkman 2007, NREL/TP-500-41958, Sec. 4.2, the quasi-static
//! line model of FAST/MAP).
//!
//! Frame: origin at the anchor on a flat seabed, x horizontal towards the fairlead, z up. The
//! fairlead sits at (X_F, Z_F) with X_F > 0, Z_F > 0. The unknowns are the horizontal tension H
//! (constant along the suspended part) and the fairlead vertical tension V_F. With w the
//! submerged weight per unit unstretched length, EA the axial stiffness, L the unstretched length
//! and C_B the seabed friction coefficient:
//!
//! - fully suspended (V_F ≥ wL; anchor uplift V_A = V_F − wL):
//!   X_F = H/w [asinh(V_F/H) − asinh(V_A/H)] + HL/EA,
//!   Z_F = H/w [√(1+(V_F/H)²) − √(1+(V_A/H)²)] + (V_F L − wL²/2)/EA;
//! - touchdown (V_F < wL), laid length L_B = L − V_F/w, friction-free point
//!   s₀ = L_B − H/(C_B w) measured from the anchor, Λ = max(s₀, 0):
//!   X_F = L_B + H/w asinh(V_F/H) + HL/EA + C_B w/(2EA) [−L_B² + s₀ Λ],
//!   Z_F = H/w [√(1+(V_F/H)²) − 1] + V_F²/(2 EA w).
//!
//! On the seabed the tension falls from H at the touchdown point towards the anchor at the rate
//! C_B w; where it would become negative (s < s₀) the laid line is slack and the anchor carries
//! no load: T_A = max(H − C_B w L_B, 0). The Jacobian ∂(X_F, Z_F)/∂(H, V_F) is analytic and is
//! checked against central differences in the tests. Differences of square roots are evaluated
//! in cancellation-free form (√(1+a²) − √(1+b²) = (a−b)(a+b)/(√(1+a²)+√(1+b²))).
//!
//! The starting point is that of Peyrot & Goulois (1979) as quoted by Jonkman (2007):
//! λ₀ = √(3((L² − Z_F²)/X_F² − 1)) (0.2 if the line is taut), H₀ = |w X_F/(2λ₀)|,
//! V₀ = w/2 (Z_F/tanh λ₀ + L).
//!
//! Units: N, m; w in N/m, EA in N, C_B dimensionless.

use super::error::{require_non_negative, require_positive, CatenaryError};
use super::newton::{self, CatenaryParams, Linearization, NewtonStats};

/// A homogeneous elastic line: unstretched length, submerged weight per unit unstretched length
/// and axial stiffness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticLine {
    /// Unstretched length L (m).
    pub length_m: f64,
    /// Submerged weight per unit unstretched length w (N/m), positive downwards.
    pub weight_n_per_m: f64,
    /// Axial stiffness EA (N).
    pub axial_stiffness_n: f64,
}

/// One line spanning from an anchor on the seabed to a fairlead: the immutable input of
/// [`solve_catenary`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Catenary {
    /// Line properties.
    pub line: ElasticLine,
    /// Horizontal distance X_F from the anchor to the fairlead (m), > 0.
    pub horizontal_span_m: f64,
    /// Height Z_F of the fairlead above the anchor (m), > 0.
    pub vertical_span_m: f64,
    /// Seabed friction coefficient C_B (-), ≥ 0; 0 for a frictionless seabed.
    pub seabed_friction: f64,
}

impl Catenary {
    /// Checks every input for its physical range; returns the first bad one by name.
    pub fn validate(&self) -> Result<(), CatenaryError> {
        require_positive("length_m", self.line.length_m)?;
        require_positive("weight_n_per_m", self.line.weight_n_per_m)?;
        require_positive("axial_stiffness_n", self.line.axial_stiffness_n)?;
        require_non_negative("seabed_friction", self.seabed_friction)?;
        if !self.vertical_span_m.is_finite() {
            return Err(CatenaryError::InvalidInput {
                field: "vertical_span_m".to_owned(),
                value: self.vertical_span_m,
                reason: "must be finite",
            });
        }
        require_positive("horizontal_span_m", self.horizontal_span_m)
    }
}

/// Equilibrium of a [`Catenary`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CatenarySolution {
    /// The solved case.
    pub catenary: Catenary,
    /// Horizontal tension H of the suspended part (N).
    pub horizontal_tension_n: f64,
    /// Vertical tension at the fairlead V_F (N), upwards on the line.
    pub fairlead_vertical_tension_n: f64,
    /// Unstretched length lying on the seabed L_B (m); 0 when fully suspended.
    pub laid_length_m: f64,
    /// Newton work counters.
    pub stats: NewtonStats,
}

impl CatenarySolution {
    /// Fairlead tension T_F = √(H² + V_F²) (N).
    pub fn fairlead_tension_n(&self) -> f64 {
        self.horizontal_tension_n
            .hypot(self.fairlead_vertical_tension_n)
    }

    /// Horizontal force on the anchor (N): H when suspended, max(H − C_B w L_B, 0) with touchdown.
    pub fn anchor_horizontal_tension_n(&self) -> f64 {
        let c = &self.catenary;
        (self.horizontal_tension_n - c.seabed_friction * c.line.weight_n_per_m * self.laid_length_m)
            .max(0.0)
    }

    /// Vertical uplift on the anchor V_A = max(V_F − wL, 0) (N).
    pub(crate) fn anchor_vertical_tension_n(&self) -> f64 {
        let l = &self.catenary.line;
        (self.fairlead_vertical_tension_n - l.weight_n_per_m * l.length_m).max(0.0)
    }

    /// Anchor tension T_A (N).
    pub fn anchor_tension_n(&self) -> f64 {
        self.anchor_horizontal_tension_n()
            .hypot(self.anchor_vertical_tension_n())
    }
}

/// Unstretched length that hangs vertically under its own weight over a height `z`:
/// z = l + w l²/(2EA), solved without cancellation.
pub(crate) fn hanging_length_m(z: f64, w: f64, ea: f64) -> f64 {
    2.0 * z / (1.0 + (1.0 + 2.0 * w * z / ea).sqrt())
}

/// Rejects lines that cannot reach the fairlead or that would be slack.
pub(crate) fn check_reach(
    length_m: f64,
    horizontal_span_m: f64,
    vertical_span_m: f64,
    hanging_length_m: f64,
    params: &CatenaryParams,
) -> Result<(), CatenaryError> {
    if vertical_span_m <= 0.0 {
        return Err(CatenaryError::LineOnSeabed { vertical_span_m });
    }
    let chord_m = horizontal_span_m.hypot(vertical_span_m);
    let reach_m = length_m * (1.0 + params.max_axial_strain);
    if chord_m >= reach_m {
        return Err(CatenaryError::TooShort {
            chord_m,
            length_m,
            reach_m,
            shortfall_m: chord_m - reach_m,
        });
    }
    let excess_length_m = length_m - hanging_length_m - horizontal_span_m;
    if excess_length_m >= 0.0 {
        return Err(CatenaryError::SlackLine {
            hanging_length_m,
            excess_length_m,
        });
    }
    Ok(())
}

/// Peyrot & Goulois starting point (H₀, V₀) for a line of length `l`, weight `w`.
pub(crate) fn initial_guess(x: f64, z: f64, l: f64, w: f64) -> [f64; 2] {
    let lambda = if x <= 0.0 {
        1e6
    } else if x.hypot(z) >= l {
        0.2
    } else {
        (3.0 * ((l * l - z * z) / (x * x) - 1.0)).sqrt()
    };
    // The Peyrot-Goulois λ₀ is ≥ 0 by construction; keep H₀ away from zero for nearly
    // vertical spans.
    let h = (w * x / (2.0 * lambda)).abs().max(1e-6 * w * l);
    let v = 0.5 * w * (z / lambda.tanh() + l);
    [h, v]
}

/// √(1+a²) − √(1+b²) without cancellation, given `a_minus_b` computed directly.
pub(crate) fn sqrt_diff(a: f64, b: f64, a_minus_b: f64) -> f64 {
    a_minus_b * (a + b) / ((1.0 + a * a).sqrt() + (1.0 + b * b).sqrt())
}

/// asinh(a) − asinh(b) without cancellation, given `a_minus_b` computed directly: for a, b of
/// the same sign it is asinh(a√(1+b²) − b√(1+a²)) with the argument rewritten as
/// (a−b)(a+b)/(a√(1+b²) + b√(1+a²)).
pub(crate) fn asinh_diff(a: f64, b: f64, a_minus_b: f64) -> f64 {
    if a * b > 0.0 {
        let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
        (a_minus_b * (a + b) / (a * sb + b * sa)).asinh()
    } else {
        a.asinh() - b.asinh()
    }
}

/// Fairlead position (X_F, Z_F) reached by the line for given (H, V_F), and its Jacobian.
pub(crate) fn fairlead_position(c: &Catenary, h: f64, v: f64) -> Linearization {
    let (l, w, ea, cb) = (
        c.line.length_m,
        c.line.weight_n_per_m,
        c.line.axial_stiffness_n,
        c.seabed_friction,
    );
    let a = v / h;
    let sa = (1.0 + a * a).sqrt();
    if v >= w * l {
        let b = (v - w * l) / h;
        let sb = (1.0 + b * b).sqrt();
        let asinh_ab = asinh_diff(a, b, w * l / h);
        let x = h / w * asinh_ab + h * l / ea;
        let z = l * (a + b) / (sa + sb) + (v * l - 0.5 * w * l * l) / ea;
        let dx_dh = (asinh_ab - a / sa + b / sb) / w + l / ea;
        let dx_dv = (1.0 / sa - 1.0 / sb) / w;
        let dz_dh = dx_dv;
        let dz_dv = (a / sa - b / sb) / w + l / ea;
        ([x, z], [[dx_dh, dx_dv], [dz_dh, dz_dv]])
    } else {
        let lb = l - v / w;
        let (fric, dfric_dh, dfric_dv) = seabed_friction_stretch(h, lb, w, ea, cb);
        let x = lb + h / w * a.asinh() + h * l / ea + fric;
        let z = h / w * sqrt_diff(a, 0.0, a) + v * v / (2.0 * ea * w);
        let dx_dh = (a.asinh() - a / sa) / w + l / ea + dfric_dh;
        let dx_dv = -1.0 / w + 1.0 / (w * sa) + dfric_dv;
        let dz_dh = (1.0 / sa - 1.0) / w;
        let dz_dv = a / (w * sa) + v / (ea * w);
        ([x, z], [[dx_dh, dx_dv], [dz_dh, dz_dv]])
    }
}

/// Jonkman's friction correction C_B w/(2EA) [−L_B² + s₀ max(s₀, 0)] of the horizontal reach and
/// its derivatives with respect to H and V_F (through L_B = L − V_F/w).
fn seabed_friction_stretch(h: f64, lb: f64, w: f64, ea: f64, cb: f64) -> (f64, f64, f64) {
    if cb == 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let s0 = lb - h / (cb * w);
    if s0 <= 0.0 {
        // Tension stays positive all the way to the anchor.
        (-cb * w * lb * lb / (2.0 * ea), 0.0, cb * lb / ea)
    } else {
        // The anchor end of the laid part (s < s₀) is slack.
        (
            cb * w / (2.0 * ea) * (s0 * s0 - lb * lb),
            -s0 / ea,
            h / (w * ea),
        )
    }
}

/// Solves the elastic catenary for H and V_F.
pub fn solve_catenary(
    catenary: &Catenary,
    params: &CatenaryParams,
) -> Result<CatenarySolution, CatenaryError> {
    params.validate()?;
    catenary.validate()?;
    let (l, w, ea) = (
        catenary.line.length_m,
        catenary.line.weight_n_per_m,
        catenary.line.axial_stiffness_n,
    );
    let (x_f, z_f) = (catenary.horizontal_span_m, catenary.vertical_span_m);
    check_reach(l, x_f, z_f, hanging_length_m(z_f, w, ea), params)?;
    let tolerance_m = params.relative_tolerance * l.max(x_f.hypot(z_f));
    let start = initial_guess(x_f, z_f, l, w);
    let (u, stats) = newton::solve(start, tolerance_m, params.max_iterations, |u| {
        let (p, jac) = fairlead_position(catenary, u[0], u[1]);
        Ok(([p[0] - x_f, p[1] - z_f], jac))
    })?;
    tracing::debug!(
        iterations = stats.iterations,
        residual_m = stats.residual_m,
        "single-line catenary solved"
    );
    Ok(CatenarySolution {
        catenary: *catenary,
        horizontal_tension_n: u[0],
        fairlead_vertical_tension_n: u[1],
        laid_length_m: (l - u[1] / w).max(0.0),
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(cb: f64) -> Catenary {
        Catenary {
            line: ElasticLine {
                length_m: 500.0,
                weight_n_per_m: 800.0,
                axial_stiffness_n: 2.0e8,
            },
            horizontal_span_m: 400.0,
            vertical_span_m: 200.0,
            seabed_friction: cb,
        }
    }

    fn jacobian_matches_central_differences(c: &Catenary, h: f64, v: f64) {
        let (_, jac) = fairlead_position(c, h, v);
        let (dh, dv) = (1e-6 * h, 1e-6 * v);
        for (j, (du, shift)) in [(dh, [dh, 0.0]), (dv, [0.0, dv])].into_iter().enumerate() {
            let (p_plus, _) = fairlead_position(c, h + shift[0], v + shift[1]);
            let (p_minus, _) = fairlead_position(c, h - shift[0], v - shift[1]);
            for i in 0..2 {
                let fd = (p_plus[i] - p_minus[i]) / (2.0 * du);
                let scale = jac[i][j]
                    .abs()
                    .max(1e-3 * (jac[i][0].abs() + jac[i][1].abs()));
                assert!(
                    (fd - jac[i][j]).abs() <= 1e-6 * scale,
                    "J[{i}][{j}] = {} but central difference {fd} at H = {h}, V = {v}",
                    jac[i][j]
                );
            }
        }
    }

    #[test]
    fn jacobian_matches_central_differences_in_every_regime() {
        // Fully suspended (V > wL = 4e5 N).
        jacobian_matches_central_differences(&case(0.0), 1.5e5, 5.0e5);
        // Touchdown, frictionless and with friction holding tension to the anchor.
        jacobian_matches_central_differences(&case(0.0), 1.0e5, 2.4e5);
        jacobian_matches_central_differences(&case(0.1), 1.0e5, 2.4e5);
        // Touchdown with friction leaving the anchor end slack.
        jacobian_matches_central_differences(&case(5.0), 1.0e5, 2.4e5);
    }

    #[test]
    fn branches_meet_continuously_at_the_touchdown_limit() {
        let c = case(0.3);
        let v = 800.0 * 500.0;
        let (above, _) = fairlead_position(&c, 1.0e5, v * (1.0 + 1e-12));
        let (below, _) = fairlead_position(&c, 1.0e5, v * (1.0 - 1e-12));
        assert!((above[0] - below[0]).abs() < 1e-6 && (above[1] - below[1]).abs() < 1e-6);
    }

    #[test]
    fn hanging_length_satisfies_its_stretch_equation() {
        let (z, w, ea) = (186.0, 1065.0, 7.5e5);
        let l = hanging_length_m(z, w, ea);
        assert!((l + w * l * l / (2.0 * ea) - z).abs() < 1e-12 * z);
    }

    #[test]
    fn non_positive_inputs_are_rejected_by_name() {
        let params = CatenaryParams::default();
        for (field, mutate) in [
            (
                "length_m",
                (|c: &mut Catenary| c.line.length_m = 0.0) as fn(&mut Catenary),
            ),
            ("weight_n_per_m", |c| c.line.weight_n_per_m = -1.0),
            ("axial_stiffness_n", |c| c.line.axial_stiffness_n = 0.0),
            ("seabed_friction", |c| c.seabed_friction = -0.1),
            ("horizontal_span_m", |c| c.horizontal_span_m = f64::NAN),
        ] {
            let mut c = case(0.0);
            mutate(&mut c);
            match solve_catenary(&c, &params) {
                Err(CatenaryError::InvalidInput { field: f, .. }) => assert_eq!(f, field),
                other => panic!("{field}: unexpected {other:?}"),
            }
        }
    }

    #[test]
    fn too_short_line_reports_its_shortfall() {
        let mut c = case(0.0);
        c.line.length_m = 400.0; // chord √(400² + 200²) = 447.2136 m
        let params = CatenaryParams {
            max_axial_strain: 0.0,
            ..CatenaryParams::default()
        };
        match solve_catenary(&c, &params) {
            Err(CatenaryError::TooShort { shortfall_m, .. }) => {
                assert!((shortfall_m - (20.0f64.sqrt() * 100.0 - 400.0)).abs() < 1e-9)
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn fairlead_at_anchor_level_is_a_line_on_the_seabed() {
        let mut c = case(0.0);
        c.vertical_span_m = 0.0;
        assert!(matches!(
            solve_catenary(&c, &CatenaryParams::default()),
            Err(CatenaryError::LineOnSeabed { .. })
        ));
    }

    #[test]
    fn line_longer_than_hang_plus_span_is_slack() {
        let mut c = case(0.0);
        c.horizontal_span_m = 250.0; // 500 m − ≈200 m hanging > 250 m
        match solve_catenary(&c, &CatenaryParams::default()) {
            Err(CatenaryError::SlackLine {
                excess_length_m, ..
            }) => assert!((excess_length_m - 50.0).abs() < 0.1),
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn taut_elastic_line_stretches_to_reach_a_chord_longer_than_its_length() {
        let mut c = case(0.0);
        c.line.length_m = 445.0; // chord 447.21 m: 0.5 % strain needed
        let sol = solve_catenary(&c, &CatenaryParams::default()).unwrap();
        assert_eq!(sol.laid_length_m, 0.0);
        let (p, _) = fairlead_position(
            &c,
            sol.horizontal_tension_n,
            sol.fairlead_vertical_tension_n,
        );
        assert!((p[0] - 400.0).abs() < 1e-8 && (p[1] - 200.0).abs() < 1e-8);
        // The stretched length, measured along the profile, is L + ∫T/EA ds and exceeds the
        // chord.
        let n = 4000;
        let ds = 445.0 / n as f64;
        let (mut polyline, mut stretch) = (0.0, 0.0);
        let mut prev = sol.at_arc_length_from_fairlead(0.0).unwrap();
        for i in 1..=n {
            let p = sol.at_arc_length_from_fairlead(i as f64 * ds).unwrap();
            polyline += (p.x_m - prev.x_m).hypot(p.z_m - prev.z_m);
            stretch += 0.5 * (p.tension_n + prev.tension_n) * ds / 2.0e8;
            prev = p;
        }
        assert!(
            (polyline - (445.0 + stretch)).abs() < 1e-6 * 445.0,
            "{polyline} vs {stretch}"
        );
        assert!(polyline > 400.0f64.hypot(200.0));
    }
}
