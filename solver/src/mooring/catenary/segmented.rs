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
//! weight at its joint, until the fairlead (x, z) is reached. Newton drives
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
use super::newton::{self, CatenaryParams, Linearization, NewtonStats};
use super::pieces::{laid_stretch, suspended};
use super::profile::ProfilePoint;
use super::single::{check_reach, initial_guess};

/// Standard acceleration of gravity (m/s²), ISO 80000-3.
pub const STANDARD_GRAVITY_M_S2: f64 = 9.80665;
/// Density of carbon steel (kg/m³), the usual design value (DNV-OS-E301 uses 7850 kg/m³).
pub const STEEL_DENSITY_KG_M3: f64 = 7850.0;
/// Density of sea water (kg/m³), as in the paper case's line data.
pub const SEAWATER_DENSITY_KG_M3: f64 = 1025.0;

/// A uniform stretch of mooring line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSegment {
    /// Unstretched length (m).
    pub length_m: f64,
    /// Submerged weight per unit unstretched length, extra masses included (N/m).
    pub weight_n_per_m: f64,
    /// Axial stiffness EA (N).
    pub axial_stiffness_n: f64,
    /// Submerged weight of a clump hung at the anchor-side end of this segment (N), 0 if none.
    pub clump_weight_n: f64,
}

impl LineSegment {
    /// A segment without clump.
    pub fn new(length_m: f64, weight_n_per_m: f64, axial_stiffness_n: f64) -> Self {
        Self {
            length_m,
            weight_n_per_m,
            axial_stiffness_n,
            clump_weight_n: 0.0,
        }
    }

    /// Adds a mass spread uniformly over the segment: w += m g (1 − ρ_water/ρ_material) / L.
    pub fn with_distributed_extra_mass(
        mut self,
        mass_kg: f64,
        material_density_kg_m3: f64,
        water_density_kg_m3: f64,
    ) -> Self {
        self.weight_n_per_m +=
            submerged_weight_n(mass_kg, material_density_kg_m3, water_density_kg_m3)
                / self.length_m;
        self
    }

    /// Hangs a clump of the given submerged weight (N) at the anchor-side end.
    pub fn with_clump_weight(mut self, clump_weight_n: f64) -> Self {
        self.clump_weight_n = clump_weight_n;
        self
    }
}

/// Submerged weight m g (1 − ρ_water/ρ_material) of a solid mass (N).
pub fn submerged_weight_n(
    mass_kg: f64,
    material_density_kg_m3: f64,
    water_density_kg_m3: f64,
) -> f64 {
    mass_kg * STANDARD_GRAVITY_M_S2 * (1.0 - water_density_kg_m3 / material_density_kg_m3)
}

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
    pub fn weight_n(&self) -> f64 {
        self.segments_fairlead_to_anchor
            .iter()
            .map(|s| s.weight_n_per_m * s.length_m + s.clump_weight_n)
            .sum()
    }
}

/// How a piece of line is held.
#[derive(Debug, Clone, Copy, PartialEq)]
enum PieceKind {
    /// On the seabed, with tension `tension_top_n` at its fairlead-side end.
    Laid { tension_top_n: f64 },
    /// Hanging, with vertical tension `vertical_tension_bottom_n` at its anchor-side end.
    Suspended { vertical_tension_bottom_n: f64 },
}

/// A uniform part of one segment, laid or suspended, stored from the anchor upwards.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    segment: usize,
    length_m: f64,
    /// Unstretched arc length from the anchor at the piece's anchor-side end.
    start_from_anchor_m: f64,
    start_x_m: f64,
    start_z_m: f64,
    kind: PieceKind,
}

impl Piece {
    /// State at `q` metres (unstretched) above the piece's anchor-side end.
    fn at(&self, q: f64, h: f64, segment: &LineSegment, cb: f64) -> ProfilePoint {
        let (w, ea) = (segment.weight_n_per_m, segment.axial_stiffness_n);
        match self.kind {
            PieceKind::Laid { tension_top_n } => {
                let (whole, _, _) = laid_stretch(tension_top_n, self.length_m, w, ea, cb);
                let (above, _, _) = laid_stretch(tension_top_n, self.length_m - q, w, ea, cb);
                let tension_n = (tension_top_n - cb * w * (self.length_m - q)).max(0.0);
                ProfilePoint {
                    x_m: self.start_x_m + q + whole - above,
                    z_m: 0.0,
                    horizontal_tension_n: tension_n,
                    vertical_tension_n: 0.0,
                    tension_n,
                    curvature_per_m: 0.0,
                    on_seabed: true,
                }
            }
            PieceKind::Suspended {
                vertical_tension_bottom_n,
            } => {
                let r = suspended(h, vertical_tension_bottom_n, q, w, ea);
                let v = vertical_tension_bottom_n + w * q;
                let tension_n = h.hypot(v);
                ProfilePoint {
                    x_m: self.start_x_m + r.dx,
                    z_m: self.start_z_m + r.dz,
                    horizontal_tension_n: h,
                    vertical_tension_n: v,
                    tension_n,
                    curvature_per_m: w * h / (tension_n * tension_n),
                    on_seabed: false,
                }
            }
        }
    }
}

/// Where the line leaves the seabed, found from V_F.
enum Touchdown {
    /// No seabed contact; the anchor carries the uplift `anchor_uplift_n`.
    None { anchor_uplift_n: f64 },
    /// Inside `segment`, with `suspended_m` of it hanging.
    Inside { segment: usize, suspended_m: f64 },
    /// At the anchor-side joint of `segment`, whose clump partly rests on the seabed; the
    /// segment's lower end carries `vertical_tension_n`.
    AtJoint {
        segment: usize,
        vertical_tension_n: f64,
    },
}

fn find_touchdown(segments: &[LineSegment], v_f: f64) -> Touchdown {
    let mut remaining = v_f;
    for (i, s) in segments.iter().enumerate() {
        let weight = s.weight_n_per_m * s.length_m;
        if remaining < weight {
            return Touchdown::Inside {
                segment: i,
                suspended_m: remaining / s.weight_n_per_m,
            };
        }
        remaining -= weight;
        if i + 1 < segments.len() {
            if remaining < s.clump_weight_n {
                return Touchdown::AtJoint {
                    segment: i,
                    vertical_tension_n: remaining,
                };
            }
            remaining -= s.clump_weight_n;
        }
    }
    Touchdown::None {
        anchor_uplift_n: remaining,
    }
}

/// Integrates the line from the anchor for unknowns (H, V_F): fairlead position, Jacobian, and
/// the pieces (written into `pieces`, anchor first).
fn shoot(model: &SegmentedCatenary, h: f64, v_f: f64, pieces: &mut Vec<Piece>) -> Linearization {
    let segs = &model.segments_fairlead_to_anchor;
    let cb = model.seabed_friction;
    pieces.clear();
    // Lowest suspended segment with its hanging length and bottom vertical tension, the
    // derivatives of those two with respect to V_F, the laid part of the touchdown segment and
    // the first segment lying wholly on the seabed.
    let n = segs.len();
    let (lowest_suspended, dl_dv, dvb_dv, partial_laid, first_full_laid) =
        match find_touchdown(segs, v_f) {
            Touchdown::None { anchor_uplift_n } => (
                (n - 1, segs[n - 1].length_m, anchor_uplift_n),
                0.0,
                1.0,
                None,
                n,
            ),
            Touchdown::Inside {
                segment,
                suspended_m,
            } => (
                (segment, suspended_m, 0.0),
                1.0 / segs[segment].weight_n_per_m,
                0.0,
                Some((segment, segs[segment].length_m - suspended_m)),
                segment + 1,
            ),
            Touchdown::AtJoint {
                segment,
                vertical_tension_n,
            } => (
                (segment, segs[segment].length_m, vertical_tension_n),
                0.0,
                1.0,
                None,
                segment + 1,
            ),
        };
    // Laid pieces from the touchdown down to the anchor, with the tension at each one's top.
    let mut jac = [[0.0; 2]; 2];
    let mut laid: Vec<(usize, f64, f64)> = Vec::with_capacity(n);
    let laid_segments = partial_laid
        .into_iter()
        .chain((first_full_laid..n).map(|j| (j, segs[j].length_m)));
    for (seg, l) in laid_segments {
        let t_top = laid
            .last()
            .map(|&(i, l, t)| t - cb * segs[i].weight_n_per_m * l)
            .unwrap_or(h);
        laid.push((seg, l, t_top));
    }
    // Place the laid pieces from the anchor upwards. Derivatives of the laid reach: every top
    // tension moves with H; the touchdown piece's length λ = L_k − l_s (first in `laid`) moves
    // the tensions of the pieces below it by −C_B w_k per metre.
    let mut x = 0.0;
    let touchdown_piece_moves = dl_dv != 0.0;
    let mut dx_dlambda = 0.0;
    let mut start_from_anchor_m = 0.0;
    for (m, &(seg, l, t_top)) in laid.iter().enumerate().rev() {
        let s = &segs[seg];
        let (stretch, ds_dt, ds_dl) =
            laid_stretch(t_top, l, s.weight_n_per_m, s.axial_stiffness_n, cb);
        jac[0][0] += ds_dt;
        if touchdown_piece_moves {
            if m == 0 {
                dx_dlambda += 1.0 + ds_dl;
            } else {
                dx_dlambda -= ds_dt * cb * segs[laid[0].0].weight_n_per_m;
            }
        }
        pieces.push(Piece {
            segment: seg,
            length_m: l,
            start_from_anchor_m,
            start_x_m: x,
            start_z_m: 0.0,
            kind: PieceKind::Laid {
                tension_top_n: t_top,
            },
        });
        x += l + stretch;
        start_from_anchor_m += l;
    }
    // dλ/dV_F = −dl_s/dV_F.
    jac[0][1] -= dx_dlambda * dl_dv;
    // Suspended pieces from the lowest upwards.
    let mut z = 0.0;
    {
        let (k, l_k, v_bottom) = lowest_suspended;
        let mut v = v_bottom;
        for i in (0..=k).rev() {
            let s = &segs[i];
            let l = if i == k { l_k } else { s.length_m };
            if i < k {
                v += s.clump_weight_n;
            }
            let r = suspended(h, v, l, s.weight_n_per_m, s.axial_stiffness_n);
            let (dv, dl) = if i == k { (dvb_dv, dl_dv) } else { (1.0, 0.0) };
            jac[0][0] += r.dx_d[0];
            jac[1][0] += r.dz_d[0];
            jac[0][1] += r.dx_d[1] * dv + r.dx_d[2] * dl;
            jac[1][1] += r.dz_d[1] * dv + r.dz_d[2] * dl;
            pieces.push(Piece {
                segment: i,
                length_m: l,
                start_from_anchor_m,
                start_x_m: x,
                start_z_m: z,
                kind: PieceKind::Suspended {
                    vertical_tension_bottom_n: v,
                },
            });
            x += r.dx;
            z += r.dz;
            start_from_anchor_m += l;
            v += s.weight_n_per_m * l;
        }
    }
    ([x, z], jac)
}

/// Unstretched length hanging vertically below the fairlead over the height `z` at zero
/// horizontal tension (clumps included), by bisection on the monotonic height of a hanging
/// length. Returns the total length if even the whole line does not span `z`.
fn hanging_length_m(segs: &[LineSegment], z: f64) -> f64 {
    let height = |hang: f64| {
        // Pieces from the fairlead down, then integrated from the free bottom end upwards.
        let mut parts = Vec::with_capacity(segs.len());
        let mut left = hang;
        for (i, s) in segs.iter().enumerate() {
            if left <= 0.0 {
                break;
            }
            parts.push((i, left.min(s.length_m)));
            left -= s.length_m;
        }
        let (mut t, mut rise) = (0.0, 0.0);
        for (m, &(i, l)) in parts.iter().enumerate().rev() {
            let s = &segs[i];
            if m + 1 < parts.len() {
                t += s.clump_weight_n;
            }
            rise += l + (t * l + 0.5 * s.weight_n_per_m * l * l) / s.axial_stiffness_n;
            t += s.weight_n_per_m * l;
        }
        rise
    };
    let total: f64 = segs.iter().map(|s| s.length_m).sum();
    if height(total) <= z {
        return total;
    }
    let (mut lo, mut hi) = (0.0, total);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if height(mid) < z {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-14 * total {
            break;
        }
    }
    0.5 * (lo + hi)
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
        let (p, jac) = shoot(catenary, u[0], u[1], &mut pieces);
        Ok(([p[0] - x_f, p[1] - z_f], jac))
    })?;
    let (h, v_f) = (u[0], u[1]);
    shoot(catenary, h, v_f, &mut pieces);
    let cb = catenary.seabed_friction;
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

    fn jacobian_matches_central_differences(model: &SegmentedCatenary, h: f64, v: f64) {
        let mut pieces = Vec::new();
        let (_, jac) = shoot(model, h, v, &mut pieces);
        for (j, (du, shift)) in [(1e-6 * h, [1e-6 * h, 0.0]), (1e-6 * v, [0.0, 1e-6 * v])]
            .into_iter()
            .enumerate()
        {
            let (p, _) = shoot(model, h + shift[0], v + shift[1], &mut pieces);
            let (m, _) = shoot(model, h - shift[0], v - shift[1], &mut pieces);
            for i in 0..2 {
                let fd = (p[i] - m[i]) / (2.0 * du);
                let scale = jac[i][0].abs() + jac[i][1].abs();
                assert!(
                    (fd - jac[i][j]).abs() <= 1e-6 * scale,
                    "J[{i}][{j}] = {} vs central difference {fd} at H = {h}, V = {v}",
                    jac[i][j]
                );
            }
        }
    }

    #[test]
    fn touchdown_walk_finds_segment_joint_or_uplift() {
        let segs = three_segment(0.0).segments_fairlead_to_anchor;
        // Chain 49 020 N, rope 21 090 N, clump 20 000 N, bottom chain 294 120 N.
        match find_touchdown(&segs, 60_000.0) {
            Touchdown::Inside {
                segment,
                suspended_m,
            } => {
                assert_eq!(segment, 1);
                assert!((suspended_m - 10_980.0 / 140.6).abs() < 1e-9);
            }
            _ => panic!("expected touchdown in the rope"),
        }
        match find_touchdown(&segs, 80_000.0) {
            Touchdown::AtJoint {
                segment,
                vertical_tension_n,
            } => {
                assert_eq!(segment, 1);
                assert!((vertical_tension_n - 9_890.0).abs() < 1e-6);
            }
            _ => panic!("expected touchdown at the clump"),
        }
        match find_touchdown(&segs, 400_000.0) {
            Touchdown::None { anchor_uplift_n } => {
                assert!((anchor_uplift_n - (400_000.0 - 384_230.0)).abs() < 1e-6)
            }
            _ => panic!("expected a suspended line"),
        }
    }

    #[test]
    fn shooting_jacobian_matches_central_differences_in_every_regime() {
        for cb in [0.0, 0.3, 5.0] {
            let model = three_segment(cb);
            // Touchdown in the bottom chain, in the rope, at the clump, and fully suspended.
            for v in [1.5e5, 6.0e4, 8.0e4, 4.0e5] {
                jacobian_matches_central_differences(&model, 2.0e5, v);
            }
        }
    }

    #[test]
    fn solved_line_lands_on_its_fairlead_with_friction_and_clump() {
        for cb in [0.0, 0.3, 5.0] {
            let model = three_segment(cb);
            let sol = solve_segmented(&model, &CatenaryParams::default()).unwrap();
            let top = sol.at_arc_length_from_fairlead(0.0).unwrap();
            let anchor = sol.at_arc_length_from_fairlead(500.0).unwrap();
            assert!((top.x_m - 420.0).abs() < 1e-7 && (top.z_m - 90.0).abs() < 1e-7);
            assert!(anchor.x_m.abs() < 1e-12 && anchor.z_m.abs() < 1e-12);
            assert!((top.tension_n - sol.fairlead_tension_n()).abs() < 1e-6 * top.tension_n);
            assert!((anchor.tension_n - sol.anchor_tension_n()).abs() < 1e-6 * top.tension_n);
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
    fn extra_mass_adds_its_submerged_weight_per_metre() {
        let seg = LineSegment::new(40.0, 140.6, 3.6e8).with_distributed_extra_mass(
            2000.0,
            STEEL_DENSITY_KG_M3,
            SEAWATER_DENSITY_KG_M3,
        );
        // 2000 kg × 9.80665 m/s² × (1 − 1025/7850) / 40 m = 426.31 N/m.
        let expected = 140.6 + 2000.0 * 9.80665 * (1.0 - 1025.0 / 7850.0) / 40.0;
        assert!((seg.weight_n_per_m - expected).abs() < 1e-12);
        assert!((seg.weight_n_per_m - 566.91).abs() < 0.01);
    }
}
