//! Rainflow counting throughput (DESIGN §7 target: ≥ 50 M samples/s on one core).
//!
//! Two signals of one million samples each: seeded white noise (the worst case: two reversals
//! in three samples) and a narrow-band signal (a few sinusoids near one frequency with random
//! phases, 20 samples per period, like a slip history sampled through wave cycles).
//! Run: `cargo bench -p moorfret-solver --bench rainflow`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use moorfret_solver::fretting::rainflow::{Cycle, RainflowCounter, RainflowOptions};
use moorfret_solver::fretting::streaming::StreamingRainflow;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

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

fn bench(c: &mut Criterion) {
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

criterion_group!(benches, bench);
criterion_main!(benches);
