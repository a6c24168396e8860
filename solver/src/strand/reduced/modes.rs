//! The layer interfaces' collective modes, measured on the FE model ([`super::ModeCoupling`]).
//!
//! At a load point reached along the FE initialisation's path, the FE state is checkpointed a
//! hair away from the point and solved back to it from the checkpoint: once as it is, and once
//! per imposed pattern of irreversible slip, the elastic gaps of every contact of one
//! interface shortened along the outer wire by `δ ψ(θ)` (their anchors moved as a slide would
//! move them). The difference of the two solutions, projected on the pattern over each
//! interface, is the interfaces' answer to that interface's pattern. A pattern of random signs
//! measures the contacts' mean answer to their own irreversible slip, which the contact laws
//! carry and the modes must not count twice.
//!
//! The uniform and cos θ patterns are orthogonal over an interface and are imposed together
//! (their answers are linear in them); the sin θ pattern alone. On the six-layer strand with
//! periodic ends, whose interfaces are rings, cos θ and sin θ answer alike within 1 %; on a
//! short strand with tied ends they do not.

use super::{LoadScaling, ModeCoupling, ReducedError, MODES};
use crate::fretting::ContactSample;
use crate::strand::history::checkpoint::HistoryCheckpoint;
use crate::strand::history::monitors::{contact_sites, ContactSite};
use crate::strand::history::{
    run_history, run_history_from, HistoryObserver, HistoryOptions, LoadSample,
};
use crate::strand::model::StrandModel;

/// Irreversible slip imposed by the patterns (m): a tenth of the campaigns' γ_e, small enough
/// to leave every stuck contact stuck.
const PATTERN_SLIP_M: f64 = 1e-6;

/// The load points of the measurement (scaled loads): tension knots over the range, at the
/// middle curvature.
pub(crate) const MODE_POINTS: [(f64, f64); 7] = [
    (-0.97, 0.0),
    (-0.9, 0.0),
    (-0.75, 0.0),
    (-0.5, 0.0),
    (0.0, 0.0),
    (0.5, 0.0),
    (0.9, 0.0),
];

/// The checkpoint and the last sample's contacts of a run.
#[derive(Default)]
struct Capture {
    checkpoint: Option<HistoryCheckpoint>,
    last: Vec<ContactSample>,
}

impl HistoryObserver for Capture {
    fn checkpoint(&mut self, checkpoint: &HistoryCheckpoint) {
        self.checkpoint = Some(checkpoint.clone());
    }

    fn sample(&mut self, _sample: &LoadSample, contacts: &[ContactSample], _elements: &[f64]) {
        self.last.clear();
        self.last.extend_from_slice(contacts);
    }
}

/// The weight of contact `c` at `site` in pattern `p`: 0 uniform, 1 cos θ, 2 random signs
/// (sin θ is imposed on its own).
fn pattern_weight(p: usize, c: usize, site: &ContactSite) -> f64 {
    match p {
        0 => 1.0,
        1 => site.theta_rad.cos(),
        _ => {
            if (c as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 63 == 0 {
                1.0
            } else {
                -1.0
            }
        }
    }
}

/// The FE state at one load point, checkpointed to be solved again with imposed slips.
struct Probe<'a> {
    model: &'a StrandModel,
    samples: [LoadSample; 3],
    options: HistoryOptions,
    checkpoint: HistoryCheckpoint,
    base: Vec<ContactSample>,
    sites: Vec<ContactSite>,
    interfaces: usize,
}

fn history_failed(source: crate::strand::history::HistoryError) -> ReducedError {
    ReducedError::History {
        chain: usize::MAX,
        source,
    }
}

impl<'a> Probe<'a> {
    /// The FE state at scaled loads (x, y), reached along the FE initialisation's path.
    fn at(
        model: &'a StrandModel,
        scaling: &LoadScaling,
        (x, y): (f64, f64),
        history: &HistoryOptions,
    ) -> Result<Self, ReducedError> {
        let load = |t: f64, x: f64, y: f64| {
            let (strain, curvature_per_m) = scaling.load(x, y);
            LoadSample {
                time_s: t,
                strain,
                curvature_per_m,
            }
        };
        let samples = [
            load(0.0, x, y),
            load(1.0, x + 1e-3, y + 1e-3),
            load(2.0, x, y),
        ];
        let options = HistoryOptions {
            checkpoint_interval_segments: 1,
            turning_point_tolerance: 0.0,
            ..*history
        };
        let mut capture = Capture::default();
        run_history(model, &samples, &options, &mut capture).map_err(history_failed)?;
        let checkpoint = capture.checkpoint.take().ok_or(ReducedError::Calibration {
            reason: "the mode measurement's FE run handed no checkpoint".into(),
        })?;
        let sites = contact_sites(model);
        let interfaces = sites.iter().map(|s| s.interface + 1).max().unwrap_or(0);
        let mut probe = Self {
            model,
            samples,
            options,
            checkpoint,
            base: Vec::new(),
            sites,
            interfaces,
        };
        probe.base = probe.solve(&probe.checkpoint)?;
        Ok(probe)
    }

    fn solve(&self, cp: &HistoryCheckpoint) -> Result<Vec<ContactSample>, ReducedError> {
        let mut run = Capture::default();
        run_history_from(self.model, &self.samples, &self.options, Some(cp), &mut run)
            .map_err(history_failed)?;
        Ok(run.last)
    }

    /// Every contact's answer, per unit of imposed slip, to the irreversible slips `w`.
    fn answer(&self, w: &dyn Fn(usize, &ContactSite) -> f64) -> Result<Vec<f64>, ReducedError> {
        let mut cp = self.checkpoint.clone();
        for (c, site) in self.sites.iter().enumerate() {
            cp.histories[c].elastic_gap_m[1] -= w(c, site) * PATTERN_SLIP_M;
        }
        let solved = self.solve(&cp)?;
        Ok(solved
            .iter()
            .zip(&self.base)
            .map(|(a, b)| (a.slip_m - b.slip_m) / PATTERN_SLIP_M)
            .collect())
    }

    /// The projection of an answer on the pattern `weight` over each interface.
    fn project(&self, d: &[f64], weight: &dyn Fn(usize, &ContactSite) -> f64) -> Vec<f64> {
        let mut wd = vec![0.0; self.interfaces];
        let mut ww = vec![0.0; self.interfaces];
        for (c, site) in self.sites.iter().enumerate() {
            let w = weight(c, site);
            wd[site.interface] += w * d[c];
            ww[site.interface] += w * w;
        }
        wd.iter()
            .zip(&ww)
            .map(|(d, w)| d / w.max(f64::MIN_POSITIVE))
            .collect()
    }
}

/// The amplifications `a[I][J][m]` at one load point (scaled `x`, `y`), net of the contacts'
/// own answer on the diagonal. Uniform patterns answer across interfaces by a few percent and
/// are kept on the diagonal only.
pub(crate) fn measure_point(
    model: &StrandModel,
    scaling: &LoadScaling,
    point: (f64, f64),
    history: &HistoryOptions,
) -> Result<Vec<Vec<[f64; MODES]>>, ReducedError> {
    let probe = Probe::at(model, scaling, point, history)?;
    let n = probe.interfaces;
    let pattern = |p: usize| move |c: usize, site: &ContactSite| pattern_weight(p, c, site);
    // random signs on every interface at once: each contact's own answer (the patterns of
    // different interfaces are uncorrelated)
    let own = probe.project(&probe.answer(&pattern(2))?, &pattern(2));
    let mut a = vec![vec![[0.0; MODES]; n]; n];
    for j in 0..n {
        // the uniform and cos θ patterns together: orthogonal over the ring
        let d = probe.answer(&|c, site| {
            if site.interface == j {
                pattern_weight(0, c, site) + pattern_weight(1, c, site)
            } else {
                0.0
            }
        })?;
        let (uniform, cos) = (
            probe.project(&d, &pattern(0)),
            probe.project(&d, &pattern(1)),
        );
        let sin_pattern = |_: usize, site: &ContactSite| site.theta_rad.sin();
        let d = probe.answer(&|c, site| {
            if site.interface == j {
                sin_pattern(c, site)
            } else {
                0.0
            }
        })?;
        let sin = probe.project(&d, &sin_pattern);
        for (i, row) in a.iter_mut().enumerate() {
            // uniform: the interface's own (across interfaces a few percent)
            row[j] = [if i == j { uniform[i] } else { 0.0 }, cos[i], sin[i]];
        }
        for v in a[j][j].iter_mut() {
            *v = (*v - own[j]).max(0.0);
        }
    }
    Ok(a)
}

/// The collective modes over the tension knots `points` (scaled loads, increasing in x), each
/// measured on its own FE run, as many at a time as `threads`.
pub(crate) fn measure(
    model: &StrandModel,
    scaling: &LoadScaling,
    points: &[(f64, f64)],
    history: &HistoryOptions,
    threads: usize,
) -> Result<ModeCoupling, ReducedError> {
    let single = HistoryOptions {
        threads: 1,
        ..*history
    };
    let results: Vec<Result<Vec<Vec<[f64; MODES]>>, ReducedError>> = std::thread::scope(|scope| {
        let concurrent = threads.clamp(1, points.len().max(1));
        let chunks: Vec<Vec<usize>> = (0..concurrent)
            .map(|t| (t..points.len()).step_by(concurrent).collect())
            .collect();
        let handles: Vec<_> = chunks
            .into_iter()
            .map(|idx| {
                let single = &single;
                scope.spawn(move || {
                    idx.into_iter()
                        .map(|k| (k, measure_point(model, scaling, points[k], single)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<(usize, Result<_, _>)> = handles
            .into_iter()
            .flat_map(|h| {
                h.join().unwrap_or_else(|_| {
                    vec![(
                        usize::MAX,
                        Err(ReducedError::Calibration {
                            reason: "a mode measurement thread panicked".into(),
                        }),
                    )]
                })
            })
            .collect();
        all.sort_by_key(|(k, _)| *k);
        all.into_iter().map(|(_, r)| r).collect()
    });
    let amplification = results.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(ModeCoupling {
        knots: points.iter().map(|p| p.0).collect(),
        amplification,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strand::model::{EndKind, StrandModelParameters};
    use crate::strand::profile::profile_from_json;
    use crate::strand::reduced::LoadRange;

    const BENCHMARK: &str = include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../campaigns/benchmarks/strand_1_6_1.json"
    ));

    /// The measurement's assumption on the 1+6+1 strand: the FE answer is linear in the
    /// imposed slips, so the uniform and cos θ patterns imposed together project as each
    /// alone; and a uniform slip over an interface moves its contacts in the same direction,
    /// by less than itself.
    #[test]
    fn the_uniform_and_cos_patterns_superpose() {
        let strand = profile_from_json(BENCHMARK)
            .expect("benchmark profile parses")
            .validate()
            .expect("benchmark profile is valid");
        let params = StrandModelParameters::penalty_contact(2e8, 1e-5, EndKind::PenaltyTies);
        let model = StrandModel::new(&strand, &params).expect("benchmark model builds");
        let range = LoadRange {
            strain: [5e-4, 1.5e-3],
            curvature_per_m: [0.0, 0.03],
        };
        let probe = Probe::at(
            &model,
            &LoadScaling::of(&range),
            (0.0, 0.0),
            &HistoryOptions::default(),
        )
        .expect("the probe solves");
        let on = |j: usize, p: usize| {
            move |c: usize, site: &ContactSite| {
                if site.interface == j {
                    pattern_weight(p, c, site)
                } else {
                    0.0
                }
            }
        };
        for j in 0..probe.interfaces {
            let uniform = probe.answer(&on(j, 0)).expect("solves");
            let cos = probe.answer(&on(j, 1)).expect("solves");
            let both = probe
                .answer(&|c, site| on(j, 0)(c, site) + on(j, 1)(c, site))
                .expect("solves");
            let u = probe.project(&uniform, &|_, _| 1.0);
            let b = probe.project(&cos, &|_, site| site.theta_rad.cos());
            let (u2, b2) = (
                probe.project(&both, &|_, _| 1.0),
                probe.project(&both, &|_, site| site.theta_rad.cos()),
            );
            for i in 0..probe.interfaces {
                assert!(u[j] > 0.0 && u[j] < 1.0, "interface {j}: uniform {}", u[j]);
                assert!(
                    (u2[i] - u[i]).abs() < 0.02 * u[j],
                    "{i} by {j}: {} vs {}",
                    u2[i],
                    u[i]
                );
                assert!(
                    (b2[i] - b[i]).abs() < 0.02 * b[j].abs().max(0.05),
                    "{i} by {j}"
                );
            }
        }
    }
}
