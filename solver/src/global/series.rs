//! Hot-spot series T(t), κ(t): what the global stage hands the strand stage. One type, one CSV
//! writer, one parser, for every file that holds such series:
//!
//! - one hot spot, `time_s,tension_n,curvature_per_m`: the artifact a global job stores per hot
//!   spot (role `hot_spot_<i>_series`), read back by its strand, calibration and reduced jobs
//!   and by the report, and a load file of `moorfret run strand --load`;
//! - several hot spots, `time_s` then `tension_n_<i>,curvature_per_m_<i>` per hot spot `i`:
//!   the `hotspots.csv` of `moorfret run global`, read by `run strand --load … --hot-spot I`.
//!
//! Every number is written in Rust's shortest round-trip form, so a series read back is
//! bit-identical to the one written (a strand job resumed elsewhere sees exactly the same load).
//!
//! The parser ([`LoadTable::parse`]) also reads the strain form of a strand load file
//! (`axial_strain` in place of `tension_n`), and columns in any order; its errors name the
//! sample, its line and the column ([`SeriesError`]).

use std::fmt::{self, Write};

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

/// Column names of a file of one hot spot.
const TIME: &str = "time_s";
const TENSION: &str = "tension_n";
const STRAIN: &str = "axial_strain";
const CURVATURE: &str = "curvature_per_m";

impl HotSpotSeries {
    /// The CSV text of one hot spot, `time_s,tension_n,curvature_per_m`.
    pub fn to_csv(&self) -> String {
        write_csv(std::slice::from_ref(self), Columns::Plain)
    }

    /// The CSV text of several hot spots sampled at the same times (those of the first),
    /// `time_s` then `tension_n_<i>,curvature_per_m_<i>` per hot spot `i`.
    pub fn table_csv(series: &[HotSpotSeries]) -> String {
        write_csv(series, Columns::Indexed)
    }

    /// Reads a file of one hot spot (or hot spot 0 of a file of several); the error names the
    /// line and the column.
    pub fn from_csv(text: &str) -> Result<Self, SeriesError> {
        LoadTable::parse(text, 0)?.into_series()
    }

    /// Reads every hot spot of a file (one for the single-hot-spot form), in the order of
    /// their indices.
    pub fn all_from_csv(text: &str) -> Result<Vec<Self>, SeriesError> {
        let hot_spots = LoadTable::header(text)?.hot_spots;
        if hot_spots.is_empty() {
            return Ok(vec![Self::from_csv(text)?]);
        }
        let mut sorted = hot_spots;
        sorted.sort_unstable();
        sorted
            .into_iter()
            .map(|k| LoadTable::parse(text, k)?.into_series())
            .collect()
    }
}

/// How the columns of a series file are named.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Columns {
    /// `tension_n`, `curvature_per_m`: one hot spot.
    Plain,
    /// `tension_n_<i>`, `curvature_per_m_<i>` per hot spot `i`.
    Indexed,
}

/// The one writer of series files (module docs).
fn write_csv(series: &[HotSpotSeries], columns: Columns) -> String {
    let time = series.first().map_or(&[][..], |s| s.time_s.as_slice());
    let mut out = String::with_capacity((24 + 40 * series.len()) * time.len() + 64);
    out.push_str(TIME);
    for i in 0..series.len() {
        match columns {
            Columns::Plain => {
                let _ = write!(out, ",{TENSION},{CURVATURE}");
            }
            Columns::Indexed => {
                let _ = write!(out, ",{TENSION}_{i},{CURVATURE}_{i}");
            }
        }
    }
    out.push('\n');
    for (j, t) in time.iter().enumerate() {
        let _ = write!(out, "{t}");
        for s in series {
            let (Some(f), Some(k)) = (s.tension_n.get(j), s.curvature_per_m.get(j)) else {
                break;
            };
            let _ = write!(out, ",{f},{k}");
        }
        out.push('\n');
    }
    out
}

/// What the load column of a series file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadKind {
    /// Tension (N), `tension_n`.
    Tension,
    /// Axial strain, `axial_strain` (a strand load file only).
    Strain,
}

impl LoadKind {
    /// The column name.
    pub fn column(self) -> &'static str {
        match self {
            Self::Tension => TENSION,
            Self::Strain => STRAIN,
        }
    }
}

/// Why a series file was refused: where, and what was wrong.
#[derive(Debug, Clone, PartialEq)]
pub enum SeriesError {
    /// The header is wrong (unknown, repeated or missing column; no such hot spot).
    Header(String),
    /// A sample is wrong: not a number, not finite, or a row of another width.
    Sample {
        /// Sample index from 0.
        index: usize,
        /// Line in the file (from 1).
        line: usize,
        /// Column name (`None` for a row of the wrong width).
        column: Option<&'static str>,
        /// What is wrong.
        reason: String,
    },
    /// The file has no samples.
    Empty,
}

impl fmt::Display for SeriesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Header(m) => f.write_str(m),
            Self::Sample {
                index,
                line,
                column,
                reason,
            } => {
                write!(f, "sample {index} (line {line})")?;
                if let Some(c) = column {
                    write!(f, ", column {c}")?;
                }
                write!(f, ": {reason}")
            }
            Self::Empty => f.write_str("no samples"),
        }
    }
}

impl std::error::Error for SeriesError {}

/// A series file as read: times, tension or strain, curvatures (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct LoadTable {
    /// What `value` holds.
    pub kind: LoadKind,
    /// Times (s).
    pub time_s: Vec<f64>,
    /// Tension (N) or axial strain, per `kind`.
    pub value: Vec<f64>,
    /// Curvature (1/m).
    pub curvature_per_m: Vec<f64>,
}

/// The header of a series file: where the columns read are, and which hot spots it holds.
struct Header {
    /// Column index of time, load value, curvature.
    columns: [usize; 3],
    kind: LoadKind,
    /// Hot spots of the indexed form, in the order of the header (empty for one hot spot).
    hot_spots: Vec<usize>,
    width: usize,
}

impl LoadTable {
    /// The series of a tension table; a strain table is refused.
    pub fn into_series(self) -> Result<HotSpotSeries, SeriesError> {
        match self.kind {
            LoadKind::Tension => Ok(HotSpotSeries {
                time_s: self.time_s,
                tension_n: self.value,
                curvature_per_m: self.curvature_per_m,
            }),
            LoadKind::Strain => Err(SeriesError::Header(format!(
                "column {STRAIN}: a hot-spot series holds {TENSION}"
            ))),
        }
    }

    /// Reads hot spot `hot_spot` of a series file (the index applies to the indexed form
    /// only); every value must be a finite number.
    pub fn parse(text: &str, hot_spot: usize) -> Result<Self, SeriesError> {
        let header = Self::header_at(text, hot_spot)?;
        let names = [TIME, header.kind.column(), CURVATURE];
        let mut table = LoadTable {
            kind: header.kind,
            time_s: Vec::new(),
            value: Vec::new(),
            curvature_per_m: Vec::new(),
        };
        for (index, (line, row)) in data_lines(text).enumerate() {
            let fields: Vec<&str> = row.split(',').map(str::trim).collect();
            if fields.len() != header.width {
                return Err(SeriesError::Sample {
                    index,
                    line,
                    column: None,
                    reason: format!("{} fields, the header has {}", fields.len(), header.width),
                });
            }
            let mut v = [0.0; 3];
            for (slot, x) in v.iter_mut().enumerate() {
                let field = fields[header.columns[slot]];
                let sample = |reason: String| SeriesError::Sample {
                    index,
                    line,
                    column: Some(names[slot]),
                    reason,
                };
                *x = field
                    .parse::<f64>()
                    .map_err(|_| sample(format!("{field:?} is not a number")))?;
                if !x.is_finite() {
                    return Err(sample(format!("{x} is not a finite number")));
                }
            }
            table.time_s.push(v[0]);
            table.value.push(v[1]);
            table.curvature_per_m.push(v[2]);
        }
        if table.time_s.is_empty() {
            return Err(SeriesError::Empty);
        }
        Ok(table)
    }

    fn header(text: &str) -> Result<Header, SeriesError> {
        let line = text
            .lines()
            .next()
            .ok_or_else(|| SeriesError::Header("no header line".into()))?;
        let mut columns: [Option<usize>; 3] = [None; 3];
        let mut kind: Option<LoadKind> = None;
        let mut hot_spots: Vec<usize> = Vec::new();
        let names: Vec<&str> = line.split(',').map(str::trim).collect();
        for (i, &name) in names.iter().enumerate() {
            let indexed = |prefix: &str| -> Option<usize> {
                name.strip_prefix(prefix)?.strip_prefix('_')?.parse().ok()
            };
            let name = match (indexed(TENSION), indexed(CURVATURE)) {
                (Some(k), _) | (None, Some(k)) => {
                    if !hot_spots.contains(&k) {
                        hot_spots.push(k);
                    }
                    continue;
                }
                (None, None) => name,
            };
            let slot = match name {
                TIME => 0,
                TENSION | STRAIN => {
                    let k = if name == TENSION {
                        LoadKind::Tension
                    } else {
                        LoadKind::Strain
                    };
                    if let Some(other) = kind.filter(|&o| o != k) {
                        return Err(SeriesError::Header(format!(
                            "column {name}: the file already has {}; give {TENSION} or \
                             {STRAIN}, not both",
                            other.column()
                        )));
                    }
                    kind = Some(k);
                    1
                }
                CURVATURE => 2,
                _ => {
                    return Err(SeriesError::Header(format!(
                        "unknown column {name:?} (expected {TIME}, {TENSION} or {STRAIN}, \
                         {CURVATURE})"
                    )))
                }
            };
            if columns[slot].replace(i).is_some() {
                return Err(SeriesError::Header(format!("column {name} appears twice")));
            }
        }
        Ok(Header {
            columns: columns.map(|c| c.unwrap_or(usize::MAX)),
            kind: kind.unwrap_or(LoadKind::Tension),
            hot_spots,
            width: names.len(),
        })
    }

    /// The header with the columns of hot spot `hot_spot` (indexed form) in place.
    fn header_at(text: &str, hot_spot: usize) -> Result<Header, SeriesError> {
        let mut header = Self::header(text)?;
        if !header.hot_spots.is_empty() {
            let line = text.lines().next().unwrap_or("");
            for (i, name) in line.split(',').map(str::trim).enumerate() {
                if name == format!("{TENSION}_{hot_spot}") {
                    if header.columns[1] != usize::MAX {
                        return Err(SeriesError::Header(format!(
                            "column {name}: the file already has {}",
                            header.kind.column()
                        )));
                    }
                    header.columns[1] = i;
                } else if name == format!("{CURVATURE}_{hot_spot}") {
                    if header.columns[2] != usize::MAX {
                        return Err(SeriesError::Header(format!(
                            "column {name}: the file already has {CURVATURE}"
                        )));
                    }
                    header.columns[2] = i;
                }
            }
        }
        let names = [TIME, "tension_n or axial_strain", CURVATURE];
        for (slot, name) in names.iter().enumerate() {
            if header.columns[slot] == usize::MAX {
                if !header.hot_spots.is_empty() && slot > 0 {
                    return Err(SeriesError::Header(format!(
                        "no hot spot {hot_spot}; the file has hot spots {:?}",
                        header.hot_spots
                    )));
                }
                return Err(SeriesError::Header(format!("missing column {name}")));
            }
        }
        Ok(header)
    }
}

/// The non-blank lines after the header, with their line numbers (from 1).
fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .skip(1)
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> HotSpotSeries {
        HotSpotSeries {
            time_s: vec![0.0, 0.1, 0.30000000000000004],
            tension_n: vec![1.0e6 / 3.0, 2.5e5, -0.0],
            curvature_per_m: vec![1e-300, std::f64::consts::PI * 1e-3, 7.0],
        }
    }

    #[test]
    fn series_round_trips_bit_for_bit_in_both_forms() {
        let s = sample();
        let text = s.to_csv();
        assert!(text.starts_with("time_s,tension_n,curvature_per_m\n"));
        let back = HotSpotSeries::from_csv(&text).unwrap();
        for (a, b) in s.tension_n.iter().zip(&back.tension_n) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
        assert_eq!(back, s);

        let mut other = sample();
        other.tension_n.reverse();
        other.curvature_per_m[0] = -2.5;
        let table = HotSpotSeries::table_csv(&[s.clone(), other.clone()]);
        assert!(table
            .starts_with("time_s,tension_n_0,curvature_per_m_0,tension_n_1,curvature_per_m_1\n"));
        assert_eq!(
            HotSpotSeries::all_from_csv(&table).unwrap(),
            [s.clone(), other.clone()]
        );
        assert_eq!(
            LoadTable::parse(&table, 1).unwrap().into_series().unwrap(),
            other
        );
        assert_eq!(HotSpotSeries::all_from_csv(&text).unwrap(), [s]);
    }

    #[test]
    fn columns_are_named_by_the_header_in_any_order() {
        let t = LoadTable::parse(
            "curvature_per_m,time_s,axial_strain\n0.01,0,1e-3\n0.02, 1 ,2e-3\n",
            0,
        )
        .unwrap();
        assert_eq!(t.kind, LoadKind::Strain);
        assert_eq!(t.time_s, [0.0, 1.0]);
        assert_eq!(t.value, [1e-3, 2e-3]);
        assert_eq!(t.curvature_per_m, [0.01, 0.02]);
        let e = LoadTable::parse("time_s,axial_strain\n0,1\n", 0).unwrap_err();
        assert_eq!(e.to_string(), "missing column curvature_per_m");
        let e =
            HotSpotSeries::from_csv("time_s,axial_strain,curvature_per_m\n0,1,0\n").unwrap_err();
        assert!(e.to_string().contains("holds tension_n"), "{e}");
    }

    #[test]
    fn refusals_name_the_line_and_the_column() {
        let e =
            LoadTable::parse("time_s,tension_n,curvature_per_m\n0,1e4,0\n1,x,0\n", 0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "sample 1 (line 3), column tension_n: \"x\" is not a number"
        );
        let e = LoadTable::parse("time_s,tension_n,curvature_per_m\n0,inf,0\n", 0).unwrap_err();
        assert!(e.to_string().contains("not a finite number"), "{e}");
        let e = LoadTable::parse("time_s,tension_n,curvature_per_m\n0,1\n", 0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "sample 0 (line 2): 2 fields, the header has 3"
        );
        let e = LoadTable::parse("time_s,tension_n,tension_n,curvature_per_m\n", 0).unwrap_err();
        assert_eq!(e.to_string(), "column tension_n appears twice");
        let e = LoadTable::parse("time_s,tension_n,curvature_per_m\n", 0).unwrap_err();
        assert_eq!(e, SeriesError::Empty);
        let table = HotSpotSeries::table_csv(&[sample(), sample()]);
        let e = LoadTable::parse(&table, 2).unwrap_err().to_string();
        assert!(e.contains("no hot spot 2") && e.contains("[0, 1]"), "{e}");
        let e = LoadTable::parse("time_s,speed,curvature_per_m\n", 0).unwrap_err();
        assert!(e.to_string().contains("unknown column \"speed\""), "{e}");
    }
}
