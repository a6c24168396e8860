//! Sparse matrix pattern built once from element connectivities, with the element-to-slot map
//! that lets every Newton iteration refill the values without searching.
//!
//! Each element is given as the list of its global equation numbers ([`Equation`]), one per
//! element DOF, where [`Equation::CONSTRAINED`] marks a DOF that is eliminated (supported or
//! prescribed): its rows and columns are skipped. The pattern is stored column-compressed (CSC)
//! with sorted row indices, either the upper triangle only ([`Storage::Upper`], for the
//! symmetric Cholesky path) or in full ([`Storage::Full`], for LU). Every equation has its
//! diagonal entry, so an equation that no element touches shows up as a zero pivot rather than
//! as a malformed matrix.
//!
//! Symmetric storage symmetrises what it is given: entry (i, j), i < j, receives
//! ½(K_ab + K_ba) from the element pairs that map to it, which is the exact matrix when the
//! element matrices are symmetric and the symmetric part otherwise.

use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use thiserror::Error;

/// Global equation number of one DOF, or the marker of an eliminated DOF.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Equation(u32);

impl Equation {
    /// Marker of a constrained (eliminated) DOF.
    pub const CONSTRAINED: Equation = Equation(u32::MAX);

    /// Free equation number `index` (must be below `u32::MAX`).
    pub fn free(index: usize) -> Result<Self, PatternError> {
        u32::try_from(index)
            .ok()
            .filter(|&i| i != u32::MAX)
            .map(Equation)
            .ok_or(PatternError::TooLarge { count: index })
    }

    /// The equation index, or `None` for a constrained DOF.
    #[inline]
    pub fn index(self) -> Option<usize> {
        (self.0 != u32::MAX).then_some(self.0 as usize)
    }
}

/// Which part of the matrix is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    /// Upper triangle (row ≤ column) of a symmetric matrix.
    Upper,
    /// Every entry of a general matrix.
    Full,
}

/// Errors while building a pattern.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PatternError {
    /// An element refers to an equation beyond the system size.
    #[error("element {element}: equation {equation} out of range 0..{size}")]
    EquationOutOfRange {
        /// Element position in the input list.
        element: usize,
        /// Offending equation number.
        equation: usize,
        /// System size.
        size: usize,
    },
    /// More entries or equations than 32-bit slot indices can address.
    #[error("{count} entries or equations exceed the 32-bit index range")]
    TooLarge {
        /// Requested count.
        count: usize,
    },
}

const SKIP: u32 = u32::MAX;

/// CSC pattern plus, for every element, the value slot of each (row DOF, column DOF) pair.
#[derive(Debug, Clone)]
pub struct SparsePattern {
    size: usize,
    storage: Storage,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Element e owns `equations[eq_ptr[e]..eq_ptr[e+1]]`.
    eq_ptr: Vec<usize>,
    equations: Vec<Equation>,
    /// Element e with n DOFs owns n² slots starting at `slot_ptr[e]`, column-major over (a, b).
    slot_ptr: Vec<usize>,
    slots: Vec<u32>,
}

impl SparsePattern {
    /// Builds the pattern of a `size` × `size` system from element equation lists.
    pub fn new<E: AsRef<[Equation]>>(
        size: usize,
        storage: Storage,
        elements: &[E],
    ) -> Result<Self, PatternError> {
        if size >= u32::MAX as usize {
            return Err(PatternError::TooLarge { count: size });
        }
        let mut eq_ptr = Vec::with_capacity(elements.len() + 1);
        let mut equations = Vec::new();
        eq_ptr.push(0);
        let mut pairs: Vec<(u32, u32)> = (0..size as u32).map(|i| (i, i)).collect();
        for (element, eqs) in elements.iter().enumerate() {
            let eqs = eqs.as_ref();
            for e in eqs {
                if let Some(i) = e.index() {
                    if i >= size {
                        return Err(PatternError::EquationOutOfRange {
                            element,
                            equation: i,
                            size,
                        });
                    }
                }
            }
            for b in eqs.iter().filter_map(|e| e.index()) {
                for a in eqs.iter().filter_map(|e| e.index()) {
                    if let Some((row, col)) = place(storage, a, b) {
                        pairs.push((col as u32, row as u32));
                    }
                }
            }
            equations.extend_from_slice(eqs);
            eq_ptr.push(equations.len());
        }
        pairs.sort_unstable();
        pairs.dedup();
        if pairs.len() >= u32::MAX as usize {
            return Err(PatternError::TooLarge { count: pairs.len() });
        }
        let mut col_ptr = vec![0usize; size + 1];
        for &(c, _) in &pairs {
            col_ptr[c as usize + 1] += 1;
        }
        for c in 0..size {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = pairs.iter().map(|&(_, r)| r as usize).collect();

        let mut slot_ptr = Vec::with_capacity(elements.len() + 1);
        let mut slots = Vec::new();
        slot_ptr.push(0);
        for e in 0..elements.len() {
            let eqs = &equations[eq_ptr[e]..eq_ptr[e + 1]];
            for eb in eqs {
                for ea in eqs {
                    let slot = match (ea.index(), eb.index()) {
                        (Some(a), Some(b)) => match place(storage, a, b) {
                            Some((row, col)) => {
                                let rows = &row_idx[col_ptr[col]..col_ptr[col + 1]];
                                // present by construction
                                match rows.binary_search(&row) {
                                    Ok(k) => (col_ptr[col] + k) as u32,
                                    Err(_) => SKIP,
                                }
                            }
                            None => SKIP,
                        },
                        _ => SKIP,
                    };
                    slots.push(slot);
                }
            }
            slot_ptr.push(slots.len());
        }
        Ok(Self {
            size,
            storage,
            col_ptr,
            row_idx,
            eq_ptr,
            equations,
            slot_ptr,
            slots,
        })
    }

    /// The upper-triangle pattern of the structural symmetrisation A ∪ Aᵀ of this pattern (no
    /// elements: values are filled through the returned map), with, for every nonzero k of this
    /// pattern, the nonzero of the upper pattern that holds entry (min(i, j), max(i, j)).
    pub(crate) fn symmetric_upper(&self) -> (SparsePattern, Vec<usize>) {
        let mut pairs: Vec<(usize, usize)> = Vec::with_capacity(self.row_idx.len());
        for col in 0..self.size {
            for &row in &self.row_idx[self.col_ptr[col]..self.col_ptr[col + 1]] {
                pairs.push((row.max(col), row.min(col)));
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        let mut col_ptr = vec![0usize; self.size + 1];
        for &(c, _) in &pairs {
            col_ptr[c + 1] += 1;
        }
        for c in 0..self.size {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = pairs.iter().map(|&(_, r)| r).collect();
        let mut map = Vec::with_capacity(self.row_idx.len());
        for col in 0..self.size {
            for &row in &self.row_idx[self.col_ptr[col]..self.col_ptr[col + 1]] {
                let (r, c) = (row.min(col), row.max(col));
                let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
                let k = rows
                    .binary_search(&r)
                    .expect("the symmetrised pattern holds every entry");
                map.push(col_ptr[c] + k);
            }
        }
        (
            SparsePattern {
                size: self.size,
                storage: Storage::Upper,
                col_ptr,
                row_idx,
                eq_ptr: vec![0],
                equations: Vec::new(),
                slot_ptr: vec![0],
                slots: Vec::new(),
            },
            map,
        )
    }

    /// Number of equations.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Stored part of the matrix.
    pub fn storage(&self) -> Storage {
        self.storage
    }

    /// Number of elements the pattern was built from.
    pub fn element_count(&self) -> usize {
        self.eq_ptr.len() - 1
    }

    /// Equations of element `element`.
    pub fn element_equations(&self, element: usize) -> &[Equation] {
        &self.equations[self.eq_ptr[element]..self.eq_ptr[element + 1]]
    }

    /// Column pointers of the CSC structure.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices of the CSC structure (sorted within each column).
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// The structure as a faer symbolic matrix.
    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(
            self.size,
            self.size,
            &self.col_ptr,
            None,
            &self.row_idx,
        )
    }

    /// A faer matrix view of `values` (length [`Self::nnz`]) on this structure.
    pub fn matrix<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.symbolic(), values)
    }

    /// Adds the element matrix `ke` (n × n, column-major, n = number of element DOFs) of
    /// element `element` into `values`.
    #[inline]
    pub fn add_element_matrix(&self, values: &mut [f64], element: usize, ke: &[f64]) {
        let slots = &self.slots[self.slot_ptr[element]..self.slot_ptr[element + 1]];
        debug_assert_eq!(slots.len(), ke.len());
        match self.storage {
            Storage::Full => {
                for (&s, &k) in slots.iter().zip(ke) {
                    if s != SKIP {
                        values[s as usize] += k;
                    }
                }
            }
            Storage::Upper => {
                let eqs = self.element_equations(element);
                let n = eqs.len();
                // (a, b) and (b, a) share one slot: visit each unordered pair once
                for b in 0..n {
                    for a in 0..=b {
                        let s = slots[b * n + a];
                        if s != SKIP {
                            let kab = ke[b * n + a];
                            values[s as usize] += if a == b {
                                kab
                            } else if eqs[a] == eqs[b] {
                                kab + ke[a * n + b]
                            } else {
                                0.5 * (kab + ke[a * n + b])
                            };
                        }
                    }
                }
            }
        }
    }

    /// Adds the element vector `fe` of element `element` into the global vector `rhs`,
    /// skipping constrained DOFs.
    #[inline]
    pub(crate) fn add_element_vector(&self, rhs: &mut [f64], element: usize, fe: &[f64]) {
        for (e, &f) in self.element_equations(element).iter().zip(fe) {
            if let Some(i) = e.index() {
                rhs[i] += f;
            }
        }
    }

    /// y ← A x for the stored matrix (the symmetric one for [`Storage::Upper`]).
    pub fn mul_vec(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for col in 0..self.size {
            let range = self.col_ptr[col]..self.col_ptr[col + 1];
            for (&row, &v) in self.row_idx[range.clone()].iter().zip(&values[range]) {
                y[row] += v * x[col];
                if self.storage == Storage::Upper && row != col {
                    y[col] += v * x[row];
                }
            }
        }
    }
}

fn place(storage: Storage, row: usize, col: usize) -> Option<(usize, usize)> {
    match storage {
        Storage::Full => Some((row, col)),
        Storage::Upper => Some((row.min(col), row.max(col))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eqs(list: &[i64]) -> Vec<Equation> {
        list.iter()
            .map(|&i| {
                if i < 0 {
                    Equation::CONSTRAINED
                } else {
                    Equation::free(i as usize).unwrap()
                }
            })
            .collect()
    }

    /// Two 2-DOF springs in series, the first grounded through a constrained DOF.
    #[test]
    fn assembled_springs_give_the_textbook_matrix_in_both_storages() {
        let elements = vec![eqs(&[-1, 0]), eqs(&[0, 1])];
        let ke = |k: f64| [k, -k, -k, k];
        for storage in [Storage::Upper, Storage::Full] {
            let p = SparsePattern::new(2, storage, &elements).unwrap();
            let mut values = vec![0.0; p.nnz()];
            p.add_element_matrix(&mut values, 0, &ke(2.0));
            p.add_element_matrix(&mut values, 1, &ke(3.0));
            let mut y = [0.0; 2];
            p.mul_vec(&values, &[1.0, 0.0], &mut y);
            assert_eq!(y, [5.0, -3.0]);
            p.mul_vec(&values, &[0.0, 1.0], &mut y);
            assert_eq!(y, [-3.0, 3.0]);
        }
    }

    #[test]
    fn upper_storage_keeps_the_symmetric_part_of_a_nonsymmetric_element() {
        let p = SparsePattern::new(2, Storage::Upper, &[eqs(&[0, 1])]).unwrap();
        assert_eq!(p.nnz(), 3);
        let mut values = vec![0.0; 3];
        // column-major [[1, 4], [2, 5]]: K01 = 4, K10 = 2
        p.add_element_matrix(&mut values, 0, &[1.0, 2.0, 4.0, 5.0]);
        assert_eq!(values, vec![1.0, 3.0, 5.0]);
    }

    #[test]
    fn out_of_range_equation_is_reported_with_its_element() {
        let err = SparsePattern::new(2, Storage::Full, &[eqs(&[0, 1]), eqs(&[1, 7])]).unwrap_err();
        assert_eq!(
            err,
            PatternError::EquationOutOfRange {
                element: 1,
                equation: 7,
                size: 2
            }
        );
    }

    #[test]
    fn untouched_equation_still_has_a_diagonal_entry() {
        let p = SparsePattern::new(3, Storage::Upper, &[eqs(&[0, 1])]).unwrap();
        assert_eq!(p.col_ptr()[3] - p.col_ptr()[2], 1);
        assert_eq!(p.row_idx()[p.col_ptr()[2]], 2);
    }
}
