//! Kinematics precomputed at a fixed set of points on a uniform time grid, for time-domain
//! simulations that sample the same points at every step.
//!
//! Grid: N = 2^p samples over one repeat period T of an [`IrregularSea`], Δt = T/N, N the
//! smallest power of two giving at least `samples_per_shortest_period` samples per period of the
//! highest component. Because every ωₙ = nΔω = 2πn/T, a component sum at t_j = jΔt is an inverse
//! DFT: Σ Re(Xₙ e^{2πi nj/N}); two real series are obtained from one complex FFT by placing
//! (Xₙ + iYₙ)/2 in bin n and (X̄ₙ + iȲₙ)/2 in bin N − n.
//!
//! Wheeler stretching makes the depth profiles depend on η(t) (see [`super::kinematics`]), which
//! a single FFT cannot express. At each point the elevation η(t_j) is computed first; the
//! stretched height s(t_j) = (z + d) d/(d + η) then stays in a known interval [s_lo, s_hi]
//! over the wet samples. The profiles e^{±k s} are entire functions of s, so each kinematic
//! series is interpolated exactly (to a bound) in s by a Chebyshev interpolant: the component
//! sums are evaluated by FFT with the profiles frozen at M Chebyshev nodes sₘ of that interval,
//! and combined at every sample by the barycentric formula at s(t_j). M is the smallest count for
//! which the interpolation bound (k_max h)^M / (2^{M−1} M!) · e^{2 k_max h} (h the interval
//! half-width, k_max the largest wavenumber) is below `chebyshev_tolerance`, so the grid values
//! equal direct summation to that relative accuracy.
//!
//! Between samples, values are interpolated by 4-point (cubic) Lagrange interpolation in time,
//! periodic over T; with s samples per shortest period the error is at most about
//! 0.023 (2π/s)⁴ of the highest component's amplitude (3e-4 for s = 16). Near the surface a point
//! switches between wet and dry; the interpolation then blends the two states over one Δt.
//!
//! Memory: 6 values × 8 bytes per point and sample (elevation, u_h, w, a_h, a_z, p), laid out
//! time-major so that sampling all points at one instant reads contiguous memory.

use nalgebra::{Complex, Vector3};

use super::error::{positive, WavesError};
use super::fft::InverseFft;
use super::kinematics::{depth_profiles, stretched_height};
use super::realisation::IrregularSea;
use super::sea::FluidKinematics;

/// Number of stored quantities per point and sample: η, u_h, w, a_h, a_z, p.
const QUANTITIES: usize = 6;

/// Parameters of the precomputation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SeriesParams {
    /// Minimum samples per period of the highest-frequency component.
    pub samples_per_shortest_period: f64,
    /// Required bound of the Chebyshev interpolation error in the stretched coordinate (relative).
    pub chebyshev_tolerance: f64,
    /// Largest number of Chebyshev nodes allowed per point.
    pub max_chebyshev_nodes: usize,
}

impl Default for SeriesParams {
    fn default() -> Self {
        Self {
            samples_per_shortest_period: 16.0,
            chebyshev_tolerance: 1e-12,
            max_chebyshev_nodes: 48,
        }
    }
}

/// Work counts and accuracy figures of a precomputation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SeriesStats {
    /// Complex FFTs of size N performed.
    pub ffts: usize,
    /// Largest Chebyshev node count used at a point.
    pub max_chebyshev_nodes: usize,
    /// Largest Chebyshev interpolation bound reached (above the tolerance only when a point hit
    /// `max_chebyshev_nodes`).
    pub max_error_bound: f64,
}

/// Surface elevation and kinematics at one point and instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointSample {
    /// Surface elevation above still water at the point's (x, y) (m).
    pub elevation_m: f64,
    /// Water kinematics at the point (zero when dry).
    pub kinematics: FluidKinematics,
}

/// Elevation and kinematics of an [`IrregularSea`] at fixed points on a uniform periodic time
/// grid.
#[derive(Debug, Clone)]
pub struct PointKinematicsSeries {
    points: Vec<Vector3<f64>>,
    samples: usize,
    time_step_s: f64,
    period_s: f64,
    direction: (f64, f64),
    data: Vec<f64>,
    stats: SeriesStats,
}

/// Scratch space of the precomputation, reusable between points.
struct Workspace {
    buf: Vec<Complex<f64>>,
    eta: Vec<f64>,
    /// Per Chebyshev node and quantity (u_h, w, a_h, a_z, p): a series of N samples.
    node_series: Vec<f64>,
}

impl PointKinematicsSeries {
    /// Precompute η and the kinematics of `sea` at `points` (m, global frame).
    pub fn new(
        sea: &IrregularSea,
        points: &[Vector3<f64>],
        params: &SeriesParams,
    ) -> Result<Self, WavesError> {
        let per_period = positive(
            "samples_per_shortest_period",
            params.samples_per_shortest_period,
        )?;
        positive("chebyshev_tolerance", params.chebyshev_tolerance)?;
        if params.max_chebyshev_nodes == 0 {
            return Err(WavesError::InvalidParameter {
                field: "max_chebyshev_nodes",
                value: 0.0,
                rule: ">= 1",
            });
        }
        for p in points {
            for (field, v) in [("point.x", p.x), ("point.y", p.y), ("point.z", p.z)] {
                super::error::finite(field, v)?;
            }
        }
        let field = sea.field();
        let period_s = sea.repeat_period_s();
        let d_omega = sea.d_omega_rad_s();
        let comps = field.components();
        let bins: Vec<usize> = comps
            .iter()
            .map(|c| (c.omega_rad_s / d_omega).round() as usize)
            .collect();
        let n_max = bins.iter().copied().max().unwrap_or(1);
        // Enough samples per shortest period, and N > 2 n_max so that bins n and N − n differ.
        let needed = ((n_max as f64) * per_period)
            .ceil()
            .max(2.0 * n_max as f64 + 1.0) as usize;
        let samples = needed.next_power_of_two();
        let fft = InverseFft::new(samples)?;
        let time_step_s = period_s / samples as f64;

        let mut series = Self {
            points: points.to_vec(),
            samples,
            time_step_s,
            period_s,
            direction: field.direction(),
            data: vec![0.0; samples * points.len() * QUANTITIES],
            stats: SeriesStats::default(),
        };
        let mut ws = Workspace {
            buf: vec![Complex::default(); samples],
            eta: vec![0.0; samples],
            node_series: Vec::new(),
        };
        for (index, p) in points.iter().enumerate() {
            series.fill_point(sea, &fft, &bins, index, p, params, &mut ws);
        }
        Ok(series)
    }

    /// Inverse-transform two real component sums given by their complex coefficients per
    /// component; writes them into `out_a` and `out_b`.
    fn transform_pair(
        fft: &InverseFft,
        bins: &[usize],
        coef_a: impl Fn(usize) -> Complex<f64>,
        coef_b: impl Fn(usize) -> Complex<f64>,
        ws_buf: &mut [Complex<f64>],
        out_a: &mut [f64],
        out_b: &mut [f64],
    ) {
        let n = ws_buf.len();
        ws_buf.fill(Complex::default());
        let i = Complex::new(0.0, 1.0);
        for (c, &bin) in bins.iter().enumerate() {
            let (a, b) = (coef_a(c), coef_b(c));
            ws_buf[bin] += 0.5 * (a + i * b);
            ws_buf[n - bin] += 0.5 * (a.conj() + i * b.conj());
        }
        fft.inverse_in_place(ws_buf);
        for (j, z) in ws_buf.iter().enumerate() {
            out_a[j] = z.re;
            out_b[j] = z.im;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn fill_point(
        &mut self,
        sea: &IrregularSea,
        fft: &InverseFft,
        bins: &[usize],
        index: usize,
        p: &Vector3<f64>,
        params: &SeriesParams,
        ws: &mut Workspace,
    ) {
        let field = sea.field();
        let comps = field.components();
        let depth = field.depth_m();
        let rho = field.water_density_kg_m3();
        let n = self.samples;
        let xb = field.along(p.x, p.y);
        // Spatial phase folded into the coefficients: Xₙ = aₙ e^{−i kₙ x_β}.
        let x: Vec<Complex<f64>> = comps
            .iter()
            .map(|c| c.amplitude_m * Complex::from_polar(1.0, -c.wavenumber_rad_m * xb))
            .collect();

        // Elevation (paired with nothing: the second slot carries zeros).
        let mut scratch = vec![0.0; n];
        Self::transform_pair(
            fft,
            bins,
            |c| x[c],
            |_| Complex::default(),
            &mut ws.buf,
            &mut ws.eta,
            &mut scratch,
        );
        self.stats.ffts += 1;
        let stride = self.points.len() * QUANTITIES;
        for j in 0..n {
            self.data[j * stride + index * QUANTITIES] = ws.eta[j];
        }

        // Range of the stretched height over the wet samples.
        let (mut s_lo, mut s_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &eta in &ws.eta {
            if let Some(s) = stretched_height(p.z, eta, depth) {
                s_lo = s_lo.min(s);
                s_hi = s_hi.max(s);
            }
        }
        if s_lo > s_hi {
            return; // never wet: kinematics stay zero
        }
        let centre = 0.5 * (s_lo + s_hi);
        let half = 0.5 * (s_hi - s_lo);
        let k_max = comps.iter().map(|c| c.wavenumber_rad_m).fold(0.0, f64::max);
        let kh = k_max * half;
        let mut m = 1;
        let mut bound = chebyshev_bound(kh, m);
        while bound > params.chebyshev_tolerance && m < params.max_chebyshev_nodes {
            m += 1;
            bound = chebyshev_bound(kh, m);
        }
        self.stats.max_chebyshev_nodes = self.stats.max_chebyshev_nodes.max(m);
        self.stats.max_error_bound = self.stats.max_error_bound.max(bound);

        let nodes: Vec<f64> = (0..m)
            .map(|i| {
                centre + half * ((2 * i + 1) as f64 * std::f64::consts::PI / (2 * m) as f64).cos()
            })
            .collect();
        let weights: Vec<f64> = (0..m)
            .map(|i| {
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                sign * ((2 * i + 1) as f64 * std::f64::consts::PI / (2 * m) as f64).sin()
            })
            .collect();

        // Series per node: u_h, w, a_h, a_z, p, in that order.
        ws.node_series.resize(m * 5 * n, 0.0);
        let i_unit = Complex::new(0.0, 1.0);
        for (node, &s) in nodes.iter().enumerate() {
            let prof: Vec<(f64, f64)> = comps
                .iter()
                .map(|c| depth_profiles(c.wavenumber_rad_m, s, depth))
                .collect();
            let om = |c: usize| comps[c].omega_rad_s;
            let base = node * 5 * n;
            let (uh, rest) = ws.node_series[base..base + 5 * n].split_at_mut(n);
            let (w, rest) = rest.split_at_mut(n);
            let (ah, rest) = rest.split_at_mut(n);
            let (az, pd) = rest.split_at_mut(n);
            Self::transform_pair(
                fft,
                bins,
                |c| om(c) * prof[c].0 * x[c],
                |c| -i_unit * om(c) * prof[c].1 * x[c],
                &mut ws.buf,
                uh,
                w,
            );
            Self::transform_pair(
                fft,
                bins,
                |c| i_unit * om(c) * om(c) * prof[c].0 * x[c],
                |c| om(c) * om(c) * prof[c].1 * x[c],
                &mut ws.buf,
                ah,
                az,
            );
            Self::transform_pair(
                fft,
                bins,
                |c| rho * om(c) * om(c) / comps[c].wavenumber_rad_m * prof[c].0 * x[c],
                |_| Complex::default(),
                &mut ws.buf,
                pd,
                &mut scratch,
            );
            self.stats.ffts += 3;
        }

        // Barycentric combination at the stretched height of every wet sample.
        let mut lagrange = vec![0.0; m];
        for j in 0..n {
            let Some(s) = stretched_height(p.z, ws.eta[j], depth) else {
                continue;
            };
            barycentric_weights(&nodes, &weights, s, &mut lagrange);
            let out = j * stride + index * QUANTITIES;
            for q in 0..5 {
                let mut v = 0.0;
                for (node, &l) in lagrange.iter().enumerate() {
                    v += l * ws.node_series[(node * 5 + q) * n + j];
                }
                self.data[out + 1 + q] = v;
            }
        }
    }

    /// The points, in the order given.
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }
    /// Number of samples N per repeat period.
    pub fn samples(&self) -> usize {
        self.samples
    }
    /// Grid step Δt = T/N (s).
    pub fn time_step_s(&self) -> f64 {
        self.time_step_s
    }
    /// Repeat period T (s); the series is periodic with it.
    pub fn period_s(&self) -> f64 {
        self.period_s
    }
    /// Work counts and accuracy figures.
    pub fn stats(&self) -> SeriesStats {
        self.stats
    }

    fn sample_from(&self, point: usize, weights: &[(usize, f64)]) -> PointSample {
        let stride = self.points.len() * QUANTITIES;
        let mut v = [0.0; QUANTITIES];
        for &(j, wgt) in weights {
            let row =
                &self.data[j * stride + point * QUANTITIES..j * stride + (point + 1) * QUANTITIES];
            for q in 0..QUANTITIES {
                v[q] += wgt * row[q];
            }
        }
        let (cx, cy) = self.direction;
        PointSample {
            elevation_m: v[0],
            kinematics: FluidKinematics {
                velocity: Vector3::new(v[1] * cx, v[1] * cy, v[2]),
                acceleration: Vector3::new(v[3] * cx, v[3] * cy, v[4]),
                dynamic_pressure_pa: v[5],
            },
        }
    }

    /// Exact grid value at point index `point` and sample `j` (taken modulo N).
    /// Panics if `point` is out of range.
    pub fn at_sample(&self, point: usize, j: usize) -> PointSample {
        self.sample_from(point, &[(j % self.samples, 1.0)])
    }

    /// Cubic Lagrange interpolation weights for time t: four (sample, weight) pairs.
    fn time_weights(&self, t: f64) -> [(usize, f64); 4] {
        let tau = (t / self.time_step_s).rem_euclid(self.samples as f64);
        let j0 = (tau.floor() as usize).min(self.samples - 1);
        let u = tau - j0 as f64;
        let n = self.samples;
        let w_m1 = -u * (u - 1.0) * (u - 2.0) / 6.0;
        let w_0 = (u + 1.0) * (u - 1.0) * (u - 2.0) / 2.0;
        let w_1 = -(u + 1.0) * u * (u - 2.0) / 2.0;
        let w_2 = (u + 1.0) * u * (u - 1.0) / 6.0;
        [
            ((j0 + n - 1) % n, w_m1),
            (j0, w_0),
            ((j0 + 1) % n, w_1),
            ((j0 + 2) % n, w_2),
        ]
    }

    /// Elevation and kinematics at point index `point` and any time `t` (s), by cubic
    /// interpolation on the periodic grid. Panics if `point` is out of range.
    pub fn sample(&self, point: usize, t: f64) -> PointSample {
        self.sample_from(point, &self.time_weights(t))
    }

    /// All points at time `t` into `out` (length must equal the number of points; extra entries
    /// are left untouched, missing ones skipped).
    pub fn sample_all(&self, t: f64, out: &mut [PointSample]) {
        let w = self.time_weights(t);
        for (point, o) in out.iter_mut().enumerate().take(self.points.len()) {
            *o = self.sample_from(point, &w);
        }
    }
}

/// Bound of the Chebyshev interpolation error of e^{k s} with `m` nodes on an interval of
/// half-width h, relative to the function's size, for kh = `kh`:
/// (kh)^m / (2^{m−1} m!) · e^{2kh}.
fn chebyshev_bound(kh: f64, m: usize) -> f64 {
    let mut b = 2.0 * (2.0 * kh).exp();
    for i in 1..=m {
        b *= kh / (2.0 * i as f64);
    }
    b
}

/// Lagrange basis values at x for Chebyshev nodes, by the barycentric formula.
fn barycentric_weights(nodes: &[f64], weights: &[f64], x: f64, out: &mut [f64]) {
    for (i, &s) in nodes.iter().enumerate() {
        if x == s {
            out.fill(0.0);
            out[i] = 1.0;
            return;
        }
    }
    let mut total = 0.0;
    for ((o, &s), &w) in out.iter_mut().zip(nodes).zip(weights) {
        *o = w / (x - s);
        total += *o;
    }
    for o in out.iter_mut() {
        *o /= total;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::realisation::RealisationParams;
    use crate::waves::sea::SeaKinematics;
    use crate::waves::spectrum::{Jonswap, PeakEnhancement};

    fn small_sea() -> IrregularSea {
        let s = Jonswap::new(6.0, 12.0, PeakEnhancement::Given(2.0)).unwrap();
        let p = RealisationParams {
            duration_s: 128.0,
            seed: 5,
            depth_m: 60.0,
            ..Default::default()
        };
        IrregularSea::new(&s, &p).unwrap()
    }

    #[test]
    fn grid_values_equal_direct_summation() {
        let sea = small_sea();
        let points = [
            Vector3::new(0.0, 0.0, -50.0),
            Vector3::new(25.0, 3.0, -8.0),
            Vector3::new(-10.0, 0.0, -1.0),
        ];
        let series = PointKinematicsSeries::new(&sea, &points, &SeriesParams::default()).unwrap();
        let mut max_err = [0.0f64; 6];
        let mut max_val = [0.0f64; 6];
        for (i, p) in points.iter().enumerate() {
            for j in (0..series.samples()).step_by(7) {
                let t = j as f64 * series.time_step_s();
                let got = series.at_sample(i, j);
                let k = sea.kinematics(p, t);
                let pairs = [
                    (got.elevation_m, sea.elevation(p.x, p.y, t)),
                    (got.kinematics.velocity.x, k.velocity.x),
                    (got.kinematics.velocity.z, k.velocity.z),
                    (got.kinematics.acceleration.x, k.acceleration.x),
                    (got.kinematics.acceleration.z, k.acceleration.z),
                    (got.kinematics.dynamic_pressure_pa, k.dynamic_pressure_pa),
                ];
                for (q, (a, b)) in pairs.iter().enumerate() {
                    max_err[q] = max_err[q].max((a - b).abs());
                    max_val[q] = max_val[q].max(b.abs());
                }
            }
        }
        for q in 0..6 {
            assert!(
                max_err[q] <= 1e-9 * max_val[q],
                "quantity {q}: {} vs {}",
                max_err[q],
                max_val[q]
            );
        }
    }

    #[test]
    fn interpolation_between_samples_is_accurate_below_the_surface() {
        let sea = small_sea();
        let p = Vector3::new(5.0, 0.0, -20.0);
        let series = PointKinematicsSeries::new(&sea, &[p], &SeriesParams::default()).unwrap();
        let mut max_err: f64 = 0.0;
        let mut max_u: f64 = 0.0;
        for i in 0..500 {
            let t = 0.2537 * i as f64;
            let u = sea.kinematics(&p, t).velocity.x;
            max_err = max_err.max((series.sample(0, t).kinematics.velocity.x - u).abs());
            max_u = max_u.max(u.abs());
        }
        // 16 samples per shortest period: the cubic error bound is 3e-4 of the highest component.
        assert!(max_err < 3e-4 * max_u, "{max_err} vs {max_u}");
    }
}
