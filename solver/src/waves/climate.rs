//! Directional wave scatter diagrams from a sea-state time series (hindcast or reanalysis
//! exports, buoy records): one scatter table per direction sector, in the text format read by
//! [`ScatterTable::parse`](super::ScatterTable::parse), and each sector's share of the year.
//!
//! # Input
//!
//! Text with a header row; `#` lines are comments and blank lines are skipped. Fields are
//! separated by tabs, semicolons or commas (the first of these found in the header line, in that
//! order) or else by runs of blanks; a field may be enclosed in double quotes (without the
//! separator inside). Numbers use a decimal point, or a decimal comma when the separator is not a
//! comma. Four columns are named by the user ([`SeriesColumns`]); every other column is ignored,
//! but every row must have as many fields as the header.
//!
//! - time: a calendar time `YYYY-MM-DD` or `YYYY/MM/DD`, optionally followed by `T` or a blank
//!   and `hh:mm[:ss[.f]]`, optionally followed by `Z`, `UTC` or an offset `±hh[:mm]` (converted
//!   to UTC); or a plain number in any unit (hours, days, seconds since an epoch). Every record
//!   takes the form of the first, and times must increase strictly.
//! - hs: significant wave height (m).
//! - tp: peak period (s).
//! - direction: where the waves come FROM, in degrees clockwise from north (the met-ocean
//!   convention), taken modulo 360: 360 is 0 and −1 is 359.
//!
//! # Model heading
//!
//! The model frame has z up and its +x axis pointing to the compass bearing B
//! ([`ClimateSettings::x_axis_bearing_deg`]); a wave heading β is the direction the waves
//! travel TO, measured from +x towards +y, counter-clockwise seen from above. Compass bearings
//! turn clockwise seen from above, so a travel bearing P makes the angle P − B clockwise from
//! +x, that is β = B − P counter-clockwise. A sea from D travels towards P = D + 180, hence
//! β = (B − D − 180) mod 360 ([`model_heading_deg`]). With +x to the north (B = 0), a sea from
//! the north has β = 180 and one from the east (travelling west, towards +y) β = 90.
//!
//! # Bins
//!
//! Hs bin k covers [k·w, (k+1)·w) m from 0; Tp columns are centred on multiples c of their
//! width w, each covering [c − w/2, c + w/2) s and labelled c; a value on an edge belongs to the
//! bin above it (values within 1e-9 of a bin width below an edge count as on it, so that decimal
//! values such as 0.3 m in 0.1 m bins are not moved down by binary rounding). The n sectors are
//! centred on 0, 360/n, 2·360/n, … degrees, each covering [centre − 180/n, centre + 180/n): with
//! 8 sectors the one centred on 0 covers [337.5, 22.5). Labels: compass points for 4, 8 and 16
//! sectors (N, NE, E, …), else the centre in degrees. A table has at most [`MAX_BINS`] rows and
//! as many columns: a larger value is refused as a likely fill value.
//!
//! # Missing, gaps and calm
//!
//! A record is missing (counted, then left out) when its Hs or Tp is empty, not a number, NaN,
//! infinite, negative or one of the declared fill values ([`ClimateSettings::missing_values`]),
//! when its Tp falls in the column centred on 0 s (below half a Tp bin), or when its direction
//! is so (or lies more than a turn outside [0, 360): below −360 or from 720 up). Time gaps are
//! counted as the intervals with no record at the series' modal time step: an interval of about
//! m steps between two records counts m − 1. Gaps are reported, not filled: the diagrams
//! describe the records there are.
//!
//! A calm record (Hs below [`ClimateSettings::calm_hs_m`]) has no meaningful direction (it may
//! be missing): calm records are spread over the sectors in proportion to each sector's non-calm
//! records, into the lowest Hs bin (which holds every calm Hs: the calm threshold may not exceed
//! the Hs bin width) and their own Tp column. A sector's share of the year is therefore its share
//! of the non-calm records, and the whole year sums to 100 %.
//!
//! # Output
//!
//! [`DirectionalClimate::table_text`]: one table per sector with records, header `lower upper
//! <Tp centres…> total`, one row per Hs bin from 0 up to the highest bin of any sector, the same
//! columns in every sector, row totals and a `total` row; cells are percent within the sector
//! with [`CELL_DECIMALS`] decimals, rounded by largest remainders so that the printed cells of a
//! sector sum to exactly 100 and every printed total is the sum of its printed cells.
//! [`DirectionalClimate::sectors_file`]: the sectors (`label`, `direction_from_deg`,
//! `heading_deg`, `share_percent`, `path`), shares rounded in the same way to sum to exactly 100;
//! a sector without records is listed with share 0 and no `path` (it has no table).

use std::collections::BTreeMap;
use std::fmt;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::text::Num;

/// Decimals of the printed cells, totals and sector shares (percent).
pub const CELL_DECIMALS: usize = 6;
/// Printed units (10^-CELL_DECIMALS %) in one percent.
const UNITS_PER_PERCENT: i64 = 1_000_000;
/// Most Hs bins (rows) or Tp columns of a table.
pub const MAX_BINS: usize = 2_000;
/// Fraction of a bin width below an edge that still counts as on the edge.
const EDGE_SLACK: f64 = 1e-9;
/// Directions from this value (included) …
const DIRECTION_MIN_DEG: f64 = -360.0;
/// … to this one (excluded) are read modulo 360; others are missing.
const DIRECTION_MAX_DEG: f64 = 720.0;
/// Most sectors.
const MAX_SECTORS: usize = 360;
/// Sixteen compass points, from north clockwise.
const COMPASS_16: [&str; 16] = [
    "N", "NNE", "NE", "ENE", "E", "ESE", "SE", "SSE", "S", "SSW", "SW", "WSW", "W", "WNW", "NW",
    "NNW",
];

/// One of the four columns read from the series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesField {
    /// Time of the record.
    Time,
    /// Significant wave height (m).
    Hs,
    /// Peak period (s).
    Tp,
    /// Direction the waves come from (deg clockwise from north).
    Direction,
}

impl SeriesField {
    /// The field's name: `time`, `hs`, `tp` or `direction`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Time => "time",
            Self::Hs => "hs",
            Self::Tp => "tp",
            Self::Direction => "direction",
        }
    }
}

impl fmt::Display for SeriesField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a series could not be turned into scatter diagrams. Lines and columns count from 1.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ClimateError {
    /// A setting is out of its admissible range; `field` is the [`ClimateSettings`] field.
    #[error("{field} must be {rule}, got {}", Num(*.value))]
    InvalidSetting {
        /// Name of the setting.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The rule it broke.
        rule: &'static str,
    },
    /// The calm threshold lies above the first Hs bin.
    #[error(
        "calm_hs_m ({}) must not exceed the lowest Hs bin's upper edge ({} m): calm records go \
         into that bin",
        Num(*.calm_hs_m),
        Num(*.hs_bin_m)
    )]
    CalmAboveFirstBin {
        /// Calm threshold (m).
        calm_hs_m: f64,
        /// Hs bin width (m).
        hs_bin_m: f64,
    },
    /// Two fields name the same column.
    #[error("the {first} and {second} columns are both `{name}`")]
    SharedColumn {
        /// One field.
        first: SeriesField,
        /// The other.
        second: SeriesField,
        /// The column name they share.
        name: String,
    },
    /// No header or no data row.
    #[error("series is empty: {reason}")]
    Empty {
        /// What is missing.
        reason: &'static str,
    },
    /// A named column is not in the header.
    #[error("line {line}: no column `{name}` for {field} (columns: {available})")]
    MissingColumn {
        /// Line of the header.
        line: usize,
        /// The field it was named for.
        field: SeriesField,
        /// The name given.
        name: String,
        /// The header's columns, comma separated.
        available: String,
    },
    /// A named column appears more than once in the header.
    #[error("line {line}: column `{name}` for {field} appears {count} times in the header")]
    AmbiguousColumn {
        /// Line of the header.
        line: usize,
        /// The field it was named for.
        field: SeriesField,
        /// The name given.
        name: String,
        /// How many header fields bear it.
        count: usize,
    },
    /// A row has another number of fields than the header.
    #[error("line {line}: expected {expected} fields as in the header, found {found}")]
    Ragged {
        /// Line number.
        line: usize,
        /// Fields in the header.
        expected: usize,
        /// Fields on this line.
        found: usize,
    },
    /// A time cannot be read (or is not of the form of the first record's).
    #[error("line {line}, column {column} (`{name}`): `{text}` is not {expected}")]
    BadTime {
        /// Line number.
        line: usize,
        /// Column number.
        column: usize,
        /// Column name.
        name: String,
        /// The offending text.
        text: String,
        /// What was expected.
        expected: &'static str,
    },
    /// A time does not follow the previous record's.
    #[error(
        "line {line}: time `{text}` is not after `{previous_text}` on line {previous_line} \
         (records must be in time order, without repeats)"
    )]
    TimeNotIncreasing {
        /// Line number.
        line: usize,
        /// Its time as written.
        text: String,
        /// Line of the previous record.
        previous_line: usize,
        /// The previous record's time as written.
        previous_text: String,
    },
    /// A value would need more than [`MAX_BINS`] bins.
    #[error(
        "line {line}, column {column} (`{name}`): {field} {} would need {bins} bins of {}, more \
         than {MAX_BINS}; if it marks missing data, declare it as a fill value",
        Num(*.value),
        Num(*.width)
    )]
    TooManyBins {
        /// Line number.
        line: usize,
        /// Column number.
        column: usize,
        /// Column name.
        name: String,
        /// Which field.
        field: SeriesField,
        /// The value read.
        value: f64,
        /// The bin width.
        width: f64,
        /// Bins it would need.
        bins: u64,
    },
    /// Every record is missing.
    #[error("none of the {read} records has a usable hs, tp and direction")]
    NoUsableRecord {
        /// Records read.
        read: u64,
    },
    /// Every usable record is calm: there is no direction to spread them by.
    #[error(
        "all {calm} usable records are calm (hs below {} m): no direction to spread them by",
        Num(*.calm_hs_m)
    )]
    AllCalm {
        /// Calm records.
        calm: u64,
        /// Calm threshold (m).
        calm_hs_m: f64,
    },
}

/// Names of the series' columns (as in its header).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SeriesColumns {
    /// Time column.
    pub time: String,
    /// Significant wave height column (m).
    pub hs: String,
    /// Peak period column (s).
    pub tp: String,
    /// Direction column (deg, coming from, clockwise from north).
    pub direction: String,
}

impl SeriesColumns {
    fn named(&self) -> [(SeriesField, &str); 4] {
        [
            (SeriesField::Time, &self.time),
            (SeriesField::Hs, &self.hs),
            (SeriesField::Tp, &self.tp),
            (SeriesField::Direction, &self.direction),
        ]
    }
}

/// How a series is binned.
#[derive(Debug, Clone, PartialEq)]
pub struct ClimateSettings {
    /// The columns read.
    pub columns: SeriesColumns,
    /// Hs bin width (m), > 0.
    pub hs_bin_m: f64,
    /// Tp bin width (s), > 0.
    pub tp_bin_s: f64,
    /// Number of direction sectors, 1 to 360.
    pub sectors: usize,
    /// Hs bin edges (m) instead of `hs_bin_m`: bins [e_k, e_k+1), the first edge 0; a record
    /// at or above the last edge is counted and left out.
    pub hs_edges_m: Option<Vec<f64>>,
    /// Tp column edges (s) instead of `tp_bin_s`: columns [e_j, e_j+1) at their midpoints; a
    /// record below the first or at or above the last edge is counted and left out.
    pub tp_edges_s: Option<Vec<f64>>,
    /// Records with Hs below this (m) are calm; 0 to the first Hs bin's upper edge.
    pub calm_hs_m: f64,
    /// Compass bearing of the model's +x axis (deg clockwise from north).
    pub x_axis_bearing_deg: f64,
    /// Values that mark missing data in the hs, tp and direction columns (e.g. 99 or 9999).
    pub missing_values: Vec<f64>,
}

impl ClimateSettings {
    /// Settings with the default bins: Hs 0.5 m, Tp 1 s, 8 sectors, no calm threshold, +x to
    /// the north, no fill values.
    pub fn new(columns: SeriesColumns) -> Self {
        Self {
            columns,
            hs_bin_m: 0.5,
            tp_bin_s: 1.0,
            sectors: 8,
            hs_edges_m: None,
            tp_edges_s: None,
            calm_hs_m: 0.0,
            x_axis_bearing_deg: 0.0,
            missing_values: Vec::new(),
        }
    }

    /// Checks every setting, naming the first one at fault.
    pub fn validate(&self) -> Result<(), ClimateError> {
        let invalid = |field, value, rule| ClimateError::InvalidSetting { field, value, rule };
        for (field, value) in [("hs_bin_m", self.hs_bin_m), ("tp_bin_s", self.tp_bin_s)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(invalid(field, value, "a finite number > 0"));
            }
        }
        if !(1..=MAX_SECTORS).contains(&self.sectors) {
            return Err(invalid(
                "sectors",
                self.sectors as f64,
                "a whole number from 1 to 360",
            ));
        }
        if !(self.calm_hs_m.is_finite() && self.calm_hs_m >= 0.0) {
            return Err(invalid("calm_hs_m", self.calm_hs_m, "a finite number >= 0"));
        }
        for (field, edges) in [
            ("hs_edges_m", &self.hs_edges_m),
            ("tp_edges_s", &self.tp_edges_s),
        ] {
            let Some(edges) = edges else {
                continue;
            };
            if edges.len() < 2 {
                return Err(invalid(field, edges.len() as f64, "at least two edges"));
            }
            if let Some(&e) = edges.iter().find(|e| !(e.is_finite() && **e >= 0.0)) {
                return Err(invalid(field, e, "edges that are finite numbers >= 0"));
            }
            if let Some(w) = edges.windows(2).find(|w| w[1] <= w[0]) {
                return Err(invalid(field, w[1], "edges in increasing order"));
            }
        }
        if let Some(e) = self.hs_edges_m.as_ref().map(|e| e[0]).filter(|&e| e != 0.0) {
            return Err(invalid(
                "hs_edges_m",
                e,
                "edges from 0 (every record has an Hs bin up to the last edge)",
            ));
        }
        if self.calm_hs_m > self.first_hs_bin_upper_m() {
            return Err(ClimateError::CalmAboveFirstBin {
                calm_hs_m: self.calm_hs_m,
                hs_bin_m: self.first_hs_bin_upper_m(),
            });
        }
        if !self.x_axis_bearing_deg.is_finite() {
            return Err(invalid(
                "x_axis_bearing_deg",
                self.x_axis_bearing_deg,
                "a finite number",
            ));
        }
        if let Some(&v) = self.missing_values.iter().find(|v| !v.is_finite()) {
            return Err(invalid(
                "missing_values",
                v,
                "finite (NaN is always missing)",
            ));
        }
        let named = self.columns.named();
        for (i, (first, name)) in named.iter().enumerate() {
            if let Some((second, _)) = named[i + 1..].iter().find(|(_, n)| n == name) {
                return Err(ClimateError::SharedColumn {
                    first: *first,
                    second: *second,
                    name: name.to_string(),
                });
            }
        }
        Ok(())
    }
}

impl ClimateSettings {
    /// Upper edge of the first Hs bin (m).
    fn first_hs_bin_upper_m(&self) -> f64 {
        self.hs_edges_m.as_ref().map_or(self.hs_bin_m, |e| e[1])
    }

    /// Hs bin of `hs_m`: `Ok(None)` at or above the last edge; `Err(bins needed)` beyond
    /// [`MAX_BINS`] uniform bins.
    fn hs_bin(&self, hs_m: f64) -> Result<Option<usize>, u64> {
        match &self.hs_edges_m {
            Some(edges) => Ok(edge_bin(edges, hs_m)),
            None => bin_index(hs_m, self.hs_bin_m, 0.0).map(Some),
        }
    }

    /// Tp column of `tp_s`, 0 below the first column: `Ok(None)` at or above the last edge.
    fn tp_bin(&self, tp_s: f64) -> Result<Option<usize>, u64> {
        match &self.tp_edges_s {
            Some(edges) if tp_s < edges[0] => Ok(Some(0)),
            Some(edges) => Ok(edge_bin(edges, tp_s).map(|j| j + 1)),
            None => bin_index(tp_s, self.tp_bin_s, 0.5).map(Some),
        }
    }

    /// Lower and upper edge of Hs bin `k` (m).
    fn hs_bounds_m(&self, k: usize) -> (f64, f64) {
        match &self.hs_edges_m {
            Some(edges) => (edges[k], edges[k + 1]),
            None => (k as f64 * self.hs_bin_m, (k + 1) as f64 * self.hs_bin_m),
        }
    }

    /// Tp of column `j` (s): its centre.
    fn tp_centre_s(&self, j: usize) -> f64 {
        match &self.tp_edges_s {
            Some(edges) => 0.5 * (edges[j - 1] + edges[j]),
            None => j as f64 * self.tp_bin_s,
        }
    }

    /// Decimals that print the Hs and the Tp bins exactly enough.
    fn decimals(&self) -> (usize, usize) {
        let of = |edges: &Option<Vec<f64>>, width: f64, halves: bool| match edges {
            Some(e) => e
                .iter()
                .map(|&x| width_decimals(if halves { x / 2.0 } else { x }))
                .max()
                .unwrap_or(0),
            None => width_decimals(width),
        };
        (
            of(&self.hs_edges_m, self.hs_bin_m, false),
            of(&self.tp_edges_s, self.tp_bin_s, true),
        )
    }

    /// How the bins read, for the tables' header.
    fn bins_text(&self) -> String {
        let list = |e: &[f64]| {
            e.iter()
                .map(|x| Num(*x).to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let hs = match &self.hs_edges_m {
            Some(e) => format!("Hs edges {} m, [lower, upper)", list(e)),
            None => format!("Hs {} m from 0 m, [lower, upper)", Num(self.hs_bin_m)),
        };
        let tp = match &self.tp_edges_s {
            Some(e) => format!("Tp edges {} s, each column at its bin's centre", list(e)),
            None => format!("Tp {} s centred on each column's value", Num(self.tp_bin_s)),
        };
        format!("{hs}; {tp}")
    }
}

/// Bin [e_k, e_k+1) of `edges` holding `value`; none below the first or at or above the last.
fn edge_bin(edges: &[f64], value: f64) -> Option<usize> {
    let k = edges.partition_point(|&e| e <= value);
    (k >= 1 && k < edges.len()).then(|| k - 1)
}

/// The form of the series' times.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeKind {
    /// Calendar times, in seconds.
    Calendar,
    /// Plain numbers, in the column's own unit.
    Number,
}

/// Records left out for one reason, with the first of them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Fault {
    /// Records with this fault.
    pub count: u64,
    /// Line and text of the first one.
    pub first: Option<(usize, String)>,
}

impl Fault {
    fn add(&mut self, line: usize, text: &str) {
        self.count += 1;
        if self.first.is_none() {
            self.first = Some((line, text.to_string()));
        }
    }
}

/// What was read, used and left out.
#[derive(Debug, Clone, PartialEq)]
pub struct ClimateCounts {
    /// Data rows read.
    pub records_read: u64,
    /// Records in the diagrams (calm ones included).
    pub records_used: u64,
    /// Records left out for a missing value.
    pub records_missing: u64,
    /// Records with an unusable Hs.
    pub hs_missing: Fault,
    /// Records with an unusable Tp.
    pub tp_missing: Fault,
    /// Records with a usable Tp below half a Tp bin (the column centred on 0 s).
    pub tp_below_first_bin: Fault,
    /// Records left out for an Hs or a Tp at or above the last bin edge (`hs_edges_m`,
    /// `tp_edges_s`).
    pub beyond_last_edge: Fault,
    /// Non-calm records with an unusable direction.
    pub direction_missing: Fault,
    /// Intervals with no record at the modal time step.
    pub gaps: u64,
    /// The modal time step (s for calendar times, else the column's unit); none with one record.
    pub time_step: Option<f64>,
    /// Form of the times.
    pub time_kind: TimeKind,
    /// First and last time as written.
    pub time_span: (String, String),
    /// Calm records (in the diagrams, spread over the sectors).
    pub calm: u64,
}

/// One direction sector.
#[derive(Debug, Clone, PartialEq)]
pub struct SectorSummary {
    /// `N`, `NE`, … for 4, 8 or 16 sectors, else the centre in degrees.
    pub label: String,
    /// Centre of the sector: direction the waves come from (deg clockwise from north).
    pub direction_from_deg: f64,
    /// First direction of the sector (deg, in [0, 360)).
    pub from_deg: f64,
    /// End of the sector, excluded (deg, in [0, 360)).
    pub to_deg: f64,
    /// Model heading of the centre: travel direction from +x towards +y (deg, in [0, 360)).
    pub heading_deg: f64,
    /// Non-calm records of the sector.
    pub records: u64,
    /// Calm records spread into the sector (a fraction of records).
    pub calm_records: f64,
    /// Share of the year (%), rounded to [`CELL_DECIMALS`] decimals; shares sum to 100.
    pub share_percent: f64,
    /// File name of its table; none when it has no records.
    pub path: Option<String>,
}

/// The sectors' file: `{"sectors": [...]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectorsFile {
    /// Every sector, from north clockwise.
    pub sectors: Vec<SectorEntry>,
}

/// One sector of [`SectorsFile`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectorEntry {
    /// Label (`N`, `NE`, … or the centre in degrees).
    pub label: String,
    /// Direction the waves come from, centre of the sector (deg clockwise from north).
    pub direction_from_deg: f64,
    /// Model heading (deg, travel direction from +x towards +y).
    pub heading_deg: f64,
    /// Share of the year (%).
    pub share_percent: f64,
    /// Scatter table of the sector, relative to the file; absent for a sector without records.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
}

/// Directional scatter diagrams of a series.
#[derive(Debug, Clone, PartialEq)]
pub struct DirectionalClimate {
    /// What was read, used and left out.
    pub counts: ClimateCounts,
    /// Every sector, from north clockwise.
    pub sectors: Vec<SectorSummary>,
    settings: ClimateSettings,
    /// Hs bins 0 to `hs_rows - 1`.
    hs_rows: usize,
    /// Tp centres (multiples of the width) of the columns: first and last.
    tp_columns: (usize, usize),
    /// Per sector, printed units `[row][column]`; none for a sector without records.
    tables: Vec<Option<Vec<Vec<i64>>>>,
}

/// Model heading (deg in [0, 360), from +x towards +y, z up) of a sea coming from compass
/// direction `direction_from_deg` when the model's +x axis points to `x_axis_bearing_deg`:
/// (B − D − 180) mod 360.
pub fn model_heading_deg(direction_from_deg: f64, x_axis_bearing_deg: f64) -> f64 {
    wrap_deg(x_axis_bearing_deg - direction_from_deg - 180.0)
}

/// An angle in [0, 360), cleared of binary noise below 1e-9 deg.
fn wrap_deg(deg: f64) -> f64 {
    let wrapped = (deg.rem_euclid(360.0) * 1e9).round() / 1e9;
    if wrapped >= 360.0 {
        0.0
    } else {
        wrapped
    }
}

/// Index of the bin holding `value` for bins of `width` starting at `offset` widths below 0,
/// or none when it would exceed [`MAX_BINS`] (the needed count is then returned as error).
fn bin_index(value: f64, width: f64, offset: f64) -> Result<usize, u64> {
    let q = (value / width + offset + EDGE_SLACK).floor();
    if q < MAX_BINS as f64 {
        Ok(q.max(0.0) as usize)
    } else {
        Err((q + 1.0) as u64)
    }
}

/// Sector of a direction (deg, any value).
fn sector_index(direction_deg: f64, sectors: usize) -> usize {
    let width = 360.0 / sectors as f64;
    let d = direction_deg.rem_euclid(360.0);
    let i = ((d + width / 2.0) / width + EDGE_SLACK).floor() as usize;
    i % sectors
}

/// Label of sector `i` of `n`.
fn sector_label(i: usize, n: usize, centre_deg: f64) -> String {
    match n {
        4 | 8 | 16 => COMPASS_16[i * (16 / n)].to_string(),
        _ => trimmed(centre_deg, 2),
    }
}

/// `value` with at most `decimals` decimals, trailing zeros dropped.
fn trimmed(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// Decimals needed to print multiples of a bin width (at most 9).
fn width_decimals(width: f64) -> usize {
    (0..9)
        .find(|&d| {
            let scaled = width * 10f64.powi(d as i32);
            (scaled - scaled.round()).abs() <= 1e-9 * scaled.max(1.0)
        })
        .unwrap_or(9)
}

/// Weights as printed units (10^-CELL_DECIMALS %) summing to exactly 100 %, by largest
/// remainders; all zero when the weights are.
fn percent_units(weights: &[f64]) -> Vec<i64> {
    let target = 100 * UNITS_PER_PERCENT;
    let total: f64 = weights.iter().sum();
    if total <= 0.0 || !total.is_finite() {
        return vec![0; weights.len()];
    }
    let exact: Vec<f64> = weights.iter().map(|w| w / total * target as f64).collect();
    let mut units: Vec<i64> = exact.iter().map(|e| e.floor() as i64).collect();
    let remainder = |i: usize, units: &[i64]| exact[i] - units[i] as f64;
    let mut order: Vec<usize> = (0..weights.len()).filter(|&i| weights[i] > 0.0).collect();
    order.sort_by(|&a, &b| {
        remainder(b, &units)
            .total_cmp(&remainder(a, &units))
            .then(a.cmp(&b))
    });
    let mut rest = target - units.iter().sum::<i64>();
    // `rest` is below the number of positive weights; binary rounding may make it negative.
    let mut cycle = order.iter().cycle();
    while rest > 0 {
        match cycle.next() {
            Some(&i) => units[i] += 1,
            None => break,
        }
        rest -= 1;
    }
    let mut cycle = order.iter().rev().cycle();
    while rest < 0 {
        match cycle.next() {
            Some(&i) if units[i] > 0 => {
                units[i] -= 1;
                rest += 1;
            }
            Some(_) => {}
            None => break,
        }
    }
    units
}

/// Printed units as a decimal number.
fn units_text(units: i64) -> String {
    format!(
        "{}.{:0width$}",
        units / UNITS_PER_PERCENT,
        units % UNITS_PER_PERCENT,
        width = CELL_DECIMALS
    )
}

/// How fields are separated.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Separator {
    Char(char),
    Blanks,
}

/// A field trimmed and without its enclosing quotes.
fn clean(field: &str) -> &str {
    let t = field.trim();
    t.strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .unwrap_or(t)
}

/// Split a line into trimmed fields without their enclosing quotes.
fn split(line: &str, sep: Separator) -> Vec<&str> {
    match sep {
        Separator::Char(c) => line.split(c).map(clean).collect(),
        Separator::Blanks => line.split_whitespace().map(clean).collect(),
    }
}

/// A finite number (decimal comma accepted when `decimal_comma`).
fn finite_number(text: &str, decimal_comma: bool) -> Option<f64> {
    let value: f64 = if decimal_comma && text.contains(',') {
        text.replace(',', ".").parse().ok()?
    } else {
        text.parse().ok()?
    };
    value.is_finite().then_some(value)
}

/// All-digit text as a number.
fn digits(text: &str) -> Option<i64> {
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

/// Days from 1970-01-01 to a proleptic Gregorian date (H. Hinnant's algorithm).
fn days_from_civil(year: i64, month: i64, day: i64) -> i64 {
    let y = if month <= 2 { year - 1 } else { year };
    let era = y.div_euclid(400);
    let year_of_era = y - era * 400;
    let day_of_year = (153 * ((month + 9) % 12) + 2) / 5 + day - 1;
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
    era * 146_097 + day_of_era - 719_468
}

/// Days in a month of a year.
fn days_in_month(year: i64, month: i64) -> i64 {
    let leap = year % 4 == 0 && (year % 100 != 0 || year % 400 == 0);
    match month {
        2 if leap => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// `hh:mm[:ss[.f]]` as seconds of the day.
fn clock_seconds(text: &str) -> Option<f64> {
    let mut parts = text.split(':');
    let hours = digits(parts.next()?).filter(|h| *h < 24)?;
    let minutes = digits(parts.next()?).filter(|m| *m < 60)?;
    let seconds = match parts.next() {
        None => 0.0,
        Some(s) => {
            let (whole, fraction) = s.split_once(['.', ',']).unwrap_or((s, "0"));
            let whole = digits(whole).filter(|s| *s <= 60)? as f64;
            let fraction = digits(fraction)? as f64 / 10f64.powi(fraction.len() as i32);
            whole + fraction
        }
    };
    if parts.next().is_some() {
        return None;
    }
    Some((hours * 3600 + minutes * 60) as f64 + seconds)
}

/// A zone (`""`, `Z`, `UTC`, `GMT`, `±hh`, `±hhmm`, `±hh:mm`) as seconds ahead of UTC.
fn zone_seconds(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.is_empty()
        || ["Z", "UTC", "GMT"]
            .iter()
            .any(|z| t.eq_ignore_ascii_case(z))
    {
        return Some(0.0);
    }
    let (sign, offset) = match t.strip_prefix('+') {
        Some(rest) => (1.0, rest),
        None => (-1.0, t.strip_prefix('-')?),
    };
    let (hours, minutes) = match offset.split_once(':') {
        Some((h, m)) => (h, m),
        None if offset.len() == 4 => (offset.get(..2)?, offset.get(2..)?),
        None => (offset, "0"),
    };
    let hours = digits(hours).filter(|h| *h <= 18)?;
    let minutes = digits(minutes).filter(|m| *m < 60)?;
    Some(sign * (hours * 3600 + minutes * 60) as f64)
}

/// A calendar time as seconds since 1970-01-01 00:00 UTC.
fn calendar_seconds(text: &str) -> Option<f64> {
    let sep = text.get(4..5)?;
    if !(sep == "-" || sep == "/") || text.get(7..8)? != sep {
        return None;
    }
    let year = digits(text.get(..4)?)?;
    let month = digits(text.get(5..7)?).filter(|m| (1..=12).contains(m))?;
    let day = digits(text.get(8..10)?).filter(|d| (1..=days_in_month(year, month)).contains(d))?;
    let date = days_from_civil(year, month, day) as f64 * 86_400.0;
    let rest = text.get(10..)?;
    if rest.is_empty() {
        return Some(date);
    }
    let rest = rest.strip_prefix(['T', 't', ' '])?.trim_start();
    let end = rest
        .find(['Z', 'z', '+', '-', ' ', 'U', 'u', 'G', 'g'])
        .unwrap_or(rest.len());
    let (clock, zone) = rest.split_at(end);
    Some(date + clock_seconds(clock)? - zone_seconds(zone)?)
}

/// What a time of each kind looks like, for messages.
fn time_form(kind: Option<TimeKind>) -> &'static str {
    match kind {
        None => "a time (YYYY-MM-DD[Thh:mm[:ss]][Z|±hh:mm] or a number)",
        Some(TimeKind::Calendar) => {
            "a calendar time like the first record's (YYYY-MM-DD[Thh:mm[:ss]][Z|±hh:mm])"
        }
        Some(TimeKind::Number) => "a number like the first record's time",
    }
}

/// The modal difference of strictly positive steps (differences within 1e-6 relative of the
/// smallest of a group count as equal; ties go to the shorter step).
fn modal_step(steps: &[f64]) -> Option<f64> {
    let mut sorted = steps.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mut best: Option<(usize, f64)> = None;
    let mut i = 0;
    while i < sorted.len() {
        let start = sorted[i];
        let end = sorted[i..]
            .iter()
            .position(|&s| s - start > 1e-6 * start)
            .map_or(sorted.len(), |p| i + p);
        if best.is_none_or(|(n, _)| end - i > n) {
            best = Some((end - i, start));
        }
        i = end;
    }
    best.map(|(_, step)| step)
}

/// Column positions of the four fields, in the order of [`SeriesColumns::named`].
fn column_positions(
    head: &[&str],
    columns: &SeriesColumns,
    line: usize,
) -> Result<[usize; 4], ClimateError> {
    let mut positions = [0; 4];
    for (slot, (field, name)) in columns.named().into_iter().enumerate() {
        let hits: Vec<usize> = (0..head.len()).filter(|&i| head[i] == name).collect();
        positions[slot] = match hits.as_slice() {
            [one] => *one,
            [] => {
                return Err(ClimateError::MissingColumn {
                    line,
                    field,
                    name: name.to_string(),
                    available: head.join(", "),
                })
            }
            many => {
                return Err(ClimateError::AmbiguousColumn {
                    line,
                    field,
                    name: name.to_string(),
                    count: many.len(),
                })
            }
        };
    }
    Ok(positions)
}

/// The records of a series as they are read.
struct Scan<'a> {
    settings: &'a ClimateSettings,
    head: Vec<String>,
    positions: [usize; 4],
    decimal_comma: bool,
    read: u64,
    missing: u64,
    hs_missing: Fault,
    tp_missing: Fault,
    tp_below_first_bin: Fault,
    beyond_last_edge: Fault,
    direction_missing: Fault,
    time_kind: Option<TimeKind>,
    /// Line, time and text of the first and of the previous record.
    first: Option<(usize, f64, String)>,
    previous: Option<(usize, f64, String)>,
    steps: Vec<f64>,
    /// Non-calm records per (sector, Hs bin, Tp centre index).
    cells: BTreeMap<(usize, usize, usize), u64>,
    /// Calm records per Tp centre index.
    calm: BTreeMap<usize, u64>,
}

impl Scan<'_> {
    fn time(&mut self, line: usize, text: &str) -> Result<(), ClimateError> {
        let column = self.positions[0];
        let kind_and_value = match finite_number(text, self.decimal_comma) {
            Some(v) => Some((TimeKind::Number, v)),
            None => calendar_seconds(text).map(|s| (TimeKind::Calendar, s)),
        };
        let value = match (kind_and_value, self.time_kind) {
            (Some((kind, v)), None) => {
                self.time_kind = Some(kind);
                v
            }
            (Some((kind, v)), Some(expected)) if kind == expected => v,
            _ => {
                return Err(ClimateError::BadTime {
                    line,
                    column: column + 1,
                    name: self.head[column].clone(),
                    text: text.to_string(),
                    expected: time_form(self.time_kind),
                })
            }
        };
        if let Some((previous_line, previous, previous_text)) = &self.previous {
            if value <= *previous {
                return Err(ClimateError::TimeNotIncreasing {
                    line,
                    text: text.to_string(),
                    previous_line: *previous_line,
                    previous_text: previous_text.clone(),
                });
            }
            self.steps.push(value - previous);
        }
        self.previous = Some((line, value, text.to_string()));
        if self.first.is_none() {
            self.first = self.previous.clone();
        }
        Ok(())
    }

    /// The bin `index` of `value` found, or the error for a value beyond [`MAX_BINS`] bins
    /// of `width`.
    fn bin(
        &self,
        line: usize,
        slot: usize,
        field: SeriesField,
        value: f64,
        index: Result<Option<usize>, u64>,
        width: f64,
    ) -> Result<Option<usize>, ClimateError> {
        index.map_err(|bins| ClimateError::TooManyBins {
            line,
            column: self.positions[slot] + 1,
            name: self.head[self.positions[slot]].clone(),
            field,
            value,
            width,
            bins,
        })
    }

    fn record(&mut self, line: usize, row: &[&str]) -> Result<(), ClimateError> {
        self.read += 1;
        self.time(line, row[self.positions[0]])?;
        let s = self.settings;
        let value = |slot: usize| {
            finite_number(row[self.positions[slot]], self.decimal_comma)
                .filter(|v| !s.missing_values.contains(v))
        };
        let hs = value(1).filter(|h| *h >= 0.0);
        let tp = value(2).filter(|t| *t >= 0.0);
        let direction = value(3).filter(|d| (DIRECTION_MIN_DEG..DIRECTION_MAX_DEG).contains(d));
        let hs_bin = match hs {
            Some(h) => self.bin(line, 1, SeriesField::Hs, h, s.hs_bin(h), s.hs_bin_m)?,
            None => None,
        };
        let tp_bin = match tp {
            Some(t) => self.bin(line, 2, SeriesField::Tp, t, s.tp_bin(t), s.tp_bin_s)?,
            None => None,
        };
        if hs.is_some() && hs_bin.is_none() {
            self.beyond_last_edge.add(line, row[self.positions[1]]);
        } else if tp.is_some() && tp_bin.is_none() {
            self.beyond_last_edge.add(line, row[self.positions[2]]);
        }
        let calm = hs.is_some_and(|h| h < s.calm_hs_m);
        let mut usable = true;
        if hs.is_none() {
            self.hs_missing.add(line, row[self.positions[1]]);
            usable = false;
        } else if hs_bin.is_none() {
            usable = false;
        }
        match tp_bin {
            None if tp.is_some() => usable = false,
            None => {
                self.tp_missing.add(line, row[self.positions[2]]);
                usable = false;
            }
            Some(0) => {
                self.tp_below_first_bin.add(line, row[self.positions[2]]);
                usable = false;
            }
            Some(_) => {}
        }
        if direction.is_none() && !calm {
            self.direction_missing.add(line, row[self.positions[3]]);
            usable = false;
        }
        match (usable, hs_bin, tp_bin, direction) {
            (false, ..) => self.missing += 1,
            (true, _, Some(j), _) if calm => *self.calm.entry(j).or_default() += 1,
            (true, Some(k), Some(j), Some(d)) => {
                let sector = sector_index(d, s.sectors);
                *self.cells.entry((sector, k, j)).or_default() += 1;
            }
            _ => self.missing += 1,
        }
        Ok(())
    }

    fn finish(self) -> Result<DirectionalClimate, ClimateError> {
        let s = self.settings;
        if self.read == 0 {
            return Err(ClimateError::Empty {
                reason: "no data row",
            });
        }
        let calm: u64 = self.calm.values().sum();
        let mut per_sector = vec![0u64; s.sectors];
        for (&(sector, _, _), &n) in &self.cells {
            per_sector[sector] += n;
        }
        let non_calm: u64 = per_sector.iter().sum();
        if non_calm + calm == 0 {
            return Err(ClimateError::NoUsableRecord { read: self.read });
        }
        if non_calm == 0 {
            return Err(ClimateError::AllCalm {
                calm,
                calm_hs_m: s.calm_hs_m,
            });
        }
        let time_step = modal_step(&self.steps);
        let gaps = time_step.map_or(0, |step| {
            self.steps
                .iter()
                .map(|d| ((d / step).round() as u64).saturating_sub(1))
                .fold(0u64, u64::saturating_add)
        });

        let hs_rows = 1 + self.cells.keys().map(|&(_, k, _)| k).max().unwrap_or(0);
        let tp_centres = self
            .cells
            .keys()
            .map(|&(_, _, j)| j)
            .chain(self.calm.keys().copied());
        let tp_columns = (
            tp_centres.clone().min().unwrap_or(1),
            tp_centres.max().unwrap_or(1),
        );
        let columns = tp_columns.1 - tp_columns.0 + 1;
        let shares = percent_units(&per_sector.iter().map(|&n| n as f64).collect::<Vec<_>>());
        let width = 360.0 / s.sectors as f64;
        let mut sectors = Vec::with_capacity(s.sectors);
        let mut tables = Vec::with_capacity(s.sectors);
        for (i, &records) in per_sector.iter().enumerate() {
            let centre = i as f64 * width;
            let spread = records as f64 / non_calm as f64;
            let path = (records > 0).then(|| format!("sector_{:03}.tsv", centre.round() as u32));
            sectors.push(SectorSummary {
                label: sector_label(i, s.sectors, centre),
                direction_from_deg: wrap_deg(centre),
                from_deg: wrap_deg(centre - width / 2.0),
                to_deg: wrap_deg(centre + width / 2.0),
                heading_deg: model_heading_deg(centre, s.x_axis_bearing_deg),
                records,
                calm_records: calm as f64 * spread,
                share_percent: shares[i] as f64 / UNITS_PER_PERCENT as f64,
                path: path.clone(),
            });
            tables.push(path.map(|_| {
                let mut weights = vec![0.0; hs_rows * columns];
                for (&(_, k, j), &n) in self.cells.range((i, 0, 0)..(i + 1, 0, 0)) {
                    weights[k * columns + (j - tp_columns.0)] += n as f64;
                }
                for (&j, &n) in &self.calm {
                    weights[j - tp_columns.0] += n as f64 * spread;
                }
                let units = percent_units(&weights);
                units.chunks(columns).map(<[i64]>::to_vec).collect()
            }));
        }
        let time_of =
            |r: &Option<(usize, f64, String)>| r.as_ref().map_or(String::new(), |r| r.2.clone());
        Ok(DirectionalClimate {
            counts: ClimateCounts {
                records_read: self.read,
                records_used: non_calm + calm,
                records_missing: self.missing,
                hs_missing: self.hs_missing,
                tp_missing: self.tp_missing,
                tp_below_first_bin: self.tp_below_first_bin,
                beyond_last_edge: self.beyond_last_edge,
                direction_missing: self.direction_missing,
                gaps,
                time_step,
                time_kind: self.time_kind.unwrap_or(TimeKind::Number),
                time_span: (time_of(&self.first), time_of(&self.previous)),
                calm,
            },
            sectors,
            settings: s.clone(),
            hs_rows,
            tp_columns,
            tables,
        })
    }
}

impl DirectionalClimate {
    /// Reads a series and bins it (see the module documentation).
    pub fn from_series(text: &str, settings: &ClimateSettings) -> Result<Self, ClimateError> {
        settings.validate()?;
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let (header_line, header) = lines.next().ok_or(ClimateError::Empty {
            reason: "no header line",
        })?;
        let sep = ['\t', ';', ',']
            .into_iter()
            .find(|&c| header.contains(c))
            .map_or(Separator::Blanks, Separator::Char);
        let head = split(header, sep);
        let positions = column_positions(&head, &settings.columns, header_line)?;
        let mut scan = Scan {
            settings,
            head: head.iter().map(|h| h.to_string()).collect(),
            positions,
            decimal_comma: sep != Separator::Char(','),
            read: 0,
            missing: 0,
            hs_missing: Fault::default(),
            tp_missing: Fault::default(),
            tp_below_first_bin: Fault::default(),
            beyond_last_edge: Fault::default(),
            direction_missing: Fault::default(),
            time_kind: None,
            first: None,
            previous: None,
            steps: Vec::new(),
            cells: BTreeMap::new(),
            calm: BTreeMap::new(),
        };
        for (line, text) in lines {
            let row = split(text, sep);
            if row.len() != head.len() {
                return Err(ClimateError::Ragged {
                    line,
                    expected: head.len(),
                    found: row.len(),
                });
            }
            scan.record(line, &row)?;
        }
        scan.finish()
    }

    /// The settings the diagrams were built with.
    pub fn settings(&self) -> &ClimateSettings {
        &self.settings
    }

    /// The sectors' file (`sectors.json`).
    pub fn sectors_file(&self) -> SectorsFile {
        SectorsFile {
            sectors: self
                .sectors
                .iter()
                .map(|s| SectorEntry {
                    label: s.label.clone(),
                    direction_from_deg: s.direction_from_deg,
                    heading_deg: s.heading_deg,
                    share_percent: s.share_percent,
                    path: s.path.clone(),
                })
                .collect(),
        }
    }

    /// The scatter table of sector `index` as text, with `#` lines naming `source` (the series'
    /// file), the columns, bins and counts; none for a sector without records (or no sector).
    pub fn table_text(&self, index: usize, source: &str) -> Option<String> {
        let units = self.tables.get(index)?.as_ref()?;
        let sector = self.sectors.get(index)?;
        let s = &self.settings;
        let c = &self.counts;
        let (hs_decimals, tp_decimals) = s.decimals();
        let mut out = String::new();
        let mut line = |text: String| {
            out.push_str(&text);
            out.push('\n');
        };
        line(format!(
            "# moorfret scatter: sector {} of {}, waves from {} to {} deg (centre {} deg, \
             clockwise from north); model heading {} deg with +x to bearing {} deg",
            sector.label,
            s.sectors,
            Num(sector.from_deg),
            Num(sector.to_deg),
            Num(sector.direction_from_deg),
            Num(sector.heading_deg),
            Num(s.x_axis_bearing_deg),
        ));
        line(format!(
            "# source: {source}; columns: time `{}`, hs `{}`, tp `{}`, direction `{}`",
            s.columns.time, s.columns.hs, s.columns.tp, s.columns.direction
        ));
        line(format!(
            "# bins: {}; calm below Hs {} m",
            s.bins_text(),
            Num(s.calm_hs_m)
        ));
        line(format!(
            "# sector: {} records and {} calm records spread in, {} % of the {} records used",
            sector.records,
            trimmed(sector.calm_records, 3),
            units_text((sector.share_percent * UNITS_PER_PERCENT as f64).round() as i64),
            c.records_used
        ));
        line(format!(
            "# series: {} records read, {} used ({} calm), {} missing, {} time gaps",
            c.records_read, c.records_used, c.calm, c.records_missing, c.gaps
        ));
        line("# cells: percent of the sector's time (they sum to 100)".to_string());
        let centres: Vec<String> = (self.tp_columns.0..=self.tp_columns.1)
            .map(|j| format!("{:.tp_decimals$}", s.tp_centre_s(j)))
            .collect();
        line(format!("lower\tupper\t{}\ttotal", centres.join("\t")));
        for (k, row) in units.iter().enumerate().take(self.hs_rows) {
            let cells: Vec<String> = row.iter().map(|&u| units_text(u)).collect();
            let (lower, upper) = s.hs_bounds_m(k);
            line(format!(
                "{:.hs_decimals$}\t{:.hs_decimals$}\t{}\t{}",
                lower,
                upper,
                cells.join("\t"),
                units_text(row.iter().sum())
            ));
        }
        let column_totals: Vec<String> = (0..centres.len())
            .map(|j| units_text(units.iter().map(|row| row[j]).sum()))
            .collect();
        let grand: i64 = units.iter().flatten().sum();
        line(format!(
            "total\t\t{}\t{}",
            column_totals.join("\t"),
            units_text(grand)
        ));
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::ScatterTable;

    fn columns() -> SeriesColumns {
        SeriesColumns {
            time: "time".into(),
            hs: "hs".into(),
            tp: "tp".into(),
            direction: "dir".into(),
        }
    }

    fn settings() -> ClimateSettings {
        ClimateSettings {
            calm_hs_m: 0.2,
            ..ClimateSettings::new(columns())
        }
    }

    /// Hourly records: 7 non-calm (5 from N, 1 NE, 1 E), 2 calm, 5 missing, 2 gap hours.
    const SERIES: &str = "\
# a buoy
time,hs,tp,dir,note
2020-01-01T00:00Z,0.5,6.5,0,Hs and Tp on an edge
2020-01-01T01:00Z,1.2,7.4,359,
2020-01-01T02:00Z,1.2,7.6,1,
2020-01-01T03:00Z,0.7,8.0,360,
2020-01-01T04:00Z,0.3,5.0,-1,

2020-01-01T05:00Z,2.0,9.0,90,
2020-01-01T06:00Z,1.0,9.49,22.5,direction on the N/NE edge
2020-01-01T07:00Z,0.1,4.0,,calm without direction
2020-01-01T08:00Z,NaN,6,45,
2020-01-01T09:00Z,1.0,,45,
2020-01-01T10:00Z,1.0,6,abc,
2020-01-01T11:00Z,-0.5,6,45,
2020-01-01T14:00Z,1.0,0.3,45,two hours missing before
2020-01-01T15:00Z,0.15,5.2,200,calm
";

    fn climate() -> DirectionalClimate {
        DirectionalClimate::from_series(SERIES, &settings()).unwrap()
    }

    fn cell(table: &ScatterTable, hs_lower_m: f64, tp_s: f64) -> f64 {
        table
            .cells()
            .into_iter()
            .find(|c| c.hs_lower_m == hs_lower_m && c.tp_s == tp_s)
            .map_or(f64::NAN, |c| c.value)
    }

    /// Bins from edges: Hs [0, 1), [1, 1.5); Tp [5, 7), [7, 10) at 6 and 8.5 s. The 2.0 m record
    /// lies above the last Hs edge, Tp 0.3 s and the calm record's 4.0 s below the first Tp edge.
    #[test]
    fn bin_edges_bin_and_count_what_lies_outside() {
        let settings = ClimateSettings {
            hs_edges_m: Some(vec![0.0, 1.0, 1.5]),
            tp_edges_s: Some(vec![5.0, 7.0, 10.0]),
            ..settings()
        };
        let climate = DirectionalClimate::from_series(SERIES, &settings).unwrap();
        let c = &climate.counts;
        assert_eq!(c.beyond_last_edge.count, 1);
        assert_eq!(c.beyond_last_edge.first, Some((9, "2.0".to_string())));
        assert_eq!(c.tp_below_first_bin.count, 2);
        // N: 0.5/6.5, 0.3/5.0 (on the edge: the upper bin), 0.7/8.0, 1.2/7.4, 1.2/7.6; NE:
        // 1.0/9.49; one calm record (0.15 m, 5.2 s)
        assert_eq!((c.records_used, c.calm), (7, 1));
        let records: Vec<u64> = climate.sectors.iter().map(|s| s.records).collect();
        assert_eq!(records, vec![5, 1, 0, 0, 0, 0, 0, 0]);
        let text = climate.table_text(0, "buoy.csv").unwrap();
        assert!(text.contains("Hs edges 0, 1, 1.5 m"), "{text}");
        let north = ScatterTable::parse(&text).unwrap();
        assert_eq!(north.hs_bins_m, vec![(0.0, 1.0), (1.0, 1.5)]);
        assert_eq!(north.tp_s, vec![6.0, 8.5]);
        // the north sector's 5 records and 5/6 of the calm one: 35/6 in all; the cell of
        // Hs [0, 1), Tp 6 s holds two records and the calm share, 17/35
        let weights = [
            (0.0, 6.0, 17.0),
            (0.0, 8.5, 6.0),
            (1.0, 6.0, 0.0),
            (1.0, 8.5, 12.0),
        ];
        for (hs, tp, w) in weights {
            assert!(
                (cell(&north, hs, tp) - 100.0 * w / 35.0).abs() < 2e-6,
                "{hs} {tp}"
            );
        }
        assert!((north.cell_sum() - 100.0).abs() < 1e-9);
    }

    #[test]
    fn bin_edges_are_checked_by_name() {
        let field = |hs: Option<Vec<f64>>, tp: Option<Vec<f64>>| {
            let s = ClimateSettings {
                hs_edges_m: hs,
                tp_edges_s: tp,
                ..settings()
            };
            match s.validate() {
                Err(ClimateError::InvalidSetting { field, .. }) => field,
                other => panic!("{other:?}"),
            }
        };
        assert_eq!(field(Some(vec![0.0]), None), "hs_edges_m");
        assert_eq!(field(Some(vec![0.0, 1.0, 1.0]), None), "hs_edges_m");
        assert_eq!(field(Some(vec![0.5, 1.0]), None), "hs_edges_m");
        assert_eq!(field(None, Some(vec![5.0, f64::NAN])), "tp_edges_s");
        assert_eq!(field(None, Some(vec![7.0, 5.0])), "tp_edges_s");
        let calm = ClimateSettings {
            hs_edges_m: Some(vec![0.0, 0.1, 1.0]),
            ..settings()
        };
        assert!(matches!(
            calm.validate(),
            Err(ClimateError::CalmAboveFirstBin { hs_bin_m, .. }) if hs_bin_m == 0.1
        ));
    }

    #[test]
    fn records_are_counted_by_what_happened_to_them() {
        let c = climate().counts;
        assert_eq!(
            (c.records_read, c.records_used, c.records_missing, c.calm),
            (14, 9, 5, 2)
        );
        assert_eq!(c.hs_missing.count, 2);
        assert_eq!(c.hs_missing.first, Some((12, "NaN".to_string())));
        assert_eq!(c.tp_missing.first, Some((13, String::new())));
        assert_eq!(c.direction_missing.count, 1);
        assert_eq!(c.direction_missing.first, Some((14, "abc".to_string())));
        assert_eq!(c.tp_below_first_bin.count, 1);
        assert_eq!(c.time_kind, TimeKind::Calendar);
        assert_eq!(c.time_step, Some(3600.0));
        assert_eq!(c.gaps, 2);
        assert_eq!(c.time_span.0, "2020-01-01T00:00Z");
        assert_eq!(c.time_span.1, "2020-01-01T15:00Z");
    }

    #[test]
    fn directions_wrap_and_edges_go_up() {
        let climate = climate();
        let records: Vec<u64> = climate.sectors.iter().map(|s| s.records).collect();
        // 0, 359, 1, 360 and -1 are all north; 22.5 is the first direction of NE.
        assert_eq!(records, vec![5, 1, 1, 0, 0, 0, 0, 0]);
        let labels: Vec<&str> = climate.sectors.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["N", "NE", "E", "SE", "S", "SW", "W", "NW"]);
        assert_eq!(
            (climate.sectors[0].from_deg, climate.sectors[0].to_deg),
            (337.5, 22.5)
        );
        let ne = ScatterTable::parse(&climate.table_text(1, "buoy.csv").unwrap()).unwrap();
        // Hs 1.0 is the lower edge of [1.0, 1.5); Tp 9.49 is in the column of 9. The sector
        // also holds 2/7 of the two calm records: the one record is 7/9 of it.
        assert_eq!(cell(&ne, 1.0, 9.0), 77.777778);
        assert_eq!(cell(&ne, 0.5, 9.0), 0.0);
        let north = ScatterTable::parse(&climate.table_text(0, "buoy.csv").unwrap()).unwrap();
        // Hs 0.5 belongs to [0.5, 1.0), Tp 6.5 to the column of 7 ([6.5, 7.5)).
        assert!(cell(&north, 0.5, 7.0) > 0.0);
        assert_eq!(cell(&north, 0.0, 7.0), 0.0);
        assert_eq!(cell(&north, 0.5, 6.0), 0.0);
    }

    #[test]
    fn shares_and_cells_sum_to_100_and_read_back_without_mismatch() {
        let climate = climate();
        let shares: Vec<f64> = climate.sectors.iter().map(|s| s.share_percent).collect();
        assert_eq!(
            shares,
            vec![71.428572, 14.285714, 14.285714, 0.0, 0.0, 0.0, 0.0, 0.0]
        );
        assert!((shares.iter().sum::<f64>() - 100.0).abs() < 1e-9);
        for (i, sector) in climate.sectors.iter().enumerate() {
            let Some(text) = climate.table_text(i, "buoy.csv") else {
                assert_eq!(sector.records, 0);
                assert!(sector.path.is_none());
                continue;
            };
            assert_eq!(
                sector.path.as_deref(),
                Some(format!("sector_{:03}.tsv", i * 45).as_str())
            );
            let table = ScatterTable::parse(&text).unwrap();
            assert!(table.total_mismatches().is_empty(), "{text}");
            assert!((table.cell_sum() - 100.0).abs() < 1e-9, "{text}");
            assert_eq!(table.grand_total, Some(100.0));
            // the same grid in every sector: Hs from 0 to the 2.0 m record, Tp 4 to 9 s
            assert_eq!(table.hs_bins_m.first(), Some(&(0.0, 0.5)));
            assert_eq!(table.hs_bins_m.last(), Some(&(2.0, 2.5)));
            assert_eq!(table.tp_s, vec![4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
        }
        assert!(climate.table_text(3, "buoy.csv").is_none());
        assert!(climate.table_text(99, "buoy.csv").is_none());
    }

    #[test]
    fn calm_records_are_spread_by_the_sectors_shares_into_the_lowest_bin() {
        let climate = climate();
        let north = ScatterTable::parse(&climate.table_text(0, "buoy.csv").unwrap()).unwrap();
        // North: 5 records and 2 × 5/7 calm ones (Tp 4 and 5): 45/7 in all.
        let sector_weight = 45.0 / 7.0;
        let close = |a: f64, b: f64| (a - b).abs() <= 1.5e-6;
        assert!(close(
            cell(&north, 0.0, 4.0),
            5.0 / 7.0 / sector_weight * 100.0
        ));
        assert!(close(
            cell(&north, 0.0, 5.0),
            (1.0 + 5.0 / 7.0) / sector_weight * 100.0
        ));
        assert!(close(cell(&north, 1.0, 7.0), 100.0 / sector_weight));
        assert!((climate.sectors[0].calm_records - 10.0 / 7.0).abs() < 1e-12);
        let east = ScatterTable::parse(&climate.table_text(2, "buoy.csv").unwrap()).unwrap();
        // East: its 2.0 m record and 2 × 1/7 calm ones.
        assert!(close(cell(&east, 2.0, 9.0), 100.0 / (9.0 / 7.0)));
        assert!(close(cell(&east, 0.0, 4.0), 100.0 / 9.0));
        // a calm record is used whatever its direction: the year is whole
        let calm_total: f64 = climate.sectors.iter().map(|s| s.calm_records).sum();
        assert!((calm_total - 2.0).abs() < 1e-12);
    }

    #[test]
    fn the_model_heading_follows_from_the_frames() {
        // Travel bearing P as a unit vector (east, north); +x points to bearing B and +y is
        // +x turned 90° counter-clockwise seen from above (z up).
        let check = |from: f64, bearing: f64| {
            let travel = (from + 180.0).to_radians();
            let p = (travel.sin(), travel.cos());
            let b = bearing.to_radians();
            let x = (b.sin(), b.cos());
            let y = (-x.1, x.0);
            let h = model_heading_deg(from, bearing).to_radians();
            let dot = |u: (f64, f64), v: (f64, f64)| u.0 * v.0 + u.1 * v.1;
            assert!(
                (h.cos() - dot(p, x)).abs() < 1e-9,
                "from {from}, bearing {bearing}"
            );
            assert!(
                (h.sin() - dot(p, y)).abs() < 1e-9,
                "from {from}, bearing {bearing}"
            );
        };
        for from in [0.0, 22.5, 90.0, 180.0, 270.0, 359.0] {
            for bearing in [0.0, 45.0, 90.0, 180.0, 270.0, -90.0, 400.0] {
                check(from, bearing);
            }
        }
        // +x north: a sea from the north travels south (-x), one from the east west (+y)
        assert_eq!(model_heading_deg(0.0, 0.0), 180.0);
        assert_eq!(model_heading_deg(90.0, 0.0), 90.0);
        // +x east: from the south travels north (+y), from the west travels east (+x)
        assert_eq!(model_heading_deg(180.0, 90.0), 90.0);
        assert_eq!(model_heading_deg(270.0, 90.0), 0.0);
        // +x west: from the north travels south, which is +y
        assert_eq!(model_heading_deg(0.0, 270.0), 90.0);
        assert_eq!(model_heading_deg(0.0, -90.0), 90.0);
        let headings = DirectionalClimate::from_series(
            SERIES,
            &ClimateSettings {
                x_axis_bearing_deg: 90.0,
                ..settings()
            },
        )
        .unwrap()
        .sectors_file();
        let h: Vec<f64> = headings.sectors.iter().map(|s| s.heading_deg).collect();
        assert_eq!(h, vec![270.0, 225.0, 180.0, 135.0, 90.0, 45.0, 0.0, 315.0]);
    }

    #[test]
    fn the_sectors_file_has_the_documented_fields() {
        let json = serde_json::to_value(climate().sectors_file()).unwrap();
        let sectors = json["sectors"].as_array().unwrap();
        assert_eq!(sectors.len(), 8);
        assert_eq!(
            sectors[0],
            serde_json::json!({"label": "N", "direction_from_deg": 0.0, "heading_deg": 180.0,
                "share_percent": 71.428572, "path": "sector_000.tsv"})
        );
        assert_eq!(
            sectors[3],
            serde_json::json!({"label": "SE", "direction_from_deg": 135.0,
                "heading_deg": 45.0, "share_percent": 0.0})
        );
        let back: SectorsFile = serde_json::from_value(json).unwrap();
        assert_eq!(back, climate().sectors_file());
    }

    #[test]
    fn sector_counts_other_than_compass_points_are_labelled_by_their_centre() {
        let one = |n: usize| {
            DirectionalClimate::from_series(
                SERIES,
                &ClimateSettings {
                    sectors: n,
                    ..settings()
                },
            )
            .unwrap()
        };
        let labels = |c: &DirectionalClimate| -> Vec<String> {
            c.sectors.iter().map(|s| s.label.clone()).collect()
        };
        assert_eq!(labels(&one(4)), ["N", "E", "S", "W"]);
        assert_eq!(labels(&one(16))[1], "NNE");
        let seven = one(7);
        assert_eq!(labels(&seven)[1], "51.43");
        assert_eq!(seven.sectors[2].path.as_deref(), Some("sector_103.tsv"));
        let whole = one(1);
        assert_eq!(whole.sectors[0].records, 7);
        assert_eq!(whole.sectors[0].share_percent, 100.0);
    }

    #[test]
    fn values_on_decimal_edges_are_not_moved_down_by_rounding() {
        assert_eq!(bin_index(0.3, 0.1, 0.0), Ok(3));
        assert_eq!(bin_index(0.29, 0.1, 0.0), Ok(2));
        assert_eq!(bin_index(0.5, 0.5, 0.0), Ok(1));
        assert_eq!(bin_index(0.4999, 0.5, 0.0), Ok(0));
        assert_eq!(bin_index(6.5, 1.0, 0.5), Ok(7));
        assert_eq!(bin_index(6.4999, 1.0, 0.5), Ok(6));
        assert_eq!(bin_index(16.25, 0.5, 0.5), Ok(33));
        assert_eq!(bin_index(1e300, 1e-300, 0.0), Err(u64::MAX));
        assert_eq!(sector_index(337.5, 8), 0);
        assert_eq!(sector_index(337.4999, 8), 7);
        assert_eq!(sector_index(22.5, 8), 1);
        assert_eq!(sector_index(359.9, 8), 0);
        assert_eq!(sector_index(-1.0, 8), 0);
        assert_eq!(sector_index(360.0, 8), 0);
        assert_eq!(sector_index(180.0, 1), 0);
        assert_eq!(width_decimals(0.5), 1);
        assert_eq!(width_decimals(0.1), 1);
        assert_eq!(width_decimals(0.25), 2);
        assert_eq!(width_decimals(2.0), 0);
    }

    #[test]
    fn printed_units_sum_to_exactly_100() {
        assert_eq!(
            percent_units(&[1.0, 1.0, 1.0]),
            vec![33_333_334, 33_333_333, 33_333_333]
        );
        assert_eq!(percent_units(&[0.0, 2.0, 0.0]), vec![0, 100_000_000, 0]);
        assert_eq!(percent_units(&[0.0, 0.0]), vec![0, 0]);
        let many: Vec<f64> = (1..=997).map(|i| (i as f64).sqrt()).collect();
        assert_eq!(percent_units(&many).iter().sum::<i64>(), 100_000_000);
        assert_eq!(units_text(100_000_000), "100.000000");
        assert_eq!(units_text(1), "0.000001");
    }

    #[test]
    fn calendar_times_and_numbers_are_read() {
        assert_eq!(calendar_seconds("1970-01-01"), Some(0.0));
        assert_eq!(
            calendar_seconds("2000-03-01T00:00:00Z"),
            Some(11_017.0 * 86_400.0)
        );
        let t = calendar_seconds("2020-02-29 13:45").unwrap();
        assert_eq!(calendar_seconds("2020/02/29T13:45:00.0"), Some(t));
        assert_eq!(calendar_seconds("2020-02-29T14:45+01:00"), Some(t));
        assert_eq!(calendar_seconds("2020-02-29T08:45-0500"), Some(t));
        assert_eq!(calendar_seconds("2020-02-29 13:45 UTC"), Some(t));
        assert_eq!(calendar_seconds("2020-02-29T13:45:30.5"), Some(t + 30.5));
        for bad in [
            "2019-02-29",
            "2020-13-01",
            "2020-01-01T25:00",
            "2020-01-01T10",
            "20200101",
            "2020-01-01T10:00+x",
            "2020-01-01T10:00:00:00",
            "2020-01-0é",
            "",
        ] {
            assert_eq!(calendar_seconds(bad), None, "{bad}");
        }
        // numbers in any unit: days here, one record missing
        let text = "t;hs;tp;dir\n0,0;1;8;10\n0,25;1;8;10\n0,75;1;8;10\n1,0;1;8;10\n";
        let c = DirectionalClimate::from_series(
            text,
            &ClimateSettings::new(SeriesColumns {
                time: "t".into(),
                ..columns()
            }),
        )
        .unwrap()
        .counts;
        assert_eq!(
            (c.time_kind, c.time_step, c.gaps),
            (TimeKind::Number, Some(0.25), 1)
        );
    }

    #[test]
    fn tabs_blanks_quotes_and_fill_values() {
        let tsv = "\u{feff}\"time\"\t\"hs\"\t\"tp\"\t\"dir\"\n1\t1,5\t8\t10\n2\t99\t8\t10\n";
        let s = ClimateSettings {
            missing_values: vec![99.0],
            ..ClimateSettings::new(columns())
        };
        let c = DirectionalClimate::from_series(tsv, &s).unwrap();
        assert_eq!((c.counts.records_used, c.counts.records_missing), (1, 1));
        assert_eq!(c.counts.hs_missing.first, Some((3, "99".to_string())));
        let blanks = "time hs tp dir\n1 1.5 8 10\n2 1.5 8 800\n3 1.5 8 -400\n";
        let c = DirectionalClimate::from_series(blanks, &s).unwrap();
        assert_eq!(c.counts.direction_missing.count, 2);
    }

    #[test]
    fn errors_name_the_line_column_and_field() {
        let s = settings();
        let err = |text: &str| DirectionalClimate::from_series(text, &s).unwrap_err();
        let e = err("time,Hs,tp,dir\n1,1,8,0\n");
        assert_eq!(
            e,
            ClimateError::MissingColumn {
                line: 1,
                field: SeriesField::Hs,
                name: "hs".into(),
                available: "time, Hs, tp, dir".into()
            }
        );
        assert_eq!(
            e.to_string(),
            "line 1: no column `hs` for hs (columns: time, Hs, tp, dir)"
        );
        assert!(matches!(
            err("time,hs,hs,tp,dir\n"),
            ClimateError::AmbiguousColumn { count: 2, .. }
        ));
        assert_eq!(
            err("# c\ntime,hs,tp,dir\n1,1,8\n"),
            ClimateError::Ragged {
                line: 3,
                expected: 4,
                found: 3
            }
        );
        assert_eq!(
            err("time,hs,tp,dir\n2020-01-01,1,8,0\n5,1,8,0\n").to_string(),
            "line 3, column 1 (`time`): `5` is not a calendar time like the first record's \
             (YYYY-MM-DD[Thh:mm[:ss]][Z|±hh:mm])"
        );
        assert!(matches!(
            err("time,hs,tp,dir\nnoon,1,8,0\n"),
            ClimateError::BadTime {
                line: 2,
                column: 1,
                ..
            }
        ));
        assert_eq!(
            err("time,hs,tp,dir\n2,1,8,0\n2,1,8,0\n"),
            ClimateError::TimeNotIncreasing {
                line: 3,
                text: "2".into(),
                previous_line: 2,
                previous_text: "2".into()
            }
        );
        let e = err("time,hs,tp,dir\n1,9999,8,0\n");
        assert!(
            matches!(
                e,
                ClimateError::TooManyBins {
                    line: 2,
                    column: 2,
                    field: SeriesField::Hs,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("declare it as a fill value"), "{e}");
        assert_eq!(
            err("# only\n"),
            ClimateError::Empty {
                reason: "no header line"
            }
        );
        assert_eq!(
            err("time,hs,tp,dir\n"),
            ClimateError::Empty {
                reason: "no data row"
            }
        );
        assert_eq!(
            err("time,hs,tp,dir\n1,x,8,0\n2,1,,0\n"),
            ClimateError::NoUsableRecord { read: 2 }
        );
        assert_eq!(
            err("time,hs,tp,dir\n1,0.1,8,\n"),
            ClimateError::AllCalm {
                calm: 1,
                calm_hs_m: 0.2
            }
        );
    }

    #[test]
    fn settings_are_checked_by_name() {
        let bad = |f: fn(&mut ClimateSettings)| {
            let mut s = settings();
            f(&mut s);
            DirectionalClimate::from_series(SERIES, &s).unwrap_err()
        };
        let field = |e: ClimateError| match e {
            ClimateError::InvalidSetting { field, .. } => field,
            other => panic!("{other}"),
        };
        assert_eq!(field(bad(|s| s.hs_bin_m = 0.0)), "hs_bin_m");
        assert_eq!(field(bad(|s| s.tp_bin_s = f64::NAN)), "tp_bin_s");
        assert_eq!(field(bad(|s| s.sectors = 0)), "sectors");
        assert_eq!(field(bad(|s| s.sectors = 361)), "sectors");
        assert_eq!(field(bad(|s| s.calm_hs_m = -0.1)), "calm_hs_m");
        assert_eq!(
            field(bad(|s| s.x_axis_bearing_deg = f64::INFINITY)),
            "x_axis_bearing_deg"
        );
        assert_eq!(
            field(bad(|s| s.missing_values = vec![f64::NAN])),
            "missing_values"
        );
        assert!(matches!(
            bad(|s| s.calm_hs_m = 0.6),
            ClimateError::CalmAboveFirstBin { .. }
        ));
        assert_eq!(
            bad(|s| s.columns.tp = "hs".into()).to_string(),
            "the hs and tp columns are both `hs`"
        );
    }

    #[test]
    fn no_input_panics() {
        let s = settings();
        for text in [
            "",
            "\n\n",
            "time,hs,tp,dir\n,,,\n",
            "time,hs,tp,dir\n1,1e308,1e308,1e308\n",
            "time,hs,tp,dir\n1,-0,0,-0\n",
            "time,hs,tp,dir\n1,inf,8,0\n",
            "time,hs,tp,dir\n1e308,1,8,0\n-1e308,1,8,0\n",
            "time,hs,tp,dir\n1e308,1,8,0\n1.7976931348623157e308,1,8,0\n",
            "time;hs;tp;dir\n1;1;8;0\n\"\n",
            "time,hs,tp,dir\n2020-01-01Té,1,8,0\n",
        ] {
            let _ = DirectionalClimate::from_series(text, &s);
        }
    }
}
