//! Cubic Hermite interpolation on one element of unstretched length L, local coordinate
//! ξ = x / L ∈ [0, 1]:
//!
//! r(x) = N₁ rᵢ + N₂ r'ᵢ + N₃ rⱼ + N₄ r'ⱼ, with N₁ = 1 − 3ξ² + 2ξ³, N₂ = L (ξ − 2ξ² + ξ³),
//! N₃ = 3ξ² − 2ξ³, N₄ = L (ξ³ − ξ²),
//!
//! the "position + gradient" interpolation of the gradient-deficient ANCF cable element
//! (Gerstmayr & Shabana 2006). Also the exact element integrals of the constant matrices
//! ∫ Nₐ N_b dx (consistent mass) and ∫ Nₐ'' N_b'' dx (bending), which are the classical
//! Euler–Bernoulli beam matrices, and the Gauss rule the elements share.

/// Values of the four shape functions and their first and second derivatives (per metre).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HermiteValues {
    /// Nₐ(ξ).
    pub n: [f64; 4],
    /// dNₐ/dx (1/m for positions, dimensionless for gradients).
    pub dn: [f64; 4],
    /// d²Nₐ/dx².
    pub ddn: [f64; 4],
}

/// Shape functions at ξ on an element of length `l`.
pub(crate) fn hermite(xi: f64, l: f64) -> HermiteValues {
    let x2 = xi * xi;
    let x3 = x2 * xi;
    HermiteValues {
        n: [
            1.0 - 3.0 * x2 + 2.0 * x3,
            l * (xi - 2.0 * x2 + x3),
            3.0 * x2 - 2.0 * x3,
            l * (x3 - x2),
        ],
        dn: [
            (-6.0 * xi + 6.0 * x2) / l,
            1.0 - 4.0 * xi + 3.0 * x2,
            (6.0 * xi - 6.0 * x2) / l,
            3.0 * x2 - 2.0 * xi,
        ],
        ddn: [
            (-6.0 + 12.0 * xi) / (l * l),
            (-4.0 + 6.0 * xi) / l,
            (6.0 - 12.0 * xi) / (l * l),
            (6.0 * xi - 2.0) / l,
        ],
    }
}

/// ∫₀ᴸ Nₐ N_b dx: the consistent mass matrix per unit mass density.
pub(crate) fn mass_integrals(l: f64) -> [[f64; 4]; 4] {
    let c = l / 420.0;
    let l2 = l * l;
    [
        [156.0 * c, 22.0 * l * c, 54.0 * c, -13.0 * l * c],
        [22.0 * l * c, 4.0 * l2 * c, 13.0 * l * c, -3.0 * l2 * c],
        [54.0 * c, 13.0 * l * c, 156.0 * c, -22.0 * l * c],
        [-13.0 * l * c, -3.0 * l2 * c, -22.0 * l * c, 4.0 * l2 * c],
    ]
}

/// ∫₀ᴸ Nₐ'' N_b'' dx: the bending stiffness matrix per unit EI.
pub(crate) fn bending_integrals(l: f64) -> [[f64; 4]; 4] {
    let c = 1.0 / (l * l * l);
    let l2 = l * l;
    [
        [12.0 * c, 6.0 * l * c, -12.0 * c, 6.0 * l * c],
        [6.0 * l * c, 4.0 * l2 * c, -6.0 * l * c, 2.0 * l2 * c],
        [-12.0 * c, -6.0 * l * c, 12.0 * c, -6.0 * l * c],
        [6.0 * l * c, 2.0 * l2 * c, -6.0 * l * c, 4.0 * l2 * c],
    ]
}

/// Three-point Gauss–Legendre rule on [0, 1]: (ξ, weight). Exact to degree 5, which covers the
/// squared axial strain of a cubic interpolation.
pub(crate) const GAUSS3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn gauss5(f: impl Fn(f64) -> f64) -> f64 {
        // Five-point Gauss–Legendre on [0, 1], exact to degree 9.
        let p = [
            (0.046_910_077_030_668, 0.118_463_442_528_095),
            (0.230_765_344_947_158, 0.239_314_335_249_683),
            (0.5, 0.284_444_444_444_444),
            (0.769_234_655_052_841, 0.239_314_335_249_683),
            (0.953_089_922_969_332, 0.118_463_442_528_095),
        ];
        p.iter().map(|&(x, w)| w * f(x)).sum()
    }

    #[test]
    fn constant_matrices_equal_their_quadrature() {
        let l = 2.7;
        let m = mass_integrals(l);
        let b = bending_integrals(l);
        for a in 0..4 {
            for c in 0..4 {
                let mq = l * gauss5(|x| hermite(x, l).n[a] * hermite(x, l).n[c]);
                let bq = l * gauss5(|x| hermite(x, l).ddn[a] * hermite(x, l).ddn[c]);
                assert!((m[a][c] - mq).abs() < 1e-12 * l * l * l);
                assert!((b[a][c] - bq).abs() < 1e-9 * b[0][0].abs());
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let l = 1.7;
        let h = 1e-6;
        for &xi in &[0.1, 0.45, 0.9] {
            let p = hermite(xi + h, l);
            let m = hermite(xi - h, l);
            let c = hermite(xi, l);
            for a in 0..4 {
                let dn = (p.n[a] - m.n[a]) / (2.0 * h * l);
                let ddn = (p.dn[a] - m.dn[a]) / (2.0 * h * l);
                assert!((dn - c.dn[a]).abs() < 1e-7, "dn {a}");
                assert!((ddn - c.ddn[a]).abs() < 1e-6, "ddn {a}");
            }
        }
    }

    #[test]
    fn interpolation_reproduces_a_cubic_exactly() {
        // Nodal values and slopes of f(x) = x³ − 2x on [0, L].
        let l = 3.0;
        let f = |x: f64| x * x * x - 2.0 * x;
        let df = |x: f64| 3.0 * x * x - 2.0;
        let q = [f(0.0), df(0.0), f(l), df(l)];
        for &xi in &[0.0, 0.3, 0.77, 1.0] {
            let s = hermite(xi, l);
            let v: f64 = (0..4).map(|a| s.n[a] * q[a]).sum();
            let dv: f64 = (0..4).map(|a| s.dn[a] * q[a]).sum();
            let ddv: f64 = (0..4).map(|a| s.ddn[a] * q[a]).sum();
            assert!((v - f(xi * l)).abs() < 1e-12);
            assert!((dv - df(xi * l)).abs() < 1e-12);
            assert!((ddv - 6.0 * xi * l).abs() < 1e-11);
        }
    }
}
