//! Streaming least squares of the contact laws ([`super`] module docs).
//!
//! The samples of the calibration run are consumed one at a time into sums (normal equations),
//! so no time series of the ~8 000 contacts is kept. The load features are the same for every
//! contact, so their Gram matrices are shared: per contact only the right-hand sides, the
//! cross terms with its own tangential force and the sums of squares are kept.
//!
//! Fits, per contact, with `φ = [1, x, y, xy, x², y²]` and `ψ = [x, y, 1]`:
//! - normal force: `f_N ≈ φ·n`;
//! - structure: `s ≈ ψ·[a, b, c] − g f_T` for `[a, b, c, g]`; if that makes `g < 0` (no
//!   physical meaning: the strand would push the contact along its own friction force),
//!   `s ≈ ψ·[a, b, c]` with `g = 0`.
//!
//! Each system is solved after Jacobi scaling (columns to unit diagonal) with a relative ridge
//! of [`RIDGE`], which only matters for a contact whose tangential force is (nearly) a linear
//! function of its slip and the loads — a contact that stuck through the whole calibration,
//! for which every `g` reproduces its stick response (the slip range is then `Δd / (1 + g k)`
//! with `Δd` fitted for that `g`).

use nalgebra::{SMatrix, SVector};

use super::{force_features, ContactLaw, FORCE_FEATURES};

/// Relative ridge of the scaled normal equations.
pub const RIDGE: f64 = 1e-10;

type ForceGram = SMatrix<f64, FORCE_FEATURES, FORCE_FEATURES>;
type ForceVec = SVector<f64, FORCE_FEATURES>;

/// Sums of one force channel fitted on the force features.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct ForceSums {
    rhs: [f64; FORCE_FEATURES],
    yy: f64,
    sum: f64,
}

impl ForceSums {
    #[inline]
    fn add(&mut self, phi: &[f64; FORCE_FEATURES], y: f64) {
        for (r, p) in self.rhs.iter_mut().zip(phi) {
            *r += p * y;
        }
        self.yy += y * y;
        self.sum += y;
    }
}

/// Sums of one contact's structure equation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct DriveSums {
    /// Σ ψ (−f_T).
    psi_f: [f64; 3],
    /// Σ f_T².
    ff: f64,
    /// Σ ψ s.
    psi_s: [f64; 3],
    /// Σ (−f_T) s.
    fs: f64,
    /// Σ s².
    ss: f64,
    /// Σ s.
    s_sum: f64,
}

/// Fit of one channel: coefficients and the residual and spread sums of squares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceFit {
    /// Coefficients on the force features.
    pub coefficients: [f64; FORCE_FEATURES],
    /// Σ residual².
    pub residual_ss: f64,
    /// Σ (y − ȳ)².
    pub spread_ss: f64,
}

/// Fit of one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactFit {
    /// The law.
    pub law: ContactLaw,
    /// Σ slip residual² (m²).
    pub slip_residual_ss: f64,
    /// Σ (s − s̄)² (m²).
    pub slip_spread_ss: f64,
    /// Normal force fit sums (N²).
    pub normal_residual_ss: f64,
    /// Σ (f_N − f̄_N)² (N²).
    pub normal_spread_ss: f64,
    /// Whether `g` was refitted at zero.
    pub compliance_clamped: bool,
}

/// Accumulates the calibration samples of every contact and wire-element channel.
#[derive(Clone, Debug)]
pub struct FitAccumulator {
    force_gram: ForceGram,
    drive_gram: SMatrix<f64, 3, 3>,
    samples: usize,
    normal: Vec<ForceSums>,
    drive: Vec<DriveSums>,
    elements: Vec<ForceSums>,
}

impl FitAccumulator {
    /// Empty sums for `contacts` contacts and `elements` wire-element channels.
    pub fn new(contacts: usize, elements: usize) -> Self {
        Self {
            force_gram: ForceGram::zeros(),
            drive_gram: SMatrix::zeros(),
            samples: 0,
            normal: vec![ForceSums::default(); contacts],
            drive: vec![DriveSums::default(); contacts],
            elements: vec![ForceSums::default(); elements],
        }
    }

    /// Samples consumed.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Adds one sample at scaled loads (x, y): every contact's (slip, f_N, f_T) and every
    /// element channel's value. Slices shorter or longer than the sums are a caller's error
    /// and are ignored beyond the shorter length.
    pub fn add(&mut self, x: f64, y: f64, contacts: &[(f64, f64, f64)], elements: &[f64]) {
        let phi = force_features(x, y);
        let psi = [x, y, 1.0];
        let phi_v = ForceVec::from_column_slice(&phi);
        self.force_gram += phi_v * phi_v.transpose();
        let psi_v = SVector::<f64, 3>::from_column_slice(&psi);
        self.drive_gram += psi_v * psi_v.transpose();
        self.samples += 1;
        for ((&(s, f_n, f_t), n), d) in contacts
            .iter()
            .zip(&mut self.normal)
            .zip(&mut self.drive)
        {
            n.add(&phi, f_n);
            let f = -f_t;
            for k in 0..3 {
                d.psi_f[k] += psi[k] * f;
                d.psi_s[k] += psi[k] * s;
            }
            d.ff += f * f;
            d.fs += f * s;
            d.ss += s * s;
            d.s_sum += s;
        }
        for (e, &v) in self.elements.iter_mut().zip(elements) {
            e.add(&phi, v);
        }
    }

    /// The fitted laws of every contact.
    pub fn contact_fits(&self) -> Vec<ContactFit> {
        let n = self.samples.max(1) as f64;
        let normal_solver = ScaledSolver::new(&self.force_gram);
        self.normal
            .iter()
            .zip(&self.drive)
            .map(|(ns, ds)| {
                let normal = self.force_fit(&normal_solver, ns);
                let (drive, g, slip_residual_ss, clamped) = self.drive_fit(ds);
                ContactFit {
                    law: ContactLaw {
                        normal: normal.coefficients,
                        drive,
                        compliance_m_per_n: g,
                    },
                    slip_residual_ss,
                    slip_spread_ss: (ds.ss - ds.s_sum * ds.s_sum / n).max(0.0),
                    normal_residual_ss: normal.residual_ss,
                    normal_spread_ss: normal.spread_ss,
                    compliance_clamped: clamped,
                }
            })
            .collect()
    }

    /// The fitted element channels.
    pub fn element_fits(&self) -> Vec<ForceFit> {
        let solver = ScaledSolver::new(&self.force_gram);
        self.elements
            .iter()
            .map(|e| self.force_fit(&solver, e))
            .collect()
    }

    fn force_fit(&self, solver: &ScaledSolver<FORCE_FEATURES>, s: &ForceSums) -> ForceFit {
        let rhs = ForceVec::from_column_slice(&s.rhs);
        let beta = solver.solve(&rhs);
        let n = self.samples.max(1) as f64;
        let residual_ss =
            (s.yy - 2.0 * beta.dot(&rhs) + (beta.transpose() * self.force_gram * beta)[0]).max(0.0);
        let mut coefficients = [0.0; FORCE_FEATURES];
        coefficients.copy_from_slice(beta.as_slice());
        ForceFit {
            coefficients,
            residual_ss,
            spread_ss: (s.yy - s.sum * s.sum / n).max(0.0),
        }
    }

    /// `[a, b, c]`, `g`, Σ residual², whether g was clamped.
    fn drive_fit(&self, d: &DriveSums) -> ([f64; 3], f64, f64, bool) {
        let mut m = SMatrix::<f64, 4, 4>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.drive_gram);
        for k in 0..3 {
            m[(k, 3)] = d.psi_f[k];
            m[(3, k)] = d.psi_f[k];
        }
        m[(3, 3)] = d.ff;
        let rhs = SVector::<f64, 4>::new(d.psi_s[0], d.psi_s[1], d.psi_s[2], d.fs);
        let residual = |beta: &SVector<f64, 4>| {
            (d.ss - 2.0 * beta.dot(&rhs) + (beta.transpose() * m * beta)[0]).max(0.0)
        };
        if d.ff > 0.0 {
            let beta = ScaledSolver::new(&m).solve(&rhs);
            if beta[3] >= 0.0 && beta.iter().all(|v| v.is_finite()) {
                return ([beta[0], beta[1], beta[2]], beta[3], residual(&beta), false);
            }
        }
        let rhs3 = SVector::<f64, 3>::new(d.psi_s[0], d.psi_s[1], d.psi_s[2]);
        let b3 = ScaledSolver::new(&self.drive_gram).solve(&rhs3);
        let beta = SVector::<f64, 4>::new(b3[0], b3[1], b3[2], 0.0);
        ([b3[0], b3[1], b3[2]], 0.0, residual(&beta), d.ff > 0.0)
    }
}

/// Jacobi-scaled, ridge-regularised solver of a symmetric positive semi-definite system.
struct ScaledSolver<const N: usize> {
    scale: SVector<f64, N>,
    inverse: SMatrix<f64, N, N>,
}

impl<const N: usize> ScaledSolver<N> {
    fn new(m: &SMatrix<f64, N, N>) -> Self {
        let scale = SVector::<f64, N>::from_fn(|i, _| {
            let d = m[(i, i)];
            if d > 0.0 && d.is_finite() {
                1.0 / d.sqrt()
            } else {
                0.0
            }
        });
        let mut a = SMatrix::<f64, N, N>::from_fn(|i, j| scale[i] * m[(i, j)] * scale[j]);
        for i in 0..N {
            a[(i, i)] += RIDGE;
        }
        let inverse = a
            .cholesky()
            .map(|c| c.inverse())
            .or_else(|| a.try_inverse())
            .unwrap_or_else(SMatrix::zeros);
        Self { scale, inverse }
    }

    fn solve(&self, rhs: &SVector<f64, N>) -> SVector<f64, N> {
        let z = self.inverse * rhs.component_mul(&self.scale);
        z.component_mul(&self.scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exact_quadratic_force_is_recovered() {
        let truth = [120.0, 30.0, -12.0, 4.0, 2.5, -1.5];
        let mut acc = FitAccumulator::new(1, 1);
        for i in 0..40 {
            let (x, y) = ((i as f64 * 0.37).sin(), (i as f64 * 0.91).cos());
            let f: f64 = force_features(x, y).iter().zip(&truth).map(|(a, b)| a * b).sum();
            acc.add(x, y, &[(0.0, f, 0.0)], &[f]);
        }
        let fits = acc.contact_fits();
        for (a, b) in fits[0].law.normal.iter().zip(&truth) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
        // exact data: what is left is the round-off of the normal equations
        assert!(fits[0].normal_residual_ss < 1e-8 * fits[0].normal_spread_ss);
        let e = acc.element_fits();
        assert!((e[0].coefficients[0] - 120.0).abs() < 1e-6);
    }

    #[test]
    fn the_structure_equation_is_recovered_with_its_compliance() {
        // s = a x + b y + c − g f_T with f_T independent of the loads: all four identifiable
        let (a, b, c, g) = (2e-6, -5e-6, 1e-7, 3e-8);
        let mut acc = FitAccumulator::new(1, 0);
        for i in 0..60 {
            let (x, y) = ((i as f64 * 0.37).sin(), (i as f64 * 0.53).cos());
            let f_t = 40.0 * (i as f64 * 1.7).sin();
            let s = a * x + b * y + c - g * f_t;
            acc.add(x, y, &[(s, 100.0, f_t)], &[]);
        }
        let fit = acc.contact_fits()[0];
        let rel = |p: f64, q: f64| (p - q).abs() / q.abs();
        assert!(rel(fit.law.drive[0], a) < 1e-6);
        assert!(rel(fit.law.drive[1], b) < 1e-6);
        assert!(rel(fit.law.drive[2], c) < 1e-5);
        assert!(rel(fit.law.compliance_m_per_n, g) < 1e-6);
        assert!(!fit.compliance_clamped);
    }

    #[test]
    fn a_negative_compliance_is_refitted_at_zero() {
        // data made with g < 0: the fit falls back to the pure drive
        let mut acc = FitAccumulator::new(1, 0);
        for i in 0..60 {
            let (x, y) = ((i as f64 * 0.37).sin(), (i as f64 * 0.53).cos());
            let f_t = 40.0 * (i as f64 * 1.7).sin();
            let s = 1e-6 * x + 4e-8 * f_t;
            acc.add(x, y, &[(s, 100.0, f_t)], &[]);
        }
        let fit = acc.contact_fits()[0];
        assert_eq!(fit.law.compliance_m_per_n, 0.0);
        assert!(fit.compliance_clamped);
        assert!(fit.slip_residual_ss > 0.0);
    }
}
