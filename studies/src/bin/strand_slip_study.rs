//! Anatomy of the Newton work of the 1+6+1 benchmark strand in bending: per load-step attempt
//! the target load factor and increment Δλ, the iterations, the number of contacts whose status
//! changes (stick ↔ slip ↔ open) between consecutive iterations, the residual history against
//! the tolerance, and why a rejected attempt failed (iteration limit or divergence).
//!
//! `cargo run --release -p moorfret-studies --bin strand_slip_study [kappa [set [verbose]]]`
//! with `set` one of `vs_analytical` (default) or `vs_surface_model`; `verbose` prints every
//! attempt of the bending stage, otherwise a summary and the first and last attempts.

use moorfret_solver::beam::frame::FrameError;
use moorfret_solver::contact::ContactStatus;
use moorfret_solver::linalg::{
    solve_load_path, NewtonParams, NewtonStats, NewtonWorkspace, NonlinearProblem,
};
use moorfret_solver::strand::driver::StrandRunParameters;
use moorfret_solver::strand::loading::LoadPath;
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::problem::StrandProblem;
use moorfret_solver::strand::profile::profile_from_json;

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));

/// One attempt of a load step.
#[derive(Debug, Default, Clone)]
struct Attempt {
    from: f64,
    target: f64,
    /// (‖r‖, tolerance, slip count, stick count, status changes since the previous iterate).
    iterates: Vec<(f64, f64, usize, usize, usize)>,
    accepted: bool,
    failed_evaluation: bool,
}

struct Probe<'a> {
    inner: StrandProblem<'a>,
    tolerance: f64,
    committed: f64,
    current: Attempt,
    previous: Vec<Option<ContactStatus>>,
    log: Vec<Attempt>,
    /// Print every bending-stage attempt as it ends.
    stream: bool,
}

impl Probe<'_> {
    fn close(&mut self, accepted: bool) {
        let mut a = std::mem::take(&mut self.current);
        a.accepted = accepted;
        if self.stream && a.from >= 1.0 {
            print_attempt(self.log.len(), &a, true);
        }
        self.log.push(a);
        self.previous.clear();
    }
}

impl NonlinearProblem for Probe<'_> {
    type Error = FrameError;
    fn evaluate(
        &mut self,
        load_factor: f64,
        residual: &mut [f64],
        tangent: Option<&mut [f64]>,
    ) -> Result<f64, FrameError> {
        if self.current.iterates.is_empty() {
            self.current.from = self.committed;
            self.current.target = load_factor;
        }
        let scale = match self.inner.evaluate(load_factor, residual, tangent) {
            Ok(s) => s,
            Err(e) => {
                self.current.failed_evaluation = true;
                return Err(e);
            }
        };
        let norm = residual.iter().map(|v| v * v).sum::<f64>().sqrt();
        let status: Vec<Option<ContactStatus>> = self
            .inner
            .responses()
            .iter()
            .map(|r| r.map(|r| r.status))
            .collect();
        let count = |s| status.iter().filter(|x| **x == Some(s)).count();
        let flips = if self.previous.is_empty() {
            0
        } else {
            status
                .iter()
                .zip(&self.previous)
                .filter(|(a, b)| a != b)
                .count()
        };
        self.current.iterates.push((
            norm,
            self.tolerance * scale,
            count(ContactStatus::Slip),
            count(ContactStatus::Stick),
            flips,
        ));
        self.previous = status;
        Ok(scale)
    }
    fn apply_increment(&mut self, increment: &[f64]) {
        self.inner.apply_increment(increment)
    }
    fn commit(&mut self, load_factor: f64) {
        self.inner.commit(load_factor);
        self.committed = load_factor;
        self.close(true);
    }
    fn restore(&mut self) {
        self.inner.restore();
        self.close(false);
    }
    fn merit_weights(&self) -> Option<&[f64]> {
        self.inner.merit_weights()
    }
    fn preconditioner(&self) -> Option<&[f64]> {
        self.inner.preconditioner()
    }
}

fn print_attempt(i: usize, a: &Attempt, full: bool) {
    let last = a.iterates.last().copied().unwrap_or_default();
    let flips: usize = a.iterates.iter().map(|x| x.4).sum();
    println!(
        "#{i:5} {} λ {:.6} Δλ {:.3e} it {:2} flips {:4} slip {:3} stick {:3} |r| {:.2e} tol {:.2e}{}",
        if a.accepted { "ok " } else { "CUT" },
        a.target,
        a.target - a.from,
        a.iterates.len().saturating_sub(1),
        flips,
        last.2,
        last.3,
        last.0,
        last.1,
        if a.failed_evaluation { " (evaluation failed)" } else { "" }
    );
    if full {
        let r: Vec<String> = a
            .iterates
            .iter()
            .map(|x| format!("{:.1e}/{}/{}:{}", x.0, x.4, x.2, x.3))
            .collect();
        println!("        |r|/changes/slip:stick: {}", r.join(" "));
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kappa: f64 = args.first().and_then(|a| a.parse().ok()).unwrap_or(1.0);
    let set = args.get(1).map_or("vs_analytical", String::as_str);
    let verbose = args.get(2).is_some();
    let (penalty, gamma) = match set {
        "vs_surface_model" => (2e6, 1e-5),
        _ => (2e8, 1e-7),
    };
    let strand = profile_from_json(BENCHMARK)
        .and_then(|p| p.validate())
        .expect("benchmark profile is valid");
    let params = StrandModelParameters::penalty_contact(penalty, gamma, EndKind::PenaltyTies);
    let model = StrandModel::new(&strand, &params).expect("model builds");
    let run = StrandRunParameters::default();
    let mut probe = Probe {
        inner: StrandProblem::new(
            &model,
            LoadPath {
                strain: 1e-3,
                curvature_per_m: kappa,
            },
        ),
        tolerance: run.newton.relative_tolerance,
        committed: 0.0,
        current: Attempt::default(),
        previous: Vec::new(),
        log: Vec::new(),
        stream: verbose,
    };
    let mut solver = model.linear_solver().expect("symbolic analysis");
    let mut ws = NewtonWorkspace::new(&model.pattern);
    let mut stats = NewtonStats::default();
    for (stage, (from, inc)) in [(0.0, run.tension_increment), (1.0, run.bending_increment)]
        .into_iter()
        .enumerate()
    {
        let t = std::time::Instant::now();
        let np = NewtonParams {
            initial_load_increment: inc,
            ..run.newton
        };
        let first = probe.log.len();
        let r = solve_load_path(
            &mut probe,
            from,
            from + 1.0,
            &model.pattern,
            &mut solver,
            &np,
            &mut ws,
            &mut stats,
        );
        let log = &probe.log[first..];
        let acc: Vec<&Attempt> = log.iter().filter(|a| a.accepted).collect();
        let cut: Vec<&Attempt> = log.iter().filter(|a| !a.accepted).collect();
        let max_it = cut
            .iter()
            .filter(|a| a.iterates.len() == run.newton.max_iterations + 1)
            .count();
        let its: usize = log.iter().map(|a| a.iterates.len() - 1).sum();
        let flips: usize = log.iter().flat_map(|a| &a.iterates).map(|x| x.4).sum();
        let acc_flips: usize = acc.iter().flat_map(|a| &a.iterates).map(|x| x.4).sum();
        let acc_its: usize = acc.iter().map(|a| a.iterates.len() - 1).sum();
        let mut dl: Vec<f64> = acc.iter().map(|a| a.target - a.from).collect();
        dl.sort_by(f64::total_cmp);
        println!(
            "stage {} κ {kappa} {set}: {:?}; {:.2} s; {} accepted, {} cut ({} at the iteration \
             limit, {} diverged or failed); iterations {} ({} in accepted steps, {:.1} per \
             accepted step); status changes {} ({} in accepted steps, {:.2} per accepted iteration)",
            stage + 1,
            r.as_ref().map(|_| "ok").map_err(|e| e.to_string()),
            t.elapsed().as_secs_f64(),
            acc.len(),
            cut.len(),
            max_it,
            cut.len() - max_it,
            its,
            acc_its,
            acc_its as f64 / acc.len().max(1) as f64,
            flips,
            acc_flips,
            acc_flips as f64 / acc_its.max(1) as f64,
        );
        if !dl.is_empty() {
            let q = |p: f64| dl[((dl.len() - 1) as f64 * p).round() as usize];
            println!(
                "  accepted Δλ: min {:.2e} median {:.2e} max {:.2e}",
                q(0.0),
                q(0.5),
                q(1.0)
            );
            let mut hist = [0usize; 32];
            for a in &acc {
                hist[(a.iterates.len() - 1).min(31)] += 1;
            }
            let h: Vec<String> = hist
                .iter()
                .enumerate()
                .filter(|(_, n)| **n > 0)
                .map(|(i, n)| format!("{i}:{n}"))
                .collect();
            println!(
                "  iterations per accepted step (iterations:count): {}",
                h.join(" ")
            );
        }
        if stage == 1 {
            for (i, a) in log.iter().enumerate() {
                if !verbose && (i < 25 || i + 10 >= log.len()) {
                    print_attempt(i, a, i < 25);
                }
            }
        }
        println!("  linear solver: {:?}", solver.stats());
    }
}
