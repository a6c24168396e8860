//! Hot-spot load series as stored in the artifact store: CSV `time_s,tension_n,curvature_per_m`
//! with every number in Rust's shortest round-trip form, so a series read back is bit-identical
//! to the one written (a strand job resumed elsewhere sees exactly the same load).

use std::fmt::Write;

/// T(t), κ(t) at one hot spot.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HotSpotSeries {
    /// Times (s, from the end of the transient).
    pub time_s: Vec<f64>,
    /// Tension (N).
    pub tension_n: Vec<f64>,
    /// Curvature (1/m).
    pub curvature_per_m: Vec<f64>,
}

/// Header line of the CSV form.
const HEADER: &str = "time_s,tension_n,curvature_per_m";

impl HotSpotSeries {
    /// The CSV text.
    pub fn to_csv(&self) -> String {
        let mut out = String::with_capacity(64 * self.time_s.len() + 40);
        out.push_str(HEADER);
        out.push('\n');
        for ((t, f), k) in self
            .time_s
            .iter()
            .zip(&self.tension_n)
            .zip(&self.curvature_per_m)
        {
            let _ = writeln!(out, "{t},{f},{k}");
        }
        out
    }

    /// Reads the CSV text; the error names the line.
    pub fn from_csv(text: &str) -> Result<Self, String> {
        let mut lines = text.lines();
        if lines.next() != Some(HEADER) {
            return Err(format!("hot-spot series: first line must be '{HEADER}'"));
        }
        let mut s = Self::default();
        for (i, line) in lines.enumerate() {
            let mut v = [0.0; 3];
            let mut fields = line.split(',');
            for x in &mut v {
                *x = fields
                    .next()
                    .and_then(|f| f.parse().ok())
                    .ok_or_else(|| format!("hot-spot series line {}: '{line}'", i + 2))?;
            }
            s.time_s.push(v[0]);
            s.tension_n.push(v[1]);
            s.curvature_per_m.push(v[2]);
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_round_trips_bit_for_bit() {
        let s = HotSpotSeries {
            time_s: vec![0.0, 0.1, 0.30000000000000004],
            tension_n: vec![1.0e6 / 3.0, 2.5e5, -0.0],
            curvature_per_m: vec![1e-300, std::f64::consts::PI * 1e-3, 7.0],
        };
        let back = HotSpotSeries::from_csv(&s.to_csv()).unwrap();
        for (a, b) in s.tension_n.iter().zip(&back.tension_n) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
        assert_eq!(back, s);
    }
}
