//! Nested-dissection fill-reducing ordering of a sparse symmetric pattern, by METIS 5
//! (`METIS_NodeND`; Karypis & Kumar 1998, *A fast and high quality multilevel scheme for
//! partitioning irregular graphs*, SIAM J. Sci. Comput. 20(1)).
//!
//! For the strand model's LDLᵀ (89 928 equations, six-layer strand) nested dissection leaves
//! about 40 % fewer factor entries than approximate minimum degree, which makes both the
//! factorisation and the triangular solves of every GMRES iteration faster (README,
//! "Strand solver").
//!
//! Indistinguishable equations, those with the same adjacency including themselves (the six
//! degrees of freedom of a beam node), are merged into one weighted vertex first
//! (supervariables, Ashcraft 1995): METIS orders the smaller node graph and each node's
//! equations stay consecutive in the ordering, which keeps the dense blocks of the supernodal
//! factorisation large.
//!
//! The ordering is deterministic: METIS runs with a fixed seed, so two processes given the same
//! pattern compute the same ordering and the same factor to the bit. METIS keeps its random
//! number generator in global state, so calls are serialised by a process-wide lock: concurrent
//! calls from several threads would otherwise interleave their random streams.
//!
//! This crate holds the workspace's only `unsafe` code: the one call into METIS.

use std::collections::HashMap;
use std::sync::Mutex;

use metis_sys::idx_t;

/// Errors of [`nested_dissection`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum OrderingError {
    /// The pattern's arrays do not describe an n × n compressed-column structure.
    #[error("invalid pattern: {reason}")]
    InvalidPattern {
        /// What is wrong.
        reason: String,
    },
    /// The graph is too large for METIS's 32-bit indices.
    #[error("graph too large for METIS's 32-bit indices ({what} = {value})")]
    TooLarge {
        /// Which count overflows.
        what: &'static str,
        /// Its value.
        value: usize,
    },
    /// METIS returned an error status.
    #[error("METIS_NodeND failed with status {status}")]
    Metis {
        /// The METIS return code.
        status: i32,
    },
}

/// A symmetric permutation: equation `perm[k]` of the original matrix is equation `k` of the
/// permuted one, and `inverse[perm[k]] == k`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ordering {
    /// New position → original equation.
    pub perm: Vec<usize>,
    /// Original equation → new position.
    pub inverse: Vec<usize>,
}

impl Ordering {
    /// The identity ordering of `n` equations.
    pub fn identity(n: usize) -> Self {
        Self {
            perm: (0..n).collect(),
            inverse: (0..n).collect(),
        }
    }
}

/// Serialises the calls into METIS (module docs).
static METIS_LOCK: Mutex<()> = Mutex::new(());

/// Fixed METIS seed (module docs).
const SEED: idx_t = 20_200_413;

/// Separators METIS computes at every level, keeping the smallest (its default: 1).
const SEPARATORS: idx_t = 20;
/// Refinement passes of every separator (default 10).
const REFINEMENT_PASSES: idx_t = 50;
/// Imbalance allowed between the two halves of a bisection, in thousandths above a perfect
/// split (the ordering's default 200, i.e. 1.2): a looser balance lets the separators follow
/// the thinnest cross-sections. On the six-layer strand's LDLᵀ these three settings leave
/// 20.3 M factor entries instead of 23.3 M and about 27 instead of 38 Gflop of factorisation
/// (upper estimates), the numeric factorisation 0.43-0.45 s instead of 0.57 s on one core, for
/// 0.85 s of ordering once per model instead of 0.15 s (`studies/src/bin/linear_solver_study.rs`).
const IMBALANCE: idx_t = 600;

/// Nested-dissection ordering of the n × n symmetric pattern given in compressed-column form
/// (`col_ptr` of length n + 1, `row_idx` the row indices; upper, lower or both triangles; the
/// diagonal is ignored).
pub fn nested_dissection(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<Ordering, OrderingError> {
    let adjacency = adjacency(n, col_ptr, row_idx)?;
    let (groups, group_of) = supervariables(&adjacency);
    // quotient graph: one vertex per group, weighted by its size
    let mut xadj: Vec<idx_t> = Vec::with_capacity(groups.len() + 1);
    let mut adjncy: Vec<idx_t> = Vec::new();
    let mut vwgt: Vec<idx_t> = Vec::with_capacity(groups.len());
    let mut seen = vec![usize::MAX; groups.len()];
    xadj.push(0);
    for (g, members) in groups.iter().enumerate() {
        seen[g] = g;
        for &i in members {
            for &j in &adjacency[i] {
                let h = group_of[j];
                if seen[h] != g {
                    seen[h] = g;
                    adjncy.push(to_idx(h, "vertex index")?);
                }
            }
        }
        xadj.push(to_idx(adjncy.len(), "adjacency length")?);
        vwgt.push(to_idx(members.len(), "vertex weight")?);
    }
    let order = if groups.len() < 2 || adjncy.is_empty() {
        (0..groups.len()).collect()
    } else {
        metis_node_nd(&mut xadj, &mut adjncy, &mut vwgt)?
    };
    let mut perm = Vec::with_capacity(n);
    for g in order {
        perm.extend_from_slice(&groups[g]);
    }
    let mut inverse = vec![0; n];
    for (k, &i) in perm.iter().enumerate() {
        inverse[i] = k;
    }
    Ok(Ordering { perm, inverse })
}

fn to_idx(value: usize, what: &'static str) -> Result<idx_t, OrderingError> {
    idx_t::try_from(value).map_err(|_| OrderingError::TooLarge { what, value })
}

/// Sorted neighbour lists (without the diagonal) of the symmetrised pattern.
fn adjacency(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<Vec<Vec<usize>>, OrderingError> {
    let invalid = |reason: String| OrderingError::InvalidPattern { reason };
    if col_ptr.len() != n + 1 {
        return Err(invalid(format!(
            "col_ptr has {} entries, expected {}",
            col_ptr.len(),
            n + 1
        )));
    }
    if col_ptr.windows(2).any(|w| w[0] > w[1]) || col_ptr[n] > row_idx.len() || col_ptr[0] != 0 {
        return Err(invalid(
            "col_ptr is not a non-decreasing range of row_idx".into(),
        ));
    }
    let mut adj = vec![Vec::new(); n];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r >= n {
                return Err(invalid(format!("row index {r} in column {c} ≥ n = {n}")));
            }
            if r != c {
                adj[c].push(r);
                adj[r].push(c);
            }
        }
    }
    for a in &mut adj {
        a.sort_unstable();
        a.dedup();
    }
    Ok(adj)
}

/// Groups of indistinguishable vertices (same closed neighbourhood), in order of their first
/// member, and the group of every vertex.
fn supervariables(adj: &[Vec<usize>]) -> (Vec<Vec<usize>>, Vec<usize>) {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_of = vec![0; adj.len()];
    let mut by_key: HashMap<Vec<usize>, usize> = HashMap::new();
    for (i, a) in adj.iter().enumerate() {
        // closed neighbourhood {i} ∪ adj(i), sorted
        let mut key = a.clone();
        let at = key.partition_point(|&j| j < i);
        key.insert(at, i);
        let g = *by_key.entry(key).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(i);
        group_of[i] = g;
    }
    (groups, group_of)
}

/// `METIS_NodeND` on the graph (xadj, adjncy) with vertex weights: the elimination order,
/// position → vertex.
fn metis_node_nd(
    xadj: &mut [idx_t],
    adjncy: &mut [idx_t],
    vwgt: &mut [idx_t],
) -> Result<Vec<usize>, OrderingError> {
    let n = vwgt.len();
    let mut nvtxs = to_idx(n, "vertices")?;
    let mut options = [0 as idx_t; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0 as idx_t; n];
    let mut iperm = vec![0 as idx_t; n];
    // a poisoned lock only means another call panicked; METIS reseeds on every call
    let _guard = METIS_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    #[allow(unsafe_code)]
    // SAFETY: the METIS 5 API reads `options` (METIS_NOPTIONS entries), `xadj` (nvtxs + 1
    // entries, last = adjncy.len()), `adjncy` and `vwgt` (nvtxs entries) and writes `perm` and
    // `iperm` (nvtxs entries each); all are live, correctly sized buffers owned here, and
    // METIS keeps no pointer past the call.
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        options[metis_sys::moptions_et_METIS_OPTION_SEED as usize] = SEED;
        options[metis_sys::moptions_et_METIS_OPTION_NSEPS as usize] = SEPARATORS;
        options[metis_sys::moptions_et_METIS_OPTION_NITER as usize] = REFINEMENT_PASSES;
        options[metis_sys::moptions_et_METIS_OPTION_UFACTOR as usize] = IMBALANCE;
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            vwgt.as_mut_ptr(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(OrderingError::Metis { status });
    }
    // METIS: row i of the permuted matrix is row perm[i] of the original
    perm.iter()
        .map(|&p| {
            usize::try_from(p)
                .ok()
                .filter(|&p| p < n)
                .ok_or(OrderingError::Metis { status })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Upper-triangle CSC pattern of a grid graph nx × ny with `dofs` equations per node.
    fn grid(nx: usize, ny: usize, dofs: usize) -> (usize, Vec<usize>, Vec<usize>) {
        let nodes = nx * ny;
        let n = nodes * dofs;
        let node = |x: usize, y: usize| y * nx + x;
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut link = |a: usize, b: usize| {
            for i in 0..dofs {
                for j in 0..dofs {
                    let (r, c) = (a * dofs + i, b * dofs + j);
                    let (r, c) = (r.min(c), r.max(c));
                    cols[c].push(r);
                }
            }
        };
        for y in 0..ny {
            for x in 0..nx {
                link(node(x, y), node(x, y));
                if x + 1 < nx {
                    link(node(x, y), node(x + 1, y));
                }
                if y + 1 < ny {
                    link(node(x, y), node(x, y + 1));
                }
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        (n, col_ptr, row_idx)
    }

    /// Entries of the Cholesky factor of the pattern permuted by `o`: row k of L holds the
    /// columns of the row subtree of k in the elimination tree (Liu 1990, *The role of
    /// elimination trees in sparse factorization*).
    fn factor_entries(n: usize, col_ptr: &[usize], row_idx: &[usize], o: &Ordering) -> usize {
        let adj = adjacency(n, col_ptr, row_idx).unwrap();
        let mut parent = vec![usize::MAX; n];
        let mut mark = vec![usize::MAX; n];
        let mut count = vec![1usize; n];
        for k in 0..n {
            mark[k] = k;
            for &j in &adj[o.perm[k]] {
                let mut p = o.inverse[j];
                if p >= k {
                    continue;
                }
                while mark[p] != k {
                    mark[p] = k;
                    count[p] += 1;
                    if parent[p] == usize::MAX {
                        parent[p] = k;
                    }
                    p = parent[p];
                }
            }
        }
        count.iter().sum()
    }

    #[test]
    fn ordering_is_a_permutation_and_keeps_node_equations_together() {
        let (n, cp, ri) = grid(12, 9, 6);
        let o = nested_dissection(n, &cp, &ri).unwrap();
        let mut sorted = o.perm.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        for (k, &i) in o.perm.iter().enumerate() {
            assert_eq!(o.inverse[i], k);
        }
        // the six equations of a node are consecutive, in order
        for chunk in o.perm.chunks(6) {
            assert_eq!(chunk[0] % 6, 0);
            for (j, &i) in chunk.iter().enumerate() {
                assert_eq!(i, chunk[0] + j);
            }
        }
    }

    #[test]
    fn nested_dissection_fills_a_grid_less_than_the_natural_order() {
        // 40 × 40 grid, one equation per node: the natural (banded) order fills about
        // n · nx entries, nested dissection O(n log n) (George 1973)
        let (n, cp, ri) = grid(40, 40, 1);
        let nd = factor_entries(n, &cp, &ri, &nested_dissection(n, &cp, &ri).unwrap());
        let natural = factor_entries(n, &cp, &ri, &Ordering::identity(n));
        eprintln!("factor entries: nested dissection {nd}, natural {natural}");
        assert!(
            (nd as f64) < 0.45 * natural as f64,
            "nested dissection {nd}, natural {natural}"
        );
    }

    #[test]
    fn the_same_pattern_gives_the_same_ordering_also_from_concurrent_threads() {
        let (n, cp, ri) = grid(20, 15, 3);
        let first = nested_dissection(n, &cp, &ri).unwrap();
        let others: Vec<Ordering> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..4)
                .map(|_| s.spawn(|| nested_dissection(n, &cp, &ri).unwrap()))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for o in others {
            assert_eq!(o, first);
        }
    }

    #[test]
    fn bad_patterns_and_trivial_graphs() {
        assert!(matches!(
            nested_dissection(3, &[0, 1], &[0]),
            Err(OrderingError::InvalidPattern { .. })
        ));
        assert!(matches!(
            nested_dissection(2, &[0, 1, 2], &[0, 5]),
            Err(OrderingError::InvalidPattern { .. })
        ));
        // diagonal only: no edges, identity
        assert_eq!(
            nested_dissection(3, &[0, 1, 2, 3], &[0, 1, 2]).unwrap(),
            Ordering::identity(3)
        );
        assert_eq!(
            nested_dissection(0, &[0], &[]).unwrap(),
            Ordering::identity(0)
        );
    }
}
