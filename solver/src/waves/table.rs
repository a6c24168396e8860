//! Kinematics of a unidirectional irregular sea tabulated on a vertical plane × time grid, for a
//! body that moves about a fixed region (the floater's members).
//!
//! A unidirectional sea depends on the horizontal position only through x_β = x cos β + y sin β,
//! and, with Wheeler stretching (see [`super::kinematics`]), on the height only through the
//! stretched coordinate σ = (z − η) d/(d + η) ∈ [−d, 0], where the depth profiles
//! C, S = (cosh, sinh)(k (σ + d))/sinh(kd) are smooth (entire) functions. So every kinematic
//! quantity is a smooth function of (x_β, σ, t), and the surface elevation of (x_β, t):
//!
//! - nodes x_i = x₀ + i Δx, σ_m = σ₀ + m Δσ (the top nodes lie above σ = 0, where the profiles
//!   are continued analytically, so that the stencil of a point just below the surface stays
//!   inside the table), time samples t_j = j Δt of the periodic grid of
//!   [`super::series::PointKinematicsSeries`] (N = 2^p samples over the repeat period, at least
//!   `samples_per_shortest_period` per period of the highest component);
//! - at every node the component sums are evaluated by inverse FFT (two real series per complex
//!   transform): η at every x_i, and u_h, w, a_h, a_z, p_d at every (x_i, σ_m);
//! - a query at (x, z, t) interpolates η(x_β, t) (Lagrange: cubic in t, quintic in x_β), returns
//!   zero kinematics above the interpolated surface, and otherwise interpolates the five
//!   quantities at σ(z, η) by tensor-product Lagrange in (t, x_β, σ) (4 × 6 × 6 = 144 stored
//!   values per quantity).
//!
//! Accuracy: P-point Lagrange interpolation with step h of a component e^{iθ} errs by at most
//! c_P (ω h)^P of its amplitude in time (θ = ωt) and c_P (k h)^P in x_β, with c₄ = 0.5625/24 =
//! 0.023 and c₆ = 3.52/720 = 4.9e-3 (the largest |Π (u − xⱼ)|/P! on the central interval); the
//! depth profiles e^{±k s} give the same bound with k Δσ, relative to the profile at the top of
//! the stencil. Time is sampled finely anyway (16 samples per shortest period: c₄ (2π/16)⁴ =
//! 5.6e-4), space coarsely (Δx = Δσ = 2.5 m: c₆ (k h)⁶ = 1.3e-3 for the shortest waves of the
//! paper's severe sea state, k = 0.32 rad/m, which carry little of its energy, and 3e-11 at its
//! peak, k = 0.017 rad/m). The tests compare the table with direct summation in that sea state:
//! largest errors 1.4e-4 of the largest value for the accelerations, less for η, velocities and
//! pressure (cubic spatial stencils gave 2.5e-3). Values are stored in
//! single precision (relative rounding 6e-8, far below the interpolation error).
//!
//! Only the samples of [0, `end_time_s`] are stored (the FFT gives the whole repeat period; the
//! series is periodic with it).
//! Queries outside the table (x_β outside the node range, σ below the lowest node, t outside
//! the stored samples, or any non-finite coordinate) return [`WavesError::OutsideTable`] with
//! the coordinate, its value and the covered range; callers fall back to direct summation. The
//! range is checked in floating point before an index is formed, so no query can index out of
//! the stored values.
//!
//! Memory: 4 bytes × (5 n_σ + 1) n_x per stored sample, laid out time-major.
//!
//! Units: m, s, Pa; z up, still water at z = 0.

use nalgebra::{Complex, Vector3};

use super::error::{finite, positive, WavesError};
use super::fft::InverseFft;
use super::kinematics::depth_profiles;
use super::realisation::IrregularSea;
use super::sea::FluidKinematics;
use super::series::{time_grid, transform_real_series};

/// Kinematic quantities per node: u_h, w, a_h, a_z, p_d.
const QUANTITIES: usize = 5;

/// Resolution of a [`PlaneKinematicsTable`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TableParams {
    /// Minimum time samples per period of the highest-frequency component.
    pub samples_per_shortest_period: f64,
    /// Node spacing along the propagation direction Δx (m).
    pub spacing_along_m: f64,
    /// Node spacing in the stretched vertical coordinate Δσ (m).
    pub spacing_stretched_m: f64,
}

impl Default for TableParams {
    fn default() -> Self {
        Self {
            samples_per_shortest_period: 16.0,
            spacing_along_m: 2.5,
            spacing_stretched_m: 2.5,
        }
    }
}

/// The region a [`PlaneKinematicsTable`] covers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableRegion {
    /// Range of x_β = x cos β + y sin β (m), lower bound first.
    pub along_m: (f64, f64),
    /// Lowest stretched coordinate σ (m, ≤ 0); the table reaches from it to the surface.
    pub lowest_stretched_m: f64,
    /// Last time to be covered (s); the table starts at t = 0.
    pub end_time_s: f64,
}

/// Elevation and kinematics of an [`IrregularSea`] on an (x_β, σ) grid × time (see the module
/// documentation).
#[derive(Debug, Clone)]
pub struct PlaneKinematicsTable {
    direction: (f64, f64),
    depth_m: f64,
    /// First node x₀ and spacing Δx (m).
    along: (f64, f64),
    /// First node σ₀ and spacing Δσ (m).
    stretched: (f64, f64),
    /// Time step Δt (s).
    time_step_s: f64,
    nx: usize,
    ns: usize,
    /// Stored samples; row r holds t_{r−1} (one sample before t = 0 for the stencil).
    rows: usize,
    /// η per (row, x node).
    elevation: Vec<f32>,
    /// Kinematics per (row, x node, σ node, quantity).
    data: Vec<f32>,
}

/// Points of the time stencil (cubic Lagrange).
const TIME_POINTS: usize = 4;
/// Points of the spatial stencils (quintic Lagrange in x_β and σ: cubic stencils would need
/// about half the spacing, four times the memory, for the same accuracy).
const SPACE_POINTS: usize = 6;

/// Lagrange weights on the `P` (even) nodes −(P/2 − 1) … P/2 at the fraction u ∈ [0, 1).
#[inline]
fn lagrange_weights<const P: usize>(u: f64) -> [f64; P] {
    let offset = (P / 2 - 1) as f64;
    let mut w = [1.0; P];
    for (j, wj) in w.iter_mut().enumerate() {
        let xj = j as f64 - offset;
        for m in 0..P {
            if m != j {
                let xm = m as f64 - offset;
                *wj *= (u - xm) / (xj - xm);
            }
        }
    }
    w
}

/// First node and weights of the `P`-point stencil of `coordinate` = `v` on the nodes
/// v₀ + i h, i < n; a [`WavesError::OutsideTable`] with the covered range when the stencil would
/// leave the nodes or `v` is not finite. The bounds are checked in floating point before any
/// index is formed, so no position, however far or non-finite, can produce an index.
#[inline]
fn stencil<const P: usize>(
    coordinate: &'static str,
    v: f64,
    origin: f64,
    step: f64,
    n: usize,
) -> Result<(usize, [f64; P]), WavesError> {
    let tau = (v - origin) / step;
    let before = (P / 2 - 1) as f64;
    // Stencil nodes i0 − before … i0 − before + P − 1 must lie in 0 … n − 1.
    let last_start = n as f64 - P as f64 + before;
    // Written so that a NaN τ is outside too.
    let inside = tau >= before && tau < last_start + 1.0;
    if !inside {
        return Err(WavesError::OutsideTable {
            coordinate,
            value: v,
            lower: origin + before * step,
            upper: origin + (last_start + 1.0) * step,
        });
    }
    let i0 = tau.floor();
    let first = (i0 - before) as usize;
    Ok((first, lagrange_weights::<P>(tau - i0)))
}

impl PlaneKinematicsTable {
    /// Tabulate `sea` over `region` with resolution `params`.
    pub fn new(
        sea: &IrregularSea,
        region: &TableRegion,
        params: &TableParams,
    ) -> Result<Self, WavesError> {
        let per_period = positive(
            "samples_per_shortest_period",
            params.samples_per_shortest_period,
        )?;
        let dx = positive("spacing_along_m", params.spacing_along_m)?;
        let ds = positive("spacing_stretched_m", params.spacing_stretched_m)?;
        let (x_lo, x_hi) = (
            finite("along_m.0", region.along_m.0)?,
            finite("along_m.1", region.along_m.1)?,
        );
        if x_hi < x_lo {
            return Err(WavesError::InvalidParameter {
                field: "along_m.1",
                value: x_hi,
                rule: ">= along_m.0",
            });
        }
        let lowest = finite("lowest_stretched_m", region.lowest_stretched_m)?;
        if lowest > 0.0 {
            return Err(WavesError::InvalidParameter {
                field: "lowest_stretched_m",
                value: lowest,
                rule: "<= 0",
            });
        }
        let end_time_s = finite("end_time_s", region.end_time_s)?.max(0.0);

        let field = sea.field();
        let depth = field.depth_m();
        let rho = field.water_density_kg_m3();
        let comps = field.components();
        let (bins, samples) = time_grid(sea, per_period);
        let fft = InverseFft::new(samples)?;
        let time_step_s = sea.repeat_period_s() / samples as f64;

        // Nodes beyond each end of the range, so that every point of the range has its full
        // stencil; σ nodes reach above the still water level (the profiles are entire functions,
        // continued analytically there; the stretched height itself never exceeds d).
        let half = SPACE_POINTS / 2;
        let nx = ((x_hi - x_lo) / dx).ceil() as usize + SPACE_POINTS + 1;
        let x0 = x_lo - (half - 1) as f64 * dx;
        let below = (-lowest / ds).ceil() as usize + half - 1;
        let ns = below + half + 1;
        let s0 = -(below as f64) * ds;
        // Rows: t_{−1} … t_{J+2} with J Δt ≥ end time (taken modulo the repeat period).
        let rows = (end_time_s / time_step_s).ceil() as usize + 4;

        let mut elevation = vec![0.0f32; rows * nx];
        let mut data = vec![0.0f32; rows * nx * ns * QUANTITIES];
        let i_unit = Complex::new(0.0, 1.0);
        let profiles: Vec<Vec<(f64, f64)>> = (0..ns)
            .map(|m| {
                let s = depth + s0 + m as f64 * ds;
                comps
                    .iter()
                    .map(|c| depth_profiles(c.wavenumber_rad_m, s, depth))
                    .collect()
            })
            .collect();
        let series_per_x = 1 + ns * QUANTITIES;
        let mut buf = vec![Complex::default(); samples];
        let mut scratch = vec![Complex::default(); fft.scratch_len()];
        // Row r holds sample j = r − 1, periodic.
        let row_samples: Vec<usize> = (0..rows).map(|r| (r + samples - 1) % samples).collect();
        let mut out = vec![0.0; series_per_x * rows];
        let mut coefs: Vec<Vec<Complex<f64>>> = vec![Vec::with_capacity(comps.len()); series_per_x];
        for i in 0..nx {
            let xb = x0 + i as f64 * dx;
            for c in coefs.iter_mut() {
                c.clear();
            }
            for (n, c) in comps.iter().enumerate() {
                // Spatial phase folded into the coefficient: Xₙ = aₙ e^{−i kₙ x_β}.
                let x = c.amplitude_m * Complex::from_polar(1.0, -c.wavenumber_rad_m * xb);
                let om = c.omega_rad_s;
                coefs[0].push(x);
                for (m, prof) in profiles.iter().enumerate() {
                    let (cp, sp) = prof[n];
                    let q = &mut coefs[1 + m * QUANTITIES..1 + (m + 1) * QUANTITIES];
                    q[0].push(om * cp * x);
                    q[1].push(-i_unit * om * sp * x);
                    q[2].push(i_unit * om * om * cp * x);
                    q[3].push(om * om * sp * x);
                    q[4].push(rho * om * om / c.wavenumber_rad_m * cp * x);
                }
            }
            transform_real_series(
                &fft,
                &bins,
                &coefs,
                &row_samples,
                (&mut buf, &mut scratch),
                &mut out,
            );
            for r in 0..rows {
                elevation[r * nx + i] = out[r] as f32;
                let base = (r * nx + i) * ns * QUANTITIES;
                for (k, v) in data[base..base + ns * QUANTITIES].iter_mut().enumerate() {
                    *v = out[(1 + k) * rows + r] as f32;
                }
            }
        }
        Ok(Self {
            direction: field.direction(),
            depth_m: depth,
            along: (x0, dx),
            stretched: (s0, ds),
            time_step_s,
            nx,
            ns,
            rows,
            elevation,
            data,
        })
    }

    /// Time step Δt of the table (s).
    pub fn time_step_s(&self) -> f64 {
        self.time_step_s
    }

    /// Nodes along x_β and in σ.
    pub fn nodes(&self) -> (usize, usize) {
        (self.nx, self.ns)
    }

    /// Memory held by the stored values (bytes).
    pub fn memory_bytes(&self) -> usize {
        (self.elevation.len() + self.data.len()) * std::mem::size_of::<f32>()
    }

    /// Row index of the first stencil sample and the time weights.
    #[inline]
    fn time_stencil(&self, t: f64) -> Result<(usize, [f64; TIME_POINTS]), WavesError> {
        // Row r is sample r − 1: the origin is one step before t = 0.
        stencil::<TIME_POINTS>("time_s", t, -self.time_step_s, self.time_step_s, self.rows)
    }

    /// The x_β stencil of the horizontal position (x, y).
    #[inline]
    fn along_stencil(&self, x: f64, y: f64) -> Result<(usize, [f64; SPACE_POINTS]), WavesError> {
        let xb = x * self.direction.0 + y * self.direction.1;
        stencil::<SPACE_POINTS>("x_beta_m", xb, self.along.0, self.along.1, self.nx)
    }

    /// η at the x_β stencil `xs` from `value(i)`, the elevation at node i.
    #[inline(always)]
    fn elevation_from((i0, wx): (usize, [f64; SPACE_POINTS]), value: impl Fn(usize) -> f64) -> f64 {
        wx.iter()
            .enumerate()
            .map(|(b, wb)| wb * value(i0 + b))
            .sum()
    }

    /// Kinematics at `p` with the x_β stencil `xs` and surface elevation `eta`, from
    /// `value(k)`, the k-th stored value of one time sample (layout x node, σ node, quantity):
    /// zero above the surface, an error below the lowest σ node.
    #[inline(always)]
    fn kinematics_from(
        &self,
        p: &Vector3<f64>,
        (i0, wx): (usize, [f64; SPACE_POINTS]),
        eta: f64,
        value: impl Fn(usize) -> f64,
    ) -> Result<FluidKinematics, WavesError> {
        let d = self.depth_m;
        if p.z > eta || d + eta <= 0.0 {
            return Ok(FluidKinematics::default());
        }
        let sigma = (p.z + d) * d / (d + eta) - d;
        let (m0, ws) = stencil::<SPACE_POINTS>(
            "stretched_height_m",
            sigma,
            self.stretched.0,
            self.stretched.1,
            self.ns,
        )?;
        let mut v = [0.0f64; QUANTITIES];
        for (b, wb) in wx.iter().enumerate() {
            let base = ((i0 + b) * self.ns + m0) * QUANTITIES;
            for (c, wc) in ws.iter().enumerate() {
                let w = wb * wc;
                let at = base + c * QUANTITIES;
                for (q, acc) in v.iter_mut().enumerate() {
                    *acc += w * value(at + q);
                }
            }
        }
        let (cx, cy) = self.direction;
        Ok(FluidKinematics {
            velocity: Vector3::new(v[0] * cx, v[0] * cy, v[1]),
            acceleration: Vector3::new(v[2] * cx, v[2] * cy, v[3]),
            dynamic_pressure_pa: v[4],
        })
    }

    /// Values of one time sample (elevations or kinematics) of `data` with `len` values per
    /// sample, interpolated in time with the stencil `(r0, wt)`.
    #[inline(always)]
    fn in_time(
        data: &[f32],
        len: usize,
        (r0, wt): (usize, [f64; TIME_POINTS]),
    ) -> impl Fn(usize) -> f64 + '_ {
        move |k| {
            wt.iter()
                .enumerate()
                .map(|(a, wa)| wa * data[(r0 + a) * len + k] as f64)
                .sum()
        }
    }

    /// Surface elevation η (m) at (x, y), time t, or [`WavesError::OutsideTable`].
    pub fn elevation(&self, x: f64, y: f64, t: f64) -> Result<f64, WavesError> {
        let ts = self.time_stencil(t)?;
        let xs = self.along_stencil(x, y)?;
        Ok(Self::elevation_from(
            xs,
            Self::in_time(&self.elevation, self.nx, ts),
        ))
    }

    /// Kinematics at `p` (m) and time `t` (s), zero above the interpolated surface, or
    /// [`WavesError::OutsideTable`].
    pub fn kinematics(&self, p: &Vector3<f64>, t: f64) -> Result<FluidKinematics, WavesError> {
        let ts = self.time_stencil(t)?;
        let xs = self.along_stencil(p.x, p.y)?;
        let eta = Self::elevation_from(xs, Self::in_time(&self.elevation, self.nx, ts));
        let plane = self.nx * self.ns * QUANTITIES;
        self.kinematics_from(p, xs, eta, Self::in_time(&self.data, plane, ts))
    }

    /// Interpolates the whole table in time at `t` into `slice` (4 multiply-adds per stored
    /// value of one sample); `false`, with `slice` emptied, when `t` is outside the table.
    ///
    /// Every floater evaluation of a coupled step samples the sea at the same instant, at some
    /// hundred strip centres: a query on the slice interpolates in space only (36 values per
    /// quantity instead of 144), and the slice costs about as much as 40 direct queries.
    pub(crate) fn fill_slice(&self, t: f64, slice: &mut TimeSlice) -> bool {
        slice.time_s = None;
        let Ok(ts) = self.time_stencil(t) else {
            return false;
        };
        let plane = self.nx * self.ns * QUANTITIES;
        for (out, src, len) in [
            (&mut slice.elevation, &self.elevation, self.nx),
            (&mut slice.data, &self.data, plane),
        ] {
            out.clear();
            out.resize(len, 0.0);
            let (r0, wt) = ts;
            for (a, wa) in wt.iter().enumerate() {
                let row = &src[(r0 + a) * len..(r0 + a + 1) * len];
                for (o, &x) in out.iter_mut().zip(row) {
                    *o += wa * x as f64;
                }
            }
        }
        slice.time_s = Some(t);
        true
    }

    /// As [`PlaneKinematicsTable::kinematics`] at the time of `slice` (filled by
    /// [`PlaneKinematicsTable::fill_slice`] of this table); [`WavesError::OutsideTable`] outside
    /// the table or for an empty slice (reported as a time outside it).
    pub(crate) fn slice_kinematics(
        &self,
        slice: &TimeSlice,
        p: &Vector3<f64>,
    ) -> Result<FluidKinematics, WavesError> {
        self.slice_time(slice)?;
        let xs = self.along_stencil(p.x, p.y)?;
        let eta = Self::elevation_from(xs, |i| slice.elevation[i]);
        self.kinematics_from(p, xs, eta, |k| slice.data[k])
    }

    /// As [`PlaneKinematicsTable::elevation`] at the time of `slice`.
    pub(crate) fn slice_elevation(
        &self,
        slice: &TimeSlice,
        x: f64,
        y: f64,
    ) -> Result<f64, WavesError> {
        self.slice_time(slice)?;
        let xs = self.along_stencil(x, y)?;
        Ok(Self::elevation_from(xs, |i| slice.elevation[i]))
    }

    /// The instant of a filled slice of this table, or [`WavesError::OutsideTable`] for an
    /// empty one (or one whose values do not have this table's layout).
    fn slice_time(&self, slice: &TimeSlice) -> Result<f64, WavesError> {
        let layout =
            slice.elevation.len() == self.nx && slice.data.len() == self.nx * self.ns * QUANTITIES;
        match slice.time_s {
            Some(t) if layout => Ok(t),
            _ => Err(WavesError::OutsideTable {
                coordinate: "time_s",
                value: slice.time_s.unwrap_or(f64::NAN),
                lower: 0.0,
                upper: (self.rows as f64 - 3.0) * self.time_step_s,
            }),
        }
    }
}

/// A [`PlaneKinematicsTable`] interpolated in time at one instant
/// (`PlaneKinematicsTable::fill_slice`), in f64.
#[derive(Debug, Clone, Default)]
pub struct TimeSlice {
    time_s: Option<f64>,
    elevation: Vec<f64>,
    data: Vec<f64>,
}

impl TimeSlice {
    /// The instant the slice holds, if filled.
    pub fn time_s(&self) -> Option<f64> {
        self.time_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::realisation::RealisationParams;
    use crate::waves::sea::SeaKinematics;
    use crate::waves::spectrum::{Jonswap, PeakEnhancement};

    /// The paper's severe sea state (Hs 8.75 m, Tp 16.5 s, γ 1.3) in 100 m of water, realised for
    /// 300 s, propagating at 30° so that both x and y matter.
    fn severe_sea() -> IrregularSea {
        let s = Jonswap::new(8.75, 16.5, PeakEnhancement::Given(1.3)).unwrap();
        let p = RealisationParams {
            duration_s: 300.0,
            seed: 3,
            depth_m: 100.0,
            heading_rad: 30f64.to_radians(),
            ..Default::default()
        };
        IrregularSea::new(&s, &p).unwrap()
    }

    fn region() -> TableRegion {
        TableRegion {
            along_m: (-40.0, 60.0),
            lowest_stretched_m: -40.0,
            end_time_s: 300.0,
        }
    }

    #[test]
    fn table_matches_direct_summation_in_the_floater_region() {
        let sea = severe_sea();
        let table = PlaneKinematicsTable::new(&sea, &region(), &TableParams::default()).unwrap();
        // Points scattered over the region (off the nodes), from the surface zone down to
        // −30 m, at times off the grid.
        let mut max_err = [0.0f64; 6];
        let mut max_val = [0.0f64; 6];
        let mut wet_flips = 0;
        let mut checked = 0;
        for i in 0..4000 {
            let f = i as f64;
            let x = -35.0 + (f * 7.31) % 90.0;
            let y = (f * 3.7) % 20.0 - 10.0;
            let z = 8.0 - (f * 1.913) % 38.0;
            let t = 0.5 + (f * 0.0731) % 299.0;
            let p = Vector3::new(x, y, z);
            let direct = sea.kinematics(&p, t);
            let eta = sea.elevation(x, y, t);
            let tab = table.kinematics(&p, t).unwrap();
            let tab_eta = table.elevation(x, y, t).unwrap();
            max_err[0] = max_err[0].max((tab_eta - eta).abs());
            max_val[0] = max_val[0].max(eta.abs());
            let dry_direct = direct == FluidKinematics::default();
            let dry_table = tab == FluidKinematics::default();
            if dry_direct != dry_table {
                // Only within the elevation error of the surface.
                assert!(
                    (z - eta).abs() < 1e-2,
                    "wet/dry differ away from the surface"
                );
                wet_flips += 1;
                continue;
            }
            checked += 1;
            let pairs = [
                (tab.velocity.x, direct.velocity.x),
                (tab.velocity.z, direct.velocity.z),
                (tab.acceleration.y, direct.acceleration.y),
                (tab.acceleration.z, direct.acceleration.z),
                (tab.dynamic_pressure_pa, direct.dynamic_pressure_pa),
            ];
            for (q, (a, b)) in pairs.iter().enumerate() {
                max_err[q + 1] = max_err[q + 1].max((a - b).abs());
                max_val[q + 1] = max_val[q + 1].max(b.abs());
            }
        }
        assert!(checked > 2500, "{checked} wet points compared");
        assert!(wet_flips < 10);
        // Elevation and kinematics within 5e-4 of their largest value (measured: 2.6e-5 for η,
        // 5e-5 for the velocities, 1.4e-4 for the accelerations, 2e-5 for the pressure).
        for q in 0..6 {
            assert!(
                max_err[q] <= 5e-4 * max_val[q],
                "quantity {q}: error {} vs largest {}",
                max_err[q],
                max_val[q]
            );
        }
    }

    /// Largest error of the table's horizontal and vertical accelerations against direct
    /// summation, relative to the largest value, at points from 0.5 m to 20 m below the still
    /// water level in the floater region.
    fn acceleration_error(sea: &IrregularSea) -> f64 {
        let region = TableRegion {
            along_m: (-40.0, 60.0),
            lowest_stretched_m: -40.0,
            end_time_s: 100.0,
        };
        let table = PlaneKinematicsTable::new(sea, &region, &TableParams::default()).unwrap();
        let (mut err, mut max) = (0.0f64, 0.0f64);
        for i in 0..1500 {
            let f = i as f64;
            let p = Vector3::new(-35.0 + (f * 7.31) % 90.0, 0.0, -0.5 - (f * 1.913) % 19.5);
            let t = 0.5 + (f * 0.0731) % 99.0;
            let direct = sea.kinematics(&p, t);
            let tab = table.kinematics(&p, t).unwrap();
            if (direct == FluidKinematics::default()) != (tab == FluidKinematics::default()) {
                continue;
            }
            err = err.max((tab.acceleration - direct.acceleration).amax());
            max = max.max(direct.acceleration.amax());
        }
        err / max
    }

    /// The cause of the short-period failures of the global stage: in a Tp = 5 s sea the
    /// shortest components (k = 3.4 rad/m, k Δ = 8.5) are far beyond what the 2.5 m table
    /// interpolates, and its accelerations near the surface are wrong by more than their own
    /// size; cut off at k Δ = 1 (1.98 rad/s) the same table matches direct summation.
    #[test]
    fn a_short_period_sea_is_tabulated_only_up_to_k_spacing_one() {
        let realise = |cut: Option<f64>| {
            let s = Jonswap::new(1.75, 5.0, PeakEnhancement::Given(1.3)).unwrap();
            let p = RealisationParams {
                duration_s: 100.0,
                seed: 1,
                cut_off_rad_s: cut,
                ..Default::default()
            };
            IrregularSea::new(&s, &p).unwrap()
        };
        let uncut = acceleration_error(&realise(None));
        let cut = acceleration_error(&realise(Some((9.81f64 * 0.4).sqrt())));
        println!("table acceleration error / largest: uncut {uncut:e}, cut {cut:e}");
        assert!(uncut > 1.0, "uncut {uncut:e}");
        assert!(cut < 5e-3, "cut {cut:e}");
    }

    #[test]
    fn queries_outside_the_table_are_refused() {
        let sea = severe_sea();
        let table = PlaneKinematicsTable::new(&sea, &region(), &TableParams::default()).unwrap();
        let c = 30f64.to_radians().cos();
        // Along the heading: inside at x_β = 50 m, outside at 80 m and −60 m.
        assert!(table.elevation(50.0 * c, 50.0 * 0.5, 10.0).is_ok());
        assert!(table.elevation(80.0 * c, 80.0 * 0.5, 10.0).is_err());
        assert!(table.elevation(-60.0 * c, -60.0 * 0.5, 10.0).is_err());
        // Time beyond the stored samples, and far below the lowest σ node.
        assert!(table.elevation(0.0, 0.0, 320.0).is_err());
        assert!(table
            .kinematics(&Vector3::new(0.0, 0.0, -90.0), 10.0)
            .is_err());
        // Dry points are answered (zero), even above the table's top node.
        assert_eq!(
            table.kinematics(&Vector3::new(0.0, 0.0, 40.0), 10.0),
            Ok(FluidKinematics::default())
        );
        assert!(table.memory_bytes() > 0);
    }

    #[test]
    fn far_or_non_finite_positions_are_bounds_errors_with_the_range() {
        let sea = severe_sea();
        let table = PlaneKinematicsTable::new(&sea, &region(), &TableParams::default()).unwrap();
        // Positions whose node index would not fit in an integer, infinite or NaN: each is an
        // error naming the coordinate, its value and the covered range, never an index.
        for x in [1e300, -1e300, f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            let e = table.elevation(x, 0.0, 10.0).unwrap_err();
            let WavesError::OutsideTable {
                coordinate,
                lower,
                upper,
                ..
            } = e
            else {
                panic!("{e}");
            };
            assert_eq!(coordinate, "x_beta_m");
            // The covered range contains the requested region.
            assert!(lower <= -40.0 && upper >= 60.0, "[{lower}, {upper}]");
            assert!(table.kinematics(&Vector3::new(x, 0.0, -5.0), 10.0).is_err());
        }
        for t in [f64::NAN, f64::INFINITY, -1e300, 1e300] {
            let e = table.elevation(0.0, 0.0, t).unwrap_err();
            assert!(e.to_string().starts_with("time_s = "), "{e}");
        }
        let e = table
            .kinematics(&Vector3::new(0.0, 0.0, f64::NEG_INFINITY), 10.0)
            .unwrap_err();
        assert!(e.to_string().starts_with("stretched_height_m = "), "{e}");
        // A slice filled by another (smaller) table is refused rather than indexed.
        let small = PlaneKinematicsTable::new(
            &sea,
            &TableRegion {
                along_m: (0.0, 5.0),
                lowest_stretched_m: -5.0,
                end_time_s: 20.0,
            },
            &TableParams::default(),
        )
        .unwrap();
        let mut slice = TimeSlice::default();
        assert!(small.fill_slice(3.0, &mut slice));
        assert!(table
            .slice_kinematics(&slice, &Vector3::new(0.0, 0.0, -5.0))
            .is_err());
        assert!(table.slice_elevation(&slice, 0.0, 0.0).is_err());
    }

    #[test]
    fn a_time_slice_answers_as_the_table_does() {
        let sea = severe_sea();
        let table = PlaneKinematicsTable::new(&sea, &region(), &TableParams::default()).unwrap();
        let mut slice = TimeSlice::default();
        let mut compared = 0;
        for (n, t) in [3.3, 127.05, 250.0].into_iter().enumerate() {
            assert!(table.fill_slice(t, &mut slice));
            assert_eq!(slice.time_s(), Some(t));
            for i in 0..200 {
                let f = (i + 1000 * n) as f64;
                let p = Vector3::new(
                    -35.0 + (f * 7.31) % 90.0,
                    (f * 3.7) % 20.0 - 10.0,
                    8.0 - (f * 1.913) % 38.0,
                );
                let (a, b) = (
                    table.kinematics(&p, t).unwrap(),
                    table.slice_kinematics(&slice, &p).unwrap(),
                );
                let scale = a.acceleration.norm() + a.velocity.norm() + 1.0;
                // The same weights summed in another order: round-off only.
                assert!((a.velocity - b.velocity).norm() <= 1e-12 * scale);
                assert!((a.acceleration - b.acceleration).norm() <= 1e-12 * scale);
                assert!(
                    (a.dynamic_pressure_pa - b.dynamic_pressure_pa).abs()
                        <= 1e-9 * (1.0 + a.dynamic_pressure_pa.abs())
                );
                let (ea, eb) = (
                    table.elevation(p.x, p.y, t).unwrap(),
                    table.slice_elevation(&slice, p.x, p.y).unwrap(),
                );
                assert!((ea - eb).abs() <= 1e-12 * (1.0 + ea.abs()));
                compared += usize::from(a != FluidKinematics::default());
            }
        }
        assert!(compared > 300, "{compared} wet points compared");
        // Outside the stored samples the slice is refused and emptied.
        assert!(!table.fill_slice(320.0, &mut slice));
        assert_eq!(slice.time_s(), None);
        assert!(table
            .slice_kinematics(&slice, &Vector3::new(0.0, 0.0, -5.0))
            .is_err());
    }
}
