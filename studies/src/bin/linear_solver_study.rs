//! Cost of the linear algebra of one Newton iteration of the strand models: the tangent of a
//! small tension step assembled, then factorised and solved with faer's sparse LU (automatic
//! simplicial / supernodal choice, and forced supernodal), and with LDLᵀ of its symmetric part
//! (AMD and nested-dissection orderings; faer's solve and the solve split over the elimination
//! tree, in double and single precision; and faer's factorisation in single precision).
//!
//! `cargo run --release -p moorfret-studies --bin linear_solver_study -- [benchmark|six_layer]
//! [--no-lu] [--solves N]` (`--no-lu` skips the two LU cases, a few minutes on the six-layer
//! strand; `--solves N` times N solves of each LDLᵀ instead of 5)

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LdltRef, SymmetricOrdering};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, NumericLu};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par, Side};
use moorfret_solver::linalg::{
    CholeskyKind, Equation, FactorPrecision, FillOrdering, LinearSolver, NonlinearProblem,
    SparseCholesky, SparseLu, SparsePattern, Storage,
};
use moorfret_solver::strand::loading::LoadPath;
use moorfret_solver::strand::model::{EndKind, StrandModel, StrandModelParameters};
use moorfret_solver::strand::problem::StrandProblem;
use moorfret_solver::strand::profile::{profile_from_json, profiles_from_json};

const BENCHMARK: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/benchmarks/strand_1_6_1.json"
));
const PROFILES: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../campaigns/data/strand_profiles.json"
));

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let which = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "benchmark".into());
    let (strand, params) = if which == "six_layer" {
        let profiles = profiles_from_json(PROFILES)?;
        (
            profiles
                .get("paper_six_layer")
                .ok_or("missing")?
                .validate()?,
            StrandModelParameters {
                ends: EndKind::Periodic,
                ..StrandModelParameters::default()
            },
        )
    } else {
        (
            profile_from_json(BENCHMARK)?.validate()?,
            StrandModelParameters::default(),
        )
    };
    let model = StrandModel::new(&strand, &params)?;
    let p = &model.pattern;
    let n = p.size();
    let mut problem = StrandProblem::new(
        &model,
        LoadPath {
            strain: 1e-3,
            curvature_per_m: 0.0,
        },
    );
    let mut r = vec![0.0; n];
    let mut k = vec![0.0; p.nnz()];
    let t = Instant::now();
    problem.evaluate(0.05, &mut r, Some(&mut k))?;
    let assembly = t.elapsed().as_secs_f64();
    let t = Instant::now();
    r.fill(0.0);
    problem.evaluate(0.05, &mut r, None)?;
    let residual_only = t.elapsed().as_secs_f64();
    println!(
        "{which}: {n} equations, {} nonzeros; assembly with tangent {:.1} ms, residual only {:.1} ms",
        p.nnz(),
        1e3 * assembly,
        1e3 * residual_only
    );
    let reps = if n > 20_000 { 5 } else { 15 };
    let solve_reps = std::env::args()
        .skip_while(|a| a != "--solves")
        .nth(1)
        .map(|v| v.parse::<usize>())
        .transpose()?
        .unwrap_or(reps);

    if !std::env::args().any(|a| a == "--no-lu") {
        // (a) faer LU, automatic choice
        let t = Instant::now();
        let mut lu = SparseLu::new(p)?;
        let sym_auto = t.elapsed().as_secs_f64();
        let mut times = Vec::new();
        for _ in 0..reps {
            let t = Instant::now();
            lu.factorize(p, &k)?;
            times.push(t.elapsed().as_secs_f64());
        }
        let mut x = r.clone();
        let t = Instant::now();
        lu.solve_in_place(&mut x)?;
        println!(
            "LU auto: symbolic {:.1} ms, factorise {:.1} ms (median of {reps}), solve {:.2} ms",
            1e3 * sym_auto,
            1e3 * median(times),
            1e3 * t.elapsed().as_secs_f64()
        );

        // (b) faer LU, forced supernodal, numeric storage reused
        let t = Instant::now();
        let symbolic = factorize_symbolic_lu(
            p.symbolic(),
            LuSymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )?;
        let sym_sn = t.elapsed().as_secs_f64();
        let mut numeric = NumericLu::<usize, f64>::new();
        let par = Par::Seq;
        let req = StackReq::or(
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        );
        let mut buf = MemBuffer::try_new(req)?;
        let mut times = Vec::new();
        let mut y = r.clone();
        for i in 0..reps {
            let t = Instant::now();
            let f = symbolic.factorize_numeric_lu(
                &mut numeric,
                p.matrix(&k),
                par,
                MemStack::new(&mut buf),
                Default::default(),
            )?;
            times.push(t.elapsed().as_secs_f64());
            if i == reps - 1 {
                let t = Instant::now();
                f.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut y, n, 1),
                    par,
                    MemStack::new(&mut buf),
                );
                println!(
                    "LU supernodal: symbolic {:.1} ms, factorise {:.1} ms (median), solve {:.2} ms; |x_auto - x_sn| / |x| = {:.1e}",
                    1e3 * sym_sn,
                    1e3 * median(times.clone()),
                    1e3 * t.elapsed().as_secs_f64(),
                    x.iter().zip(&y).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt()
                        / x.iter().map(|a| a * a).sum::<f64>().sqrt()
                );
            }
        }
    }

    // (c) LDLᵀ of the symmetric part (A + Aᵀ)/2
    let mut pairs: Vec<[Equation; 2]> = Vec::with_capacity(p.nnz());
    let (cp, ri) = (p.col_ptr(), p.row_idx());
    for c in 0..n {
        for &row in &ri[cp[c]..cp[c + 1]] {
            if row <= c {
                pairs.push([Equation::free(row)?, Equation::free(c)?]);
            }
        }
    }
    let up = SparsePattern::new(n, Storage::Upper, &pairs)?;
    let mut kv = vec![0.0; up.nnz()];
    let mut e = 0;
    let mut kfull = std::collections::HashMap::new();
    for c in 0..n {
        for (j, &row) in ri[cp[c]..cp[c + 1]].iter().enumerate() {
            kfull.insert((row, c), k[cp[c] + j]);
        }
    }
    for c in 0..n {
        for &row in &ri[cp[c]..cp[c + 1]] {
            if row <= c {
                let v = if row == c {
                    kfull[&(row, c)]
                } else {
                    0.5 * (kfull[&(row, c)] + kfull.get(&(c, row)).copied().unwrap_or(0.0))
                };
                // element [row, c]: column-major 2×2, the (0,1) entry is (row, c)
                let ke = if row == c {
                    [v, 0.0, 0.0, 0.0]
                } else {
                    [0.0, v, 0.0, 0.0]
                };
                up.add_element_matrix(&mut kv, e, &ke);
                e += 1;
            }
        }
    }
    let residual = |x: &[f64]| {
        let mut ax = vec![0.0; n];
        up_mul(&up, &kv, x, &mut ax);
        ax.iter()
            .zip(&r)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt()
            / r.iter().map(|b| b * b).sum::<f64>().sqrt()
    };
    for (ordering, threads, tree) in [
        (FillOrdering::Amd, 1, None),
        (FillOrdering::NestedDissection, 1, None),
        (FillOrdering::NestedDissection, 2, None),
        (
            FillOrdering::NestedDissection,
            1,
            Some(FactorPrecision::Double),
        ),
        (
            FillOrdering::NestedDissection,
            2,
            Some(FactorPrecision::Double),
        ),
        (
            FillOrdering::NestedDissection,
            1,
            Some(FactorPrecision::Single),
        ),
        (
            FillOrdering::NestedDissection,
            2,
            Some(FactorPrecision::Single),
        ),
    ] {
        let par = if threads > 1 {
            Par::rayon(threads)
        } else {
            Par::Seq
        };
        let t = Instant::now();
        let mut ldlt = SparseCholesky::with_ordering(&up, CholeskyKind::Ldlt, par, ordering)?;
        let sym_ch = t.elapsed().as_secs_f64();
        let solve_kind = match tree {
            Some(precision) if ldlt.use_tree_solve(precision) => format!(
                "tree solve in {precision:?} (top {:.1} % of the factor; {:.2} Gflop to factorise, \
                 {:.3} Gflop per solve)",
                100.0 * ldlt.tree_top_share().unwrap_or(0.0),
                1e-9 * ldlt.tree_flops().unwrap_or_default().0,
                1e-9 * ldlt.tree_flops().unwrap_or_default().1,
            ),
            _ => "faer's solve".to_string(),
        };
        let mut times = Vec::new();
        for _ in 0..reps {
            let t = Instant::now();
            ldlt.factorize(&up, &kv)?;
            times.push(t.elapsed().as_secs_f64());
        }
        let mut solves = Vec::new();
        let mut z = r.clone();
        for _ in 0..solve_reps {
            z.copy_from_slice(&r);
            let t = Instant::now();
            ldlt.solve_in_place(&mut z)?;
            solves.push(t.elapsed().as_secs_f64());
        }
        println!(
            "LDLt of the symmetric part, {ordering:?} ordering, {threads} thread(s), {solve_kind}: symbolic \
             {:.1} ms, factorise \
             {:.1} ms (median), solve {:.2} ms (median), supernodal {}, factor {} values, \
             relative residual {:.1e}",
            1e3 * sym_ch,
            1e3 * median(times),
            1e3 * median(solves),
            ldlt.is_supernodal(),
            ldlt.factor_len(),
            residual(&z)
        );
    }

    // (d) the same LDLᵀ in single precision (a preconditioner need not be exact)
    let par = Par::Seq;
    let symbolic = factorize_symbolic_cholesky(
        up.symbolic(),
        Side::Upper,
        SymmetricOrdering::Amd,
        Default::default(),
    )?;
    let kv32: Vec<f32> = kv.iter().map(|&v| v as f32).collect();
    let a32 = SparseColMatRef::new(up.symbolic(), &kv32);
    let mut factor32 = vec![0.0f32; symbolic.len_val()];
    let req = StackReq::or(
        symbolic.factorize_numeric_ldlt_scratch::<f32>(par, Default::default()),
        symbolic.solve_in_place_scratch::<f32>(1, par),
    );
    let mut buf = MemBuffer::try_new(req)?;
    let mut times = Vec::new();
    for _ in 0..reps {
        let t = Instant::now();
        symbolic.factorize_numeric_ldlt(
            &mut factor32,
            a32,
            Side::Upper,
            Default::default(),
            par,
            MemStack::new(&mut buf),
            Default::default(),
        )?;
        times.push(t.elapsed().as_secs_f64());
    }
    let mut z32: Vec<f32> = r.iter().map(|&v| v as f32).collect();
    let t = Instant::now();
    LdltRef::new(&symbolic, &factor32).solve_in_place_with_conj(
        Conj::No,
        MatMut::from_column_major_slice_mut(&mut z32, n, 1),
        par,
        MemStack::new(&mut buf),
    );
    let solve32 = t.elapsed().as_secs_f64();
    let z64: Vec<f64> = z32.iter().map(|&v| v as f64).collect();
    println!(
        "LDLt in f32: factorise {:.1} ms (median), solve {:.2} ms, relative residual {:.1e}",
        1e3 * median(times),
        1e3 * solve32,
        residual(&z64)
    );
    Ok(())
}

/// y = S x for the upper-stored symmetric S.
fn up_mul(up: &SparsePattern, values: &[f64], x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    let (cp, ri) = (up.col_ptr(), up.row_idx());
    for c in 0..up.size() {
        for (j, &row) in ri[cp[c]..cp[c + 1]].iter().enumerate() {
            let v = values[cp[c] + j];
            y[row] += v * x[c];
            if row != c {
                y[c] += v * x[row];
            }
        }
    }
}
