//! Water kinematics as the coupled run samples them: a start-up ramp on the waves, and the
//! per-line cache of kinematics precomputed at the line's quadrature points in their static
//! position.
//!
//! Ramp: every wave quantity is multiplied by r(t) = ½ (1 − cos(π t / t_r)) for t < t_r (1
//! afterwards), so the coupled system starts from its calm static equilibrium without an
//! impulsive load; the ṙ terms of the acceleration are neglected (they act only inside the
//! discarded transient).
//!
//! Line cache: the line model samples the sea once per time step, at the quadrature points of
//! its elements in a fixed order (`crate::mooring::assembly::update_water`: element by element,
//! three points per cable element, two per bar). [`LineSeaCache`] records that order once at the
//! static shape, precomputes the kinematics at those fixed points with
//! [`PointKinematicsSeries`] (FFT over the repeat period) and then answers the i-th query of a
//! sweep with point i of the series, interpolated in time. This is the usual "kinematics at the
//! static node positions" approximation of mooring codes: for the paper case the fairlead moves
//! some metres, small against the ≈ 400 m peak wavelength. A query farther than
//! `guard_distance_m` from the point it is matched with (a change of the sampling order, or a
//! very large excursion) is answered by direct summation instead, so a mismatch costs time,
//! never accuracy. A unidirectional sea depends on the horizontal position only through the
//! distance x_β along its direction, so lines laid symmetrically about that direction (lines
//! 1/2, 3/6 and 4/5 of the paper case in a head sea) sample it at the same (x_β, z) points:
//! such a line shares the series of the first line whose points match within
//! `SHARED_SERIES_TOLERANCE_M` ([`LineSeaCache::for_lines`]), which halves the precomputation
//! and its memory there.
//!
//! Floater table: the floater samples the sea at every wetted strip centre of its members
//! (≈ 1 m strips) in its current pose, several times per step. [`FloaterSeaTable`] answers
//! those queries from a [`PlaneKinematicsTable`] (FFT over the repeat period on an
//! (x_β, stretched height) grid × time, interpolated) covering the members in the static pose
//! with a margin for the motions: the body moves metres, the table follows it exactly within its
//! interpolation accuracy (see `crate::waves::table`). A query outside the table is answered
//! by direct summation and counted.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use nalgebra::Vector3;

use crate::floater::{BodyState, Floater};
use crate::mooring::assembly::{update_water, WaterCache};
use crate::mooring::LineModel;
use crate::waves::{
    FluidKinematics, IrregularSea, PlaneKinematicsTable, PointKinematicsSeries, SeaKinematics,
    SeriesParams, TableParams, TableRegion, TimeSlice, WavesError,
};

/// Start-up ramp of the waves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// Ramp duration t_r (s); 0 for none.
    pub duration_s: f64,
}

impl Ramp {
    /// Factor r(t).
    pub fn factor(&self, t: f64) -> f64 {
        if self.duration_s > 0.0 && t < self.duration_s {
            if t <= 0.0 {
                0.0
            } else {
                0.5 * (1.0 - (std::f64::consts::PI * t / self.duration_s).cos())
            }
        } else {
            1.0
        }
    }
}

fn scaled(k: FluidKinematics, r: f64) -> FluidKinematics {
    FluidKinematics {
        velocity: k.velocity * r,
        acceleration: k.acceleration * r,
        dynamic_pressure_pa: k.dynamic_pressure_pa * r,
    }
}

/// A sea with the start-up ramp applied.
#[derive(Debug, Clone, Copy)]
pub struct RampedSea<'a, S: SeaKinematics + ?Sized> {
    /// Underlying sea.
    pub sea: &'a S,
    /// Ramp.
    pub ramp: Ramp,
}

impl<S: SeaKinematics + ?Sized> SeaKinematics for RampedSea<'_, S> {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        let r = self.ramp.factor(t);
        if r == 0.0 {
            return FluidKinematics::default();
        }
        scaled(self.sea.kinematics(x, t), r)
    }
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        self.ramp.factor(t) * self.sea.elevation(x, y, t)
    }
}

/// Records the points a line samples, in order.
struct Recorder(Mutex<Vec<Vector3<f64>>>);

impl SeaKinematics for Recorder {
    fn kinematics(&self, x: &Vector3<f64>, _t: f64) -> FluidKinematics {
        if let Ok(mut v) = self.0.lock() {
            v.push(*x);
        }
        FluidKinematics::default()
    }
    fn elevation(&self, _x: f64, _y: f64, _t: f64) -> f64 {
        0.0
    }
}

/// Largest difference (m) of x_β and of z between the corresponding sampling points of two
/// lines for them to share one precomputed series: the kinematics change by k · 1e-6 m,
/// far below the interpolation error of the series.
pub(crate) const SHARED_SERIES_TOLERANCE_M: f64 = 1e-6;

/// The points at which `model` in state `q` samples the sea, in its sampling order.
pub fn sampled_points(model: &LineModel, q: &[f64]) -> Vec<Vector3<f64>> {
    let recorder = Recorder(Mutex::new(Vec::new()));
    let mut water: WaterCache = Vec::new();
    update_water(model, q, 0.0, &recorder, &mut water);
    recorder.0.into_inner().unwrap_or_default()
}

/// Whether the unidirectional `sea` has the same kinematics at the points `a` as at `b`, point
/// by point (equal x_β and z within [`SHARED_SERIES_TOLERANCE_M`]).
pub(crate) fn same_sea_at(sea: &IrregularSea, a: &[Vector3<f64>], b: &[Vector3<f64>]) -> bool {
    let f = sea.field();
    a.len() == b.len()
        && a.iter().zip(b).all(|(p, q)| {
            (f.along(p.x, p.y) - f.along(q.x, q.y)).abs() <= SHARED_SERIES_TOLERANCE_M
                && (p.z - q.z).abs() <= SHARED_SERIES_TOLERANCE_M
        })
}

/// Precomputed kinematics of one line (see the module documentation).
#[derive(Debug)]
pub struct LineSeaCache<'a> {
    sea: &'a IrregularSea,
    series: Arc<PointKinematicsSeries>,
    /// The line's own sampling points (those of a shared series may be mirrored ones).
    points: Vec<Vector3<f64>>,
    ramp: Ramp,
    guard_distance_m: f64,
    cursor: AtomicUsize,
    misses: AtomicUsize,
}

impl<'a> LineSeaCache<'a> {
    /// Cache for `model` in the static state `q`, for times up to `end_time_s` (later queries
    /// are answered by direct summation).
    pub fn new(
        model: &LineModel,
        q: &[f64],
        sea: &'a IrregularSea,
        ramp: Ramp,
        params: &SeriesParams,
        guard_distance_m: f64,
        end_time_s: f64,
    ) -> Result<Self, WavesError> {
        let points = sampled_points(model, q);
        let series = PointKinematicsSeries::new_until(sea, &points, params, end_time_s)?;
        Ok(Self::with_series(
            sea,
            Arc::new(series),
            points,
            ramp,
            guard_distance_m,
        ))
    }

    /// Caches for the lines `lines` (model, static state), as [`LineSeaCache::new`] each,
    /// except that a line sampling the sea at the same (x_β, z) points as an earlier one
    /// (`same_sea_at`) shares that line's series; the series are built on `pool`, one line
    /// per task.
    pub fn for_lines(
        lines: &[(&LineModel, &[f64])],
        sea: &'a IrregularSea,
        ramp: Ramp,
        params: &SeriesParams,
        guard_distance_m: f64,
        end_time_s: f64,
        pool: Option<&rayon::ThreadPool>,
    ) -> Result<Vec<Self>, WavesError> {
        let points: Vec<Vec<Vector3<f64>>> =
            lines.iter().map(|(m, q)| sampled_points(m, q)).collect();
        // The line whose series each line uses: the first earlier owner with the same sea.
        let mut owner: Vec<usize> = Vec::with_capacity(points.len());
        for k in 0..points.len() {
            let found = (0..k).find(|&j| owner[j] == j && same_sea_at(sea, &points[j], &points[k]));
            owner.push(found.unwrap_or(k));
        }
        let build = |k: usize| {
            (owner[k] == k)
                .then(|| PointKinematicsSeries::new_until(sea, &points[k], params, end_time_s))
                .transpose()
        };
        let built: Vec<Result<Option<PointKinematicsSeries>, WavesError>> = match pool {
            Some(p) => {
                use rayon::prelude::*;
                p.install(|| (0..points.len()).into_par_iter().map(build).collect())
            }
            None => (0..points.len()).map(build).collect(),
        };
        let mut series: Vec<Option<Arc<PointKinematicsSeries>>> = Vec::new();
        for b in built {
            series.push(b?.map(Arc::new));
        }
        let mut caches = Vec::with_capacity(points.len());
        for (k, p) in points.into_iter().enumerate() {
            let shared = series[owner[k]]
                .clone()
                .ok_or(WavesError::InvalidParameter {
                    field: "line series owner",
                    value: owner[k] as f64,
                    rule: "an owner builds its series",
                })?;
            caches.push(Self::with_series(sea, shared, p, ramp, guard_distance_m));
        }
        Ok(caches)
    }

    fn with_series(
        sea: &'a IrregularSea,
        series: Arc<PointKinematicsSeries>,
        points: Vec<Vector3<f64>>,
        ramp: Ramp,
        guard_distance_m: f64,
    ) -> Self {
        Self {
            sea,
            series,
            points,
            ramp,
            guard_distance_m,
            cursor: AtomicUsize::new(0),
            misses: AtomicUsize::new(0),
        }
    }

    /// Number of cached points.
    pub fn points(&self) -> usize {
        self.points.len()
    }

    /// Memory held by the precomputed series (bytes; a shared series counts for each line).
    pub fn memory_bytes(&self) -> usize {
        self.series.memory_bytes()
    }

    /// Whether this cache and `other` use the same precomputed series.
    pub fn shares_series_with(&self, other: &LineSeaCache<'_>) -> bool {
        Arc::ptr_eq(&self.series, &other.series)
    }

    /// Queries answered by direct summation because they were too far from their cached point
    /// (or later than the precomputed times).
    pub fn misses(&self) -> usize {
        self.misses.load(Ordering::Relaxed)
    }
}

impl SeaKinematics for LineSeaCache<'_> {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        let r = self.ramp.factor(t);
        let n = self.points.len();
        if n == 0 {
            return scaled(self.sea.kinematics(x, t), r);
        }
        let i = self.cursor.fetch_add(1, Ordering::Relaxed) % n;
        if r == 0.0 {
            return FluidKinematics::default();
        }
        let p = &self.points[i];
        if (p - x).norm() > self.guard_distance_m || t > self.series.covered_until_s() {
            self.misses.fetch_add(1, Ordering::Relaxed);
            return scaled(self.sea.kinematics(x, t), r);
        }
        scaled(self.series.sample(i, t).kinematics, r)
    }
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        self.ramp.factor(t) * self.sea.elevation(x, y, t)
    }
}

/// Horizontal margin (m) of the floater table around the members in the static pose: the
/// excursions of the floater about its mean offset in the severe sea state are some metres
/// (surge amplitudes below 15 m for the paper case), so 30 m leaves room for larger ones.
pub(crate) const FLOATER_TABLE_MARGIN_ALONG_M: f64 = 30.0;
/// Vertical margin (m) of the floater table below the deepest member end in the static pose:
/// heave and pitch move the deepest point by a few metres and Wheeler stretching under a crest
/// lowers its stretched height by |z| η/(d + η) (≈ 2 m for the paper case).
pub(crate) const FLOATER_TABLE_MARGIN_DEPTH_M: f64 = 25.0;

/// The floater's sea: a [`PlaneKinematicsTable`] around the floater with the ramp applied, and
/// direct summation for queries outside the table (see the module documentation).
#[derive(Debug)]
pub struct FloaterSeaTable<'a> {
    sea: &'a IrregularSea,
    table: PlaneKinematicsTable,
    ramp: Ramp,
    misses: AtomicUsize,
    /// The table at the instant of the latest query (the queries of a coupled step share it).
    slice: Mutex<TimeSlice>,
}

impl<'a> FloaterSeaTable<'a> {
    /// Table of `sea` around the members of `floater` in the pose `body`, with margins
    /// `FLOATER_TABLE_MARGIN_ALONG_M` and `FLOATER_TABLE_MARGIN_DEPTH_M`, up to `end_time_s`.
    pub fn new(
        floater: &Floater,
        body: &BodyState,
        sea: &'a IrregularSea,
        ramp: Ramp,
        end_time_s: f64,
        params: &TableParams,
    ) -> Result<Self, WavesError> {
        let field = sea.field();
        let (mut lo, mut hi, mut z_min) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for m in floater.members() {
            let (a, b) = m.global_ends(body);
            for p in [a, b] {
                let xb = field.along(p.x, p.y);
                lo = lo.min(xb);
                hi = hi.max(xb);
                z_min = z_min.min(p.z);
            }
        }
        if lo > hi {
            (lo, hi) = (0.0, 0.0);
        }
        let region = TableRegion {
            along_m: (
                lo - FLOATER_TABLE_MARGIN_ALONG_M,
                hi + FLOATER_TABLE_MARGIN_ALONG_M,
            ),
            lowest_stretched_m: (z_min - FLOATER_TABLE_MARGIN_DEPTH_M).max(-field.depth_m()),
            end_time_s,
        };
        Ok(Self {
            sea,
            table: PlaneKinematicsTable::new(sea, &region, params)?,
            ramp,
            misses: AtomicUsize::new(0),
            slice: Mutex::new(TimeSlice::default()),
        })
    }

    /// The table.
    pub fn table(&self) -> &PlaneKinematicsTable {
        &self.table
    }

    /// Queries answered by direct summation because they fell outside the table.
    pub fn misses(&self) -> usize {
        self.misses.load(Ordering::Relaxed)
    }

    /// `query` on the table's slice at `t` (filled first if it holds another instant);
    /// `None` when `t` or the point is outside the table.
    fn on_slice<R>(
        &self,
        t: f64,
        query: impl FnOnce(&PlaneKinematicsTable, &TimeSlice) -> Result<R, WavesError>,
    ) -> Option<R> {
        let mut slice = match self.slice.lock() {
            Ok(s) => s,
            Err(poisoned) => poisoned.into_inner(),
        };
        if slice.time_s() != Some(t) && !self.table.fill_slice(t, &mut slice) {
            return None;
        }
        query(&self.table, &slice).ok()
    }
}

impl SeaKinematics for FloaterSeaTable<'_> {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        let r = self.ramp.factor(t);
        if r == 0.0 {
            return FluidKinematics::default();
        }
        let k = self
            .on_slice(t, |table, slice| table.slice_kinematics(slice, x))
            .unwrap_or_else(|| {
                self.misses.fetch_add(1, Ordering::Relaxed);
                self.sea.kinematics(x, t)
            });
        scaled(k, r)
    }
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        let r = self.ramp.factor(t);
        if r == 0.0 {
            return 0.0;
        }
        let e = self
            .on_slice(t, |table, slice| table.slice_elevation(slice, x, y))
            .unwrap_or_else(|| {
                self.misses.fetch_add(1, Ordering::Relaxed);
                self.sea.elevation(x, y, t)
            });
        r * e
    }
}

/// Sea samples of the floater held over one coupling pass.
///
/// The floater's hydrodynamic loads sample the sea at its strip centres (direct summation over
/// every wave component, the dominant cost of a floater evaluation). Inside a coupling pass the
/// floater Newton iterations move the body by millimetres, so [`PassSea`] records the samples of
/// the pass's first evaluation and answers the queries of the following inner iterations, in
/// the same order, with them. A query at another time or farther than `tolerance_m` from its
/// recorded point (a strip that became wet or dry changes the order) is answered directly.
/// Only the inner iterations see held samples: every pass starts by recording, so the residual
/// that decides convergence is always the exact one.
pub(crate) struct PassSea<'a> {
    sea: &'a dyn SeaKinematics,
    tolerance_m: f64,
    held: Mutex<Held>,
}

#[derive(Default)]
struct Held {
    replay: bool,
    time_s: f64,
    kinematics: Vec<(Vector3<f64>, FluidKinematics)>,
    elevations: Vec<([f64; 2], f64)>,
    next_kinematics: usize,
    next_elevation: usize,
}

impl<'a> PassSea<'a> {
    /// Direct sampling of `sea`, held samples used within `tolerance_m` of their point.
    pub(crate) fn new(sea: &'a dyn SeaKinematics, tolerance_m: f64) -> Self {
        PassSea {
            sea,
            tolerance_m,
            held: Mutex::new(Held::default()),
        }
    }

    fn with_held<R>(&self, f: impl FnOnce(&mut Held) -> R) -> R {
        match self.held.lock() {
            Ok(mut h) => f(&mut h),
            Err(poisoned) => f(&mut poisoned.into_inner()),
        }
    }

    /// The next evaluation samples the sea directly and records the samples.
    pub(crate) fn record(&self) {
        self.with_held(|h| {
            h.replay = false;
            h.kinematics.clear();
            h.elevations.clear();
        });
    }

    /// The next evaluation reuses the recorded samples.
    pub(crate) fn replay(&self) {
        self.with_held(|h| {
            h.replay = true;
            h.next_kinematics = 0;
            h.next_elevation = 0;
        });
    }
}

impl SeaKinematics for PassSea<'_> {
    fn kinematics(&self, x: &Vector3<f64>, t: f64) -> FluidKinematics {
        let held = self.with_held(|h| {
            if !h.replay {
                return None;
            }
            let i = h.next_kinematics;
            h.next_kinematics += 1;
            match h.kinematics.get(i) {
                Some((p, k)) if h.time_s == t && (p - x).norm() <= self.tolerance_m => Some(*k),
                _ => None,
            }
        });
        if let Some(k) = held {
            return k;
        }
        let k = self.sea.kinematics(x, t);
        self.with_held(|h| {
            if !h.replay {
                h.time_s = t;
                h.kinematics.push((*x, k));
            }
        });
        k
    }
    fn elevation(&self, x: f64, y: f64, t: f64) -> f64 {
        let held = self.with_held(|h| {
            if !h.replay {
                return None;
            }
            let i = h.next_elevation;
            h.next_elevation += 1;
            match h.elevations.get(i) {
                Some((p, e)) if h.time_s == t && (p[0] - x).hypot(p[1] - y) <= self.tolerance_m => {
                    Some(*e)
                }
                _ => None,
            }
        });
        if let Some(e) = held {
            return e;
        }
        let e = self.sea.elevation(x, y, t);
        self.with_held(|h| {
            if !h.replay {
                h.time_s = t;
                h.elevations.push(([x, y], e));
            }
        });
        e
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_rises_smoothly_from_zero_to_one() {
        let r = Ramp { duration_s: 10.0 };
        assert_eq!(r.factor(0.0), 0.0);
        assert!((r.factor(5.0) - 0.5).abs() < 1e-15);
        assert_eq!(r.factor(10.0), 1.0);
        assert_eq!(r.factor(30.0), 1.0);
        assert_eq!(Ramp { duration_s: 0.0 }.factor(0.0), 1.0);
    }
}
