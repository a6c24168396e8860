//! Directional wave climates: the scatter tables of a campaign and the heading each runs at.
//!
//! A campaign gives its sea climate in one of two forms:
//!
//! - one table (`scatter.path`, `scatter.reading`), every sea state at
//!   `simulation.heading_deg`: one wave direction, as the paper's case (its ARGOSS sector
//!   holds 43.758 % of the year);
//! - directional sectors (`scatter.sectors`), each with its label, the model heading its sea
//!   states run at, its share of the year and its table, whose cells are percent within the
//!   sector (they sum to 100). `moorfret scatter` writes such tables from a hindcast or buoy
//!   series. The shares of all sectors sum to at most 100 % of the year.
//!
//! Heading convention: the direction the waves travel towards, in degrees from the model's +x
//! axis towards +y (counter-clockwise seen from above), as `simulation.heading_deg` and the
//! global case's `sea_state.heading_deg`. A sector may also carry the met-ocean direction the
//! waves come from (`direction_from_deg`, clockwise from north), which is free text for the
//! report: only `heading_deg` enters the simulation.
//!
//! Both forms become a list of [`ScatterSource`]s, planned in order: the single table is one
//! source without a label.

use serde::{Deserialize, Serialize};

use crate::error::CampaignError;
use crate::spec::{ScatterReading, ScatterSpec};

/// Largest number of sectors of a campaign.
pub const MAX_SECTORS: usize = 360;

/// One directional sector of a campaign's climate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectorSpec {
    /// Short unique name (`N`, `W`, `sector_270`…), shown in tables and the report.
    pub label: String,
    /// Heading the sector's sea states run at (deg, towards which the waves travel, from +x
    /// towards +y).
    pub heading_deg: f64,
    /// The sector's share of the year (%).
    pub share_percent: f64,
    /// Its scatter table (cells: percent within the sector), relative to the campaign file.
    pub path: String,
    /// Met-ocean direction the sector's waves come from (deg clockwise from north), for the
    /// report only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction_from_deg: Option<f64>,
}

/// One scatter table of a campaign, with how its cells are read and the heading its sea states
/// run at.
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterSource {
    /// The field naming the table (`scatter.path`, `scatter.sectors[2].path`).
    pub field: String,
    /// The table's path, relative to the campaign file.
    pub path: String,
    /// How its cells become occurrence fractions of the year.
    pub reading: ScatterReading,
    /// Heading of its sea states (deg).
    pub heading_deg: f64,
    /// The sector's label; `None` for a campaign of one table.
    pub label: Option<String>,
}

impl ScatterSpec {
    /// The campaign's scatter tables in plan order; `simulation_heading_deg` is the heading of a
    /// single table. Call after [`ScatterSpec::validate`].
    pub fn sources(&self, simulation_heading_deg: f64) -> Vec<ScatterSource> {
        if self.sectors.is_empty() {
            return vec![ScatterSource {
                field: "scatter.path".into(),
                path: self.path.clone().unwrap_or_default(),
                reading: self.reading.unwrap_or(ScatterReading::JointPercent),
                heading_deg: simulation_heading_deg,
                label: None,
            }];
        }
        self.sectors
            .iter()
            .enumerate()
            .map(|(i, s)| ScatterSource {
                field: format!("scatter.sectors[{i}].path"),
                path: s.path.clone(),
                reading: ScatterReading::Sector {
                    share_percent: s.share_percent,
                },
                heading_deg: s.heading_deg,
                label: Some(s.label.clone()),
            })
            .collect()
    }

    /// Checks the form (one table, or sectors) and every sector's values; a sector campaign
    /// must leave `simulation.heading_deg` at 0, its headings being the sectors'.
    pub fn validate(&self, simulation_heading_deg: f64) -> Result<(), CampaignError> {
        if self.sectors.is_empty() {
            if self.path.is_none() {
                return Err(invalid(
                    "scatter.path",
                    "(absent)",
                    "is required, unless the climate is given as scatter.sectors",
                ));
            }
            if self.reading.is_none() {
                return Err(invalid(
                    "scatter.reading",
                    "(absent)",
                    "is required with scatter.path (\"joint_percent\" or {\"sector\": \
                     {\"share_percent\": …}})",
                ));
            }
            if let Some(ScatterReading::Sector { share_percent }) = self.reading {
                share("scatter.reading.sector.share_percent", share_percent)?;
            }
            return Ok(());
        }
        for (field, given) in [
            ("scatter.path", self.path.is_some()),
            ("scatter.reading", self.reading.is_some()),
        ] {
            if given {
                return Err(invalid(
                    field,
                    "(given)",
                    "must be absent with scatter.sectors: each sector names its own table \
                     and share",
                ));
            }
        }
        if simulation_heading_deg != 0.0 {
            return Err(invalid(
                "simulation.heading_deg",
                simulation_heading_deg,
                "must be absent with scatter.sectors: each sector's sea states run at its \
                 heading_deg",
            ));
        }
        if self.sectors.len() > MAX_SECTORS {
            return Err(invalid(
                "scatter.sectors",
                self.sectors.len(),
                &format!("at most {MAX_SECTORS} sectors"),
            ));
        }
        let mut total = 0.0;
        for (i, s) in self.sectors.iter().enumerate() {
            let label_ok = !s.label.is_empty()
                && s.label.len() <= 32
                && s.label
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
            if !label_ok {
                return Err(invalid(
                    format!("scatter.sectors[{i}].label"),
                    &s.label,
                    "must be 1-32 ASCII letters, digits, '-', '_' or '.'",
                ));
            }
            if let Some(j) = self.sectors[..i].iter().position(|o| o.label == s.label) {
                return Err(invalid(
                    format!("scatter.sectors[{i}].label"),
                    &s.label,
                    &format!("is also the label of scatter.sectors[{j}]"),
                ));
            }
            if !s.heading_deg.is_finite() {
                return Err(invalid(
                    format!("scatter.sectors[{i}].heading_deg"),
                    s.heading_deg,
                    "must be a finite angle",
                ));
            }
            if let Some(d) = s.direction_from_deg {
                if !d.is_finite() {
                    return Err(invalid(
                        format!("scatter.sectors[{i}].direction_from_deg"),
                        d,
                        "must be a finite angle",
                    ));
                }
            }
            if s.path.is_empty() {
                return Err(invalid(
                    format!("scatter.sectors[{i}].path"),
                    "\"\"",
                    "must name the sector's scatter table",
                ));
            }
            share(
                &format!("scatter.sectors[{i}].share_percent"),
                s.share_percent,
            )?;
            total += s.share_percent;
        }
        // the shares as printed: a rounding of each share may add up to a little over 100
        if total > 100.0 + 1e-6 * self.sectors.len() as f64 {
            return Err(invalid(
                "scatter.sectors",
                format!("shares summing to {total} %"),
                "the sectors' shares of the year must sum to at most 100 %",
            ));
        }
        Ok(())
    }
}

fn share(field: &str, share_percent: f64) -> Result<(), CampaignError> {
    if share_percent.is_finite() && share_percent > 0.0 && share_percent <= 100.0 {
        Ok(())
    } else {
        Err(invalid(field, share_percent, "must be in (0, 100]"))
    }
}

fn invalid(field: impl Into<String>, value: impl std::fmt::Display, reason: &str) -> CampaignError {
    CampaignError::Invalid {
        field: field.into(),
        value: value.to_string(),
        reason: reason.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::OutsideModel;

    fn sector(label: &str, heading_deg: f64, share_percent: f64) -> SectorSpec {
        SectorSpec {
            label: label.into(),
            heading_deg,
            share_percent,
            path: format!("{label}.tsv"),
            direction_from_deg: None,
        }
    }

    fn sectors(list: Vec<SectorSpec>) -> ScatterSpec {
        ScatterSpec {
            path: None,
            reading: None,
            sectors: list,
            cells_outside_model: OutsideModel::Refuse,
        }
    }

    #[test]
    fn one_table_is_one_source_at_the_simulation_heading() {
        let spec = ScatterSpec {
            path: Some("t.tsv".into()),
            reading: Some(ScatterReading::JointPercent),
            sectors: Vec::new(),
            cells_outside_model: OutsideModel::Refuse,
        };
        spec.validate(30.0).unwrap();
        let sources = spec.sources(30.0);
        assert_eq!(sources.len(), 1);
        assert_eq!(sources[0].field, "scatter.path");
        assert_eq!(sources[0].heading_deg, 30.0);
        assert_eq!(sources[0].label, None);
    }

    #[test]
    fn sectors_become_sources_read_as_sector_percent_at_their_headings() {
        let spec = sectors(vec![sector("W", 0.0, 43.758), sector("NW", 315.0, 56.242)]);
        spec.validate(0.0).unwrap();
        let sources = spec.sources(0.0);
        assert_eq!(sources.len(), 2);
        assert_eq!(sources[1].field, "scatter.sectors[1].path");
        assert_eq!(sources[1].heading_deg, 315.0);
        assert_eq!(sources[1].label.as_deref(), Some("NW"));
        assert_eq!(
            sources[0].reading,
            ScatterReading::Sector {
                share_percent: 43.758
            }
        );
    }

    #[test]
    fn bad_sector_climates_are_refused_naming_the_field() {
        let cases: Vec<(ScatterSpec, f64, &str)> = vec![
            (
                sectors(vec![sector("W", 0.0, 60.0), sector("W", 90.0, 10.0)]),
                0.0,
                "scatter.sectors[1].label",
            ),
            (
                sectors(vec![sector("W", 0.0, 60.0), sector("E", 90.0, 50.0)]),
                0.0,
                "sum to at most 100",
            ),
            (
                sectors(vec![sector("W", 0.0, 0.0)]),
                0.0,
                "scatter.sectors[0].share_percent",
            ),
            (
                sectors(vec![sector("W", f64::NAN, 10.0)]),
                0.0,
                "scatter.sectors[0].heading_deg",
            ),
            (
                sectors(vec![sector("W E", 0.0, 10.0)]),
                0.0,
                "scatter.sectors[0].label",
            ),
            (
                sectors(vec![sector("W", 0.0, 10.0)]),
                45.0,
                "simulation.heading_deg",
            ),
            (sectors(Vec::new()), 0.0, "scatter.path"),
        ];
        for (spec, heading, expected) in cases {
            let e = spec.validate(heading).unwrap_err().to_string();
            assert!(e.contains(expected), "{e} should name {expected}");
        }
        let mut both = sectors(vec![sector("W", 0.0, 10.0)]);
        both.path = Some("t.tsv".into());
        let e = both.validate(0.0).unwrap_err().to_string();
        assert!(e.contains("scatter.path") && e.contains("absent"), "{e}");
    }
}
