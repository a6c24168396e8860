//! Kinematics for the global stage of the paper case: ~600 line nodes + ~100 floater strip
//! points, Hs = 8.75 m, Tp = 16.5 s, γ = 1.3, 100 m depth, 1000 s. Compares precomputation by
//! FFT plus interpolation with direct summation over the wave components.

use criterion::{criterion_group, criterion_main, Criterion};
use moorfret_solver::waves::{
    IrregularSea, Jonswap, PeakEnhancement, PointKinematicsSeries, PointSample, RealisationParams,
    SeaKinematics, SeriesParams,
};
use nalgebra::Vector3;

fn paper_sea() -> IrregularSea {
    let s = Jonswap::new(8.75, 16.5, PeakEnhancement::Given(1.3)).unwrap();
    IrregularSea::new(
        &s,
        &RealisationParams {
            seed: 1,
            ..Default::default()
        },
    )
    .unwrap()
}

/// Six lines of 100 nodes from their fairleads (radius 40.9 m, z = −14 m) over 555 m to the
/// anchors, suspended over the first 250 m and on the seabed (z = −100 m) beyond, as in the
/// paper case; and 100 strip points on the floater's columns between z = −20 m and the still
/// water level.
fn points() -> Vec<Vector3<f64>> {
    let mut p = Vec::new();
    for line in 0..6 {
        let azimuth = (line as f64 * 60.0 + 5.0).to_radians();
        let (c, s) = (azimuth.cos(), azimuth.sin());
        for i in 0..100 {
            let r = 555.0 * i as f64 / 99.0;
            let z = -14.0 - 86.0 * (r / 250.0).min(1.0).powf(1.5);
            p.push(Vector3::new((40.9 + r) * c, (40.9 + r) * s, z));
        }
    }
    p.extend((0..100).map(|i| {
        let a = (i / 10) as f64 * 0.6;
        Vector3::new(
            28.9 * a.cos(),
            28.9 * a.sin(),
            -20.0 * (i % 10) as f64 / 9.0,
        )
    }));
    p
}

fn bench(c: &mut Criterion) {
    let sea = paper_sea();
    let pts = points();
    let mut g = c.benchmark_group("waves_700_points");
    g.sample_size(10);
    g.bench_function("series_build", |b| {
        b.iter(|| PointKinematicsSeries::new(&sea, &pts, &SeriesParams::default()).unwrap())
    });
    g.bench_function("series_build_2_threads", |b| {
        b.iter(|| {
            PointKinematicsSeries::new(
                &sea,
                &pts,
                &SeriesParams {
                    threads: 2,
                    ..Default::default()
                },
            )
            .unwrap()
        })
    });
    let series = PointKinematicsSeries::new(&sea, &pts, &SeriesParams::default()).unwrap();
    let mut out = vec![PointSample::default(); pts.len()];
    let mut t = 0.0;
    g.bench_function("series_sample_all_one_step", |b| {
        b.iter(|| {
            t += 0.05;
            series.sample_all(t, &mut out);
            out[0].kinematics.velocity.x
        })
    });
    g.bench_function("direct_summation_one_step", |b| {
        b.iter(|| {
            t += 0.05;
            pts.iter()
                .map(|p| sea.kinematics(p, t).velocity.x)
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
