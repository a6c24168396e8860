//! Scalars and 3-vectors generic over plain `f64` and a forward-mode dual number.
//!
//! The contact element writes its internal force once, generically over [`Scalar`]. Evaluated
//! with `f64` it gives the residual; evaluated with [`Dual`] — whose 12 derivative slots are
//! seeded with the variations of the element's kinematic quantities under the spatial DOFs
//! [δu₁, δθ₁, δu₂, δθ₂] — the derivative slots of the force are the rows of the consistent
//! tangent. The tangent is therefore exact (to round-off) for whatever force the element computes,
//! including the stick/slip return mapping and the dependence of the tangential stiffness on the
//! normal force.
//!
//! Everything is fixed-size and on the stack: no allocation.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Number of element degrees of freedom (two nodes × (3 translations + 3 rotations)).
pub(crate) const NDOF: usize = 12;

/// The arithmetic the contact kernel needs.
pub(crate) trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Add<f64, Output = Self>
{
    /// A constant (zero derivative).
    fn cst(v: f64) -> Self;
    /// The value, without derivatives.
    fn val(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Real power.
    fn powf(self, p: f64) -> Self;
}

impl Scalar for f64 {
    #[inline]
    fn cst(v: f64) -> Self {
        v
    }
    #[inline]
    fn val(self) -> f64 {
        self
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn powf(self, p: f64) -> Self {
        f64::powf(self, p)
    }
}

/// Forward-mode dual number with [`NDOF`] derivative directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dual {
    /// Value.
    pub v: f64,
    /// Derivatives with respect to the element DOFs.
    pub d: [f64; NDOF],
}

impl Dual {
    /// A value with one unit derivative in direction `k`.
    #[cfg(test)]
    pub(crate) fn seeded(v: f64, k: usize) -> Self {
        let mut d = [0.0; NDOF];
        d[k] = 1.0;
        Self { v, d }
    }

    #[inline]
    fn map2(self, o: Self, a: f64, b: f64) -> [f64; NDOF] {
        let mut d = [0.0; NDOF];
        for ((x, p), q) in d.iter_mut().zip(&self.d).zip(&o.d) {
            *x = a * p + b * q;
        }
        d
    }

    #[inline]
    fn scaled(self, a: f64) -> [f64; NDOF] {
        let mut d = self.d;
        for x in &mut d {
            *x *= a;
        }
        d
    }
}

impl Add for Dual {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            d: self.map2(o, 1.0, 1.0),
        }
    }
}
impl Sub for Dual {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self {
            v: self.v - o.v,
            d: self.map2(o, 1.0, -1.0),
        }
    }
}
impl Mul for Dual {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            d: self.map2(o, o.v, self.v),
        }
    }
}
impl Div for Dual {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        let q = self.v * inv;
        Self {
            v: q,
            d: self.map2(o, inv, -q * inv),
        }
    }
}
impl Neg for Dual {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            d: self.scaled(-1.0),
        }
    }
}
impl Mul<f64> for Dual {
    type Output = Self;
    #[inline]
    fn mul(self, a: f64) -> Self {
        Self {
            v: self.v * a,
            d: self.scaled(a),
        }
    }
}
impl Add<f64> for Dual {
    type Output = Self;
    #[inline]
    fn add(self, a: f64) -> Self {
        Self {
            v: self.v + a,
            d: self.d,
        }
    }
}

impl Scalar for Dual {
    #[inline]
    fn cst(v: f64) -> Self {
        Self { v, d: [0.0; NDOF] }
    }
    #[inline]
    fn val(self) -> f64 {
        self.v
    }
    #[inline]
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        Self {
            v: s,
            d: self.scaled(0.5 / s),
        }
    }
    #[inline]
    fn powf(self, p: f64) -> Self {
        let y = self.v.powf(p);
        Self {
            v: y,
            d: self.scaled(p * y / self.v),
        }
    }
}

/// A 3-vector over a [`Scalar`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct V3<S> {
    /// Components.
    pub c: [S; 3],
}

impl<S: Scalar> V3<S> {
    /// From components.
    #[inline]
    pub(crate) fn new(x: S, y: S, z: S) -> Self {
        Self { c: [x, y, z] }
    }
    /// A constant vector.
    #[inline]
    pub(crate) fn cst(v: &nalgebra::Vector3<f64>) -> Self {
        Self::new(S::cst(v.x), S::cst(v.y), S::cst(v.z))
    }
    /// Value part as a nalgebra vector.
    #[inline]
    pub(crate) fn val(&self) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::new(self.c[0].val(), self.c[1].val(), self.c[2].val())
    }
    /// Dot product.
    #[inline]
    pub(crate) fn dot(&self, o: &Self) -> S {
        self.c[0] * o.c[0] + self.c[1] * o.c[1] + self.c[2] * o.c[2]
    }
    /// Cross product.
    #[inline]
    pub(crate) fn cross(&self, o: &Self) -> Self {
        let [a0, a1, a2] = self.c;
        let [b0, b1, b2] = o.c;
        Self::new(a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0)
    }
    /// Euclidean norm.
    #[inline]
    pub(crate) fn norm(&self) -> S {
        self.dot(self).sqrt()
    }
    /// Multiplication by a scalar.
    #[inline]
    pub(crate) fn scale(&self, s: S) -> Self {
        Self::new(self.c[0] * s, self.c[1] * s, self.c[2] * s)
    }
    /// Multiplication by a constant.
    #[inline]
    pub(crate) fn scalef(&self, s: f64) -> Self {
        Self::new(self.c[0] * s, self.c[1] * s, self.c[2] * s)
    }
}

impl<S: Scalar> Add for V3<S> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.c[0] + o.c[0], self.c[1] + o.c[1], self.c[2] + o.c[2])
    }
}
impl<S: Scalar> Sub for V3<S> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.c[0] - o.c[0], self.c[1] - o.c[1], self.c[2] - o.c[2])
    }
}
impl<S: Scalar> Neg for V3<S> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.c[0], -self.c[1], -self.c[2])
    }
}

/// A vector whose variation is δv = δθ × v under the spatial rotation DOFs starting at
/// `first_rotation_dof` (3 consecutive slots), i.e. a director carried by a node's triad.
pub(crate) fn director(v: &nalgebra::Vector3<f64>, first_rotation_dof: usize) -> V3<Dual> {
    let mut out = V3::<Dual>::cst(v);
    // (δθ × v)_i = Σ_j ε_ijk δθ_j v_k → ∂(·)_i/∂θ_j = -v̂_ij
    let m = crate::beam::rotation::skew(v);
    for i in 0..3 {
        for j in 0..3 {
            out.c[i].d[first_rotation_dof + j] = -m[(i, j)];
        }
    }
    out
}

/// A position whose variation is δx = δu under the translation DOFs starting at
/// `first_translation_dof`.
pub(crate) fn point(x: &nalgebra::Vector3<f64>, first_translation_dof: usize) -> V3<Dual> {
    let mut out = V3::<Dual>::cst(x);
    for i in 0..3 {
        out.c[i].d[first_translation_dof + i] = 1.0;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dual_derivatives_match_calculus_rules() {
        let x = Dual::seeded(2.0, 0);
        let y = Dual::seeded(3.0, 1);
        let f = (x * y + x.sqrt()) / y - x.powf(1.5) * 2.0;
        let dfdx = 1.0 + 0.5 / 2f64.sqrt() / 3.0 - 3.0 * 2f64.sqrt();
        let dfdy = -2f64.sqrt() / 9.0;
        assert!((f.d[0] - dfdx).abs() < 1e-14);
        assert!((f.d[1] - dfdy).abs() < 1e-14);
    }

    #[test]
    fn director_variation_is_spin_cross_vector() {
        let v = nalgebra::Vector3::new(0.3, -0.4, 0.866);
        let d = director(&v, 3);
        let spin = nalgebra::Vector3::new(0.1, 0.2, -0.7);
        let expect = spin.cross(&v);
        for i in 0..3 {
            let got: f64 = (0..3).map(|j| d.c[i].d[3 + j] * spin[j]).sum();
            assert!((got - expect[i]).abs() < 1e-15);
        }
    }
}
