//! Resolution of a campaign file: read it, read and hash every file it references (relative to
//! the campaign file), parse them, and check everything that can be checked before anything
//! runs. Nothing here touches a store, so a bad campaign leaves every database untouched.
//!
//! The stored form ([`ResolvedCampaign::stored_spec`]) is the spec itself plus the sha256 of
//! the campaign file and of every referenced file; its own sha256 identifies the campaign's
//! inputs.

use std::path::{Path, PathBuf};

use moorfret_solver::floater::FloaterSpec;
use moorfret_solver::fretting::HertzModel;
use moorfret_solver::global::case::FloaterSource;
use moorfret_solver::global::CaseSpec;
use moorfret_solver::mooring::spec::LineTypeSpec;
use moorfret_solver::strand::profile::{select_profile, ProfileError};
use moorfret_solver::waves::scatter::{ScatterTable, TotalMismatch};
use serde::Serialize;
use serde_json::Value;
use sha2::{Digest, Sha256};

use crate::error::CampaignError;
use crate::fatigue::interface_geometry;
use crate::payload::{CampaignInputs, FloaterContent, SOLVER_VERSION};
use crate::screening::{self, HotSpots};
use crate::sea_limits::{self, CellLimits};
use crate::sectors::ScatterSource;
use crate::spec::{CampaignSpec, OutsideModel, ScatterReading};
use crate::stiffness::AxialStiffnessRule;
use moorfret_solver::text::Num;

/// A referenced file as read.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ResolvedFile {
    /// Field of the campaign file naming it (`campaign`, `scatter.path`, …).
    pub field: String,
    /// Path as written (relative to the campaign file), or the campaign file's own path.
    pub path: String,
    /// sha256 (hex) of the content.
    pub sha256: String,
}

/// A campaign with every referenced file read, parsed and checked.
#[derive(Debug, Clone)]
pub struct ResolvedCampaign {
    /// Spec and file contents, as workers use them.
    pub inputs: CampaignInputs,
    /// Every file read, the campaign file first.
    pub files: Vec<ResolvedFile>,
    /// The climate's scatter tables in plan order: the campaign's one table, or one per
    /// directional sector ([`crate::sectors`]).
    pub sectors: Vec<ResolvedScatter>,
}

/// One scatter table of a campaign, read and checked.
#[derive(Debug, Clone)]
pub struct ResolvedScatter {
    /// Where it comes from, how it is read and the heading of its sea states.
    pub source: ScatterSource,
    /// The table; cells left out of the plan are zero.
    pub table: ScatterTable,
    /// Printed totals that differ from their cells.
    pub mismatches: Vec<TotalMismatch>,
    /// Cells the wave model cannot carry, left out of the plan (zeroed in `table`) under
    /// `scatter.cells_outside_model = "leave_out"`.
    pub left_out: Vec<LeftOutCell>,
    /// What the wave model makes of every planned sea state, in table order (the energy kept
    /// below the cut-off among it).
    pub planned_limits: Vec<CellLimits>,
}

impl ResolvedCampaign {
    /// Cells left out of the plan, with the table they belong to.
    pub fn left_out(&self) -> impl Iterator<Item = (&ResolvedScatter, &LeftOutCell)> {
        self.sectors
            .iter()
            .flat_map(|s| s.left_out.iter().map(move |c| (s, c)))
    }

    /// What the wave model makes of every planned sea state, in plan order.
    pub fn planned_limits(&self) -> impl Iterator<Item = &CellLimits> {
        self.sectors.iter().flat_map(|s| s.planned_limits.iter())
    }
}

/// A scatter cell left out of the plan.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOutCell {
    /// Row of the Hs bin (from 0).
    pub row: usize,
    /// Period column (from 0).
    pub column: usize,
    /// The cell's value as printed.
    pub value: f64,
    /// Why.
    pub limits: CellLimits,
}

fn read_file(
    base: &Path,
    field: &str,
    relative: &str,
) -> Result<(PathBuf, String, ResolvedFile), CampaignError> {
    let path = base.join(relative);
    let bytes = std::fs::read(&path).map_err(|source| CampaignError::Io {
        field: field.to_owned(),
        path: path.clone(),
        source,
    })?;
    let mut text = String::from_utf8(bytes).map_err(|e| CampaignError::File {
        field: field.to_owned(),
        path: path.clone(),
        message: format!("not UTF-8 text: {e}"),
    })?;
    // A byte-order mark (spreadsheet exports) is not content.
    if text.starts_with('\u{feff}') {
        text.drain(..'\u{feff}'.len_utf8());
    }
    let file = ResolvedFile {
        field: field.to_owned(),
        path: relative.to_owned(),
        sha256: hex::encode(Sha256::digest(text.as_bytes())),
    };
    Ok((path, text, file))
}

fn file_error(field: &str, path: &Path, message: impl ToString) -> CampaignError {
    CampaignError::File {
        field: field.to_owned(),
        path: path.to_owned(),
        message: message.to_string(),
    }
}

/// Checks a scatter diagram as occurrences of sea states: no negative cell, no cell above
/// 100 % of the year, cells that sum to at most 100 % (within the table's rounding), no Tp column
/// twice and no two Hs bins that overlap (either would plan the same sea state twice and count
/// its occurrence twice). Messages name the row, column or value.
pub fn check_scatter(table: &ScatterTable) -> Result<(), String> {
    for c in table.cells() {
        if !(0.0..=100.0).contains(&c.value) {
            return Err(format!(
                "cell Hs {}-{} m, Tp {} s is {}: an occurrence must be from 0 to 100 percent",
                c.hs_lower_m, c.hs_upper_m, c.tp_s, c.value
            ));
        }
    }
    let sum = table.cell_sum();
    if sum > 100.0 + table.rounding_tolerance() {
        return Err(format!(
            "the cells sum to {sum} percent: more than the whole year"
        ));
    }
    for (j, tp) in table.tp_s.iter().enumerate() {
        if let Some(k) = table.tp_s[..j].iter().position(|t| t == tp) {
            return Err(format!(
                "Tp = {tp} s heads columns {} and {} (period columns counted from 1)",
                k + 1,
                j + 1
            ));
        }
    }
    let mut bins: Vec<(f64, f64)> = table.hs_bins_m.clone();
    bins.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in bins.windows(2) {
        if w[1].0 < w[0].1 {
            return Err(format!(
                "Hs bins {}-{} m and {}-{} m overlap",
                w[0].0, w[0].1, w[1].0, w[1].1
            ));
        }
    }
    Ok(())
}

/// Reads, hashes and checks the campaign file at `path` and everything it references.
pub fn resolve(path: &Path) -> Result<ResolvedCampaign, CampaignError> {
    let base = path.parent().unwrap_or(Path::new(""));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (_, text, campaign_file) = read_file(base, "campaign file", &name)?;
    let mut spec = CampaignSpec::from_json_str(&text)?;
    spec.validate()?;
    // the default rule is stored with the campaign (`StrandSpec::axial_stiffness`)
    spec.strand
        .axial_stiffness
        .get_or_insert(AxialStiffnessRule::StrandModel);
    let mut files = vec![campaign_file];

    let mut tables = Vec::new();
    for source in spec.scatter.sources(spec.simulation.heading_deg) {
        let field = source.field.as_str();
        let (path, text, file) = read_file(base, field, &source.path)?;
        files.push(file);
        let table = ScatterTable::parse(&text).map_err(|e| file_error(field, &path, e))?;
        if table.cell_sum() <= 0.0 {
            return Err(file_error(field, &path, "every cell is zero"));
        }
        check_scatter(&table).map_err(|m| file_error(field, &path, m))?;
        tables.push((path, table, source));
    }
    let (case_path, text, file) = read_file(base, "global.case_path", &spec.global.case_path)?;
    files.push(file);
    let base_case = CaseSpec::from_json_str(&text).map_err(|e| {
        // the field path at fault, which the case's own reader does not give
        match crate::spec::from_json_with_path::<CaseSpec>(&text) {
            Err(with_path) if with_path.starts_with("field `") => {
                file_error("global.case_path", &case_path, with_path)
            }
            _ => file_error("global.case_path", &case_path, e),
        }
    })?;
    let relative_to_campaign = |p: &str| -> String {
        Path::new(&spec.global.case_path)
            .parent()
            .unwrap_or(Path::new(""))
            .join(p)
            .to_string_lossy()
            .into_owned()
    };
    let floater = match &base_case.floater {
        FloaterSource::RigidBody { spec_path } => {
            let field = "global.case_path: floater.rigid_body.spec_path";
            let (p, text, file) = read_file(base, field, &relative_to_campaign(spec_path))?;
            files.push(file);
            let f = FloaterSpec::from_json_str(&text).map_err(|e| {
                // the field path at fault, which the floater's own reader does not give
                match crate::spec::from_json_with_path::<FloaterSpec>(&text) {
                    Err(with_path) if with_path.starts_with("field `") => file_error(
                        field,
                        &p,
                        format!("not a valid floater description: {with_path}"),
                    ),
                    _ => file_error(field, &p, e),
                }
            })?;
            FloaterContent::RigidBody(Box::new(f))
        }
        FloaterSource::PrescribedMotion { csv_path } => {
            let field = "global.case_path: floater.prescribed_motion.csv_path";
            let (p, text, file) = read_file(base, field, &relative_to_campaign(csv_path))?;
            files.push(file);
            moorfret_solver::floater::prescribed::PrescribedMotion::from_csv_str(&text)
                .map_err(|e| file_error(field, &p, e))?;
            FloaterContent::PrescribedMotionCsv(text)
        }
    };
    let (profiles_path, text, file) =
        read_file(base, "strand.profiles_path", &spec.strand.profiles_path)?;
    files.push(file);
    let mut profile =
        select_profile(&text, spec.strand.profile.as_deref()).map_err(|e| match e {
            ProfileError::UnknownProfile { name, known } => CampaignError::Invalid {
                field: "strand.profile".into(),
                value: name,
                reason: format!(
                    "is not in {} (it has: {})",
                    spec.strand.profiles_path,
                    known.join(", ")
                ),
            },
            e => file_error("strand.profiles_path", &profiles_path, e),
        })?;
    if let Some(mu) = spec.strand.friction_coefficient {
        profile.friction_coefficient = Some(mu);
    }
    let strand = profile
        .validate()
        .map_err(|e| file_error("strand.profile", &profiles_path, e))?;
    if strand.layers.is_empty() {
        return Err(file_error(
            "strand.profile",
            &profiles_path,
            "the profile has no helical layer: a core alone has no inter-wire contact",
        ));
    }
    // The Hertz geometry of every layer interface must be valid for the fretting indicators.
    for (i, pair) in interface_geometry(&strand).iter().enumerate() {
        HertzModel::crossed_cylinders(pair).map_err(|e| CampaignError::Invalid {
            field: format!("strand.profile.layers[{i}]"),
            value: format!("crossing angle {} rad", pair.crossing_angle_rad),
            reason: format!("gives no Hertz contact with the layer inside it: {e}"),
        })?;
    }

    let mut inputs = CampaignInputs {
        spec,
        base_case,
        floater,
        profile,
        hot_spot_axial_stiffness_n: Vec::new(),
        hot_spot_screening: Vec::new(),
    };
    // listed hot spots are checked at once; `"auto"` ones are found once every cell is checked
    if !inputs.spec.hot_spots.is_auto() {
        set_hot_spots(&mut inputs)?;
    }
    // The base case with the first planned sea state must be a valid case (a fault of the
    // case itself is named there), then every cell is checked.
    for (_, table, source) in &tables {
        let first = table
            .cells()
            .into_iter()
            .find(|c| c.value > 0.0)
            .map(|c| (0.5 * (c.hs_lower_m + c.hs_upper_m), c.tp_s))
            .unwrap_or((1.0, 10.0));
        inputs
            .case_at(first.0, first.1, 1, source.heading_deg)
            .validate()
            .map_err(|e| file_error("global.case_path", &case_path, e))?;
    }
    let mut sectors = Vec::with_capacity(tables.len());
    for (path, table, source) in tables {
        sectors.push(check_cells(&inputs, path, table, source)?);
    }
    check_intervals(&inputs, &sectors)?;
    if inputs.spec.hot_spots.is_auto() {
        let views: Vec<(&ScatterTable, &ScatterSource)> =
            sectors.iter().map(|s| (&s.table, &s.source)).collect();
        let outer_wire_radius_m = strand
            .layers
            .last()
            .map_or(strand.core_wire_radius_m, |l| l.wire_radius_m);
        let found = screening::screen(&inputs, &views, outer_wire_radius_m)?;
        inputs.spec.hot_spots = HotSpots::Listed(found.iter().map(|f| f.hot_spot()).collect());
        // what the screening found is stored in its place
        inputs.spec.hot_spot_screening = None;
        inputs.hot_spot_screening = found;
        set_hot_spots(&mut inputs)?;
    }
    Ok(ResolvedCampaign {
        inputs,
        files,
        sectors,
    })
}

/// Checks every non-zero cell of one table before anything is stored: each must make a valid
/// case, and one the wave model can carry ([`crate::sea_limits`]), else it is refused or, with
/// `scatter.cells_outside_model = "leave_out"`, zeroed in the table and listed.
fn check_cells(
    inputs: &CampaignInputs,
    path: PathBuf,
    mut table: ScatterTable,
    source: ScatterSource,
) -> Result<ResolvedScatter, CampaignError> {
    let field = source.field.as_str();
    let mismatches = table.total_mismatches();
    let mut faults = Vec::new();
    let mut left_out = Vec::new();
    let mut planned = Vec::new();
    for (row, &(lower, upper)) in table.hs_bins_m.iter().enumerate() {
        for (column, &tp_s) in table.tp_s.iter().enumerate() {
            let value = table.values[row][column];
            if value <= 0.0 {
                continue;
            }
            let hs_m = 0.5 * (lower + upper);
            let cell = format!(
                "cell Hs {lower}-{upper} m, Tp {tp_s} s (row {}, period column {})",
                row + 1,
                column + 1
            );
            let limits = sea_limits::check(inputs, hs_m, tp_s)
                .map_err(|e| file_error(field, &path, format!("{cell}: {e}")))?;
            if limits.faults.is_empty() {
                planned.push(limits);
            } else {
                faults.push(format!("{cell}: {}", limits.faults.join("; ")));
                left_out.push(LeftOutCell {
                    row,
                    column,
                    value,
                    limits,
                });
            }
        }
    }
    if !faults.is_empty() && inputs.spec.scatter.cells_outside_model == OutsideModel::Refuse {
        return Err(file_error(
            field,
            &path,
            format!(
                "{} sea state(s) the wave model cannot carry (set \
                 scatter.cells_outside_model to \"leave_out\" to plan without them): {}",
                faults.len(),
                faults.join(" | ")
            ),
        ));
    }
    if planned.is_empty() {
        return Err(file_error(
            field,
            &path,
            format!(
                "no sea state the wave model can carry: {}",
                faults.join(" | ")
            ),
        ));
    }
    for c in &left_out {
        table.values[c.row][c.column] = 0.0;
    }
    Ok(ResolvedScatter {
        source,
        mismatches,
        table,
        left_out,
        planned_limits: planned,
    })
}

/// The output and load intervals must resolve the shortest planned peak period of every table.
fn check_intervals(
    inputs: &CampaignInputs,
    sectors: &[ResolvedScatter],
) -> Result<(), CampaignError> {
    let Some(shortest_tp) = sectors
        .iter()
        .flat_map(|s| s.planned_limits.iter().map(|l| l.tp_s))
        .reduce(f64::min)
    else {
        return Ok(());
    };
    let sim = &inputs.spec.simulation;
    let needed = shortest_tp / sea_limits::MIN_SAMPLES_PER_PEAK_PERIOD;
    for (field, value) in [
        ("simulation.output_interval_s", sim.output_interval_s),
        ("strand.load_interval_s", inputs.spec.strand.load_interval_s),
    ] {
        if value > needed * (1.0 + 1e-9) {
            return Err(CampaignError::Invalid {
                field: field.into(),
                value: Num(value).to_string(),
                reason: format!(
                    "cannot resolve the waves of the shortest planned peak period, Tp {} s: \
                     at most {} s ({} samples per period) is needed",
                    Num(shortest_tp),
                    Num(needed),
                    Num(sea_limits::MIN_SAMPLES_PER_PEAK_PERIOD)
                ),
            });
        }
    }
    Ok(())
}

/// Line type of the segment holding arc length `arc_length_m` (from the fairlead), if any.
pub fn hot_spot_line_type(case: &CaseSpec, arc_length_m: f64) -> Option<&LineTypeSpec> {
    let mut start = 0.0;
    for seg in &case.mooring.segments {
        if arc_length_m <= start + seg.length_m {
            return case.mooring.line_types.get(&seg.line_type);
        }
        start += seg.length_m;
    }
    None
}

/// The (chain, rope) segment names when `arc_length_m` is the end a chain segment shares with
/// a rope segment.
pub(crate) fn junction_with_rope(case: &CaseSpec, arc_length_m: f64) -> Option<(String, String)> {
    let segments = &case.mooring.segments;
    let is_rope = |k: usize| {
        case.mooring
            .line_types
            .get(&segments[k].line_type)
            .is_some_and(|t| t.is_rope())
    };
    let mut end = 0.0;
    for k in 0..segments.len() {
        end += segments[k].length_m;
        if k + 1 < segments.len() && arc_length_m == end && is_rope(k) != is_rope(k + 1) {
            let (chain, rope) = if is_rope(k) { (k + 1, k) } else { (k, k + 1) };
            return Some((segments[chain].name.clone(), segments[rope].name.clone()));
        }
    }
    None
}

/// Arc-length spans of the rope segments, e.g. `30-160 m`.
fn rope_spans(case: &CaseSpec) -> String {
    let mut spans: Vec<(f64, f64)> = Vec::new();
    let mut start = 0.0;
    for seg in &case.mooring.segments {
        let end = start + seg.length_m;
        if case
            .mooring
            .line_types
            .get(&seg.line_type)
            .is_some_and(|t| t.is_rope())
        {
            match spans.last_mut() {
                Some(last) if last.1 == start => last.1 = end,
                _ => spans.push((start, end)),
            }
        }
        start = end;
    }
    if spans.is_empty() {
        return "none".into();
    }
    spans
        .iter()
        .map(|(a, b)| format!("{a}-{b} m"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Puts the campaign's (listed or found) hot spots into its base case, with the EA of each.
fn set_hot_spots(inputs: &mut CampaignInputs) -> Result<(), CampaignError> {
    inputs.base_case.hot_spots = inputs.spec.hot_spots.to_vec();
    inputs.hot_spot_axial_stiffness_n = hot_spot_stiffness(&inputs.spec, &inputs.base_case)?;
    Ok(())
}

/// EA of the segment holding each hot spot; checks the line id, the arc length and that it lies
/// on a rope.
fn hot_spot_stiffness(spec: &CampaignSpec, case: &CaseSpec) -> Result<Vec<f64>, CampaignError> {
    let total: f64 = case.mooring.segments.iter().map(|s| s.length_m).sum();
    let mut out = Vec::with_capacity(spec.hot_spots.len());
    for (i, h) in spec.hot_spots.iter().enumerate() {
        if !case.mooring.lines.iter().any(|l| l.id == h.line) {
            return Err(CampaignError::Invalid {
                field: format!("hot_spots[{i}].line"),
                value: h.line.to_string(),
                reason: "is not a line of the global case".into(),
            });
        }
        if h.arc_length_m > total {
            return Err(CampaignError::Invalid {
                field: format!("hot_spots[{i}].arc_length_m"),
                value: h.arc_length_m.to_string(),
                reason: format!("must not exceed the line length {total} m"),
            });
        }
        let line_type =
            hot_spot_line_type(case, h.arc_length_m).ok_or_else(|| CampaignError::Invalid {
                field: format!("hot_spots[{i}].arc_length_m"),
                value: h.arc_length_m.to_string(),
                reason: "lies on a segment whose line type is not defined".into(),
            })?;
        // The strand model and the rope T-N curves describe a wire rope: a hot spot on a
        // chain (no bending stiffness) would get a rope's fretting and T-N damage.
        if !line_type.is_rope() {
            let reason = match junction_with_rope(case, h.arc_length_m) {
                Some((chain, rope)) => format!(
                    "lies at the junction of chain segment `{chain}` and rope segment `{rope}`, \
                     where the chain's properties hold; a hot spot must lie inside the \
                     spiral-strand rope (ropes: {}, their ends at a chain excluded)",
                    rope_spans(case)
                ),
                None => format!(
                    "lies on a chain segment of the global case (ropes: {}); a hot spot must be \
                     on the spiral-strand rope",
                    rope_spans(case)
                ),
            };
            return Err(CampaignError::Invalid {
                field: format!("hot_spots[{i}].arc_length_m"),
                value: h.arc_length_m.to_string(),
                reason,
            });
        }
        out.push(line_type.axial_stiffness_n);
    }
    Ok(out)
}

impl ResolvedCampaign {
    /// The resolved spec as stored with the campaign, and its sha256. Cells left out of the
    /// plan are kept under `left_out` (only when there are any: the stored form of a campaign
    /// without them is unchanged), so that the report can name them.
    pub fn stored_spec(&self) -> (Value, String) {
        let mut value = serde_json::json!({
            "inputs": self.inputs,
            "files": self.files,
            "solver_version": SOLVER_VERSION,
        });
        let left_out: Vec<Value> = self
            .left_out()
            .map(|(s, c)| {
                let occurrence = match s.source.reading {
                    ScatterReading::JointPercent => c.value / 100.0,
                    ScatterReading::Sector { share_percent } => {
                        c.value / 100.0 * share_percent / 100.0
                    }
                };
                serde_json::json!({
                    "sector": s.source.label,
                    "hs_m": c.limits.hs_m,
                    "tp_s": c.limits.tp_s,
                    "occurrence_fraction": occurrence,
                    "reason": c.limits.faults.join("; "),
                })
            })
            .collect();
        if !left_out.is_empty() {
            value["left_out"] = Value::Array(left_out);
        }
        let text = value.to_string();
        (value, hex::encode(Sha256::digest(text.as_bytes())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> ScatterTable {
        ScatterTable::parse(text).unwrap()
    }

    #[test]
    fn scatter_diagrams_that_double_count_the_year_are_refused() {
        let good = table("lower\tupper\t5\t7\n0\t1\t40\t10\n1\t2\t30\t20\n");
        assert!(check_scatter(&good).is_ok());
        let cases = [
            (
                "lower\tupper\t5\t7\n0\t1\t60\t10\n1\t2\t30\t20.1\n",
                "sum to 120.1",
            ),
            ("lower\tupper\t5\t7\n0\t1\t101\t0\n", "is 101"),
            ("lower\tupper\t5\t5\n0\t1\t1\t2\n", "heads columns 1 and 2"),
            (
                "lower\tupper\t5\t7\n0\t1\t1\t2\n0.5\t1.5\t1\t2\n",
                "overlap",
            ),
            ("lower\tupper\t5\t7\n0\t1\t1\t2\n0\t1\t1\t2\n", "overlap"),
        ];
        for (text, expected) in cases {
            let e = check_scatter(&table(text)).unwrap_err();
            assert!(e.contains(expected), "{text:?}: {e}");
        }
    }
}
