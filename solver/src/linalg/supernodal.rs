//! Triangular solves with a supernodal LDLᵀ factor of faer, split over the elimination tree
//! and with the factor optionally held in single precision.
//!
//! faer's own solve visits the supernodes one after the other; the dense operations inside a
//! supernode are too small to share between threads, so a solve runs on one core and is bound
//! by the memory traffic of the factor (the six-layer strand's 27 M entries, 216 MB read twice
//! per solve). Here the elimination tree is cut into [`GROUPS`] sets of disjoint subtrees of
//! about equal work and the ancestors above them (the "top"):
//!
//! - forward, L y = b: every group eliminates its subtrees on its own copy of the vector, the
//!   updates it sends to the top rows collected apart; the groups run in parallel; their
//!   top-row updates are then added in group order and the top supernodes eliminated;
//! - D z = y on every row;
//! - backward, Lᵀ x = z: the top supernodes first, then every group on its own copy, in
//!   parallel.
//!
//! The arithmetic does not depend on the number of threads (the groups and the order of the
//! additions are fixed), so one and two threads give the same solution to the bit.
//!
//! The values can be kept in `f32` ([`FactorPrecision::Single`]): the solve then reads half the
//! bytes and still accumulates in `f64`. This is for preconditioning (a Krylov method corrects
//! what the rounding of the factor leaves), not for direct solves.
//!
//! The kernels are compiled for the processor's vector extensions at run time (pulp's
//! dispatch), as faer's own are.

use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};

/// Number of groups of subtrees solved independently (the parallel width of a solve).
pub(crate) const GROUPS: usize = 2;

/// Storage precision of the factor values used by the solves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FactorPrecision {
    /// The values as factorised.
    #[default]
    Double,
    /// Rounded to `f32`: half the memory traffic of a solve; for preconditioners.
    Single,
}

/// Factor values in the chosen precision.
#[derive(Debug, Clone)]
enum Values {
    Double(Vec<f64>),
    Single(Vec<f32>),
}

/// Layout of one supernode: columns `start..start + width`, the rows below its diagonal block
/// `rows[row_begin..row_end]`, values (column-major, (width + rows) × width) from `value_begin`.
#[derive(Debug, Clone, Copy)]
struct Supernode {
    start: usize,
    width: usize,
    row_begin: usize,
    row_end: usize,
    value_begin: usize,
}

impl Supernode {
    fn height(&self) -> usize {
        self.width + self.row_end - self.row_begin
    }
}

/// A set of subtrees of the elimination tree and its private work vectors.
#[derive(Debug, Clone)]
struct Group {
    /// Supernodes in ascending (elimination) order.
    supernodes: Vec<usize>,
    /// Column ranges of these supernodes.
    columns: Vec<(usize, usize)>,
    /// Full-length work vector (only the group's and the top columns are used).
    work: Vec<f64>,
    /// A supernode's rows, gathered (diagonal block, then the rows below).
    scratch: Vec<f64>,
}

/// Solver of L D Lᵀ x = b on a supernodal factor, split over the elimination tree.
#[derive(Debug, Clone)]
pub struct SupernodalSolve {
    size: usize,
    /// Fill-reducing permutation: permuted row i is original row `forward[i]`.
    forward: Vec<usize>,
    supernodes: Vec<Supernode>,
    rows: Vec<u32>,
    values: Values,
    groups: Vec<Group>,
    /// Supernodes above the groups, ascending.
    top: Vec<usize>,
    /// Column ranges of the top supernodes.
    top_columns: Vec<(usize, usize)>,
    /// Permuted right-hand side, and scratch of the top supernodes.
    permuted: Vec<f64>,
    scratch: Vec<f64>,
}

impl SupernodalSolve {
    /// Layout and tree split of a supernodal symbolic factorisation (`None` when faer chose a
    /// simplicial one).
    pub fn new(symbolic: &SymbolicCholesky<usize>, precision: FactorPrecision) -> Option<Self> {
        let SymbolicCholeskyRaw::Supernodal(sym) = symbolic.raw() else {
            return None;
        };
        let size = sym.nrows();
        let count = sym.n_supernodes();
        let (begin, row_ptr, val_ptr) = (
            sym.supernode_begin(),
            sym.col_ptr_for_row_idx(),
            sym.col_ptr_for_val(),
        );
        let supernodes: Vec<Supernode> = (0..count)
            .map(|s| Supernode {
                start: begin[s],
                width: sym.supernode_end()[s] - begin[s],
                row_begin: row_ptr[s],
                row_end: row_ptr[s + 1],
                value_begin: val_ptr[s],
            })
            .collect();
        let rows: Vec<u32> = sym.row_idx().iter().map(|&r| r as u32).collect();
        let forward = match symbolic.perm() {
            Some(p) => p.arrays().0.to_vec(),
            None => (0..size).collect(),
        };
        let membership = split_tree(&supernodes, &rows, size);
        let max_rows = supernodes.iter().map(Supernode::height).max().unwrap_or(0);
        let mut groups: Vec<Group> = (0..GROUPS)
            .map(|_| Group {
                supernodes: Vec::new(),
                columns: Vec::new(),
                work: vec![0.0; size],
                scratch: vec![0.0; max_rows],
            })
            .collect();
        let mut top = Vec::new();
        for (s, m) in membership.iter().enumerate() {
            match m {
                Some(g) => groups[*g].supernodes.push(s),
                None => top.push(s),
            }
        }
        for g in &mut groups {
            g.columns = column_ranges(&supernodes, &g.supernodes);
        }
        let top_columns = column_ranges(&supernodes, &top);
        let len = sym.len_val();
        let values = match precision {
            FactorPrecision::Double => Values::Double(vec![0.0; len]),
            FactorPrecision::Single => Values::Single(vec![0.0; len]),
        };
        Some(Self {
            size,
            forward,
            supernodes,
            rows,
            values,
            groups,
            top,
            top_columns,
            permuted: vec![0.0; size],
            scratch: vec![0.0; max_rows],
        })
    }

    /// Share of the factor's entries in the top supernodes (solved on one thread).
    pub(crate) fn top_share(&self) -> f64 {
        let entries = |s: &Supernode| s.height() * s.width;
        let top: usize = self.top.iter().map(|&s| entries(&self.supernodes[s])).sum();
        let total: usize = self.supernodes.iter().map(entries).sum();
        top as f64 / total.max(1) as f64
    }

    /// Floating-point operations of the numeric factorisation (w³/3 + w² m + w m² multiply-adds
    /// per supernode of width w and m rows below, multiply and add counted apart: an upper
    /// estimate, the update of the rows below counted as the full m × m product of which only
    /// the lower half is formed) and of one solve.
    pub(crate) fn flops(&self) -> (f64, f64) {
        self.supernodes.iter().fold((0.0, 0.0), |(f, s), sn| {
            let (w, m) = (sn.width as f64, (sn.row_end - sn.row_begin) as f64);
            (
                f + 2.0 * (w * w * w / 3.0 + w * w * m + w * m * m),
                s + 4.0 * (w * w / 2.0 + w * m),
            )
        })
    }

    /// Takes the numeric factor (faer's value layout) for the next solves.
    pub fn load(&mut self, factor: &[f64]) {
        match &mut self.values {
            Values::Double(v) => v.copy_from_slice(factor),
            Values::Single(v) => v.iter_mut().zip(factor).for_each(|(s, &d)| *s = d as f32),
        }
    }

    /// Solves L D Lᵀ x = b in place, the groups on two threads when `parallel`.
    pub fn solve_in_place(&mut self, rhs: &mut [f64], parallel: bool) {
        debug_assert_eq!(rhs.len(), self.size);
        for (p, &f) in self.permuted.iter_mut().zip(&self.forward) {
            *p = rhs[f];
        }
        let Self {
            supernodes,
            rows,
            values,
            groups,
            top,
            top_columns,
            permuted,
            scratch,
            ..
        } = self;
        let (supernodes, rows, top_columns) = (&supernodes[..], &rows[..], &top_columns[..]);
        match values {
            Values::Double(values) => solve(
                Factor {
                    supernodes,
                    rows,
                    values,
                    top_columns,
                },
                groups,
                top,
                permuted,
                scratch,
                parallel,
            ),
            Values::Single(values) => solve(
                Factor {
                    supernodes,
                    rows,
                    values,
                    top_columns,
                },
                groups,
                top,
                permuted,
                scratch,
                parallel,
            ),
        }
        for (p, &f) in self.permuted.iter().zip(&self.forward) {
            rhs[f] = *p;
        }
    }
}

/// Column ranges of `list` (ascending supernodes), adjacent ones merged.
fn column_ranges(supernodes: &[Supernode], list: &[usize]) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    for &s in list {
        let (a, b) = (
            supernodes[s].start,
            supernodes[s].start + supernodes[s].width,
        );
        match out.last_mut() {
            Some(last) if last.1 == a => last.1 = b,
            _ => out.push((a, b)),
        }
    }
    out
}

/// Assigns every supernode to a group (`Some(g)`) or to the top (`None`): whole subtrees go
/// to the groups, balanced by their entries (longest-processing-time first). Starting from
/// the roots, the largest subtree is split again and again (its root moved to the top, its
/// children to the candidates); of the splits seen, the one with the least critical path
/// (top entries + the largest group's) is kept.
fn split_tree(supernodes: &[Supernode], rows: &[u32], size: usize) -> Vec<Option<usize>> {
    /// Splits tried before the best one is taken.
    const SPLITS: usize = 256;
    let count = supernodes.len();
    let mut owner = vec![0usize; size];
    for (s, sn) in supernodes.iter().enumerate() {
        owner[sn.start..sn.start + sn.width].fill(s);
    }
    // parent: the supernode of the first row below the diagonal block (rows are sorted)
    let parent: Vec<Option<usize>> = supernodes
        .iter()
        .map(|sn| (sn.row_end > sn.row_begin).then(|| owner[rows[sn.row_begin] as usize]))
        .collect();
    let mut children = vec![Vec::new(); count];
    let mut roots = Vec::new();
    let own: Vec<f64> = supernodes
        .iter()
        .map(|sn| (sn.height() * sn.width) as f64)
        .collect();
    let mut work = own.clone();
    for s in 0..count {
        match parent[s] {
            Some(p) => {
                debug_assert!(p > s, "children come before their parent");
                children[p].push(s);
                let w = work[s];
                work[p] += w;
            }
            None => roots.push(s),
        }
    }
    let assign = |frontier: &[usize]| {
        let mut order = frontier.to_vec();
        order.sort_by(|a, b| work[*b].total_cmp(&work[*a]).then(a.cmp(b)));
        let mut load = [0.0f64; GROUPS];
        let mut bins = vec![Vec::new(); GROUPS];
        for s in order {
            let g = (0..GROUPS)
                .min_by(|&i, &j| load[i].total_cmp(&load[j]))
                .unwrap_or(0);
            load[g] += work[s];
            bins[g].push(s);
        }
        let worst = load.iter().cloned().fold(0.0, f64::max);
        (bins, worst)
    };
    let mut frontier = roots;
    let mut top: Vec<usize> = Vec::new();
    let mut top_work = 0.0;
    let (mut best_bins, worst) = assign(&frontier);
    let (mut best_cost, mut best_top) = (worst, 0);
    for _ in 0..SPLITS {
        let largest = frontier
            .iter()
            .copied()
            .filter(|&s| !children[s].is_empty())
            .max_by(|a, b| work[*a].total_cmp(&work[*b]).then(b.cmp(a)));
        let Some(largest) = largest else { break };
        frontier.retain(|&s| s != largest);
        frontier.extend(children[largest].iter().copied());
        top.push(largest);
        top_work += own[largest];
        let (bins, worst) = assign(&frontier);
        if top_work + worst < best_cost {
            (best_cost, best_bins, best_top) = (top_work + worst, bins, top.len());
        }
    }
    let mut in_top = vec![false; count];
    for &s in &top[..best_top] {
        in_top[s] = true;
    }
    let mut membership = vec![None; count];
    for (g, bin) in best_bins.iter().enumerate() {
        for &r in bin {
            membership[r] = Some(g);
        }
    }
    // below a group's subtree roots, every supernode belongs to the group of its parent
    for s in (0..count).rev() {
        if membership[s].is_none() && !in_top[s] {
            membership[s] = parent[s].and_then(|p| membership[p]);
        }
    }
    membership
}

/// Scalar types the factor may be stored in.
trait Entry: Copy + Send + Sync {
    fn wide(self) -> f64;
}

impl Entry for f64 {
    #[inline(always)]
    fn wide(self) -> f64 {
        self
    }
}

impl Entry for f32 {
    #[inline(always)]
    fn wide(self) -> f64 {
        f64::from(self)
    }
}

/// Columns handled together by the kernels: every entry of the vector they update is loaded
/// and stored once per four columns instead of once per column.
const BLOCK: usize = 4;

/// Forward elimination through a panel (height h, `width` columns, column-major, unit lower
/// diagonal block on top): u[i] −= Σ_{j < i} P[i, j] u[j], column by column, four at a time.
#[inline(always)]
fn panel_forward<T: Entry>(panel: &[T], h: usize, width: usize, u: &mut [f64]) {
    let mut j = 0;
    while j + BLOCK <= width {
        let c = [
            &panel[j * h..(j + 1) * h],
            &panel[(j + 1) * h..(j + 2) * h],
            &panel[(j + 2) * h..(j + 3) * h],
            &panel[(j + 3) * h..(j + 4) * h],
        ];
        let a0 = u[j];
        let a1 = u[j + 1] - c[0][j + 1].wide() * a0;
        let a2 = u[j + 2] - c[0][j + 2].wide() * a0 - c[1][j + 2].wide() * a1;
        let a3 =
            u[j + 3] - c[0][j + 3].wide() * a0 - c[1][j + 3].wide() * a1 - c[2][j + 3].wide() * a2;
        u[j + 1] = a1;
        u[j + 2] = a2;
        u[j + 3] = a3;
        let rest = j + BLOCK;
        for ((((ui, p0), p1), p2), p3) in u[rest..h]
            .iter_mut()
            .zip(&c[0][rest..])
            .zip(&c[1][rest..])
            .zip(&c[2][rest..])
            .zip(&c[3][rest..])
        {
            *ui -= p0.wide() * a0 + p1.wide() * a1 + p2.wide() * a2 + p3.wide() * a3;
        }
        j += BLOCK;
    }
    while j < width {
        let col = &panel[j * h..(j + 1) * h];
        let a = u[j];
        for (ui, p) in u[j + 1..h].iter_mut().zip(&col[j + 1..]) {
            *ui -= p.wide() * a;
        }
        j += 1;
    }
}

/// Σ_k x_k · u_k for four columns at once over the same rows, in interleaved partial sums
/// (vectorisable).
#[inline(always)]
fn dot4<T: Entry>(c: [&[T]; BLOCK], u: &[f64]) -> [f64; BLOCK] {
    const LANES: usize = 4;
    let mut acc = [[0.0f64; LANES]; BLOCK];
    let n = u.len() / LANES * LANES;
    for i in (0..n).step_by(LANES) {
        let ui = &u[i..i + LANES];
        for (k, col) in c.iter().enumerate() {
            let ck = &col[i..i + LANES];
            for l in 0..LANES {
                acc[k][l] += ck[l].wide() * ui[l];
            }
        }
    }
    let mut out = [0.0; BLOCK];
    for (k, col) in c.iter().enumerate() {
        let mut sum = (acc[k][0] + acc[k][2]) + (acc[k][1] + acc[k][3]);
        for i in n..u.len() {
            sum += col[i].wide() * u[i];
        }
        out[k] = sum;
    }
    out
}

/// x · u in interleaved partial sums.
#[inline(always)]
fn dot<T: Entry>(x: &[T], u: &[f64]) -> f64 {
    const LANES: usize = 8;
    let mut acc = [0.0f64; LANES];
    let n = u.len() / LANES * LANES;
    for i in (0..n).step_by(LANES) {
        for l in 0..LANES {
            acc[l] += x[i + l].wide() * u[i + l];
        }
    }
    let mut sum = ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
    for i in n..u.len() {
        sum += x[i].wide() * u[i];
    }
    sum
}

/// Backward substitution through a panel: u[j] −= Σ_{i > j} P[i, j] u[i] for the columns from
/// the last to the first, the rows below the diagonal block already final; four columns at a
/// time.
#[inline(always)]
fn panel_backward<T: Entry>(panel: &[T], h: usize, width: usize, u: &mut [f64]) {
    let blocks = width / BLOCK;
    for j in (blocks * BLOCK..width).rev() {
        let col = &panel[j * h..(j + 1) * h];
        u[j] -= dot(&col[j + 1..], &u[j + 1..h]);
    }
    for b in (0..blocks).rev() {
        let j = b * BLOCK;
        let c = [
            &panel[j * h..(j + 1) * h],
            &panel[(j + 1) * h..(j + 2) * h],
            &panel[(j + 2) * h..(j + 3) * h],
            &panel[(j + 3) * h..(j + 4) * h],
        ];
        let rest = j + BLOCK;
        let s = dot4(
            [&c[0][rest..], &c[1][rest..], &c[2][rest..], &c[3][rest..]],
            &u[rest..h],
        );
        let a3 = u[j + 3] - s[3];
        let a2 = u[j + 2] - s[2] - c[2][j + 3].wide() * a3;
        let a1 = u[j + 1] - s[1] - c[1][j + 2].wide() * a2 - c[1][j + 3].wide() * a3;
        let a0 = u[j]
            - s[0]
            - c[0][j + 1].wide() * a1
            - c[0][j + 2].wide() * a2
            - c[0][j + 3].wide() * a3;
        u[j..rest].copy_from_slice(&[a0, a1, a2, a3]);
    }
}

/// Forward elimination with one supernode: its columns of y solved (unit lower diagonal
/// block), their updates subtracted from the rows below. `u` is scratch of the panel's height.
#[inline(always)]
fn forward<T: Entry>(sn: &Supernode, rows: &[u32], values: &[T], x: &mut [f64], u: &mut [f64]) {
    let (w, h) = (sn.width, sn.height());
    let below = &rows[sn.row_begin..sn.row_end];
    let u = &mut u[..h];
    u[..w].copy_from_slice(&x[sn.start..sn.start + w]);
    u[w..].fill(0.0);
    panel_forward(&values[sn.value_begin..sn.value_begin + w * h], h, w, u);
    x[sn.start..sn.start + w].copy_from_slice(&u[..w]);
    for (&r, ui) in below.iter().zip(&u[w..]) {
        x[r as usize] += ui;
    }
}

/// Backward substitution with one supernode: its columns of x from the rows below (already
/// solved) and the unit upper diagonal block.
#[inline(always)]
fn backward<T: Entry>(sn: &Supernode, rows: &[u32], values: &[T], x: &mut [f64], u: &mut [f64]) {
    let (w, h) = (sn.width, sn.height());
    let below = &rows[sn.row_begin..sn.row_end];
    let u = &mut u[..h];
    u[..w].copy_from_slice(&x[sn.start..sn.start + w]);
    for (ui, &r) in u[w..].iter_mut().zip(below) {
        *ui = x[r as usize];
    }
    panel_backward(&values[sn.value_begin..sn.value_begin + w * h], h, w, u);
    x[sn.start..sn.start + w].copy_from_slice(&u[..w]);
}

/// Diagonal D of the supernodes: x ← D⁻¹ x.
#[inline(always)]
fn diagonal<T: Entry>(supernodes: &[Supernode], values: &[T], x: &mut [f64]) {
    for sn in supernodes {
        let h = sn.height();
        for j in 0..sn.width {
            x[sn.start + j] /= values[sn.value_begin + j * h + j].wide();
        }
    }
}

impl Group {
    /// Forward elimination of the group's subtrees on its work vector, which starts from `x`
    /// on the group's columns and from zero on the top's.
    #[inline(always)]
    fn forward<T: Entry>(
        &mut self,
        x: &[f64],
        top_columns: &[(usize, usize)],
        supernodes: &[Supernode],
        rows: &[u32],
        values: &[T],
    ) {
        for &(a, b) in &self.columns {
            self.work[a..b].copy_from_slice(&x[a..b]);
        }
        for &(a, b) in top_columns {
            self.work[a..b].fill(0.0);
        }
        for &s in &self.supernodes {
            forward(
                &supernodes[s],
                rows,
                values,
                &mut self.work,
                &mut self.scratch,
            );
        }
    }

    /// Backward substitution of the group's subtrees on its work vector, which starts from
    /// `x` (the top already solved).
    #[inline(always)]
    fn backward<T: Entry>(
        &mut self,
        x: &[f64],
        top_columns: &[(usize, usize)],
        supernodes: &[Supernode],
        rows: &[u32],
        values: &[T],
    ) {
        for &(a, b) in self.columns.iter().chain(top_columns) {
            self.work[a..b].copy_from_slice(&x[a..b]);
        }
        for &s in self.supernodes.iter().rev() {
            backward(
                &supernodes[s],
                rows,
                values,
                &mut self.work,
                &mut self.scratch,
            );
        }
    }
}

/// The shared, read-only part of a solve.
#[derive(Clone, Copy)]
struct Factor<'a, T> {
    supernodes: &'a [Supernode],
    rows: &'a [u32],
    values: &'a [T],
    top_columns: &'a [(usize, usize)],
}

/// One phase of a solve, run through pulp's dispatch so that the kernels inlined into it are
/// compiled for the processor's vector extensions (a closure would not be inlined reliably).
enum Phase<'a> {
    /// A group's forward elimination, from the vector before it.
    GroupForward(&'a mut Group, &'a [f64]),
    /// A group's backward substitution, from the vector with the top solved.
    GroupBackward(&'a mut Group, &'a [f64]),
    /// The top supernodes forward, the diagonal, the top supernodes backward.
    Top {
        top: &'a [usize],
        x: &'a mut [f64],
        scratch: &'a mut [f64],
    },
}

struct Run<'a, T> {
    factor: Factor<'a, T>,
    phase: Phase<'a>,
}

impl<T: Entry> pulp::WithSimd for Run<'_, T> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Factor {
            supernodes,
            rows,
            values,
            top_columns,
        } = self.factor;
        match self.phase {
            Phase::GroupForward(g, x) => g.forward(x, top_columns, supernodes, rows, values),
            Phase::GroupBackward(g, x) => g.backward(x, top_columns, supernodes, rows, values),
            Phase::Top { top, x, scratch } => {
                for &s in top {
                    forward(&supernodes[s], rows, values, x, scratch);
                }
                diagonal(supernodes, values, x);
                for &s in top.iter().rev() {
                    backward(&supernodes[s], rows, values, x, scratch);
                }
            }
        }
    }
}

/// Runs `phase` on every group, on two threads when `parallel`.
fn for_groups<T: Entry>(
    factor: Factor<'_, T>,
    groups: &mut [Group],
    x: &[f64],
    parallel: bool,
    backward: bool,
) {
    let arch = pulp::Arch::new();
    let run = |g: &mut Group| {
        let phase = if backward {
            Phase::GroupBackward(g, x)
        } else {
            Phase::GroupForward(g, x)
        };
        arch.dispatch(Run { factor, phase });
    };
    match groups {
        [a, b] if parallel => {
            rayon::join(|| run(a), || run(b));
        }
        _ => groups.iter_mut().for_each(run),
    }
}

fn solve<T: Entry>(
    factor: Factor<'_, T>,
    groups: &mut [Group],
    top: &[usize],
    x: &mut [f64],
    scratch: &mut [f64],
    parallel: bool,
) {
    let top_columns = factor.top_columns;
    for_groups(factor, groups, x, parallel, false);
    for g in groups.iter() {
        for &(a, b) in &g.columns {
            x[a..b].copy_from_slice(&g.work[a..b]);
        }
    }
    for g in groups.iter() {
        for &(a, b) in top_columns {
            for (xi, wi) in x[a..b].iter_mut().zip(&g.work[a..b]) {
                *xi += wi;
            }
        }
    }
    pulp::Arch::new().dispatch(Run {
        factor,
        phase: Phase::Top { top, x, scratch },
    });
    for_groups(factor, groups, x, parallel, true);
    for g in groups.iter() {
        for &(a, b) in &g.columns {
            x[a..b].copy_from_slice(&g.work[a..b]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::cholesky::{CholeskyKind, FillOrdering, SparseCholesky};
    use crate::linalg::linear_solver::LinearSolver;
    use crate::linalg::pattern::{Equation, SparsePattern, Storage};
    use faer::Par;

    /// Springs between the neighbours of an n × n × `length` grid (a bar, as the strand), three equations per node coupled
    /// by each spring (a symmetric positive definite, diagonally weighted stiffness), upper
    /// storage.
    fn grid(n: usize, length: usize) -> (SparsePattern, Vec<f64>) {
        let node = |i: usize, j: usize, k: usize| (i * n + j) * length + k;
        let mut pairs = Vec::new();
        for i in 0..n {
            for j in 0..n {
                for k in 0..length {
                    let a = node(i, j, k);
                    if i + 1 < n {
                        pairs.push((a, node(i + 1, j, k)));
                    }
                    if j + 1 < n {
                        pairs.push((a, node(i, j + 1, k)));
                    }
                    if k + 1 < length {
                        pairs.push((a, node(i, j, k + 1)));
                    }
                }
            }
        }
        let eq = |v: usize, d: usize| Equation::free(3 * v + d).unwrap();
        let elements: Vec<Vec<Equation>> = pairs
            .iter()
            .map(|&(a, b)| {
                (0..3)
                    .map(|d| eq(a, d))
                    .chain((0..3).map(|d| eq(b, d)))
                    .collect()
            })
            .collect();
        let size = 3 * n * n * length;
        let p = SparsePattern::new(size, Storage::Upper, &elements).unwrap();
        let mut values = vec![0.0; p.nnz()];
        for (e, &(a, b)) in pairs.iter().enumerate() {
            // k [[S, -S], [-S, S]] with S = I + 0.3 (ones - I), stiffness varying along the grid
            let k = 1.0 + ((a * 7 + b * 3) % 11) as f64;
            let mut ke = vec![0.0; 36];
            for r in 0..6 {
                for c in 0..6 {
                    let s = if r % 3 == c % 3 { 1.0 } else { 0.3 };
                    let sign = if (r < 3) == (c < 3) { 1.0 } else { -1.0 };
                    ke[c * 6 + r] = k * s * sign;
                }
            }
            p.add_element_matrix(&mut values, e, &ke);
        }
        // ground every node weakly so that the matrix is definite
        for i in 0..size {
            let range = p.col_ptr()[i]..p.col_ptr()[i + 1];
            let d = range.clone().find(|&slot| p.row_idx()[slot] == i).unwrap();
            values[d] += 1e-3;
        }
        (p, values)
    }

    fn rhs(size: usize) -> Vec<f64> {
        (0..size)
            .map(|i| ((i * 37) % 101) as f64 / 50.0 - 1.0)
            .collect()
    }

    #[test]
    fn tree_solve_splits_the_factor_and_matches_faers_solve() {
        let (p, values) = grid(8, 80);
        let mut faer = SparseCholesky::with_ordering(
            &p,
            CholeskyKind::Ldlt,
            Par::Seq,
            FillOrdering::NestedDissection,
        )
        .unwrap();
        assert!(faer.is_supernodal());
        faer.factorize(&p, &values).unwrap();
        let b = rhs(p.size());
        let mut reference = b.clone();
        faer.solve_in_place(&mut reference).unwrap();

        let mut tree = SparseCholesky::with_ordering(
            &p,
            CholeskyKind::Ldlt,
            Par::rayon(2),
            FillOrdering::NestedDissection,
        )
        .unwrap();
        assert!(tree.use_tree_solve(FactorPrecision::Double));
        let top = tree.tree_top_share().unwrap();
        assert!(top > 0.0 && top < 0.25, "top share {top}");
        tree.factorize(&p, &values).unwrap();
        let mut x = b.clone();
        tree.solve_in_place(&mut x).unwrap();
        let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = x
            .iter()
            .zip(&reference)
            .fold(0.0f64, |m, (a, r)| m.max((a - r).abs()));
        assert!(diff <= 1e-12 * scale, "{diff} of {scale}");

        // the residual of the solve itself, against the assembled matrix
        let mut full_values = vec![0.0; p.nnz()];
        full_values.copy_from_slice(&values);
        let mut ax = vec![0.0; p.size()];
        p.mul_vec(&full_values, &x, &mut ax);
        let residual = ax
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(residual < 1e-9, "{residual}");
    }

    #[test]
    fn one_and_two_threads_give_the_same_solution_to_the_bit() {
        let (p, values) = grid(6, 60);
        let b = rhs(p.size());
        let solutions: Vec<Vec<f64>> = [Par::Seq, Par::rayon(2)]
            .into_iter()
            .map(|par| {
                let mut s = SparseCholesky::with_ordering(
                    &p,
                    CholeskyKind::Ldlt,
                    par,
                    FillOrdering::NestedDissection,
                )
                .unwrap();
                assert!(s.use_tree_solve(FactorPrecision::Single));
                s.factorize(&p, &values).unwrap();
                let mut x = b.clone();
                s.solve_in_place(&mut x).unwrap();
                x
            })
            .collect();
        // the factorisation itself may differ in round-off between thread counts; the
        // solve with one factor must not
        let mut s = SparseCholesky::with_ordering(
            &p,
            CholeskyKind::Ldlt,
            Par::Seq,
            FillOrdering::NestedDissection,
        )
        .unwrap();
        s.factorize(&p, &values).unwrap();
        let mut single = SupernodalSolve::new(&s.symbolic, FactorPrecision::Single).unwrap();
        single.load(&s.factor_values);
        let (mut x1, mut x2) = (b.clone(), b.clone());
        single.solve_in_place(&mut x1, false);
        single.solve_in_place(&mut x2, true);
        assert_eq!(x1, x2);
        // single-precision values: a preconditioner, close to the exact solve
        let scale = solutions[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let diff = solutions[0]
            .iter()
            .zip(&solutions[1])
            .fold(0.0f64, |m, (a, r)| m.max((a - r).abs()));
        assert!(diff <= 1e-5 * scale, "{diff}");
    }
}
