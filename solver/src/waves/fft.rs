//! Power-of-two complex FFT used to evaluate sums of wave components on a uniform time grid.
//!
//! Only the unnormalised inverse transform is needed: z_j = Σ_b Z_b e^{+2πi b j / N}. The
//! transform is RustFFT's plan for size N (mixed-radix, vectorised with the instruction set the
//! processor offers, chosen at run time); its rounding error grows like log₂N · ε, as for the
//! radix-2 transform it replaced (kept in the tests as the reference: the two agree to a few
//! ε · ‖Z‖₁, test `planned_transform_agrees_with_radix_2_on_a_sea_spectrum`).

use std::sync::Arc;

use nalgebra::Complex;
use rustfft::{Fft, FftPlanner};

use super::error::WavesError;

/// Precomputed plan for one transform size N (a power of two).
#[derive(Clone)]
pub struct InverseFft {
    n: usize,
    plan: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for InverseFft {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InverseFft").field("n", &self.n).finish()
    }
}

impl InverseFft {
    /// Plan for size `n`, which must be a power of two ≥ 2.
    pub fn new(n: usize) -> Result<Self, WavesError> {
        if n < 2 || !n.is_power_of_two() {
            return Err(WavesError::InvalidParameter {
                field: "fft_size",
                value: n as f64,
                rule: "a power of two >= 2",
            });
        }
        let plan = FftPlanner::new().plan_fft_inverse(n);
        Ok(Self { n, plan })
    }

    /// Transform size N.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a plan has N ≥ 2.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Length of the scratch that [`InverseFft::inverse_with_scratch`] needs.
    pub(crate) fn scratch_len(&self) -> usize {
        self.plan.get_inplace_scratch_len()
    }

    /// In place z_j = Σ_b Z_b e^{+2πi b j/N}. `buf` must have length N. Allocates its scratch;
    /// see `InverseFft::inverse_with_scratch` for repeated transforms.
    pub fn inverse_in_place(&self, buf: &mut [Complex<f64>]) {
        let mut scratch = vec![Complex::default(); self.scratch_len()];
        self.inverse_with_scratch(buf, &mut scratch);
    }

    /// As [`InverseFft::inverse_in_place`] with caller-held scratch of at least
    /// [`InverseFft::scratch_len`] entries.
    pub(crate) fn inverse_with_scratch(
        &self,
        buf: &mut [Complex<f64>],
        scratch: &mut [Complex<f64>],
    ) {
        assert_eq!(buf.len(), self.n, "buffer length must equal the plan size");
        let len = self.scratch_len();
        self.plan.process_with_scratch(buf, &mut scratch[..len]);
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    /// The radix-2 decimation-in-time transform used before the planned one (twiddles from
    /// sin/cos of 2πm/N), kept as a reference.
    fn radix_2_inverse(buf: &mut [Complex<f64>]) {
        let n = buf.len();
        let bits = n.trailing_zeros();
        for i in 0..n {
            let j = i.reverse_bits() >> (usize::BITS - bits);
            if i < j {
                buf.swap(i, j);
            }
        }
        let mut half = 1;
        while half < n {
            let tw: Vec<Complex<f64>> = (0..half)
                .map(|m| {
                    let (s, c) = (PI * m as f64 / half as f64).sin_cos();
                    Complex::new(c, s)
                })
                .collect();
            for block in buf.chunks_exact_mut(2 * half) {
                let (lo, hi) = block.split_at_mut(half);
                for ((a, b), w) in lo.iter_mut().zip(hi.iter_mut()).zip(&tw) {
                    let t = *b * w;
                    *b = *a - t;
                    *a += t;
                }
            }
            half *= 2;
        }
    }

    #[test]
    fn inverse_fft_equals_direct_sum() {
        let n = 64;
        let plan = InverseFft::new(n).unwrap();
        let input: Vec<Complex<f64>> = (0..n)
            .map(|b| Complex::new((b as f64 * 0.37).sin(), (b as f64 * 1.3).cos()))
            .collect();
        let mut buf = input.clone();
        plan.inverse_in_place(&mut buf);
        for (j, z) in buf.iter().enumerate() {
            let direct: Complex<f64> = input
                .iter()
                .enumerate()
                .map(|(b, &x)| x * Complex::from_polar(1.0, 2.0 * PI * (b * j) as f64 / n as f64))
                .sum();
            assert!((z - direct).norm() < 1e-12 * n as f64);
        }
    }

    #[test]
    fn planned_transform_agrees_with_radix_2_on_a_sea_spectrum() {
        // As the precomputation fills it: a few hundred components in the lowest bins and
        // their conjugates mirrored at N − bin, N = 16 384 as in the paper case.
        let n = 16_384;
        let plan = InverseFft::new(n).unwrap();
        let mut input = vec![Complex::default(); n];
        for bin in 85..580 {
            let a = (-((bin as f64 - 200.0) / 80.0).powi(2)).exp() * 3.0;
            let z = Complex::from_polar(a, bin as f64 * 2.399);
            input[bin] += 0.5 * z;
            input[n - bin] += 0.5 * z.conj();
        }
        let l1: f64 = input.iter().map(|z| z.norm()).sum();
        let mut got = input.clone();
        let mut scratch = vec![Complex::default(); plan.scratch_len()];
        plan.inverse_with_scratch(&mut got, &mut scratch);
        let mut reference = input;
        radix_2_inverse(&mut reference);
        let err = got
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(err <= 1e-14 * l1, "{err} against ‖Z‖₁ = {l1}");
    }

    #[test]
    fn non_power_of_two_size_is_rejected() {
        assert!(InverseFft::new(48).is_err());
        assert!(InverseFft::new(1).is_err());
    }
}
