//! Elementary pieces of a segmented catenary: a uniform stretch of line hanging freely, or lying
//! on a flat seabed with Coulomb friction, with the partial derivatives the shooting Jacobian
//! needs.
//!
//! Suspended piece of unstretched length l, weight w, stiffness EA, horizontal tension H and
//! vertical tension V_s at its lower end (V_e = V_s + w l at the upper end), from the elastic
//! catenary (Jonkman 2007, NREL/TP-500-41958, Sec. 4.2):
//!   Δx = H/w [asinh(V_e/H) − asinh(V_s/H)] + H l/EA,
//!   Δz = H/w [√(1+(V_e/H)²) − √(1+(V_s/H)²)] + (V_s l + w l²/2)/EA.
//!
//! Laid piece of length l whose tension is T_top at its upper (fairlead-side) end and falls
//! towards the anchor at the rate C_B w: Δz = 0 and Δx = l + (1/EA) ∫₀ˡ max(T_top − C_B w q, 0) dq.

use super::single::{asinh_diff, sqrt_diff};

/// Rise of a suspended piece and its derivatives with respect to H, V_s and l.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SuspendedRise {
    /// Horizontal advance Δx (m).
    pub(crate) dx: f64,
    /// Rise Δz (m).
    pub(crate) dz: f64,
    /// ∂Δx/∂(H, V_s, l).
    pub(crate) dx_d: [f64; 3],
    /// ∂Δz/∂(H, V_s, l).
    pub(crate) dz_d: [f64; 3],
}

/// Δx, Δz of a suspended piece (see the module docs) with derivatives.
pub(crate) fn suspended(h: f64, vs: f64, l: f64, w: f64, ea: f64) -> SuspendedRise {
    let ve = vs + w * l;
    let (a, b) = (ve / h, vs / h);
    let (sa, sb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
    let a_minus_b = w * l / h;
    let asinh_ab = asinh_diff(a, b, a_minus_b);
    let dx = h / w * asinh_ab + h * l / ea;
    let dz = h / w * sqrt_diff(a, b, a_minus_b) + (vs * l + 0.5 * w * l * l) / ea;
    let cross = (1.0 / sa - 1.0 / sb) / w;
    SuspendedRise {
        dx,
        dz,
        dx_d: [
            (asinh_ab - a / sa + b / sb) / w + l / ea,
            cross,
            1.0 / sa + h / ea,
        ],
        dz_d: [cross, (a / sa - b / sb) / w + l / ea, a / sa + ve / ea],
    }
}

/// Elastic stretch (m) of a laid piece and its derivatives with respect to T_top and l.
pub(crate) fn laid_stretch(t_top: f64, l: f64, w: f64, ea: f64, cb: f64) -> (f64, f64, f64) {
    if t_top <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let t_bottom = t_top - cb * w * l;
    if t_bottom >= 0.0 {
        (0.5 * (t_top + t_bottom) * l / ea, l / ea, t_bottom / ea)
    } else {
        // Tension reaches zero inside the piece; below that point the line is slack.
        (
            t_top * t_top / (2.0 * cb * w * ea),
            t_top / (cb * w * ea),
            0.0,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suspended_derivatives_match_central_differences() {
        let (w, ea) = (566.9, 3.6e8);
        for (h, vs, l) in [
            (2.0e5, 0.0, 40.0),
            (2.0e5, 1.5e5, 100.0),
            (5.0e3, 2.0e4, 30.0),
        ] {
            let r = suspended(h, vs, l, w, ea);
            let base = [h, vs, l];
            for j in 0..3 {
                let d = 1e-6 * base[j].abs().max(1.0);
                let mut p = base;
                let mut m = base;
                p[j] += d;
                m[j] -= d;
                let rp = suspended(p[0], p[1], p[2], w, ea);
                let rm = suspended(m[0], m[1], m[2], w, ea);
                let fd_x = (rp.dx - rm.dx) / (2.0 * d);
                let fd_z = (rp.dz - rm.dz) / (2.0 * d);
                let tol_x = 1e-6 * r.dx_d.iter().map(|v| v.abs()).fold(0.0, f64::max);
                let tol_z = 1e-6 * r.dz_d.iter().map(|v| v.abs()).fold(0.0, f64::max);
                assert!(
                    (fd_x - r.dx_d[j]).abs() < tol_x,
                    "dx/d{j}: {fd_x} vs {}",
                    r.dx_d[j]
                );
                assert!(
                    (fd_z - r.dz_d[j]).abs() < tol_z,
                    "dz/d{j}: {fd_z} vs {}",
                    r.dz_d[j]
                );
            }
        }
    }

    #[test]
    fn suspended_piece_of_vanishing_weight_is_a_straight_elastic_bar() {
        let (h, vs, l, ea) = (3.0e5, 4.0e5, 10.0, 1.0e8);
        let r = suspended(h, vs, l, 1e-6, ea);
        let t = h.hypot(vs);
        let stretched = l * (1.0 + t / ea);
        assert!((r.dx - stretched * h / t).abs() < 1e-9);
        assert!((r.dz - stretched * vs / t).abs() < 1e-9);
    }

    #[test]
    fn laid_stretch_and_derivatives_match_the_integral_in_every_regime() {
        let (w, ea, cb) = (980.4, 4.93e8, 0.5);
        // Tension positive throughout, vanishing inside, and already zero at the top.
        for (t_top, l) in [(2.0e5, 100.0), (2.0e4, 100.0), (-10.0, 5.0)] {
            let (s, ds_dt, ds_dl) = laid_stretch(t_top, l, w, ea, cb);
            let n = 20_000;
            let dq = l / n as f64;
            let integral: f64 = (0..n)
                .map(|i| (t_top - cb * w * (i as f64 + 0.5) * dq).max(0.0) * dq / ea)
                .sum();
            assert!(
                (s - integral).abs() < 1e-6 * integral.max(1e-12),
                "{s} vs {integral}"
            );
            let (sp, _, _) = laid_stretch(t_top + 1.0, l, w, ea, cb);
            let (sm, _, _) = laid_stretch(t_top - 1.0, l, w, ea, cb);
            assert!(((sp - sm) / 2.0 - ds_dt).abs() < 1e-9 * ds_dt.abs().max(1e-12));
            let (sp, _, _) = laid_stretch(t_top, l + 1e-3, w, ea, cb);
            let (sm, _, _) = laid_stretch(t_top, l - 1e-3, w, ea, cb);
            assert!(((sp - sm) / 2e-3 - ds_dl).abs() < 1e-9);
        }
    }
}
