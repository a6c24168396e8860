//! The reduced strand response against the FE model, from one recorded FE calibration run.
//!
//! The FE run of a calibration is what costs (minutes); the fit and a reduced history are
//! seconds. This study records the FE run of the six-layer paper strand's calibration once
//! (every contact's slip, normal and tangential force at every designed sample: 110 MB), then
//! fits the reduced response on the recording ([`fit_recorded`]) and runs it through held-out
//! hot-spot histories whose FE results are on disk, printing per layer interface the
//! reduced-versus-FE difference of the largest slip range, of the accumulated slip Σ n Δs over
//! cycles of at least 1 µm and of their number, and the spread over the interface's contacts
//! of the reduced / FE ratio of each contact's largest slip range. A change to the fit or to
//! the drive's form is then measured in seconds on the same FE data
//! (docs/notes/2026-11-27-reduced-strand-forms.md).
//!
//! ```text
//! reduced_strand_forms record --ea EA --margin 0.05 --load A.csv [--load B.csv …] REC.bin
//! reduced_strand_forms fit REC.bin --ea EA --margin 0.05 --load A.csv … \
//!     --held-out LOAD.csv FE_DIR [--held-out …] [--run-in-s 100] [--write CALIB.json] \
//!     [--probe HELD.bin]
//! reduced_strand_forms record-load HELD.bin LOAD.csv --to-s T --ea EA --load A.csv …
//! reduced_strand_forms record-path PATH.bin --path "x,y;x,y;…" [--parts 8] --ea EA --load A.csv …
//! reduced_strand_forms slopes A.bin:t0:t1 B.bin:t0:t1 … --ea EA --load A.csv …
//! reduced_strand_forms trace REC.bin --probe HELD.bin --interface I [--contact C] --ea EA --load A.csv …
//! reduced_strand_forms open HELD.bin --ea EA --load A.csv …
//! ```
//!
//! `record-load` records an FE history run of a load file (up to `--to-s`) sample by sample;
//! `record-path` one along straight strokes between points of the scaled loads (x, y) of the
//! range; `slopes` compares, per contact, the slip's slope on the curvature over windows of such
//! recordings; `fit --probe` compares the reduced slip with a recorded FE run contact by contact
//! and sample by sample (docs/notes/2026-11-27-reduced-strand-state.md), with the contacts'
//! elastic states, and `--x-above X` only above a scaled tension; `trace` prints one contact's
//! FE and reduced series (by default the interface-I contact with the largest FE slip range,
//! `--contact C` for contact C); `open` the share of open contacts per interface and tension bin
//! (docs/notes/2026-11-27-reduced-strand-tension.md).
//!
//! The model is the paper campaign's: the six-layer strand, periodic ends, ε_N = 2e8 N/m,
//! γ_e = 10 µm; loads are `moorfret run global` hot-spot files (hot spot 0), ε = T / EA with
//! the EA that `moorfret run strand` prints. The range is the loads' widened by `--margin`, as
//! `moorfret strand calibrate` makes it. `--write` stores the fitted calibration with the key
//! of this model, for `moorfret run strand --fidelity reduced --calibration`.

use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

use moorfret_solver::fretting::{ContactRecord, ContactSample};
use moorfret_solver::strand::history::monitors::ContactSite;
use moorfret_solver::strand::history::stiffness::{samples_from_tension, SlackTension};
use moorfret_solver::strand::history::{
    checkpoint::HistoryCheckpoint, run_history, run_history_from, HistoryObserver, HistoryOptions,
    HistoryProgress, LoadSample,
};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::profiles_from_json;
use moorfret_solver::strand::reduced::compare::compare_records;
use moorfret_solver::strand::reduced::{
    calibration_design, contact_series, fit_recorded, model_key, run_reduced, CalibrationOptions,
    LoadRange, ModeCoupling, RecordedSample, ReducedStrand,
};
use moorfret_studies::load_file;

const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));

type Error = Box<dyn std::error::Error>;

/// The paper campaign's strand model, with the contact-mechanics laws if `contact_mechanics`.
fn model(contact_mechanics: bool) -> Result<(StrandModel, String), Error> {
    let strand = profiles_from_json(PROFILES)?
        .get("paper_six_layer")
        .ok_or("profile paper_six_layer missing")?
        .validate()?;
    let params = if contact_mechanics {
        StrandModelParameters::contact_mechanics(EndKind::Periodic)
    } else {
        StrandModelParameters::penalty_contact(2e8, 1e-5, EndKind::Periodic)
    };
    let key = model_key(&strand, &params, &CalibrationOptions::default());
    Ok((StrandModel::new(&strand, &params)?, key))
}

/// Hot spot 0 of a `moorfret run global` hot-spot file as load samples, ε = T / EA.
fn read_load(path: &str, ea: f64) -> Result<Vec<LoadSample>, Error> {
    let [t, tension, kappa] = load_file::read_load(path, f64::NEG_INFINITY, f64::INFINITY)?;
    Ok(samples_from_tension(&t, &tension, &kappa, ea, 1, SlackTension::Refuse)?.0)
}

/// The range of the loads widened by `margin`.
fn range_of(loads: &[String], ea: f64, margin: f64) -> Result<LoadRange, Error> {
    let mut range: Option<LoadRange> = None;
    for path in loads {
        let r = LoadRange::of(&read_load(path, ea)?).ok_or("empty load")?;
        range = Some(range.map_or(r, |a| a.union(r)));
    }
    Ok(range.ok_or("give --load")?.widened(margin))
}

/// Writes every sample the FE run solves.
struct Recorder<W: Write> {
    out: W,
    error: Option<std::io::Error>,
    samples: usize,
}

impl<W: Write> Recorder<W> {
    fn put(&mut self, values: impl IntoIterator<Item = f64>) {
        for v in values {
            if self.error.is_none() {
                if let Err(e) = self.out.write_all(&v.to_le_bytes()) {
                    self.error = Some(e);
                }
            }
        }
    }
}

impl<W: Write> HistoryObserver for Recorder<W> {
    fn progress(&mut self, _progress: &HistoryProgress) {}

    fn checkpoint(&mut self, _checkpoint: &HistoryCheckpoint) {}

    fn sample(&mut self, sample: &LoadSample, contacts: &[ContactSample], elements: &[f64]) {
        self.put([
            sample.time_s,
            sample.strain,
            sample.curvature_per_m,
            contacts.len() as f64,
            elements.len() as f64,
        ]);
        self.put(
            contacts
                .iter()
                .flat_map(|c| [c.slip_m, c.normal_force_n, c.tangential_force_n]),
        );
        self.put(elements.iter().copied());
        self.samples += 1;
        if self.samples % 100 == 0 {
            eprintln!("  {} samples recorded", self.samples);
        }
    }

    fn should_stop(&mut self) -> bool {
        self.error.is_some()
    }
}

/// Runs every chain of `chains` through the FE model, one run each, and writes every sample
/// they solve to `path`, chain after chain (each chain's times start at 0).
/// A chain's recording, or why its FE run failed.
type ChainBytes = Result<Vec<u8>, String>;

fn record(
    model: &StrandModel,
    chains: &[Vec<LoadSample>],
    options: &HistoryOptions,
    path: &str,
) -> Result<(), Error> {
    // the chains run side by side, one thread each, into buffers written in chain order
    let workers = options.threads.clamp(1, chains.len().max(1));
    let per_run = HistoryOptions {
        threads: 1,
        ..*options
    };
    let next = std::sync::atomic::AtomicUsize::new(0);
    let t = std::time::Instant::now();
    let buffers: Vec<std::sync::Mutex<Option<ChainBytes>>> =
        chains.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                let Some(samples) = chains.get(k) else { break };
                let mut recorder = Recorder {
                    out: Vec::new(),
                    error: None,
                    samples: 0,
                };
                let outcome = run_history(model, samples, &per_run, &mut recorder)
                    .map(|fe| {
                        println!(
                            "chain {k}: {} samples, {} sub-steps, {} Newton iterations, {:.1} s so far",
                            samples.len(),
                            fe.stats.substeps,
                            fe.stats.iterations,
                            t.elapsed().as_secs_f64()
                        );
                        recorder.out
                    })
                    .map_err(|e| format!("chain {k}: {e}"));
                if let Ok(mut slot) = buffers[k].lock() {
                    *slot = Some(outcome);
                }
            });
        }
    });
    let mut out = BufWriter::new(std::fs::File::create(path)?);
    for slot in buffers {
        match slot.into_inner().ok().flatten() {
            Some(Ok(bytes)) => out.write_all(&bytes)?,
            Some(Err(e)) => return Err(e.into()),
            None => return Err("a chain did not run".into()),
        }
    }
    out.flush()?;
    println!(
        "recorded {} chains in {:.1} s",
        chains.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(())
}

/// A recording of the calibration's chains split back into them: a sample whose time is not
/// after the previous one's starts a chain.
fn chains_of(recording: Vec<RecordedSample>) -> Vec<Vec<RecordedSample>> {
    let mut chains: Vec<Vec<RecordedSample>> = Vec::new();
    for sample in recording {
        let new_chain = chains
            .last()
            .and_then(|c| c.last())
            .is_none_or(|last| sample.0.time_s <= last.0.time_s);
        if new_chain {
            chains.push(Vec::new());
        }
        if let Some(chain) = chains.last_mut() {
            chain.push(sample);
        }
    }
    chains
}

/// Reads a recording written by [`Recorder`].
fn read_recording(path: &Path) -> Result<Vec<RecordedSample>, Error> {
    let mut r = BufReader::new(std::fs::File::open(path)?);
    let next = |r: &mut BufReader<std::fs::File>| -> std::io::Result<f64> {
        let mut b = [0u8; 8];
        r.read_exact(&mut b)?;
        Ok(f64::from_le_bytes(b))
    };
    let mut out = Vec::new();
    loop {
        let time_s = match next(&mut r) {
            Ok(v) => v,
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(e) => return Err(e.into()),
        };
        let (strain, curvature_per_m) = (next(&mut r)?, next(&mut r)?);
        let (nc, ne) = (next(&mut r)? as usize, next(&mut r)? as usize);
        let mut contacts = Vec::with_capacity(nc);
        for _ in 0..nc {
            contacts.push(ContactSample {
                slip_m: next(&mut r)?,
                normal_force_n: next(&mut r)?,
                tangential_force_n: next(&mut r)?,
            });
        }
        let elements = (0..ne).map(|_| next(&mut r)).collect::<Result<_, _>>()?;
        out.push((
            LoadSample {
                time_s,
                strain,
                curvature_per_m,
            },
            contacts,
            elements,
        ));
    }
    Ok(out)
}

/// Per interface: the distribution of the reduced / FE ratio of each contact's largest slip
/// range, and the contacts holding the interface's largest range in each.
fn per_contact(fe: &[ContactRecord], reduced: &[ContactRecord]) {
    let max_range = |r: &ContactRecord| r.cycles.iter().map(|c| c.slip.range).fold(0.0, f64::max);
    let interfaces = fe.iter().map(|r| r.interface + 1).max().unwrap_or(0);
    for i in 0..interfaces {
        let mut ratios = Vec::new();
        let (mut best_fe, mut best_red) = ((0.0, 0), (0.0, 0));
        for (c, (a, b)) in fe.iter().zip(reduced).enumerate() {
            if a.interface != i {
                continue;
            }
            let (ra, rb) = (max_range(a), max_range(b));
            if ra > 0.0 {
                ratios.push(rb / ra);
            }
            if ra > best_fe.0 {
                best_fe = (ra, c);
            }
            if rb > best_red.0 {
                best_red = (rb, c);
            }
        }
        ratios.sort_by(f64::total_cmp);
        let q = |f: f64| {
            ratios
                .get(((ratios.len() as f64 - 1.0) * f) as usize)
                .copied()
                .unwrap_or(0.0)
        };
        let (fe_at_best, reduced_at_best) = (
            reduced.get(best_fe.1).map_or(0.0, max_range),
            fe.get(best_red.1).map_or(0.0, max_range),
        );
        println!(
            "    interface {i}: contact ratio p10 {:.3}, median {:.3}, p90 {:.3}, max {:.3}; \
             FE largest at contact {} ({:.3e} m, reduced {:.3e}); reduced largest at {} \
             ({:.3e} m, FE {:.3e})",
            q(0.1),
            q(0.5),
            q(0.9),
            q(1.0),
            best_fe.1,
            best_fe.0,
            fe_at_best,
            best_red.1,
            best_red.0,
            reduced_at_best
        );
    }
}

/// The number of layer interfaces of the contacts at `sites`.
fn interface_count(sites: &[ContactSite]) -> usize {
    sites.iter().map(|s| s.interface + 1).max().unwrap_or(0)
}

/// Percentiles 10, 50, 90 of `v` (sorted in place).
fn percentiles(v: &mut [f64]) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    let q = |f: f64| {
        v.get(((v.len() as f64 - 1.0) * f) as usize)
            .copied()
            .unwrap_or(f64::NAN)
    };
    [q(0.1), q(0.5), q(0.9)]
}

/// Least squares of `y` on the columns `x` (all the same length): coefficients and the
/// residual's root mean square.
fn least_squares(x: &[Vec<f64>], y: &[f64]) -> (Vec<f64>, f64) {
    let k = x.len();
    let a = nalgebra::DMatrix::<f64>::from_fn(y.len(), k, |i, j| x[j][i]);
    let b = nalgebra::DVector::<f64>::from_column_slice(y);
    let svd = a.clone().svd(true, true);
    let beta = svd
        .solve(&b, 1e-12)
        .unwrap_or_else(|_| nalgebra::DVector::zeros(k));
    let r = &a * &beta - &b;
    (
        beta.as_slice().to_vec(),
        (r.norm_squared() / y.len() as f64).sqrt(),
    )
}

/// The contacts' elastic slips `s_e = f_T γ_e / (μ f_N)` in the reduced and the FE run, per
/// interface: at the first sample (the state the initialisation leaves) and over the run, the
/// rms difference in units of γ_e and the share of contacts at the sliding limit in each.
fn elastic_states(reduced: &ReducedStrand, held: &[RecordedSample], series: &[Vec<ContactSample>]) {
    let mu = reduced.friction_coefficient;
    let unit = |c: &ContactSample| {
        if c.normal_force_n > 0.0 {
            c.tangential_force_n / (mu * c.normal_force_n)
        } else {
            0.0
        }
    };
    let interfaces = interface_count(&reduced.sites);
    println!("elastic slip / γ_e, reduced against FE: first sample | whole run");
    for i in 0..interfaces {
        let mut out = Vec::new();
        for window in [0..1.min(held.len()), 0..held.len()] {
            let (mut d2, mut n, mut lim_fe, mut lim_red) = (0.0, 0usize, 0usize, 0usize);
            for (c, site) in reduced.sites.iter().enumerate() {
                if site.interface != i {
                    continue;
                }
                for k in window.clone() {
                    let (a, b) = (unit(&held[k].1[c]), unit(&series[c][k]));
                    d2 += (a - b) * (a - b);
                    n += 1;
                    lim_fe += usize::from(a.abs() >= 0.95);
                    lim_red += usize::from(b.abs() >= 0.95);
                }
            }
            let n = n.max(1) as f64;
            out.push(format!(
                "rms diff {:.3}, at limit FE {:.3} reduced {:.3}",
                (d2 / n).sqrt(),
                lim_fe as f64 / n,
                lim_red as f64 / n
            ));
        }
        // open contacts (no normal force): the FE resets their elastic slip
        let (mut open_fe, mut open_red, mut n) = (0usize, 0usize, 0usize);
        for (c, site) in reduced.sites.iter().enumerate() {
            if site.interface != i {
                continue;
            }
            for k in 0..held.len() {
                n += 1;
                open_fe += usize::from(held[k].1[c].normal_force_n <= 0.0);
                open_red += usize::from(series[c][k].normal_force_n <= 0.0);
            }
        }
        println!(
            "  interface {i}: {} | {}; open samples FE {:.4} reduced {:.4}",
            out[0],
            out[1],
            open_fe as f64 / n.max(1) as f64,
            open_red as f64 / n.max(1) as f64
        );
    }
}

/// Sample by sample, per contact, the FE slip of a recorded held-out run against the reduced
/// model's and against the best function of the loads alone fitted on that run itself; per
/// interface the spread over contacts of: the gain of the FE slip on the reduced slip, the FE
/// slip's slope on the curvature in the reduced model and in the FE run, and the share of the
/// FE slip's spread that a quadratic in the loads leaves.
fn probe_recorded(
    reduced: &ReducedStrand,
    held: &[RecordedSample],
    run_in_s: f64,
    x_above: f64,
) -> Result<(), Error> {
    let loads: Vec<LoadSample> = held.iter().map(|h| h.0).collect();
    let series = contact_series(reduced, &loads)?;
    elastic_states(reduced, held, &series);
    let from = loads.iter().position(|s| s.time_s >= run_in_s).unwrap_or(0);
    // the samples compared: from the run-in on, at scaled tensions above `x_above`
    let kept: Vec<usize> = (from..loads.len())
        .filter(|&k| {
            let s = &loads[k];
            reduced.scaling.scaled(s.strain, s.curvature_per_m).0 > x_above
        })
        .collect();
    let held: Vec<RecordedSample> = kept.iter().map(|&k| held[k].clone()).collect();
    let series: Vec<Vec<ContactSample>> = series
        .iter()
        .map(|s| kept.iter().map(|&k| s[k]).collect())
        .collect();
    let (held, from) = (&held[..], 0);
    let xy: Vec<(f64, f64)> = held
        .iter()
        .map(|h| reduced.scaling.scaled(h.0.strain, h.0.curvature_per_m))
        .collect();
    let col = |f: &dyn Fn(f64, f64) -> f64| xy.iter().map(|&(x, y)| f(x, y)).collect::<Vec<_>>();
    let linear = vec![col(&|_, _| 1.0), col(&|x, _| x), col(&|_, y| y)];
    let quadratic = vec![
        col(&|_, _| 1.0),
        col(&|x, _| x),
        col(&|_, y| y),
        col(&|x, y| x * y),
        col(&|x, _| x * x),
        col(&|_, y| y * y),
    ];
    let interfaces = interface_count(&reduced.sites);
    println!(
        "probe: {} samples from t = {run_in_s} s at x > {x_above}; per interface p10 / median / \
         p90 over contacts",
        xy.len()
    );
    for i in 0..interfaces {
        let (mut gain, mut slope_ratio, mut quad_left, mut lin_left, mut range_ratio) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut x_slope_ratio = Vec::new();
        // sliding samples (|f_T| ≥ 0.99 μ f_N) in the FE run and in the reduced, and the normal
        // force's relative rms error at low (x < −0.8) and other tensions
        let mu = reduced.friction_coefficient;
        let (mut slide_fe, mut slide_red, mut n_samples) = (0usize, 0usize, 0usize);
        let (mut fn_low, mut fn_low_ref, mut fn_rest, mut fn_rest_ref) = (0.0, 0.0, 0.0, 0.0);
        for (c, site) in reduced.sites.iter().enumerate() {
            if site.interface != i {
                continue;
            }
            for (k, (h, r)) in held[from..].iter().zip(&series[c][from..]).enumerate() {
                let (a, b) = (&h.1[c], r);
                n_samples += 1;
                if a.tangential_force_n.abs() >= 0.99 * mu * a.normal_force_n {
                    slide_fe += 1;
                }
                if b.tangential_force_n.abs() >= 0.99 * mu * b.normal_force_n {
                    slide_red += 1;
                }
                let e = (b.normal_force_n - a.normal_force_n).powi(2);
                if xy[k].0 < -0.8 {
                    fn_low += e;
                    fn_low_ref += a.normal_force_n.powi(2);
                } else {
                    fn_rest += e;
                    fn_rest_ref += a.normal_force_n.powi(2);
                }
            }
            let fe: Vec<f64> = held[from..].iter().map(|h| h.1[c].slip_m).collect();
            let red: Vec<f64> = series[c][from..].iter().map(|s| s.slip_m).collect();
            let spread = {
                let m = fe.iter().sum::<f64>() / fe.len() as f64;
                (fe.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / fe.len() as f64).sqrt()
            };
            if spread <= 0.0 {
                continue;
            }
            let range = |v: &[f64]| {
                v.iter().cloned().fold(f64::MIN, f64::max)
                    - v.iter().cloned().fold(f64::MAX, f64::min)
            };
            range_ratio.push(range(&red) / range(&fe));
            let (g, _) = least_squares(&[linear[0].clone(), red.clone()], &fe);
            gain.push(1.0 / g[1]);
            let (bf, rl) = least_squares(&linear, &fe);
            let (br, _) = least_squares(&linear, &red);
            slope_ratio.push(br[2] / bf[2]);
            x_slope_ratio.push(br[1] / bf[1]);
            lin_left.push(rl / spread);
            let (_, rq) = least_squares(&quadratic, &fe);
            quad_left.push(rq / spread);
        }
        let show = |name: &str, v: &mut Vec<f64>| {
            let [a, b, c] = percentiles(v);
            format!("{name} {a:.3} / {b:.3} / {c:.3}")
        };
        println!(
            "  interface {i}: {}; {}; {}; {}; {}; {}",
            show("range red/FE", &mut range_ratio),
            show("gain red/FE", &mut gain),
            show("dy slope red/FE", &mut slope_ratio),
            show("dx slope red/FE", &mut x_slope_ratio),
            show("FE left by linear", &mut lin_left),
            show("by quadratic", &mut quad_left)
        );
        println!(
            "    sliding samples FE {:.4}, reduced {:.4}; f_N rel. rms error x < -0.8 {:.3}, \
             else {:.3}",
            slide_fe as f64 / n_samples.max(1) as f64,
            slide_red as f64 / n_samples.max(1) as f64,
            (fn_low / fn_low_ref.max(f64::MIN_POSITIVE)).sqrt(),
            (fn_rest / fn_rest_ref.max(f64::MIN_POSITIVE)).sqrt()
        );
    }
    Ok(())
}

/// Captures a run's checkpoints and the contacts of its last sample.
#[derive(Default)]
struct Capture {
    checkpoint: Option<HistoryCheckpoint>,
    last: Vec<ContactSample>,
}

impl HistoryObserver for Capture {
    fn progress(&mut self, _progress: &HistoryProgress) {}

    fn checkpoint(&mut self, checkpoint: &HistoryCheckpoint) {
        self.checkpoint = Some(checkpoint.clone());
    }

    fn sample(&mut self, _sample: &LoadSample, contacts: &[ContactSample], _elements: &[f64]) {
        self.last = contacts.to_vec();
    }

    fn should_stop(&mut self) -> bool {
        false
    }
}

/// The contacts' answer to a plastic slip `delta` imposed at one contact (or at every contact
/// of its interface within `sector_rad` of its angle), along the outer wire, at a load point
/// reached along the FE initialisation's path: the columns of the influence matrix of the
/// contacts' irreversible slips on their slips, measured on the FE model.
///
/// The FE state is checkpointed at a load a hair away from the point, then solved back to the
/// point twice from the checkpoint: as it is (the baseline) and with the chosen contacts'
/// elastic gaps shortened by `delta` along the outer wire (their anchors moved as a slide of
/// `delta` would move them). The difference of the two solutions is the answer.
#[allow(clippy::too_many_arguments)]
fn couple(
    model: &StrandModel,
    scaling: &moorfret_solver::strand::reduced::LoadScaling,
    point: (f64, f64),
    contacts: &[usize],
    delta: f64,
    sector_rad: f64,
    pattern: usize,
    reduced: Option<&ReducedStrand>,
    mut csv: Option<&mut std::fs::File>,
) -> Result<(), Error> {
    let load = |t: f64, x: f64, y: f64| {
        let (strain, curvature_per_m) = scaling.load(x, y);
        LoadSample {
            time_s: t,
            strain,
            curvature_per_m,
        }
    };
    let (x, y) = point;
    let samples = [
        load(0.0, x, y),
        load(1.0, x + 1e-3, y + 1e-3),
        load(2.0, x, y),
    ];
    let options = HistoryOptions {
        checkpoint_interval_segments: 1,
        ..HistoryOptions::default()
    };
    let t0 = std::time::Instant::now();
    let mut capture = Capture::default();
    run_history(model, &samples, &options, &mut capture)?;
    let checkpoint = capture.checkpoint.take().ok_or("no checkpoint")?;
    let base = capture.last.clone();
    let sites = moorfret_solver::strand::history::monitors::contact_sites(model);
    let mu = model.strand.friction_coefficient;
    let gamma = 1e-5;
    println!(
        "point x {x:.3} y {y:.3} (strain {:.4e}, curvature {:.4e} 1/m): {:.1} s",
        samples[0].strain,
        samples[0].curvature_per_m,
        t0.elapsed().as_secs_f64()
    );
    println!(
        "contact interface theta f_N f_T s_e/gamma perturbed self_ds/delta implied(gk+r) \
         law(gk+r) same_sector_sum other_same_interface_sum inner_interface_sum \
         outer_interface_sum largest_other(contact,ds/delta) count>0.05self"
    );
    let angle = |a: f64, b: f64| {
        let d = (a - b).rem_euclid(std::f64::consts::TAU);
        d.min(std::f64::consts::TAU - d)
    };
    for &j in contacts {
        let site = sites.get(j).ok_or("contact index beyond the model")?;
        // the contacts perturbed and the share of `delta` each gets: `sector_rad` > 0, every
        // contact of the interface within that angle; < 0, the whole interface with the
        // pattern `pattern` (0: uniform, 1: cos θ, 2: sin θ)
        let weight = |c: usize| match pattern {
            1 => sites[c].theta_rad.cos(),
            2 => sites[c].theta_rad.sin(),
            // random signs (a fixed hash of the contact): the projection on this pattern is the
            // interface's mean answer of a contact to its own irreversible slip
            3 => {
                if (c as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 63 == 0 {
                    1.0
                } else {
                    -1.0
                }
            }
            _ => 1.0,
        };
        let perturbed: Vec<(usize, f64)> = if sector_rad != 0.0 {
            (0..sites.len())
                .filter(|&c| {
                    sites[c].interface == site.interface
                        && (sector_rad < 0.0
                            || angle(sites[c].theta_rad, site.theta_rad) <= sector_rad)
                })
                .map(|c| (c, weight(c)))
                .collect()
        } else {
            vec![(j, 1.0)]
        };
        let mut cp = checkpoint.clone();
        for &(c, w) in &perturbed {
            cp.histories[c].elastic_gap_m[1] -= w * delta;
        }
        let mut run = Capture::default();
        run_history_from(model, &samples, &options, Some(&cp), &mut run)?;
        let ds: Vec<f64> = run
            .last
            .iter()
            .zip(&base)
            .map(|(a, b)| (a.slip_m - b.slip_m) / delta)
            .collect();
        if let Some(out) = csv.as_mut() {
            writeln!(
                out,
                "{x},{y},{j},{},{pattern},{}",
                sector_rad,
                ds.iter()
                    .map(|v| format!("{v:.6e}"))
                    .collect::<Vec<_>>()
                    .join(",")
            )?;
        }
        let b = &base[j];
        let k = mu * b.normal_force_n / gamma;
        let se = if k > 0.0 {
            b.tangential_force_n / k
        } else {
            0.0
        };
        let a = ds[j];
        let law = reduced.map_or(f64::NAN, |r| {
            let l = &r.laws[j];
            let (xs, ys) = r
                .scaling
                .scaled(samples[0].strain, samples[0].curvature_per_m);
            let fnl = l.normal_force_n(&[1.0, xs, ys, xs * ys, xs * xs, ys * ys]);
            l.compliance[0] * mu * fnl / gamma + l.compliance[1]
        });
        let (mut sector, mut same, mut inner, mut outer) = (0.0, 0.0, 0.0, 0.0);
        let (mut largest, mut count) = ((0usize, 0.0_f64), 0usize);
        for (c, (&d, s)) in ds.iter().zip(&sites).enumerate() {
            if c == j {
                continue;
            }
            if d.abs() > 0.05 * a.abs() {
                count += 1;
            }
            if d.abs() > largest.1.abs() {
                largest = (c, d);
            }
            if s.interface == site.interface {
                if angle(s.theta_rad, site.theta_rad) <= 0.13 {
                    sector += d;
                } else {
                    same += d;
                }
            } else if s.interface + 1 == site.interface {
                inner += d;
            } else if s.interface == site.interface + 1 {
                outer += d;
            }
        }
        // by the wires: the contacts of j's own wire pair, of its outer wire with others, of
        // its inner wire with others, the rest
        let wires = |c: usize| {
            let [a, b] = model.mesh.contacts[c].nodes;
            (model.mesh.nodes[a.0].wire, model.mesh.nodes[b.0].wire)
        };
        let (wa, wb) = wires(j);
        let mut by_wire = [(0.0, 0usize); 4];
        for (c, &d) in ds.iter().enumerate() {
            if c == j {
                continue;
            }
            let (a, b) = wires(c);
            let k = if (a, b) == (wa, wb) {
                0
            } else if a == wb || b == wb {
                1
            } else if a == wa || b == wa {
                2
            } else {
                3
            };
            by_wire[k].0 += d;
            by_wire[k].1 += 1;
        }
        println!(
            "  by wires: own pair {:.4} ({} contacts), outer wire's others {:.4} ({}), inner \
             wire's others {:.4} ({}), rest {:.4} ({})",
            by_wire[0].0,
            by_wire[0].1,
            by_wire[1].0,
            by_wire[1].1,
            by_wire[2].0,
            by_wire[2].1,
            by_wire[3].0,
            by_wire[3].1
        );
        // per interface: the answer projected on the pattern, and what is left
        let interfaces = sites.iter().map(|s| s.interface + 1).max().unwrap_or(0);
        let mut line = String::from("  on the pattern per interface (coef, rms left, rms):");
        for i in 0..interfaces {
            let (mut wd, mut ww, mut dd, mut n) = (0.0, 0.0, 0.0, 0usize);
            for (c, &d) in ds.iter().enumerate() {
                if sites[c].interface == i && c != j {
                    wd += weight(c) * d;
                    ww += weight(c) * weight(c);
                    dd += d * d;
                    n += 1;
                }
            }
            let coef = wd / ww.max(f64::MIN_POSITIVE);
            let left = ((dd - coef * wd).max(0.0) / n.max(1) as f64).sqrt();
            line.push_str(&format!(
                " i{i} {coef:.4e} {left:.2e} {:.2e};",
                (dd / n.max(1) as f64).sqrt()
            ));
        }
        println!("{line}");
        println!(
            "{j} {} {:.3} {:.2} {:.3} {:.3} {} {:.4} {:.3} {:.3} {:.4} {:.4} {:.4} {:.4} ({},{:.4}) {count}",
            site.interface,
            site.theta_rad,
            b.normal_force_n,
            b.tangential_force_n,
            se / gamma,
            perturbed.len(),
            a,
            a / (1.0 - a),
            law,
            sector,
            same,
            inner,
            outer,
            largest.0,
            largest.1,
        );
    }
    println!("{:.1} s in all", t0.elapsed().as_secs_f64());
    Ok(())
}

/// The collective modes of `measure-modes`, from their JSON file.
fn modes_of(path: &Option<String>) -> Result<ModeCoupling, Error> {
    let path = path
        .as_ref()
        .ok_or("--modes MODES.json (written by `measure-modes`)")?;
    Ok(serde_json::from_str(&std::fs::read_to_string(path)?)?)
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().ok_or("record | fit")?.clone();
    let (mut ea, mut margin, mut run_in_s, mut to_s) = (None, 0.05, 100.0, f64::INFINITY);
    let mut x_above = f64::NEG_INFINITY;
    let (mut interface, mut contact) = (0usize, None::<usize>);
    let mut probe: Option<String> = None;
    let (mut path, mut parts) = (String::new(), 8usize);
    let (mut loads, mut held_out, mut positional) = (Vec::new(), Vec::new(), Vec::new());
    let mut write: Option<String> = None;
    let (mut points, mut couple_contacts, mut delta, mut sector_rad) =
        (Vec::new(), Vec::new(), 1e-6, 0.0);
    let mut pattern = 0usize;
    let mut calibration: Option<String> = None;
    let mut modes_file: Option<String> = None;
    let mut contact_mechanics = false;
    let mut it = args[1..].iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().cloned().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--ea" => ea = Some(value()?.parse::<f64>()?),
            "--margin" => margin = value()?.parse()?,
            "--run-in-s" => run_in_s = value()?.parse()?,
            "--to-s" => to_s = value()?.parse()?,
            "--x-above" => x_above = value()?.parse()?,
            "--interface" => interface = value()?.parse()?,
            "--contact" => contact = Some(value()?.parse()?),
            "--path" => path = value()?,
            "--parts" => parts = value()?.parse()?,
            "--probe" => probe = Some(value()?),
            "--load" => loads.push(value()?),
            "--held-out" => {
                let load = value()?;
                held_out.push((load, value()?));
            }
            "--write" => write = Some(value()?),
            "--at" => {
                let v = value()?;
                let (x, y) = v.split_once(',').ok_or("--at x,y")?;
                points.push((x.trim().parse::<f64>()?, y.trim().parse::<f64>()?));
            }
            "--contacts" => {
                for c in value()?.split(',') {
                    couple_contacts.push(c.trim().parse::<usize>()?);
                }
            }
            "--delta" => delta = value()?.parse()?,
            "--sector-rad" => sector_rad = value()?.parse()?,
            "--pattern" => pattern = value()?.parse()?,
            "--calibration" => calibration = Some(value()?),
            "--modes" => modes_file = Some(value()?),
            "--contact-mechanics" => contact_mechanics = true,
            _ => positional.push(a.clone()),
        }
    }
    let ea = ea.ok_or("--ea N (the strand model's EA, as `moorfret run strand` prints it)")?;
    let recording = positional.first().ok_or("REC.bin")?.clone();
    let recording = &recording;
    let (model, key) = model(contact_mechanics)?;
    let range = range_of(&loads, ea, margin)?;
    println!(
        "range: strain {:?}, curvature {:?} 1/m",
        range.strain, range.curvature_per_m
    );
    let options = CalibrationOptions::default();
    if mode == "measure-modes" {
        // the interfaces' collective modes as a calibration measures them, to a JSON file
        // (for `fit` with MF_MODES_FILE)
        let t = std::time::Instant::now();
        let two = CalibrationOptions {
            history: HistoryOptions {
                threads: 2,
                ..options.history
            },
            ..options.clone()
        };
        let modes = moorfret_solver::strand::reduced::measure_modes(&model, range, &two)?;
        std::fs::write(recording, serde_json::to_string(&modes)?)?;
        println!("modes measured in {:.1} s", t.elapsed().as_secs_f64());
        return Ok(());
    }
    if mode == "couple" {
        let scaling = moorfret_solver::strand::reduced::LoadScaling::of(&range);
        let reduced = match &calibration {
            Some(path) => Some(ReducedStrand::from_json(&std::fs::read(path)?)?),
            None => None,
        };
        let mut csv = match positional.get(1) {
            Some(path) => Some(std::fs::File::create(path)?),
            None => None,
        };
        for &point in &points {
            couple(
                &model,
                &scaling,
                point,
                &couple_contacts,
                delta,
                sector_rad,
                pattern,
                reduced.as_ref(),
                csv.as_mut(),
            )?;
        }
        return Ok(());
    }
    if mode == "record-path" {
        // a straight-line path through scaled load vertices "x,y;x,y;…", `parts` samples per
        // stretch, one second apart
        let scaling = moorfret_solver::strand::reduced::LoadScaling::of(&range);
        let mut vertices = Vec::new();
        for v in path.split(';') {
            let (x, y) = v.split_once(',').ok_or("--path x,y;x,y;…")?;
            vertices.push((x.trim().parse::<f64>()?, y.trim().parse::<f64>()?));
        }
        let mut samples = Vec::new();
        let mut push = |x: f64, y: f64| {
            let (strain, curvature_per_m) = scaling.load(x, y);
            samples.push(LoadSample {
                time_s: samples.len() as f64,
                strain,
                curvature_per_m,
            });
        };
        push(vertices[0].0, vertices[0].1);
        for w in vertices.windows(2) {
            for k in 1..=parts {
                let f = k as f64 / parts as f64;
                push(
                    w[0].0 + f * (w[1].0 - w[0].0),
                    w[0].1 + f * (w[1].1 - w[0].1),
                );
            }
        }
        return record(
            &model,
            std::slice::from_ref(&samples),
            &HistoryOptions::default(),
            recording,
        );
    }
    if mode == "slopes" {
        // per contact, the slip's slope on y (linear fit on 1, x, y) over a window of each
        // recording "REC.bin:t0:t1"; per interface the spread of the ratio to the first's
        let scaling = moorfret_solver::strand::reduced::LoadScaling::of(&range);
        let mut fits: Vec<Vec<(usize, f64, f64)>> = Vec::new();
        for spec in &positional[0..] {
            let mut it = spec.split(':');
            let file = it.next().ok_or("REC.bin:t0:t1")?;
            let t0: f64 = it.next().ok_or("t0")?.parse()?;
            let t1: f64 = it.next().ok_or("t1")?.parse()?;
            let rec: Vec<RecordedSample> = read_recording(Path::new(file))?
                .into_iter()
                .filter(|r| r.0.time_s >= t0 && r.0.time_s <= t1)
                .collect();
            let xy: Vec<(f64, f64)> = rec
                .iter()
                .map(|r| scaling.scaled(r.0.strain, r.0.curvature_per_m))
                .collect();
            let cols = vec![
                vec![1.0; xy.len()],
                xy.iter().map(|p| p.0).collect::<Vec<_>>(),
                xy.iter().map(|p| p.1).collect::<Vec<_>>(),
            ];
            let nc = rec.first().map_or(0, |r| r.1.len());
            let sites = moorfret_solver::strand::history::monitors::contact_sites(&model);
            let mut f = Vec::with_capacity(nc);
            for (c, site) in sites.iter().enumerate().take(nc) {
                let y: Vec<f64> = rec.iter().map(|r| r.1[c].slip_m).collect();
                let (beta, rms) = least_squares(&cols, &y);
                f.push((site.interface, beta[2], rms));
            }
            println!(
                "{spec}: {} samples, y from {:.3} to {:.3}, x from {:.3} to {:.3}",
                xy.len(),
                xy.iter().map(|p| p.1).fold(f64::MAX, f64::min),
                xy.iter().map(|p| p.1).fold(f64::MIN, f64::max),
                xy.iter().map(|p| p.0).fold(f64::MAX, f64::min),
                xy.iter().map(|p| p.0).fold(f64::MIN, f64::max)
            );
            fits.push(f);
        }
        let interfaces = fits[0].iter().map(|f| f.0 + 1).max().unwrap_or(0);
        for (k, f) in fits.iter().enumerate().skip(1) {
            println!("{} against {}:", positional[k], positional[0]);
            for i in 0..interfaces {
                let mut r: Vec<f64> = f
                    .iter()
                    .zip(&fits[0])
                    .filter(|(a, b)| a.0 == i && b.1.abs() > 0.0)
                    .map(|(a, b)| a.1 / b.1)
                    .collect();
                let [p10, p50, p90] = percentiles(&mut r);
                let mut big: Vec<(f64, f64)> = f
                    .iter()
                    .zip(&fits[0])
                    .filter(|(a, _)| a.0 == i)
                    .map(|(a, b)| (b.1.abs(), a.1 / b.1))
                    .collect();
                big.sort_by(|a, b| b.0.total_cmp(&a.0));
                let top: Vec<String> = big.iter().take(5).map(|v| format!("{:.3}", v.1)).collect();
                println!(
                    "  interface {i}: slope ratio p10 {p10:.3}, median {p50:.3}, p90 {p90:.3};                      five steepest {}",
                    top.join(" ")
                );
            }
        }
        return Ok(());
    }
    if mode == "open" {
        // per interface and tension bin, the share of a recording's contacts without normal
        // force (open: the FE resets their elastic slip)
        let rec = read_recording(Path::new(recording))?;
        let scaling = moorfret_solver::strand::reduced::LoadScaling::of(&range);
        let sites = moorfret_solver::strand::history::monitors::contact_sites(&model);
        let interfaces = interface_count(&sites);
        let bins = [-1.1, -0.95, -0.9, -0.8, -0.6, -0.2, 0.2, 1.1];
        for i in 0..interfaces {
            let mut line = format!("interface {i}:");
            for b in bins.windows(2) {
                let (mut open, mut n) = (0usize, 0usize);
                for r in &rec {
                    let x = scaling.scaled(r.0.strain, r.0.curvature_per_m).0;
                    if x < b[0] || x >= b[1] {
                        continue;
                    }
                    for (c, site) in sites.iter().enumerate() {
                        if site.interface == i {
                            n += 1;
                            open += usize::from(r.1[c].normal_force_n <= 0.0);
                        }
                    }
                }
                line.push_str(&format!(
                    " [{:.2},{:.2}) {:.4} of {}",
                    b[0],
                    b[1],
                    open as f64 / n.max(1) as f64,
                    n
                ));
            }
            println!("{line}");
        }
        return Ok(());
    }
    if mode == "trace" {
        // REC --probe HELD --interface I: the series of the interface-I contact with the largest
        // FE slip range in HELD (or of `--contact C`), FE against reduced, sample by sample
        let rec = chains_of(read_recording(Path::new(recording))?);
        let mut reduced = fit_recorded(&model, range, &options, modes_of(&modes_file)?, rec)?;
        reduced.model_key = key;
        let held = read_recording(Path::new(probe.as_deref().ok_or("--probe HELD.bin")?))?;
        let loads: Vec<LoadSample> = held.iter().map(|h| h.0).collect();
        let series = contact_series(&reduced, &loads)?;
        let range_of = |c: usize| {
            let v = held.iter().map(|h| h.1[c].slip_m);
            v.clone().fold(f64::MIN, f64::max) - v.fold(f64::MAX, f64::min)
        };
        let c = if let Some(c) = contact {
            c
        } else {
            (0..reduced.sites.len())
                .filter(|&c| reduced.sites[c].interface == interface)
                .max_by(|&a, &b| range_of(a).total_cmp(&range_of(b)))
                .ok_or("no contact")?
        };
        // the interface's f_N error at the first sample, per contact
        let mut errs: Vec<f64> = (0..reduced.sites.len())
            .filter(|&c| reduced.sites[c].interface == interface)
            .map(|c| series[c][0].normal_force_n / held[0].1[c].normal_force_n - 1.0)
            .filter(|v| v.is_finite())
            .collect();
        println!(
            "f_N red/FE - 1 at the first sample, p10/50/90: {:?}",
            percentiles(&mut errs)
        );
        let law = &reduced.laws[c];
        println!(
            "contact {c} theta {:.3} g {:?}",
            reduced.sites[c].theta_rad, law.compliance
        );
        println!("t x y s_fe s_red ft_fe ft_red fn_fe fn_red");
        for (h, r) in held.iter().zip(&series[c]) {
            let (x, y) = reduced.scaling.scaled(h.0.strain, h.0.curvature_per_m);
            let a = &h.1[c];
            println!(
                "{:.1} {x:.3} {y:.3} {:.4e} {:.4e} {:.3} {:.3} {:.2} {:.2}",
                h.0.time_s,
                a.slip_m,
                r.slip_m,
                a.tangential_force_n,
                r.tangential_force_n,
                a.normal_force_n,
                r.normal_force_n
            );
        }
        return Ok(());
    }
    if mode == "record-load" {
        let load = positional
            .get(1)
            .ok_or("record-load REC.bin LOAD.csv --to-s T")?;
        let samples: Vec<LoadSample> = read_load(load, ea)?
            .into_iter()
            .filter(|s| s.time_s <= to_s)
            .collect();
        println!("{} load samples up to t = {to_s} s", samples.len());
        return record(
            &model,
            std::slice::from_ref(&samples),
            &HistoryOptions::default(),
            recording,
        );
    }
    if mode == "record" {
        let (design, history) = calibration_design(&model, range, &options)?;
        println!(
            "{} designed samples in {} chains",
            design.iter().map(Vec::len).sum::<usize>(),
            design.len()
        );
        let history = HistoryOptions {
            threads: 2,
            ..history
        };
        return record(&model, &design, &history, recording);
    }
    let samples = chains_of(read_recording(Path::new(recording))?);
    println!(
        "{} recorded samples in {} chains",
        samples.iter().map(Vec::len).sum::<usize>(),
        samples.len()
    );
    let mut references = Vec::new();
    for (load, dir) in &held_out {
        let text = std::fs::read_to_string(Path::new(dir).join("contact_records.json"))?;
        let fe: Vec<ContactRecord> = serde_json::from_str(&text)?;
        references.push((read_load(load, ea)?, fe, dir.clone()));
    }
    let mut reduced = fit_recorded(&model, range, &options, modes_of(&modes_file)?, samples)?;
    reduced.model_key = key;
    for f in &reduced.calibration.fits {
        println!(
            "fit interface {}: slip rms residual / spread {:.3}",
            f.interface,
            f.slip_rms_residual_m / f.slip_rms_m.max(f64::MIN_POSITIVE)
        );
    }
    if let Some(path) = &probe {
        probe_recorded(
            &reduced,
            &read_recording(Path::new(path))?,
            run_in_s,
            x_above,
        )?;
    }
    if let Some(path) = &write {
        std::fs::write(path, serde_json::to_string(&reduced)?)?;
    }
    for (load, fe, dir) in &references {
        let r = run_reduced(&reduced, load, &HistoryOptions::default())?;
        let dt = load.get(1).map_or(0.1, |s| s.time_s) - load[0].time_s;
        let from = (run_in_s / dt).round() as usize;
        println!("{dir}: largest slip range, accumulated slip, cycles ≥ 1 µm (reduced / FE − 1)");
        for c in compare_records(fe, &r.contacts, 1e-6, from) {
            println!(
                "  interface {}: {:.3e} → {:.3e} m ({:+.1} %), {:.4e} → {:.4e} m ({:+.1} %), \
                 {} → {} ({:+.1} %)",
                c.interface,
                c.reference.max_slip_range_m,
                c.compared.max_slip_range_m,
                100.0 * c.max_slip_range_error,
                c.reference.accumulated_slip_m,
                c.compared.accumulated_slip_m,
                100.0 * c.accumulated_slip_error,
                c.reference.cycles,
                c.compared.cycles,
                100.0 * c.cycles_error
            );
        }
        per_contact(fe, &r.contacts);
    }
    Ok(())
}
