//! Scratch memory of the line solvers (allocated once per line, reused every iteration) and the
//! linear-algebra steps they share: applying the prescribed unknowns, factorising the banded
//! iteration matrix, solving for the Newton correction and condensing the line onto its
//! fairlead.
//!
//! Condensation: with p the three fairlead position DOFs and i the free DOFs, the change of the
//! fairlead reaction for a fairlead displacement, the free DOFs re-equilibrated, is the Schur
//! complement K_c = S_pp − S_pi S_ii⁻¹ S_ip of the iteration matrix S. The force on the floater
//! is −R_p, so it changes by −K_c dx.

use nalgebra::Matrix3;

use super::assembly::WaterCache;
use super::banded::BandMatrix;
use super::error::LineError;
use super::line::LineModel;

/// Scratch space of one line.
#[derive(Debug, Clone)]
pub struct LineWorkspace {
    pub(crate) residual: Vec<f64>,
    pub(crate) rhs: Vec<f64>,
    pub(crate) matrix: BandMatrix,
    pub(crate) water: WaterCache,
    pub(crate) trial_q: Vec<f64>,
    /// Columns S_{·p} of the fairlead DOFs, saved before the constraints are applied.
    fairlead_columns: [Vec<f64>; 3],
    /// Rows S_{p·} of the fairlead DOFs.
    fairlead_rows: [Vec<f64>; 3],
    /// S_ii⁻¹ S_ip e_j of the last condensation (zero at prescribed DOFs).
    fairlead_modes: [Vec<f64>; 3],
    /// Whether `fairlead_modes` holds a condensation.
    has_modes: bool,
    /// Factorisations made so far, and the one `condensed` and `fairlead_modes` belong to: the
    /// condensation is a function of the factorisation alone, so a step that reused the
    /// factorisation of an earlier one reuses its condensation too.
    factorizations: u64,
    condensed_factorization: Option<u64>,
    /// K_c of the last condensation (N/m).
    condensed: Matrix3<f64>,
}

impl LineWorkspace {
    /// Workspace sized for `model`.
    pub fn new(model: &LineModel) -> LineWorkspace {
        let n = model.dof_count();
        LineWorkspace {
            residual: vec![0.0; n],
            rhs: vec![0.0; n],
            matrix: BandMatrix::new(n, model.half_bandwidth()),
            water: Vec::new(),
            trial_q: vec![0.0; n],
            fairlead_columns: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            fairlead_rows: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            fairlead_modes: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            has_modes: false,
            factorizations: 0,
            condensed_factorization: None,
            condensed: Matrix3::zeros(),
        }
    }

    /// Saves the fairlead rows and columns, replaces the prescribed rows and columns by the
    /// identity and factorises. The right-hand side `rhs` is set to −R with zeros at the
    /// prescribed DOFs.
    pub(crate) fn prepare_and_factorize(
        &mut self,
        model: &LineModel,
        tiny_pivot: f64,
    ) -> Result<(), LineError> {
        let n = model.dof_count();
        let b = model.half_bandwidth();
        for p in 0..3 {
            let col = &mut self.fairlead_columns[p];
            let row = &mut self.fairlead_rows[p];
            col.fill(0.0);
            row.fill(0.0);
            for i in 0..(p + b + 1).min(n) {
                col[i] = self.matrix.get(i, p);
                row[i] = self.matrix.get(p, i);
            }
        }
        for dof in model.fairlead_dofs().chain(model.anchor_dofs()) {
            self.matrix.set_identity_row_col(dof);
        }
        for (i, (r, x)) in self.rhs.iter_mut().zip(&self.residual).enumerate() {
            *r = if model.is_constrained(i) { 0.0 } else { -x };
        }
        self.factorizations += 1;
        self.matrix
            .factorize(tiny_pivot)
            .map_err(|(dof, pivot)| LineError::SingularMatrix {
                line: model.name().to_string(),
                dof,
                pivot,
            })
    }

    /// Sets `rhs` to −R with zeros at the prescribed DOFs, for a solve with the factorisation
    /// already held by the matrix.
    pub(crate) fn load_rhs(&mut self, model: &LineModel) {
        for (i, (r, x)) in self.rhs.iter_mut().zip(&self.residual).enumerate() {
            *r = if model.is_constrained(i) { 0.0 } else { -x };
        }
    }

    /// Newton correction into `rhs`, after [`LineWorkspace::prepare_and_factorize`].
    pub(crate) fn solve_correction(&mut self) {
        self.matrix.solve_in_place(&mut self.rhs);
    }

    /// Schur complement of the factorised matrix onto the fairlead DOFs (N/m); computed once
    /// per factorisation (the three columns in one sweep over the factors).
    pub(crate) fn condense_fairlead(&mut self, model: &LineModel) -> Matrix3<f64> {
        if self.has_modes && self.condensed_factorization == Some(self.factorizations) {
            return self.condensed;
        }
        for (mode, column) in self.fairlead_modes.iter_mut().zip(&self.fairlead_columns) {
            for (i, (m, c)) in mode.iter_mut().zip(column).enumerate() {
                *m = if model.is_constrained(i) { 0.0 } else { *c };
            }
        }
        self.matrix.solve3_in_place(&mut self.fairlead_modes);
        let mut k = Matrix3::zeros();
        for (j, x) in self.fairlead_modes.iter().enumerate() {
            for p in 0..3 {
                let mut s = self.fairlead_rows[p][j];
                for (i, xi) in x.iter().enumerate() {
                    if !model.is_constrained(i) {
                        s -= self.fairlead_rows[p][i] * xi;
                    }
                }
                k[(p, j)] = s;
            }
        }
        self.has_modes = true;
        self.condensed_factorization = Some(self.factorizations);
        self.condensed = k;
        k
    }

    /// The vectors S_ii⁻¹ S_ip e_j (j = x, y, z) of the last condensation, if any.
    pub(crate) fn fairlead_modes(&self) -> Option<&[Vec<f64>; 3]> {
        self.has_modes.then_some(&self.fairlead_modes)
    }
}
