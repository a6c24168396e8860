//! A small result table (named columns, JSON values) and its text, CSV and JSON renderings.

use anyhow::Context;
use serde::Serialize;
use serde_json::{Map, Value};

/// Spaces between two text columns.
const COLUMN_GAP: usize = 2;

/// Output format of a query.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum OutputFormat {
    /// Aligned text columns for a terminal.
    #[default]
    Table,
    /// Comma-separated values with a header line.
    Csv,
    /// An array of objects, one per row.
    Json,
}

/// Rows of values under named columns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, each with one value per column.
    pub rows: Vec<Vec<Value>>,
}

impl Table {
    /// A table of the fields `columns` of each serialised row (missing fields are null).
    pub fn from_rows<T: Serialize>(columns: &[&str], rows: &[T]) -> anyhow::Result<Self> {
        let rows = rows
            .iter()
            .map(|row| {
                let value = serde_json::to_value(row).context("serialising a result row")?;
                Ok(columns
                    .iter()
                    .map(|c| value.get(c).cloned().unwrap_or(Value::Null))
                    .collect())
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        Ok(Self {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows,
        })
    }

    /// Appends a column (one value per row).
    pub fn push_column(&mut self, name: String, values: Vec<Value>) {
        self.columns.push(name);
        for (row, value) in self.rows.iter_mut().zip(values) {
            row.push(value);
        }
    }

    /// Rows as JSON objects.
    pub fn to_json(&self) -> Value {
        Value::Array(
            self.rows
                .iter()
                .map(|row| {
                    let mut object = Map::new();
                    for (c, v) in self.columns.iter().zip(row) {
                        object.insert(c.clone(), v.clone());
                    }
                    Value::Object(object)
                })
                .collect(),
        )
    }

    /// Renders the table as text no wider than `width` characters: the columns from the left
    /// that fit (at least the first), then a note naming the ones left out and how to see
    /// them. Every column when they all fit.
    pub fn render_fitted(&self, width: usize) -> anyhow::Result<String> {
        let cells = self.text_cells();
        let widths = self.column_widths(&cells);
        let mut used = 0;
        let mut shown = 0;
        for (k, w) in widths.iter().enumerate() {
            let add = if k == 0 { *w } else { w + COLUMN_GAP };
            if k > 0 && used + add > width {
                break;
            }
            used += add;
            shown = k + 1;
        }
        let mut out = self.text_lines(&cells, &widths[..shown]);
        let hidden = &self.columns[shown..];
        if !hidden.is_empty() {
            let mut note = format!(
                "{} more column{} (--wide, or --format csv|json):",
                hidden.len(),
                if hidden.len() == 1 { "" } else { "s" }
            );
            let mut line_len = note.chars().count();
            for name in hidden {
                let len = name.chars().count() + 1;
                if line_len + len > width {
                    note += "\n ";
                    line_len = 1;
                }
                note.push(' ');
                note += name;
                line_len += len;
            }
            out += &note;
            out.push('\n');
        }
        Ok(out)
    }

    /// The text cells of every row.
    fn text_cells(&self) -> Vec<Vec<String>> {
        self.rows
            .iter()
            .map(|r| r.iter().map(readable_cell).collect())
            .collect()
    }

    /// Each column's width in characters: its widest cell or its name.
    fn column_widths(&self, cells: &[Vec<String>]) -> Vec<usize> {
        (0..self.columns.len())
            .map(|k| {
                cells
                    .iter()
                    .map(|r| r[k].chars().count())
                    .chain([self.columns[k].chars().count()])
                    .max()
                    .unwrap_or(0)
            })
            .collect()
    }

    /// The header and the rows, right-aligned in `widths` (the first `widths.len()` columns).
    fn text_lines(&self, cells: &[Vec<String>], widths: &[usize]) -> String {
        let gap = " ".repeat(COLUMN_GAP);
        let line = |items: &mut dyn Iterator<Item = &String>| {
            items
                .zip(widths.iter().copied())
                .map(|(s, w)| format!("{s:>w$}"))
                .collect::<Vec<_>>()
                .join(&gap)
                .trim_end()
                .to_owned()
                + "\n"
        };
        let mut out = line(&mut self.columns.iter());
        for r in cells {
            out += &line(&mut r.iter());
        }
        out
    }

    /// Renders the table in `format`.
    pub fn render(&self, format: OutputFormat) -> anyhow::Result<String> {
        match format {
            OutputFormat::Json => Ok(serde_json::to_string_pretty(&self.to_json())? + "\n"),
            OutputFormat::Csv => {
                let mut writer = csv::Writer::from_writer(Vec::new());
                writer.write_record(&self.columns)?;
                for row in &self.rows {
                    writer.write_record(row.iter().map(cell))?;
                }
                Ok(String::from_utf8(writer.into_inner()?)?)
            }
            OutputFormat::Table => {
                let cells = self.text_cells();
                Ok(self.text_lines(&cells, &self.column_widths(&cells)))
            }
        }
    }
}

/// A number to four significant figures: fixed notation from 0.001 to 10⁶, else scientific.
pub fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    if (-3..6).contains(&magnitude) {
        let decimals = (3 - magnitude).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.3e}")
    }
}

/// Text of one value for reading: floating-point numbers to four significant figures
/// ([`significant`]), the rest as [`cell`].
fn readable_cell(value: &Value) -> String {
    match value {
        Value::Number(n) if n.is_f64() => n.as_f64().map_or_else(|| n.to_string(), significant),
        other => cell(other),
    }
}

/// Text of one value: numbers in full precision (shortest round-trip form), strings bare,
/// null empty, objects as compact JSON.
fn cell(value: &Value) -> String {
    match value {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        Value::Number(n) => n.to_string(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readable_numbers_have_four_significant_figures() {
        assert_eq!(significant(0.018730000000000004), "0.01873");
        assert_eq!(significant(6.987354589123571e-9), "6.987e-9");
        assert_eq!(significant(12345.678), "12346");
        assert_eq!(significant(1.5e300), "1.500e300");
        assert_eq!(significant(-2.0), "-2.000");
        assert_eq!(significant(0.0), "0");
        assert_eq!(readable_cell(&serde_json::json!(3)), "3");
    }

    #[derive(Serialize)]
    struct Row {
        a: i64,
        b: Option<f64>,
        c: &'static str,
    }

    #[test]
    fn renders_columns_in_the_given_order() {
        let rows = [
            Row {
                a: 1,
                b: Some(2.5e-7),
                c: "outer_arc",
            },
            Row {
                a: 10,
                b: None,
                c: "x,y",
            },
        ];
        let t = Table::from_rows(&["c", "a", "b", "missing"], &rows).unwrap();
        let csv = t.render(OutputFormat::Csv).unwrap();
        assert_eq!(csv, "c,a,b,missing\nouter_arc,1,2.5e-7,\n\"x,y\",10,,\n");
        let text = t.render(OutputFormat::Table).unwrap();
        assert_eq!(
            text,
            "        c   a         b  missing\nouter_arc   1  2.500e-7\n      x,y  10\n"
        );
        let json: Value = serde_json::from_str(&t.render(OutputFormat::Json).unwrap()).unwrap();
        assert_eq!(json[1]["a"], 10);
        assert_eq!(json[0]["b"], 2.5e-7);
        assert!(json[1]["b"].is_null());
    }

    #[test]
    fn a_fitted_table_keeps_the_columns_that_fit_and_names_the_others() {
        let rows = [Row {
            a: 1,
            b: Some(2.5e-7),
            c: "outer_arc",
        }];
        let t = Table::from_rows(&["c", "a", "b", "missing"], &rows).unwrap();
        // "        c   a         b  missing": 9 + 2 + 1 + 2 + 8 + 2 + 7 = 31 characters
        assert_eq!(
            t.render_fitted(31).unwrap(),
            t.render(OutputFormat::Table).unwrap()
        );
        let fitted = t.render_fitted(30).unwrap();
        assert_eq!(
            fitted,
            "        c  a         b\nouter_arc  1  2.500e-7\n\
             1 more column (--wide, or --format csv|json):\n  missing\n"
        );
        // the first column is always shown; the note wraps at the width
        let narrow = t.render_fitted(10).unwrap();
        assert!(narrow.starts_with("        c\nouter_arc\n3 more columns"));
        for line in narrow.lines().skip(2) {
            assert!(line.chars().count() <= 50, "{line}");
        }
        assert!(narrow.contains(" a") && narrow.contains(" b") && narrow.contains(" missing"));
    }

    #[test]
    fn every_line_of_a_fitted_table_fits_its_width() {
        let columns: Vec<String> = (0..20).map(|k| format!("column_number_{k}")).collect();
        let names: Vec<&str> = columns.iter().map(String::as_str).collect();
        let row: serde_json::Map<String, Value> = columns
            .iter()
            .map(|c| (c.clone(), Value::from(1.234_567e-5)))
            .collect();
        let t = Table::from_rows(&names, &[Value::Object(row)]).unwrap();
        let text = t.render_fitted(120).unwrap();
        for line in text.lines() {
            assert!(line.chars().count() <= 120, "{} > 120: {line}", line.len());
        }
        let shown = text.lines().next().unwrap().split_whitespace().count();
        assert!((6..20).contains(&shown), "{shown} columns shown");
        assert!(text.contains(&format!("{} more columns", 20 - shown)));
    }
}
