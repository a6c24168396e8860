//! Rainflow counting throughput (target ≥ 50 M samples/s on one core,
//! `docs/benchmarks.md`).
//!
//! Two signals of one million samples each: seeded white noise (the worst case: two reversals
//! in three samples) and a narrow-band signal (a few sinusoids near one frequency with random
//! phases, 20 samples per period, like a slip history sampled through wave cycles).
//! Run: `cargo bench -p moorfret-solver --bench rainflow`.
//!
//! Time is the CPU time of the benchmarking thread (Linux `/proc/thread-self/schedstat`), so
//! the figures are single-core throughput even on a machine shared with other work; elsewhere
//! it falls back to wall-clock time.

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use moorfret_solver::fretting::rainflow::{Cycle, RainflowCounter, RainflowOptions};
use moorfret_solver::fretting::streaming::StreamingRainflow;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Instant;

/// CPU time of the current thread in nanoseconds, wall-clock time where unavailable.
struct ThreadCpuTime {
    origin: Instant,
}

impl ThreadCpuTime {
    fn now_ns(&self) -> f64 {
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
            .unwrap_or_else(|| self.origin.elapsed().as_nanos() as f64)
    }
}

impl Measurement for ThreadCpuTime {
    type Intermediate = f64;
    type Value = f64;
    fn start(&self) -> f64 {
        self.now_ns()
    }
    fn end(&self, start: f64) -> f64 {
        self.now_ns() - start
    }
    fn add(&self, a: &f64, b: &f64) -> f64 {
        a + b
    }
    fn zero(&self) -> f64 {
        0.0
    }
    fn to_f64(&self, value: &f64) -> f64 {
        *value
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &NanosFormatter
    }
}

/// Formats nanoseconds as ms and throughputs as M elements / s.
struct NanosFormatter;

impl ValueFormatter for NanosFormatter {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        values.iter_mut().for_each(|v| *v *= 1e-6);
        "ms"
    }
    fn scale_throughputs(
        &self,
        _typical: f64,
        throughput: &Throughput,
        values: &mut [f64],
    ) -> &'static str {
        let per_iteration = match *throughput {
            Throughput::Elements(n) | Throughput::Bytes(n) | Throughput::BytesDecimal(n) => {
                n as f64
            }
        };
        values
            .iter_mut()
            .for_each(|v| *v = per_iteration / (*v * 1e-9) * 1e-6);
        "Melem/s"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

const N: usize = 1_000_000;

fn white_noise(seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..N).map(|_| rng.gen_range(-1.0..1.0)).collect()
}

fn narrow_band(seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let components: Vec<(f64, f64, f64)> = (0..8)
        .map(|_| {
            let freq = 1.0 / 20.0 * rng.gen_range(0.9..1.1);
            (
                rng.gen_range(0.2..1.0),
                freq,
                rng.gen_range(0.0..std::f64::consts::TAU),
            )
        })
        .collect();
    (0..N)
        .map(|i| {
            let t = i as f64;
            components
                .iter()
                .map(|(a, f, p)| a * (std::f64::consts::TAU * f * t + p).sin())
                .sum()
        })
        .collect()
}

fn bench(c: &mut Criterion<ThreadCpuTime>) {
    let signals = [
        ("white_noise", white_noise(1)),
        ("narrow_band", narrow_band(2)),
    ];
    let mut group = c.benchmark_group("rainflow");
    group.throughput(Throughput::Elements(N as u64));
    group.sample_size(20);
    for (name, history) in &signals {
        let mut counter = RainflowCounter::new(RainflowOptions::default()).unwrap();
        let mut out: Vec<Cycle> = Vec::with_capacity(N);
        group.bench_with_input(BenchmarkId::new("batch", name), history, |b, h| {
            b.iter(|| {
                out.clear();
                counter.count_into(black_box(h), &mut out).unwrap();
                black_box(out.len())
            })
        });
        group.bench_with_input(BenchmarkId::new("streaming", name), history, |b, h| {
            b.iter(|| {
                out.clear();
                let mut s = StreamingRainflow::<()>::new(0.0).unwrap();
                for &x in black_box(h) {
                    s.push(x, &mut out).unwrap();
                }
                s.finish(&mut out);
                black_box(out.len())
            })
        });
    }
    group.finish();
}

fn cpu_time() -> Criterion<ThreadCpuTime> {
    Criterion::default().with_measurement(ThreadCpuTime {
        origin: Instant::now(),
    })
}

criterion_group! {
    name = benches;
    config = cpu_time();
    targets = bench
}
criterion_main!(benches);
