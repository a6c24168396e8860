//! Cost of the strand model's building blocks: one corotational element (force + tangent),
//! assembly of 12 000 elements into the sparse pattern, and the sparse Cholesky factor + solve
//! of a ~75 000-DOF system of 121 parallel wires × 100 elements tied by ~7 300 springs (the
//! size of the six-layer strand model).
//!
//! Run: `cargo bench -p moorfret-solver --bench beam`.
//!
//! Figures on the 2-core development machine (shared, so the 2-thread rows are not a clean
//! speed-up measurement): element force 0.75 µs, force + tangent 2.4 µs; scatter of 12 000
//! 12 × 12 matrices into the symmetric pattern 2.1 ms; bundle (72 600 DOF, 12 100 beams,
//! 7 334 ties, 0.95 M stored entries) assembly 44 ms; symbolic analysis with AMD 0.19 s
//! (19.6 M factor entries, supernodal); numeric LLᵀ 0.94 s; solve 61 ms.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use faer::Par;
use moorfret_solver::beam::corotational::{CorotationalBeam, Matrix12, Vector12};
use moorfret_solver::beam::frame::{
    assemble_frame, assemble_frame_parallel, BeamFrame, DofMap, FrameState, FrameWorkspace, NodeId,
};
use moorfret_solver::beam::rotation::exp_so3;
use moorfret_solver::beam::section::BeamSection;
use moorfret_solver::linalg::{
    CholeskyKind, Equation, LinearSolver, SparseCholesky, SparsePattern, Storage,
};
use nalgebra::Vector3;

const WIRE_RADIUS_M: f64 = 2.3e-3;
const LENGTH_M: f64 = 0.58;

fn wire_section() -> BeamSection {
    BeamSection::circle(WIRE_RADIUS_M, 210e9, 0.3).expect("valid section")
}

fn bench_element(c: &mut Criterion) {
    let x1 = Vector3::new(0.0, 0.0, 0.0);
    let x2 = Vector3::new(0.0015, 0.0, 0.0058);
    let beam = CorotationalBeam::new(&x1, &x2, &Vector3::x(), &wire_section()).expect("element");
    let r = exp_so3(&Vector3::new(0.02, -0.01, 0.3));
    let y1 = r * x1;
    let y2 = r * x2 + Vector3::new(1e-6, -2e-6, 3e-6);
    let l1 = exp_so3(&Vector3::new(1e-3, 2e-3, -1e-3)) * r;
    let l2 = exp_so3(&Vector3::new(-2e-3, 1e-3, 2e-3)) * r;
    let mut f = Vector12::zeros();
    let mut k = Matrix12::zeros();
    c.bench_function("element internal force", |b| {
        b.iter(|| {
            beam.internal_force(black_box(&y1), &y2, &l1, &l2, &mut f)
                .expect("evaluates");
            black_box(&f);
        })
    });
    c.bench_function("element internal force + tangent", |b| {
        b.iter(|| {
            beam.internal_force_and_tangent(black_box(&y1), &y2, &l1, &l2, &mut f, &mut k)
                .expect("evaluates");
            black_box(&k);
        })
    });
}

/// 121 straight wires along z on an 11 × 11 grid (pitch 4.7 mm), 100 elements each, the first
/// node of every wire clamped; lateral springs tie neighbouring wires every third node with a
/// staggered start, ≈ 7 300 ties.
struct Bundle {
    frame: BeamFrame,
    state: FrameState,
    pattern: SparsePattern,
    tie_stiffness_n_per_m: f64,
}

fn bundle(elements_per_wire: usize) -> Bundle {
    let side = 11;
    let pitch = 2.0 * WIRE_RADIUS_M + 1e-4;
    let section = wire_section();
    let mut frame = BeamFrame::default();
    let mut wires = Vec::new();
    for i in 0..side {
        for j in 0..side {
            let base = Vector3::new(i as f64 * pitch, j as f64 * pitch, 0.0);
            let points: Vec<Vector3<f64>> = (0..=elements_per_wire)
                .map(|k| base + Vector3::z() * (LENGTH_M * k as f64 / elements_per_wire as f64))
                .collect();
            wires.push(
                frame
                    .add_polyline(&points, &Vector3::x(), &section)
                    .expect("wire"),
            );
        }
    }
    let clamps: Vec<(NodeId, [bool; 6])> = wires.iter().map(|w| (w[0], [true; 6])).collect();
    let dofs = DofMap::new(frame.node_count(), &clamps).expect("dofs");
    let mut elements: Vec<Vec<Equation>> = dofs
        .element_equations(&frame)
        .iter()
        .map(|e| e.to_vec())
        .collect();
    let dofs_ref = &dofs;
    let node_eqs = |n: NodeId| (0..6).map(move |k| dofs_ref.equation(n, k));
    let mut ties = 0;
    for i in 0..side {
        for j in 0..side {
            let w = &wires[i * side + j];
            for (di, dj) in [(1, 0), (0, 1)] {
                if i + di >= side || j + dj >= side {
                    continue;
                }
                let v = &wires[(i + di) * side + j + dj];
                for k in ((i + j + di) % 3..=elements_per_wire).step_by(3) {
                    if k == 0 {
                        continue;
                    }
                    elements.push(node_eqs(w[k]).chain(node_eqs(v[k])).collect());
                    ties += 1;
                }
            }
        }
    }
    let pattern =
        SparsePattern::new(dofs.free_count(), Storage::Upper, &elements).expect("pattern");
    eprintln!(
        "bundle: {} DOF, {} beam elements, {} ties, {} stored entries",
        pattern.size(),
        frame.elements().len(),
        ties,
        pattern.nnz()
    );
    // stretched by 0.1 % (the strand's working strain): the tangent carries the geometric
    // term of the axial force and stays positive definite
    let mut state = FrameState::reference(&frame);
    for x in state.positions.iter_mut() {
        x.z *= 1.001;
    }
    Bundle {
        frame,
        state,
        pattern,
        tie_stiffness_n_per_m: 1e7,
    }
}

/// Assembles beams and ties; returns the residual norm as a check value.
fn assemble(b: &Bundle, residual: &mut [f64], values: &mut [f64]) -> f64 {
    residual.iter_mut().for_each(|v| *v = 0.0);
    values.iter_mut().for_each(|v| *v = 0.0);
    assemble_frame(&b.frame, &b.state, &b.pattern, 0, residual, Some(values)).expect("assembles");
    let k = b.tie_stiffness_n_per_m;
    let mut tie = Matrix12::zeros();
    for d in 0..3 {
        tie[(d, d)] = k;
        tie[(6 + d, 6 + d)] = k;
        tie[(d, 6 + d)] = -k;
        tie[(6 + d, d)] = -k;
    }
    for e in b.frame.elements().len()..b.pattern.element_count() {
        b.pattern.add_element_matrix(values, e, tie.as_slice());
    }
    residual.iter().map(|r| r * r).sum::<f64>().sqrt()
}

fn bench_assembly_and_solve(c: &mut Criterion) {
    let b = bundle(100);
    let n = b.pattern.size();
    let mut residual = vec![0.0; n];
    let mut values = vec![0.0; b.pattern.nnz()];

    // scatter only: 12 000 precomputed element matrices into the pattern
    let beam_count = b.frame.elements().len().min(12_000);
    let ke = Matrix12::from_fn(|i, j| 1.0 + (i * 12 + j) as f64 * 1e-3);
    c.bench_function("scatter 12000 element matrices", |bench| {
        bench.iter(|| {
            for e in 0..beam_count {
                b.pattern.add_element_matrix(&mut values, e, ke.as_slice());
            }
            black_box(&values);
        })
    });

    let mut group = c.benchmark_group("bundle 121x100");
    group.sample_size(10);
    group.bench_function("assemble beams + ties (force + tangent)", |bench| {
        bench.iter(|| black_box(assemble(&b, &mut residual, &mut values)))
    });
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool");
    let mut ws = FrameWorkspace::new(&b.frame);
    group.bench_function("assemble beams (force + tangent, 2 threads)", |bench| {
        bench.iter(|| {
            residual.iter_mut().for_each(|v| *v = 0.0);
            values.iter_mut().for_each(|v| *v = 0.0);
            assemble_frame_parallel(
                &pool,
                &b.frame,
                &b.state,
                &b.pattern,
                0,
                &mut residual,
                Some(&mut values),
                &mut ws,
            )
            .expect("assembles");
            black_box(&values);
        })
    });
    assemble(&b, &mut residual, &mut values);

    let t0 = std::time::Instant::now();
    let mut solver =
        SparseCholesky::new(&b.pattern, CholeskyKind::Llt, Par::Seq).expect("symbolic");
    eprintln!(
        "symbolic analysis {:.3} s, factor entries {}, supernodal {}",
        t0.elapsed().as_secs_f64(),
        solver.factor_len(),
        solver.is_supernodal()
    );
    let rhs: Vec<f64> = (0..n).map(|i| ((i % 13) as f64 - 6.0) * 1e-2).collect();
    // check the solve once
    solver.factorize(&b.pattern, &values).expect("factorises");
    let mut x = rhs.clone();
    solver.solve_in_place(&mut x).expect("solves");
    let mut ax = vec![0.0; n];
    b.pattern.mul_vec(&values, &x, &mut ax);
    let err = ax
        .iter()
        .zip(&rhs)
        .map(|(a, r)| (a - r).abs())
        .fold(0.0, f64::max);
    eprintln!("solve residual max |Ax - b| = {err:e}");

    group.bench_function("cholesky numeric factorisation (1 thread)", |bench| {
        bench.iter(|| solver.factorize(&b.pattern, &values).expect("factorises"))
    });
    group.bench_function("cholesky solve (1 thread)", |bench| {
        bench.iter(|| {
            x.copy_from_slice(&rhs);
            solver.solve_in_place(&mut x).expect("solves");
            black_box(&x);
        })
    });
    if let Some(two) = std::num::NonZeroUsize::new(2) {
        let mut solver2 =
            SparseCholesky::new(&b.pattern, CholeskyKind::Llt, Par::Rayon(two)).expect("symbolic");
        group.bench_function("cholesky numeric factorisation (2 threads)", |bench| {
            bench.iter(|| solver2.factorize(&b.pattern, &values).expect("factorises"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_element, bench_assembly_and_solve);
criterion_main!(benches);
