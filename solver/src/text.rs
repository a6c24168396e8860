//! How numbers read in messages: [`Num`] shows a value as it was written (the shortest text
//! that reads back to it), in exponent form beyond 10¹⁵ or below 10⁻⁵ so that an echoed
//! `1e300` stays `1e300` rather than 301 digits.

use std::fmt;

/// A number as messages show it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        let a = v.abs();
        if v.is_finite() && a != 0.0 && !(1e-5..1e15).contains(&a) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_written_and_extremes_in_exponent_form() {
        let shown = |v: f64| Num(v).to_string();
        assert_eq!(shown(1e300), "1e300");
        assert_eq!(shown(-2.5e-9), "-2.5e-9");
        assert_eq!(shown(5.8516723170686385e-9), "5.8516723170686385e-9");
        assert_eq!(shown(120.0), "120");
        assert_eq!(shown(-3.0), "-3");
        assert_eq!(shown(0.1), "0.1");
        assert_eq!(shown(0.0), "0");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(f64::INFINITY), "inf");
    }
}
