//! Multi-segment elastic catenary (chain, wire rope, extra masses) solved by shooting from the
//! anchor.
//!
//! The line is a fairlead-to-anchor list of [`LineSegment`]s. For trial unknowns (H, V_F) the
//! touchdown point is where the weight hanging below the fairlead equals V_F: walking down from
//! the fairlead, each segment takes w_i L_i of V_F and each clump its weight. Everything below the
//! touchdown lies on the seabed; its tension falls from H at the touchdown towards the anchor at
//! the rate C_B w_i (clamped at zero, as in Jonkman 2007, NREL/TP-500-41958, Sec. 4.2). From the
//! anchor the laid pieces and then the suspended pieces are integrated in closed form
//! (`pieces`), the vertical tension growing by w_i per unit length and jumping by each clump
//! weight at its joint, until the fairlead (x, z) is reached (`shooting`). Newton drives
//! (x − X_F, z − Z_F) to zero with the Jacobian assembled analytically from the piece
//! derivatives; the touchdown moves with V_F (∂l/∂V_F = 1/w on the touchdown segment).
//!
//! Extra masses: [`LineSegment::with_distributed_extra_mass`] spreads a mass uniformly over the
//! segment and adds its submerged weight m g (1 − ρ_water/ρ_material) / L to w (the paper case's
//! 2 t on the 40 m "wire rope-2" segment, Bussolati et al. 2020 Sec. 3.1, treated as solid steel
//! of 7850 kg/m³ in sea water of 1025 kg/m³ — the paper does not say how the mass is built).
//! A clump weight hangs at the anchor-side end of its segment. Clumps resting on the seabed
//! add no friction.
//!
//! Frame and units as in the parent module: anchor at the origin, x towards the fairlead, z up;
//! N, m.

use super::error::{require_non_negative, require_positive, CatenaryError};
use super::newton::{self, CatenaryParams, NewtonStats};
use super::profile::ProfilePoint;
use super::shooting::{hanging_length_m, shoot, Piece, PieceKind};
use super::single::{check_reach, initial_guess};

pub use super::segment::{
    submerged_weight_n, LineSegment, SEAWATER_DENSITY_KG_M3, STANDARD_GRAVITY_M_S2,
    STEEL_DENSITY_KG_M3,
};

/// A multi-segment line from an anchor on the seabed to a fairlead: the immutable input of
/// [`solve_segmented`].
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentedCatenary {
    /// Segments in order from the fairlead to the anchor.
    pub segments_fairlead_to_anchor: Vec<LineSegment>,
    /// Horizontal distance X_F from the anchor to the fairlead (m), > 0.
    pub horizontal_span_m: f64,
    /// Height Z_F of the fairlead above the anchor (m), > 0.
    pub vertical_span_m: f64,
    /// Seabed friction coefficient C_B (-), ≥ 0.
    pub seabed_friction: f64,
}

impl SegmentedCatenary {
    /// Checks every input; errors name the field, e.g. `segments[2].weight_n_per_m`.
    pub fn validate(&self) -> Result<(), CatenaryError> {
        let n = self.segments_fairlead_to_anchor.len();
        if n == 0 {
            return Err(CatenaryError::InvalidInput {
                field: "segments".to_owned(),
                value: 0.0,
                reason: "at least one segment is needed",
            });
        }
        for (i, s) in self.segments_fairlead_to_anchor.iter().enumerate() {
            require_positive(&format!("segments[{i}].length_m"), s.length_m)?;
            require_positive(&format!("segments[{i}].weight_n_per_m"), s.weight_n_per_m)?;
            require_positive(
                &format!("segments[{i}].axial_stiffness_n"),
                s.axial_stiffness_n,
            )?;
            require_non_negative(&format!("segments[{i}].clump_weight_n"), s.clump_weight_n)?;
        }
        if self.segments_fairlead_to_anchor[n - 1].clump_weight_n != 0.0 {
            return Err(CatenaryError::InvalidInput {
                field: format!("segments[{}].clump_weight_n", n - 1),
                value: self.segments_fairlead_to_anchor[n - 1].clump_weight_n,
                reason: "must be 0: a clump at the anchor end would rest on the anchor",
            });
        }
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

    /// Total unstretched length (m).
    pub fn length_m(&self) -> f64 {
        self.segments_fairlead_to_anchor
            .iter()
            .map(|s| s.length_m)
            .sum()
    }

    /// Total submerged weight of the line and its clumps (N).
    pub(crate) fn weight_n(&self) -> f64 {
        self.segments_fairlead_to_anchor
            .iter()
            .map(|s| s.weight_n_per_m * s.length_m + s.clump_weight_n)
            .sum()
    }
}

/// Equilibrium of a [`SegmentedCatenary`].
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentedSolution {
    /// The solved case.
    pub catenary: SegmentedCatenary,
    /// Horizontal tension H of the suspended part (N).
    pub horizontal_tension_n: f64,
    /// Vertical tension at the fairlead V_F (N).
    pub fairlead_vertical_tension_n: f64,
    /// Unstretched length lying on the seabed (m).
    pub laid_length_m: f64,
    /// Horizontal force on the anchor (N): H less the seabed friction, never negative.
    pub anchor_horizontal_tension_n: f64,
    /// Vertical uplift on the anchor (N), zero with touchdown.
    pub anchor_vertical_tension_n: f64,
    /// Newton work counters.
    pub stats: NewtonStats,
    pieces: Vec<Piece>,
}

impl SegmentedSolution {
    /// Fairlead tension √(H² + V_F²) (N).
    pub fn fairlead_tension_n(&self) -> f64 {
        self.horizontal_tension_n
            .hypot(self.fairlead_vertical_tension_n)
    }

    /// Anchor tension (N).
    pub fn anchor_tension_n(&self) -> f64 {
        self.anchor_horizontal_tension_n
            .hypot(self.anchor_vertical_tension_n)
    }

    /// Unstretched arc lengths from the fairlead of the segment ends: 0 (fairlead), then each
    /// joint, then the total length (anchor).
    pub fn joint_arc_lengths_from_fairlead_m(&self) -> Vec<f64> {
        let mut s = 0.0;
        let mut out = vec![0.0];
        for seg in &self.catenary.segments_fairlead_to_anchor {
            s += seg.length_m;
            out.push(s);
        }
        out
    }

    /// Profile at the unstretched arc length `arc_length_m` from the fairlead, in [0, L]. At a
    /// joint the state just on its fairlead side is returned.
    pub fn at_arc_length_from_fairlead(
        &self,
        arc_length_m: f64,
    ) -> Result<ProfilePoint, CatenaryError> {
        let length_m = self.catenary.length_m();
        let out_of_range = CatenaryError::ArcLengthOutOfRange {
            arc_length_m,
            length_m,
        };
        if !(0.0..=length_m).contains(&arc_length_m) {
            return Err(out_of_range);
        }
        let sigma = length_m - arc_length_m;
        let piece = self
            .pieces
            .iter()
            .rev()
            .find(|p| p.start_from_anchor_m <= sigma && p.length_m > 0.0)
            .or_else(|| self.pieces.first())
            .ok_or(out_of_range)?;
        let q = (sigma - piece.start_from_anchor_m).clamp(0.0, piece.length_m);
        let segment = &self.catenary.segments_fairlead_to_anchor[piece.segment];
        Ok(piece.at(
            q,
            self.horizontal_tension_n,
            segment,
            self.catenary.seabed_friction,
        ))
    }
}

/// Solves a multi-segment line for H and V_F by shooting from the anchor.
pub fn solve_segmented(
    catenary: &SegmentedCatenary,
    params: &CatenaryParams,
) -> Result<SegmentedSolution, CatenaryError> {
    params.validate()?;
    catenary.validate()?;
    let segs = &catenary.segments_fairlead_to_anchor;
    let (x_f, z_f) = (catenary.horizontal_span_m, catenary.vertical_span_m);
    let length_m = catenary.length_m();
    let weight_n = catenary.weight_n();
    if z_f <= 0.0 {
        return Err(CatenaryError::LineOnSeabed {
            vertical_span_m: z_f,
        });
    }
    check_reach(length_m, x_f, z_f, hanging_length_m(segs, z_f), params)?;
    let tolerance_m = params.relative_tolerance * length_m.max(x_f.hypot(z_f));
    let start = initial_guess(x_f, z_f, length_m, weight_n / length_m);
    let mut pieces = Vec::with_capacity(segs.len() + 1);
    let (u, stats) = newton::solve(start, tolerance_m, params.max_iterations, |u| {
        let (p, jac) = shoot(segs, catenary.seabed_friction, u[0], u[1], &mut pieces);
        Ok(([p[0] - x_f, p[1] - z_f], jac))
    })?;
    let (h, v_f) = (u[0], u[1]);
    let cb = catenary.seabed_friction;
    shoot(segs, cb, h, v_f, &mut pieces);
    let mut laid_length_m = 0.0;
    let mut anchor_horizontal_tension_n = h;
    let mut anchor_vertical_tension_n = 0.0;
    for (i, p) in pieces.iter().enumerate() {
        match p.kind {
            PieceKind::Laid { tension_top_n } => {
                laid_length_m += p.length_m;
                if i == 0 {
                    let w = segs[p.segment].weight_n_per_m;
                    anchor_horizontal_tension_n = (tension_top_n - cb * w * p.length_m).max(0.0);
                }
            }
            PieceKind::Suspended {
                vertical_tension_bottom_n,
            } => {
                if i == 0 {
                    anchor_vertical_tension_n = vertical_tension_bottom_n;
                }
            }
        }
    }
    tracing::debug!(
        iterations = stats.iterations,
        residual_m = stats.residual_m,
        segments = segs.len(),
        "multi-segment catenary solved"
    );
    Ok(SegmentedSolution {
        catenary: catenary.clone(),
        horizontal_tension_n: h,
        fairlead_vertical_tension_n: v_f,
        laid_length_m,
        anchor_horizontal_tension_n,
        anchor_vertical_tension_n,
        stats,
        pieces,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chain-rope-chain line with a clump between rope and bottom chain.
    fn three_segment(cb: f64) -> SegmentedCatenary {
        SegmentedCatenary {
            segments_fairlead_to_anchor: vec![
                LineSegment::new(50.0, 980.4, 4.93e8),
                LineSegment::new(150.0, 140.6, 3.6e8).with_clump_weight(2.0e4),
                LineSegment::new(300.0, 980.4, 4.93e8),
            ],
            horizontal_span_m: 420.0,
            vertical_span_m: 90.0,
            seabed_friction: cb,
        }
    }

    #[test]
    fn solved_line_lands_on_its_fairlead_with_friction_and_clump() {
        // Touchdown in the rope (420 m), at the clump, which partly rests on the seabed
        // (470 m: exactly the bottom chain laid), and in the bottom chain (488 m).
        for (span, laid) in [(420.0, None), (470.0, Some(300.0)), (488.0, None)] {
            for cb in [0.0, 0.3, 5.0] {
                let mut model = three_segment(cb);
                model.horizontal_span_m = span;
                let sol = solve_segmented(&model, &CatenaryParams::default()).unwrap();
                let top = sol.at_arc_length_from_fairlead(0.0).unwrap();
                let anchor = sol.at_arc_length_from_fairlead(500.0).unwrap();
                assert!((top.x_m - span).abs() < 1e-7 && (top.z_m - 90.0).abs() < 1e-7);
                assert!(anchor.x_m.abs() < 1e-12 && anchor.z_m.abs() < 1e-12);
                let t_f = top.tension_n;
                assert!((t_f - sol.fairlead_tension_n()).abs() < 1e-6 * t_f);
                assert!((anchor.tension_n - sol.anchor_tension_n()).abs() < 1e-6 * t_f);
                if let Some(laid) = laid {
                    assert_eq!(sol.laid_length_m, laid, "span {span}, C_B {cb}");
                }
            }
        }
    }

    #[test]
    fn segment_errors_name_the_segment_and_field() {
        let mut model = three_segment(0.0);
        model.segments_fairlead_to_anchor[1].axial_stiffness_n = -1.0;
        match solve_segmented(&model, &CatenaryParams::default()) {
            Err(CatenaryError::InvalidInput { field, .. }) => {
                assert_eq!(field, "segments[1].axial_stiffness_n")
            }
            other => panic!("unexpected {other:?}"),
        }
        let mut model = three_segment(0.0);
        model.segments_fairlead_to_anchor[2].clump_weight_n = 1.0;
        assert!(matches!(
            solve_segmented(&model, &CatenaryParams::default()),
            Err(CatenaryError::InvalidInput { .. })
        ));
    }

    #[test]
    fn slack_and_short_segmented_lines_are_reported() {
        let mut model = three_segment(0.0);
        model.horizontal_span_m = 300.0; // 500 m of line, ≈ 90 m hanging: 110 m to spare
        assert!(matches!(
            solve_segmented(&model, &CatenaryParams::default()),
            Err(CatenaryError::SlackLine { .. })
        ));
        model.horizontal_span_m = 600.0;
        match solve_segmented(&model, &CatenaryParams::default()) {
            Err(CatenaryError::TooShort { shortfall_m, .. }) => {
                assert!((shortfall_m - (600.0f64.hypot(90.0) - 525.0)).abs() < 1e-9)
            }
            other => panic!("unexpected {other:?}"),
        }
    }

    #[test]
    fn profile_tangent_follows_the_tension_in_every_segment() {
        // dx/ds = (H/T)(1 + T/EA), dz/ds = (V/T)(1 + T/EA) with the section of the segment the
        // point lies in; the vertical tension jumps by the clump weight across its joint.
        let mut model = three_segment(0.3);
        model.horizontal_span_m = 488.0; // nearly taut: touchdown in the bottom chain
        let sol = solve_segmented(&model, &CatenaryParams::default()).unwrap();
        assert!(
            sol.laid_length_m > 0.0 && sol.laid_length_m < 300.0,
            "{sol:?}"
        );
        let ds = 1e-4;
        for (s, ea) in [
            (10.0, 4.93e8),
            (40.0, 4.93e8),
            (120.0, 3.6e8),
            (190.0, 3.6e8),
        ] {
            let p = sol.at_arc_length_from_fairlead(s).unwrap();
            assert!(!p.on_seabed);
            let up = sol.at_arc_length_from_fairlead(s - ds).unwrap();
            let down = sol.at_arc_length_from_fairlead(s + ds).unwrap();
            let stretch = 1.0 + p.tension_n / ea;
            let dx = (up.x_m - down.x_m) / (2.0 * ds);
            let dz = (up.z_m - down.z_m) / (2.0 * ds);
            assert!(
                (dx - p.horizontal_tension_n / p.tension_n * stretch).abs() < 1e-7,
                "s = {s}"
            );
            assert!(
                (dz - p.vertical_tension_n / p.tension_n * stretch).abs() < 1e-7,
                "s = {s}"
            );
        }
        let above = sol.at_arc_length_from_fairlead(200.0 - 1e-9).unwrap();
        let below = sol.at_arc_length_from_fairlead(200.0 + 1e-9).unwrap();
        assert!(!below.on_seabed);
        let jump = above.vertical_tension_n - below.vertical_tension_n;
        assert!((jump - 2.0e4).abs() < 1e-3, "jump {jump} N");
    }
}
