//! Square band matrix with LU factorisation without pivoting, in place.
//!
//! A line's iteration matrix couples only neighbouring nodes, so with node-by-node numbering it
//! is banded with half-bandwidth b ≤ 11. It is not symmetric in dynamics (the drag and friction
//! tangents are not), hence LU rather than LDLᵀ. Pivoting is not needed: the matrix is
//! dominated by its diagonal blocks (mass β' M, tension and bending stiffness), and a tiny pivot
//! is reported as an error rather than hidden. Storage is row-major with 2b + 1 entries per
//! row; factorisation costs ≈ n b² and solving ≈ 4 n b multiply-adds, and nothing is allocated
//! after construction.

/// Band matrix of order n and half-bandwidth b.
#[derive(Debug, Clone)]
pub struct BandMatrix {
    n: usize,
    b: usize,
    width: usize,
    data: Vec<f64>,
    /// Reciprocals of the pivots of the last factorisation.
    inverse_pivots: Vec<f64>,
}

impl BandMatrix {
    /// Zero matrix of order `n` with half-bandwidth `b`.
    pub fn new(n: usize, b: usize) -> BandMatrix {
        let width = 2 * b + 1;
        BandMatrix {
            n,
            b,
            width,
            data: vec![0.0; n * width],
            inverse_pivots: vec![0.0; n],
        }
    }

    /// Order.
    pub fn order(&self) -> usize {
        self.n
    }

    /// Half-bandwidth.
    pub fn half_bandwidth(&self) -> usize {
        self.b
    }

    /// Sets every entry to zero.
    pub fn clear(&mut self) {
        self.data.fill(0.0);
    }

    #[inline]
    fn index(&self, i: usize, j: usize) -> usize {
        debug_assert!(i < self.n && j < self.n && i + self.b >= j && j + self.b >= i);
        i * self.width + j + self.b - i
    }

    /// Entry (i, j); zero outside the band.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i + self.b < j || j + self.b < i {
            0.0
        } else {
            self.data[self.index(i, j)]
        }
    }

    /// Adds `v` to entry (i, j), which must lie in the band.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let k = self.index(i, j);
        self.data[k] += v;
    }

    /// Adds `v` to the consecutive entries (i, j), (i, j + 1), … of row i, which must lie in
    /// the band (they are contiguous in storage).
    #[inline]
    pub(crate) fn add_row(&mut self, i: usize, j: usize, v: &[f64]) {
        let k = self.index(i, j);
        debug_assert!(j + v.len() <= i + self.b + 1);
        for (a, x) in self.data[k..k + v.len()].iter_mut().zip(v) {
            *a += x;
        }
    }

    /// Replaces row and column `i` by those of the identity (for a prescribed unknown).
    pub(crate) fn set_identity_row_col(&mut self, i: usize) {
        let lo = i.saturating_sub(self.b);
        let hi = (i + self.b).min(self.n - 1);
        for j in lo..=hi {
            let a = self.index(i, j);
            let c = self.index(j, i);
            self.data[a] = 0.0;
            self.data[c] = 0.0;
        }
        let d = self.index(i, i);
        self.data[d] = 1.0;
    }

    /// y = A x.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate().take(self.n) {
            let lo = i.saturating_sub(self.b);
            let hi = (i + self.b).min(self.n - 1);
            *yi = (lo..=hi).map(|j| self.data[self.index(i, j)] * x[j]).sum();
        }
    }

    /// Factorises in place into L U (unit lower L). On a pivot smaller than `tiny` times the
    /// largest diagonal entry, returns `Err((row, pivot))` and leaves the matrix unusable.
    ///
    /// The half-bandwidths of the line models (11 with gradient nodes, 5 for bar-only lines)
    /// run through a copy of the elimination whose row length is a compile-time constant, so
    /// that each row update is unrolled and vectorised in full; every entry sees the same
    /// operations in the same order as in the general loop, so the factors are the same to
    /// the bit.
    pub fn factorize(&mut self, tiny: f64) -> Result<(), (usize, f64)> {
        match self.b {
            11 => self.factorize_fixed::<11>(tiny),
            5 => self.factorize_fixed::<5>(tiny),
            _ => self.factorize_general(tiny),
        }
    }

    fn pivot_threshold(&self, tiny: f64) -> f64 {
        let (b, w) = (self.b, self.width);
        let scale = (0..self.n)
            .map(|i| self.data[i * w + b].abs())
            .fold(0.0, f64::max);
        tiny * scale.max(f64::MIN_POSITIVE)
    }

    /// [`BandMatrix::factorize`] for any half-bandwidth.
    fn factorize_general(&mut self, tiny: f64) -> Result<(), (usize, f64)> {
        let n = self.n;
        let b = self.b;
        let threshold = self.pivot_threshold(tiny);
        for k in 0..n {
            let inv = self.take_pivot(k, threshold)?;
            self.eliminate_below(k, (k + b).min(n - 1), inv);
        }
        Ok(())
    }

    /// Checks pivot k against `threshold` and stores its reciprocal, which it returns.
    #[inline]
    fn take_pivot(&mut self, k: usize, threshold: f64) -> Result<f64, (usize, f64)> {
        let pivot = self.data[k * self.width + self.b];
        if pivot.is_nan() || pivot.abs() <= threshold {
            return Err((k, pivot));
        }
        let inv = 1.0 / pivot;
        self.inverse_pivots[k] = inv;
        Ok(inv)
    }

    /// Eliminates column k from rows k+1 … `last` (pivot reciprocal `inv`), any bandwidth.
    #[inline]
    fn eliminate_below(&mut self, k: usize, last: usize, inv: f64) {
        let (b, w) = (self.b, self.width);
        for i in k + 1..=last {
            // Entry (i, k) sits at column offset k + b − i of row i.
            let ik = i * w + k + b - i;
            let l = self.data[ik] * inv;
            if l == 0.0 {
                continue;
            }
            self.data[ik] = l;
            let row_k = k * w + b - k;
            // Row i's entries k+1 … last lie after row k's in storage, right after (i, k):
            // split there so that the update runs over two disjoint slices (no bounds checks,
            // vectorised).
            let len = last - k;
            let (head, tail) = self.data.split_at_mut(ik + 1);
            let pivot_row = &head[row_k + k + 1..row_k + k + 1 + len];
            for (a, p) in tail[..len].iter_mut().zip(pivot_row) {
                *a -= l * p;
            }
        }
    }

    /// [`BandMatrix::factorize_general`] with the half-bandwidth `B` known at compile time:
    /// the rows k + 1 … k + B below a pivot far from the end are updated with a copy of the
    /// pivot row's B entries, a fixed-length loop; the last B pivots take the general path.
    fn factorize_fixed<const B: usize>(&mut self, tiny: f64) -> Result<(), (usize, f64)> {
        debug_assert_eq!(self.b, B);
        let n = self.n;
        let w = self.width;
        let threshold = self.pivot_threshold(tiny);
        for k in 0..n {
            let inv = self.take_pivot(k, threshold)?;
            if k + B < n {
                // Row k's entries k+1 … k+B start at k·w + B + 1.
                let start = k * w + B + 1;
                let pivot_row: [f64; B] = self.data[start..start + B]
                    .try_into()
                    .expect("a band row holds B entries right of its diagonal");
                for i in k + 1..=k + B {
                    // Entry (i, k) at column offset k + B − i of row i, its entries
                    // k+1 … k+B right after it.
                    let ik = i * w + k + B - i;
                    let l = self.data[ik] * inv;
                    if l == 0.0 {
                        continue;
                    }
                    self.data[ik] = l;
                    let row: &mut [f64; B] = (&mut self.data[ik + 1..ik + 1 + B])
                        .try_into()
                        .expect("a band row holds B entries right of (i, k)");
                    for (a, p) in row.iter_mut().zip(&pivot_row) {
                        *a -= l * p;
                    }
                }
            } else {
                self.eliminate_below(k, n - 1, inv);
            }
        }
        Ok(())
    }

    /// Solves A x = rhs in place after [`BandMatrix::factorize`].
    ///
    /// Both substitutions subtract the known unknowns from a row in the order in which they
    /// became known, the latest last: the subtractions of the earlier ones then run while the
    /// latest is still being computed, instead of the whole row waiting for it. The division
    /// by a pivot is a multiplication by the reciprocal the factorisation stored.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let n = self.n;
        let b = self.b;
        let w = self.width;
        for i in 0..n {
            let lo = i.saturating_sub(b);
            let row = i * w + b - i;
            let mut s = x[i];
            for (a, xj) in self.data[row + lo..row + i].iter().zip(&x[lo..i]) {
                s -= a * xj;
            }
            x[i] = s;
        }
        for i in (0..n).rev() {
            let hi = (i + b).min(n - 1);
            let row = i * w + b - i;
            let mut s = x[i];
            for (a, xj) in self.data[row + i + 1..=row + hi]
                .iter()
                .zip(&x[i + 1..=hi])
                .rev()
            {
                s -= a * xj;
            }
            x[i] = s * self.inverse_pivots[i];
        }
    }

    /// Solves A xₖ = rhsₖ for three right-hand sides in place after [`BandMatrix::factorize`],
    /// in one sweep over the factors; each xₖ equals [`BandMatrix::solve_in_place`] on it to
    /// the bit (same operations in the same order).
    pub(crate) fn solve3_in_place(&self, x: &mut [Vec<f64>; 3]) {
        let n = self.n;
        let b = self.b;
        let w = self.width;
        let [x0, x1, x2] = x;
        let (x0, x1, x2) = (&mut x0[..n], &mut x1[..n], &mut x2[..n]);
        for i in 0..n {
            let lo = i.saturating_sub(b);
            let row = &self.data[i * w + b - i + lo..i * w + b];
            let (mut s0, mut s1, mut s2) = (x0[i], x1[i], x2[i]);
            for (k, a) in row.iter().enumerate() {
                let j = lo + k;
                s0 -= a * x0[j];
                s1 -= a * x1[j];
                s2 -= a * x2[j];
            }
            (x0[i], x1[i], x2[i]) = (s0, s1, s2);
        }
        for i in (0..n).rev() {
            let hi = (i + b).min(n - 1);
            let base = i * w + b - i;
            let row = &self.data[base + i + 1..=base + hi];
            let (mut s0, mut s1, mut s2) = (x0[i], x1[i], x2[i]);
            for (k, a) in row.iter().enumerate().rev() {
                let j = i + 1 + k;
                s0 -= a * x0[j];
                s1 -= a * x1[j];
                s2 -= a * x2[j];
            }
            let d = self.inverse_pivots[i];
            (x0[i], x1[i], x2[i]) = (s0 * d, s1 * d, s2 * d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(n: usize, b: usize) -> BandMatrix {
        let mut a = BandMatrix::new(n, b);
        for i in 0..n {
            for j in i.saturating_sub(b)..=(i + b).min(n - 1) {
                let v = if i == j {
                    10.0 + i as f64
                } else {
                    ((i * 7 + j * 3) % 5) as f64 - 2.0 + 0.1 * (i as f64 - j as f64)
                };
                a.add(i, j, v);
            }
        }
        a
    }

    #[test]
    fn lu_solution_satisfies_the_nonsymmetric_system() {
        let (n, b) = (40, 5);
        let a = sample(n, b);
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut rhs = vec![0.0; n];
        a.mul_vec(&x_true, &mut rhs);
        let mut f = a.clone();
        f.factorize(1e-14).unwrap();
        f.solve_in_place(&mut rhs);
        let err = rhs
            .iter()
            .zip(&x_true)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "error {err}");
    }

    #[test]
    fn three_right_hand_sides_solve_exactly_as_one() {
        let (n, b) = (40, 5);
        let mut f = sample(n, b);
        f.factorize(1e-14).unwrap();
        let mut many: [Vec<f64>; 3] = std::array::from_fn(|k| {
            (0..n)
                .map(|i| ((i * (k + 2)) as f64 * 0.29).cos())
                .collect()
        });
        let singles: Vec<Vec<f64>> = many
            .iter()
            .map(|x| {
                let mut y = x.clone();
                f.solve_in_place(&mut y);
                y
            })
            .collect();
        f.solve3_in_place(&mut many);
        for (a, b) in many.iter().zip(&singles) {
            assert_eq!(a, b);
        }
    }

    #[test]
    fn identity_rows_decouple_prescribed_unknowns() {
        let mut a = sample(12, 3);
        a.set_identity_row_col(0);
        a.set_identity_row_col(11);
        assert_eq!(a.get(0, 0), 1.0);
        assert_eq!(a.get(0, 2), 0.0);
        assert_eq!(a.get(2, 0), 0.0);
        assert_eq!(a.get(9, 11), 0.0);
    }

    #[test]
    fn fixed_bandwidth_factors_equal_the_general_ones_to_the_bit() {
        for (n, b) in [(60, 11), (8, 11), (40, 5), (12, 5)] {
            let mut a = sample(n, b);
            // Some zero multipliers, as at the decoupled DOFs of a line.
            a.set_identity_row_col(0);
            a.set_identity_row_col(n - 1);
            let mut fixed = a.clone();
            let mut general = a.clone();
            fixed.factorize(1e-14).unwrap();
            general.factorize_general(1e-14).unwrap();
            assert_eq!(fixed.data, general.data, "n {n}, b {b}");
            assert_eq!(fixed.inverse_pivots, general.inverse_pivots);
        }
    }

    #[test]
    fn zero_pivot_is_reported() {
        let mut a = BandMatrix::new(3, 1);
        a.add(0, 0, 1.0);
        a.add(2, 2, 1.0);
        assert_eq!(a.factorize(1e-14), Err((1, 0.0)));
    }
}
