//! Shooting integration of a segmented catenary for trial unknowns (H, V_F): where the line
//! leaves the seabed, the laid and suspended pieces from the anchor up to the fairlead, and the
//! analytic Jacobian of the fairlead position (the method is described with the multi-segment
//! solver, see the parent module).
//!
//! Touchdown: walking down from the fairlead, each segment takes w_i L_i of V_F and each clump
//! its weight; the touchdown is where nothing is left. Laid pieces carry the tension H at the
//! touchdown falling towards the anchor at C_B w_i (clamped at zero); suspended pieces carry H
//! and a vertical tension growing by w_i per metre and by each clump at its joint. The touchdown
//! moves with V_F: ∂l_s/∂V_F = 1/w_k on the touchdown segment k, and the laid length of that
//! segment changes by the opposite amount.

use super::newton::Linearization;
use super::pieces::{laid_stretch, suspended};
use super::profile::ProfilePoint;
use super::segment::LineSegment;

/// How a piece of line is held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum PieceKind {
    /// On the seabed, with tension `tension_top_n` at its fairlead-side end.
    Laid { tension_top_n: f64 },
    /// Hanging, with vertical tension `vertical_tension_bottom_n` at its anchor-side end.
    Suspended { vertical_tension_bottom_n: f64 },
}

/// A uniform part of one segment, laid or suspended, stored from the anchor upwards.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Piece {
    pub(crate) segment: usize,
    pub(crate) length_m: f64,
    /// Unstretched arc length from the anchor at the piece's anchor-side end.
    pub(crate) start_from_anchor_m: f64,
    pub(crate) start_x_m: f64,
    pub(crate) start_z_m: f64,
    pub(crate) kind: PieceKind,
}

impl Piece {
    /// State at `q` metres (unstretched) above the piece's anchor-side end.
    pub(crate) fn at(&self, q: f64, h: f64, segment: &LineSegment, cb: f64) -> ProfilePoint {
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

/// Integrates the line `segs` (fairlead to anchor) on a seabed of friction coefficient `cb`
/// from the anchor for unknowns (H, V_F): fairlead position, Jacobian, and the pieces (written
/// into `pieces`, anchor first).
pub(crate) fn shoot(
    segs: &[LineSegment],
    cb: f64,
    h: f64,
    v_f: f64,
    pieces: &mut Vec<Piece>,
) -> Linearization {
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
pub(crate) fn hanging_length_m(segs: &[LineSegment], z: f64) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Chain-rope-chain line with a clump between rope and bottom chain, fairlead to anchor.
    fn three_segment() -> Vec<LineSegment> {
        vec![
            LineSegment::new(50.0, 980.4, 4.93e8),
            LineSegment::new(150.0, 140.6, 3.6e8).with_clump_weight(2.0e4),
            LineSegment::new(300.0, 980.4, 4.93e8),
        ]
    }

    fn jacobian_matches_central_differences(segs: &[LineSegment], cb: f64, h: f64, v: f64) {
        let mut pieces = Vec::new();
        let (_, jac) = shoot(segs, cb, h, v, &mut pieces);
        for (j, (du, shift)) in [(1e-6 * h, [1e-6 * h, 0.0]), (1e-6 * v, [0.0, 1e-6 * v])]
            .into_iter()
            .enumerate()
        {
            let (p, _) = shoot(segs, cb, h + shift[0], v + shift[1], &mut pieces);
            let (m, _) = shoot(segs, cb, h - shift[0], v - shift[1], &mut pieces);
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
        let segs = three_segment();
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
        let segs = three_segment();
        for cb in [0.0, 0.3, 5.0] {
            // Touchdown in the bottom chain, in the rope, at the clump, and fully suspended.
            for v in [1.5e5, 6.0e4, 8.0e4, 4.0e5] {
                jacobian_matches_central_differences(&segs, cb, 2.0e5, v);
            }
        }
    }
}
