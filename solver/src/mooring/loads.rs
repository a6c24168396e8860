//! Distributed loads at one quadrature point and their consistent linearisation.
//!
//! A load per unit unstretched length f(r, v, a, r') acting at a point interpolated as
//! r = Σ Nₐ qₐ contributes −∫ Nₐ f dx to the residual R = M q̈ + f_int − f_ext of coefficient a,
//! and −∫ Nₐ (N_b J + N_b' J_{r'}) dx to the iteration matrix block (a, b), where
//! J = ∂f/∂r + γ' ∂f/∂v + β' ∂f/∂a is the combination the time integrator asks for
//! (γ' = ∂v/∂q, β' = ∂q̈/∂q; both zero in statics) and J_{r'} = ∂f/∂r' accounts for
//! loads that depend on the line direction (drag and added mass split normal / tangential).

use nalgebra::{Matrix3, Vector3};

/// Strain half-width of the smoothed slack transition of the axial law.
pub(crate) const SLACK_SMOOTHING_STRAIN: f64 = 2e-5;

/// Axial force law of chain and rope: no compression (a chain folds, a wire rope buckles at a
/// negligible load), smoothed so that Newton's method converges through slack events:
/// N/EA = 0 for ε ≤ −ε₀, (ε + ε₀)² / (4 ε₀) for |ε| < ε₀, ε for ε ≥ ε₀ (C¹; at most
/// EA ε₀ / 4 of tension is added near zero strain, about 2 kN for the paper-case chain and
/// rope). Returns (N, dN/dε, strain energy per unit length).
pub(crate) fn slack_axial_force(ea_n: f64, strain: f64) -> (f64, f64, f64) {
    let e0 = SLACK_SMOOTHING_STRAIN;
    if strain <= -e0 {
        (0.0, 0.0, 0.0)
    } else if strain < e0 {
        let x = strain + e0;
        (
            ea_n * x * x / (4.0 * e0),
            ea_n * x / (2.0 * e0),
            ea_n * x * x * x / (12.0 * e0),
        )
    } else {
        (
            ea_n * strain,
            ea_n,
            ea_n * (2.0 * e0 * e0 / 3.0 + 0.5 * (strain * strain - e0 * e0)),
        )
    }
}

/// A force per unit length at a point and its partial derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PointLoad {
    /// Force per unit unstretched length (N/m).
    pub f: Vector3<f64>,
    /// ∂f/∂r (N/m²).
    pub d_r: Matrix3<f64>,
    /// ∂f/∂v, v the structural velocity (N s/m²).
    pub d_v: Matrix3<f64>,
    /// ∂f/∂a, a the structural acceleration (kg/m).
    pub d_a: Matrix3<f64>,
    /// ∂f/∂r', r' the gradient of the position along the line (N/m).
    pub d_rx: Matrix3<f64>,
}

impl PointLoad {
    /// No load.
    pub(crate) fn zero() -> PointLoad {
        PointLoad {
            f: Vector3::zeros(),
            d_r: Matrix3::zeros(),
            d_v: Matrix3::zeros(),
            d_a: Matrix3::zeros(),
            d_rx: Matrix3::zeros(),
        }
    }

    /// Adds another load at the same point.
    pub(crate) fn add(&mut self, o: &PointLoad) {
        self.f += o.f;
        self.d_r += o.d_r;
        self.d_v += o.d_v;
        self.d_a += o.d_a;
        self.d_rx += o.d_rx;
    }
}

/// Derivatives of the current state with respect to the positions, set by the integrator.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Coefficients {
    /// ∂q̈/∂q (1/s²); zero in statics.
    pub beta_p: f64,
    /// ∂q̇/∂q (1/s); zero in statics.
    pub gamma_p: f64,
    /// Axial structural damping ratio at each element's axial frequency (see
    /// [`super::section::Section::axial_damping_n_s`]); zero in statics.
    pub axial_damping_ratio: f64,
}

/// Element-local residual and iteration matrix over `NC` vector coefficients of 3 components.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LocalSystem<const NC: usize> {
    /// Residual per coefficient.
    pub r: [Vector3<f64>; NC],
    /// Iteration matrix blocks.
    pub k: [[Matrix3<f64>; NC]; NC],
}

impl<const NC: usize> LocalSystem<NC> {
    /// All zero.
    pub(crate) fn zero() -> Self {
        LocalSystem {
            r: [Vector3::zeros(); NC],
            k: [[Matrix3::zeros(); NC]; NC],
        }
    }

    /// Adds the contribution of `load` at a point with shape values `n`, derivatives `dn`
    /// (per metre) and quadrature weight `w` (m).
    pub(crate) fn add_point_load(
        &mut self,
        n: &[f64; NC],
        dn: &[f64; NC],
        w: f64,
        load: &PointLoad,
        c: &Coefficients,
    ) {
        let j = (load.d_r + load.d_v * c.gamma_p + load.d_a * c.beta_p) * w;
        let jt = load.d_rx * w;
        // Block (a, b) is n_a (J n_b + J_{r'} n_b'): the bracket once per b.
        let column: [Matrix3<f64>; NC] = std::array::from_fn(|b| j * n[b] + jt * dn[b]);
        for ((r, row), &na) in self.r.iter_mut().zip(self.k.iter_mut()).zip(n) {
            *r -= load.f * (w * na);
            for (k, m) in row.iter_mut().zip(&column) {
                *k -= m * na;
            }
        }
    }

    /// Adds a constant matrix of the form C ⊗ I₃ (scaled by `s`) acting on `x`: residual
    /// += s C x, matrix += `k_scale` · s C ⊗ I₃.
    pub(crate) fn add_scalar_matrix(
        &mut self,
        c: &[[f64; NC]; NC],
        s: f64,
        x: &[Vector3<f64>; NC],
        k_scale: f64,
    ) {
        for (a, row) in c.iter().enumerate() {
            for (b, (&cab, xb)) in row.iter().zip(x).enumerate() {
                let v = s * cab;
                self.r[a] += xb * v;
                let kd = v * k_scale;
                self.k[a][b][(0, 0)] += kd;
                self.k[a][b][(1, 1)] += kd;
                self.k[a][b][(2, 2)] += kd;
            }
        }
    }
}

/// Interpolated kinematics at a quadrature point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PointKinematics {
    /// Position (m).
    pub r: Vector3<f64>,
    /// Gradient ∂r/∂s (stretch × unit tangent).
    pub r_x: Vector3<f64>,
    /// Velocity (m/s).
    pub v: Vector3<f64>,
    /// Acceleration (m/s²).
    pub a: Vector3<f64>,
}

impl PointKinematics {
    /// Interpolates coefficient values `q`, `v`, `a` with shape values `n` and derivatives `dn`.
    pub(crate) fn interpolate<const NC: usize>(
        n: &[f64; NC],
        dn: &[f64; NC],
        q: &[Vector3<f64>; NC],
        v: &[Vector3<f64>; NC],
        a: &[Vector3<f64>; NC],
    ) -> Self {
        let mut k = PointKinematics {
            r: Vector3::zeros(),
            r_x: Vector3::zeros(),
            v: Vector3::zeros(),
            a: Vector3::zeros(),
        };
        for i in 0..NC {
            k.r += q[i] * n[i];
            k.r_x += q[i] * dn[i];
            k.v += v[i] * n[i];
            k.a += a[i] * n[i];
        }
        k
    }
}
