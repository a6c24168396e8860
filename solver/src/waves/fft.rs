//! Power-of-two complex FFT (iterative radix-2, decimation in time) used to evaluate sums of wave
//! components on a uniform time grid.
//!
//! Only the unnormalised inverse transform is needed: z_j = Σ_b Z_b e^{+2πi b j / N}. Twiddle
//! factors are computed directly from sin/cos of 2πm/N (not by recurrence), so the rounding error
//! grows like log₂N · ε.

use std::f64::consts::PI;

use nalgebra::Complex;

use super::error::WavesError;

/// Precomputed plan for one transform size N (a power of two).
#[derive(Debug, Clone)]
pub struct InverseFft {
    n: usize,
    /// Twiddles of every stage, contiguous: stage with half-length h uses entries h−1 … 2h−2,
    /// e^{2πi m/(2h)} for m < h.
    twiddles: Vec<Complex<f64>>,
    bit_reversed: Vec<usize>,
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
        let mut twiddles = Vec::with_capacity(n);
        let mut half = 1;
        while half < n {
            twiddles.extend((0..half).map(|m| {
                let (s, c) = (PI * m as f64 / half as f64).sin_cos();
                Complex::new(c, s)
            }));
            half *= 2;
        }
        let bits = n.trailing_zeros();
        let bit_reversed = (0..n)
            .map(|i| i.reverse_bits() >> (usize::BITS - bits))
            .collect();
        Ok(Self {
            n,
            twiddles,
            bit_reversed,
        })
    }

    /// Transform size N.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a plan has N ≥ 2.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Length of the scratch that [`InverseFft::inverse_with_scratch`] needs (none).
    pub fn scratch_len(&self) -> usize {
        0
    }

    /// As [`InverseFft::inverse_in_place`]; the transform needs no scratch.
    pub fn inverse_with_scratch(&self, buf: &mut [Complex<f64>], _scratch: &mut [Complex<f64>]) {
        self.inverse_in_place(buf);
    }

    /// In place z_j = Σ_b Z_b e^{+2πi b j/N}. `buf` must have length N.
    pub fn inverse_in_place(&self, buf: &mut [Complex<f64>]) {
        debug_assert_eq!(buf.len(), self.n);
        for i in 0..self.n {
            let j = self.bit_reversed[i];
            if i < j {
                buf.swap(i, j);
            }
        }
        let mut half = 1;
        while half < self.n {
            let tw = &self.twiddles[half - 1..2 * half - 1];
            for block in buf.chunks_exact_mut(2 * half) {
                let (lo, hi) = block.split_at_mut(half);
                for ((a, b), w) in lo.iter_mut().zip(hi.iter_mut()).zip(tw) {
                    let t = *b * w;
                    *b = *a - t;
                    *a += t;
                }
            }
            half *= 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn non_power_of_two_size_is_rejected() {
        assert!(InverseFft::new(48).is_err());
        assert!(InverseFft::new(1).is_err());
    }
}
