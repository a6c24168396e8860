//! Wave scatter diagrams: a table of occurrence values per significant-wave-height bin (rows) and
//! peak period (columns), read from text, with a check of its printed totals.
//!
//! Text format: `#` lines are comments; blank lines are skipped. Fields are separated by tabs,
//! semicolons or commas (the first of these found in the header line, in that order). Numbers
//! use a decimal point, or a decimal comma when the separator is not a comma. The header holds
//! two labels for the Hs bin edges (lower, upper), then one peak period per column (s), then
//! optionally `total`. Each data row holds the lower and upper Hs edge (m), one value per period,
//! and the row total when the header has a `total` column. An optional last row starts with
//! `total` and holds the column totals (its second field may be empty) and the grand total.
//!
//! Printed totals are compared with the sums of the cells. A difference counts as a mismatch when
//! it exceeds 1.5 units of the finest decimal printed in the table: each total may carry half a
//! unit of its own rounding and the rounded cells about one unit more. Values are returned as
//! printed (typically percent of the year); interpreting them is the campaign's business.

use thiserror::Error;

/// Why a scatter table could not be read. Lines and columns count from 1.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ScatterError {
    /// No header or no data row.
    #[error("scatter table is empty: {reason}")]
    Empty {
        /// What is missing.
        reason: &'static str,
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
    /// A field is not a number.
    #[error("line {line}, column {column}: '{text}' is not a number")]
    NonNumeric {
        /// Line number.
        line: usize,
        /// Column number.
        column: usize,
        /// The offending text.
        text: String,
    },
    /// A cell, total or bin edge is negative.
    #[error("line {line}, column {column}: negative value {value}")]
    Negative {
        /// Line number.
        line: usize,
        /// Column number.
        column: usize,
        /// The value read.
        value: f64,
    },
    /// A bin's upper edge is not above its lower edge.
    #[error("line {line}: Hs bin upper edge {upper} must exceed lower edge {lower}")]
    InvertedBin {
        /// Line number.
        line: usize,
        /// Lower edge (m).
        lower: f64,
        /// Upper edge (m).
        upper: f64,
    },
    /// The header has no period column.
    #[error("line {line}: header has no peak-period column")]
    NoPeriods {
        /// Line number.
        line: usize,
    },
}

/// One cell of the diagram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScatterCell {
    /// Lower edge of the Hs bin (m).
    pub hs_lower_m: f64,
    /// Upper edge of the Hs bin (m).
    pub hs_upper_m: f64,
    /// Peak period of the column (s).
    pub tp_s: f64,
    /// Value as printed (occurrence, usually percent of the year).
    pub value: f64,
}

/// Which printed total disagrees with its cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TotalKind {
    /// A row total: the Hs bin (lower, upper) in m.
    Row {
        /// Lower Hs edge (m).
        hs_lower_m: f64,
        /// Upper Hs edge (m).
        hs_upper_m: f64,
    },
    /// A column total: the peak period in s.
    Column {
        /// Peak period (s).
        tp_s: f64,
    },
    /// The grand total (compared with the sum of all cells).
    Grand,
}

/// A printed total that differs from the sum of its cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TotalMismatch {
    /// Which total.
    pub kind: TotalKind,
    /// Line of the printed total in the text.
    pub line: usize,
    /// Printed value.
    pub printed: f64,
    /// Sum of the cells.
    pub computed: f64,
}

/// A parsed scatter diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterTable {
    /// Peak period of each column (s).
    pub tp_s: Vec<f64>,
    /// Hs bins (lower, upper) of each row (m).
    pub hs_bins_m: Vec<(f64, f64)>,
    /// Values, row-major: `values[row][column]`.
    pub values: Vec<Vec<f64>>,
    /// Printed row totals with their line numbers, when the table has a total column.
    pub row_totals: Option<Vec<(usize, f64)>>,
    /// Printed column totals, when the table has a total row.
    pub column_totals: Option<Vec<f64>>,
    /// Printed grand total, when the table has both.
    pub grand_total: Option<f64>,
    /// Line of the total row.
    total_row_line: usize,
    /// Finest number of decimals printed anywhere in the values.
    decimals: u32,
}

/// Split a line into trimmed fields.
fn fields(line: &str, sep: char) -> Vec<&str> {
    line.split(sep).map(str::trim).collect()
}

/// Parse one number (decimal comma accepted unless commas separate fields); returns the value
/// and the number of decimals printed.
fn number(text: &str, sep: char, line: usize, column: usize) -> Result<(f64, u32), ScatterError> {
    let normalised = if sep == ',' {
        text.to_string()
    } else {
        text.replace(',', ".")
    };
    let value: f64 = normalised
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| ScatterError::NonNumeric {
            line,
            column,
            text: text.to_string(),
        })?;
    if value < 0.0 {
        return Err(ScatterError::Negative {
            line,
            column,
            value,
        });
    }
    let decimals = normalised
        .split_once('.')
        .map_or(0, |(_, frac)| frac.len() as u32);
    Ok((value, decimals))
}

impl ScatterTable {
    /// Parse a scatter table from text.
    pub fn parse(text: &str) -> Result<Self, ScatterError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let (header_line, header) = lines.next().ok_or(ScatterError::Empty {
            reason: "no header line",
        })?;
        let sep = ['\t', ';', ',']
            .into_iter()
            .find(|&c| header.contains(c))
            .unwrap_or('\t');
        let head = fields(header, sep);
        let has_total_column = head.last().is_some_and(|h| h.eq_ignore_ascii_case("total"));
        let period_end = if has_total_column {
            head.len() - 1
        } else {
            head.len()
        };
        if period_end <= 2 {
            return Err(ScatterError::NoPeriods { line: header_line });
        }
        let mut decimals = 0;
        let mut tp_s = Vec::with_capacity(period_end - 2);
        for (c, h) in head.iter().enumerate().take(period_end).skip(2) {
            tp_s.push(number(h, sep, header_line, c + 1)?.0);
        }

        let mut table = Self {
            tp_s,
            hs_bins_m: Vec::new(),
            values: Vec::new(),
            row_totals: has_total_column.then(Vec::new),
            column_totals: None,
            grand_total: None,
            total_row_line: 0,
            decimals: 0,
        };
        for (line, text) in lines {
            let row = fields(text, sep);
            if row.len() != head.len() {
                return Err(ScatterError::Ragged {
                    line,
                    expected: head.len(),
                    found: row.len(),
                });
            }
            let mut num = |c: usize| -> Result<f64, ScatterError> {
                let (v, d) = number(row[c], sep, line, c + 1)?;
                decimals = decimals.max(d);
                Ok(v)
            };
            if row[0].eq_ignore_ascii_case("total") {
                let totals = (2..period_end)
                    .map(&mut num)
                    .collect::<Result<Vec<_>, _>>()?;
                table.column_totals = Some(totals);
                if has_total_column {
                    table.grand_total = Some(num(period_end)?);
                }
                table.total_row_line = line;
                continue;
            }
            let (lower, upper) = (num(0)?, num(1)?);
            if upper <= lower {
                return Err(ScatterError::InvertedBin { line, lower, upper });
            }
            let cells = (2..period_end)
                .map(&mut num)
                .collect::<Result<Vec<_>, _>>()?;
            if let Some(totals) = table.row_totals.as_mut() {
                totals.push((line, num(period_end)?));
            }
            table.hs_bins_m.push((lower, upper));
            table.values.push(cells);
        }
        if table.values.is_empty() {
            return Err(ScatterError::Empty {
                reason: "no data row",
            });
        }
        table.decimals = decimals;
        Ok(table)
    }

    /// Every cell, row by row.
    pub fn cells(&self) -> Vec<ScatterCell> {
        self.hs_bins_m
            .iter()
            .zip(&self.values)
            .flat_map(|(&(lo, hi), row)| {
                self.tp_s
                    .iter()
                    .zip(row)
                    .map(move |(&tp, &value)| ScatterCell {
                        hs_lower_m: lo,
                        hs_upper_m: hi,
                        tp_s: tp,
                        value,
                    })
            })
            .collect()
    }

    /// Sum of all cells.
    pub fn cell_sum(&self) -> f64 {
        self.values.iter().flatten().sum()
    }

    /// Tolerance below which a printed total is taken as a rounding of its cells' sum: 1.5 units
    /// of the finest printed decimal.
    pub fn rounding_tolerance(&self) -> f64 {
        1.5 * 10f64.powi(-(self.decimals as i32))
    }

    /// Every printed total (rows, columns, grand) that differs from the sum of its cells by more
    /// than [`Self::rounding_tolerance`].
    pub fn total_mismatches(&self) -> Vec<TotalMismatch> {
        // A small relative allowance keeps binary rounding of the sums from tipping a borderline
        // difference over the tolerance.
        let tol = self.rounding_tolerance() * (1.0 + 1e-9);
        let mut out = Vec::new();
        if let Some(rows) = &self.row_totals {
            for ((&(line, printed), row), &(lo, hi)) in
                rows.iter().zip(&self.values).zip(&self.hs_bins_m)
            {
                let computed: f64 = row.iter().sum();
                if (printed - computed).abs() > tol {
                    out.push(TotalMismatch {
                        kind: TotalKind::Row {
                            hs_lower_m: lo,
                            hs_upper_m: hi,
                        },
                        line,
                        printed,
                        computed,
                    });
                }
            }
        }
        if let Some(cols) = &self.column_totals {
            for (c, (&printed, &tp)) in cols.iter().zip(&self.tp_s).enumerate() {
                let computed: f64 = self.values.iter().map(|r| r[c]).sum();
                if (printed - computed).abs() > tol {
                    out.push(TotalMismatch {
                        kind: TotalKind::Column { tp_s: tp },
                        line: self.total_row_line,
                        printed,
                        computed,
                    });
                }
            }
        }
        if let Some(printed) = self.grand_total {
            let computed = self.cell_sum();
            if (printed - computed).abs() > tol {
                out.push(TotalMismatch {
                    kind: TotalKind::Grand,
                    line: self.total_row_line,
                    printed,
                    computed,
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str =
        "# comment\nlo;hi;5;7,5;total\n0;1;1,5;0,25;1,75\n1;2;0;2;2,5\ntotal;;1,5;2,25;3,75\n";

    #[test]
    fn semicolon_table_with_decimal_commas_is_read() {
        let t = ScatterTable::parse(SMALL).unwrap();
        assert_eq!(t.tp_s, vec![5.0, 7.5]);
        assert_eq!(t.hs_bins_m, vec![(0.0, 1.0), (1.0, 2.0)]);
        assert_eq!(t.values, vec![vec![1.5, 0.25], vec![0.0, 2.0]]);
        assert_eq!(t.grand_total, Some(3.75));
        assert_eq!(t.cells().len(), 4);
        assert_eq!(
            t.cells()[1],
            ScatterCell {
                hs_lower_m: 0.0,
                hs_upper_m: 1.0,
                tp_s: 7.5,
                value: 0.25
            }
        );
        let m = t.total_mismatches();
        assert_eq!(m.len(), 1);
        assert_eq!(
            m[0].kind,
            TotalKind::Row {
                hs_lower_m: 1.0,
                hs_upper_m: 2.0
            }
        );
        assert_eq!((m[0].line, m[0].printed, m[0].computed), (4, 2.5, 2.0));
    }

    #[test]
    fn comma_separated_table_with_decimal_points_and_no_totals_is_read() {
        let t = ScatterTable::parse("lo,hi,4,6\n0,0.5,0.1,0.2\n").unwrap();
        assert_eq!(t.values, vec![vec![0.1, 0.2]]);
        assert!(t.row_totals.is_none() && t.column_totals.is_none());
        assert!(t.total_mismatches().is_empty());
    }

    #[test]
    fn errors_carry_line_and_column() {
        let e = ScatterTable::parse("lo\thi\t5\n0\t1\tx\n").unwrap_err();
        assert_eq!(
            e,
            ScatterError::NonNumeric {
                line: 2,
                column: 3,
                text: "x".into()
            }
        );
        let e = ScatterTable::parse("lo\thi\t5\n0\t1\t-0,2\n").unwrap_err();
        assert_eq!(
            e,
            ScatterError::Negative {
                line: 2,
                column: 3,
                value: -0.2
            }
        );
        let e = ScatterTable::parse("# c\nlo\thi\t5\n0\t1\n").unwrap_err();
        assert_eq!(
            e,
            ScatterError::Ragged {
                line: 3,
                expected: 3,
                found: 2
            }
        );
        let e = ScatterTable::parse("# only\n\n").unwrap_err();
        assert!(matches!(e, ScatterError::Empty { .. }));
        let e = ScatterTable::parse("lo\thi\t5\n").unwrap_err();
        assert!(matches!(e, ScatterError::Empty { .. }));
        assert_eq!(e.to_string(), "scatter table is empty: no data row");
        let e = ScatterTable::parse("lo\thi\t5\n1\t0,5\t1\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 2: Hs bin upper edge 0.5 must exceed lower edge 1"
        );
    }
}
