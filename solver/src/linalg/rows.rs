//! Row-major copy of a full-storage sparse matrix for products y = A x split by rows.
//!
//! The assembly patterns are column-major (faer's layout); a product in that layout scatters
//! into y and cannot be shared between threads without reductions. The copy here holds the
//! same values row by row (column indices as `u32`, half the index traffic), so two threads
//! each compute a contiguous block of rows. Within a row the terms are added in increasing
//! column order, the order of the column-major product, so the result is the same to the bit
//! whatever the number of threads.

use super::pattern::{SparsePattern, Storage};

/// A full-storage matrix by rows, refilled from the column-major values of its pattern.
#[derive(Debug, Clone)]
pub(crate) struct RowMajor {
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    /// Column-major position of every row-major entry.
    source: Vec<usize>,
    values: Vec<f64>,
    /// First row of the second half of the entries (for two threads).
    split: usize,
}

impl RowMajor {
    /// Structure of `pattern` (full storage) by rows.
    pub(crate) fn new(pattern: &SparsePattern) -> Self {
        debug_assert_eq!(pattern.storage(), Storage::Full);
        let n = pattern.size();
        let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
        let mut row_ptr = vec![0usize; n + 1];
        for &r in row_idx {
            row_ptr[r + 1] += 1;
        }
        for i in 0..n {
            row_ptr[i + 1] += row_ptr[i];
        }
        let nnz = row_idx.len();
        let mut next = row_ptr.clone();
        let (mut col, mut source) = (vec![0u32; nnz], vec![0usize; nnz]);
        for c in 0..n {
            for (k, &r) in row_idx
                .iter()
                .enumerate()
                .take(col_ptr[c + 1])
                .skip(col_ptr[c])
            {
                col[next[r]] = c as u32;
                source[next[r]] = k;
                next[r] += 1;
            }
        }
        let split = row_ptr.partition_point(|&p| p < nnz / 2).min(n);
        Self {
            row_ptr,
            col,
            source,
            values: vec![0.0; nnz],
            split,
        }
    }

    /// Takes the matrix's column-major values.
    pub(crate) fn load(&mut self, values: &[f64]) {
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = values[k];
        }
    }

    /// y ← A x, the rows in two halves on two threads when `parallel`.
    pub(crate) fn mul_vec(&self, x: &[f64], y: &mut [f64], parallel: bool) {
        let (first, second) = y.split_at_mut(self.split);
        if parallel {
            rayon::join(
                || self.rows(0, x, first),
                || self.rows(self.split, x, second),
            );
        } else {
            self.rows(0, x, first);
            self.rows(self.split, x, second);
        }
    }

    fn rows(&self, start: usize, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            let range = self.row_ptr[start + i]..self.row_ptr[start + i + 1];
            let mut sum = 0.0;
            for (&c, &v) in self.col[range.clone()].iter().zip(&self.values[range]) {
                sum += v * x[c as usize];
            }
            *yi = sum;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::pattern::Equation;

    #[test]
    fn row_major_product_equals_the_column_major_one_to_the_bit() {
        // overlapping 3-equation elements with unsymmetric values
        let n = 40;
        let elements: Vec<Vec<Equation>> = (0..n - 2)
            .map(|i| (i..i + 3).map(|e| Equation::free(e).unwrap()).collect())
            .collect();
        let p = SparsePattern::new(n, Storage::Full, &elements).unwrap();
        let mut values = vec![0.0; p.nnz()];
        for e in 0..elements.len() {
            let ke: Vec<f64> = (0..9).map(|k| ((e * 9 + k) as f64 * 0.77).sin()).collect();
            p.add_element_matrix(&mut values, e, &ke);
        }
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 1.3).cos()).collect();
        let mut expected = vec![0.0; n];
        p.mul_vec(&values, &x, &mut expected);
        let mut rows = RowMajor::new(&p);
        rows.load(&values);
        for parallel in [false, true] {
            let mut y = vec![f64::NAN; n];
            rows.mul_vec(&x, &mut y, parallel);
            assert_eq!(y, expected);
        }
    }
}
