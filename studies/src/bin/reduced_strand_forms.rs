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
//!     --held-out LOAD.csv FE_DIR [--held-out …] [--run-in-s 100] [--write CALIB.json]
//! ```
//!
//! The model is the paper campaign's: the six-layer strand, periodic ends, ε_N = 2e8 N/m,
//! γ_e = 10 µm; loads are `moorfret run global` hot-spot files (hot spot 0), ε = T / EA with
//! the EA that `moorfret run strand` prints. The range is the loads' widened by `--margin`, as
//! `moorfret strand calibrate` makes it. `--write` stores the fitted calibration with the key
//! of this model, for `moorfret run strand --fidelity reduced --calibration`.

use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

use moorfret_solver::fretting::{ContactRecord, ContactSample};
use moorfret_solver::strand::history::stiffness::{samples_from_tension, SlackTension};
use moorfret_solver::strand::history::{
    checkpoint::HistoryCheckpoint, run_history, HistoryObserver, HistoryOptions, HistoryProgress,
    LoadSample,
};
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::profile::profiles_from_json;
use moorfret_solver::strand::reduced::compare::compare_records;
use moorfret_solver::strand::reduced::{
    calibration_design, fit_recorded, model_key, run_reduced, CalibrationOptions, LoadRange,
    RecordedSample,
};
use moorfret_studies::load_file;

const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));

type Error = Box<dyn std::error::Error>;

/// The paper campaign's strand model.
fn model() -> Result<(StrandModel, String), Error> {
    let strand = profiles_from_json(PROFILES)?
        .get("paper_six_layer")
        .ok_or("profile paper_six_layer missing")?
        .validate()?;
    let params = StrandModelParameters::penalty_contact(2e8, 1e-5, EndKind::Periodic);
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

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().ok_or("record | fit")?.clone();
    let (mut ea, mut margin, mut run_in_s) = (None, 0.05, 100.0);
    let (mut loads, mut held_out, mut positional) = (Vec::new(), Vec::new(), Vec::new());
    let mut write: Option<String> = None;
    let mut it = args[1..].iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().cloned().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--ea" => ea = Some(value()?.parse::<f64>()?),
            "--margin" => margin = value()?.parse()?,
            "--run-in-s" => run_in_s = value()?.parse()?,
            "--load" => loads.push(value()?),
            "--held-out" => {
                let load = value()?;
                held_out.push((load, value()?));
            }
            "--write" => write = Some(value()?),
            _ => positional.push(a.clone()),
        }
    }
    let ea = ea.ok_or("--ea N (the strand model's EA, as `moorfret run strand` prints it)")?;
    let recording = positional.first().ok_or("REC.bin")?;
    let (model, key) = model()?;
    let range = range_of(&loads, ea, margin)?;
    println!(
        "range: strain {:?}, curvature {:?} 1/m",
        range.strain, range.curvature_per_m
    );
    let options = CalibrationOptions::default();
    if mode == "record" {
        let (design, history) = calibration_design(&model, range, &options)?;
        println!("{} designed samples", design.len());
        let mut recorder = Recorder {
            out: BufWriter::new(std::fs::File::create(recording)?),
            error: None,
            samples: 0,
        };
        let t = std::time::Instant::now();
        let fe = run_history(&model, &design, &history, &mut recorder)?;
        recorder.out.flush()?;
        if let Some(e) = recorder.error {
            return Err(e.into());
        }
        println!(
            "recorded {} samples: {} sub-steps, {} Newton iterations, {:.1} s",
            recorder.samples,
            fe.stats.substeps,
            fe.stats.iterations,
            t.elapsed().as_secs_f64()
        );
        return Ok(());
    }
    let samples = read_recording(Path::new(recording))?;
    println!("{} recorded samples", samples.len());
    let mut references = Vec::new();
    for (load, dir) in &held_out {
        let text = std::fs::read_to_string(Path::new(dir).join("contact_records.json"))?;
        let fe: Vec<ContactRecord> = serde_json::from_str(&text)?;
        references.push((read_load(load, ea)?, fe, dir.clone()));
    }
    let mut reduced = fit_recorded(&model, range, &options, samples)?;
    reduced.model_key = key;
    for f in &reduced.calibration.fits {
        println!(
            "fit interface {}: slip rms residual / spread {:.3}",
            f.interface,
            f.slip_rms_residual_m / f.slip_rms_m.max(f64::MIN_POSITIVE)
        );
    }
    if let Some(path) = &write {
        std::fs::write(path, serde_json::to_string(&reduced)?)?;
    }
    for (load, fe, dir) in &references {
        let r = run_reduced(&reduced, load, HistoryOptions::default().slip_gate_m)?;
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
