//! Hot spots found by a screening run (`"hot_spots": "auto"`, `docs/design-check.md`).
//!
//! On every line the hot spot is the rope node of the largest tension-bending proxy over a
//! screening run of each sector's severest sea states. Per node, from the envelope of each
//! screening run j (extremes after the transient):
//!
//! ```text
//! Δε_j = ΔT_j / EA + r_w Δκ_j
//! ε_eq = ( Σ_j w_j Δε_j^m / Σ_j w_j )^(1/m),   m = 4.8
//! ```
//!
//! ΔT and Δκ are the node's tension and curvature ranges, EA the axial stiffness of the node's
//! line type, r_w the radius of the strand's outer wires (the wire's own bending strain), w_j
//! the share of the year of run j's sector divided among its screened sea states, and m the
//! inverse slope of the spiral-rope T-N curve of DNV-OS-E301 (`moorfret_solver::fatigue::tn`).
//! ε_eq is an equivalent strain range: a ranking of positions along a line and between lines,
//! not a damage. Chain segments and the rope ends at a chain (where the chain's properties
//! hold) are excluded. The screening is deterministic (fixed seed), so a campaign resolved
//! twice finds the same hot spots and keeps its cache keys.

use moorfret_solver::floater::prescribed::PrescribedMotion;
use moorfret_solver::global::case::{CaseSpec, HotSpotSpec};
use moorfret_solver::global::{run, FloaterInput, GlobalModel, GlobalResult, RunParams};
use moorfret_solver::mooring::hotspot::Envelope;
use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::error::CampaignError;
use crate::payload::{CampaignInputs, FloaterContent};
use crate::resolve::{hot_spot_line_type, junction_with_rope};
use crate::sea_limits;
use crate::sectors::ScatterSource;
use crate::spec::ScatterReading;
use moorfret_solver::waves::scatter::ScatterTable;

/// Inverse slope of the spiral-rope T-N curve (DNV-OS-E301), the proxy's exponent.
pub const PROXY_EXPONENT: f64 = 4.8;

/// A campaign's hot spots: listed by hand, or found by screening.
#[derive(Debug, Clone, PartialEq)]
pub enum HotSpots {
    /// Listed (a campaign's hot spots once resolved, whether listed or found).
    Listed(Vec<HotSpotSpec>),
    /// `"auto"`: to be found by [`screen`] when the campaign is resolved.
    Auto,
}

impl HotSpots {
    /// Whether the hot spots are still to be found.
    pub fn is_auto(&self) -> bool {
        matches!(self, Self::Auto)
    }
}

impl std::ops::Deref for HotSpots {
    type Target = [HotSpotSpec];

    /// The listed hot spots; none before an `"auto"` campaign is resolved.
    fn deref(&self) -> &[HotSpotSpec] {
        match self {
            Self::Listed(v) => v,
            Self::Auto => &[],
        }
    }
}

impl Serialize for HotSpots {
    /// A list as the campaign file has it (so a listed campaign keeps its cache keys), or
    /// `"auto"`.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Listed(v) => v.serialize(s),
            Self::Auto => s.serialize_str("auto"),
        }
    }
}

impl<'de> Deserialize<'de> for HotSpots {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct HotSpotsVisitor;
        impl<'de> Visitor<'de> for HotSpotsVisitor {
            type Value = HotSpots;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a list of hot spots ({\"line\": 1, \"arc_length_m\": 79}) or \"auto\"")
            }

            fn visit_str<E: de::Error>(self, v: &str) -> Result<HotSpots, E> {
                if v == "auto" {
                    Ok(HotSpots::Auto)
                } else {
                    Err(E::invalid_value(de::Unexpected::Str(v), &self))
                }
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<HotSpots, A::Error> {
                let mut v = Vec::with_capacity(seq.size_hint().unwrap_or(0));
                while let Some(h) = seq.next_element::<HotSpotSpec>()? {
                    v.push(h);
                }
                Ok(HotSpots::Listed(v))
            }
        }
        d.deserialize_any(HotSpotsVisitor)
    }
}

/// Settings of the screening run of `"hot_spots": "auto"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScreeningSpec {
    /// Sea states screened per sector (or per table): those of largest Hs, the most frequent
    /// first among equal Hs.
    #[serde(default = "one")]
    pub sea_states_per_sector: usize,
    /// Recorded duration of a screening run (s); by default the campaign's
    /// `simulation.duration_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

fn one() -> usize {
    1
}

impl Default for ScreeningSpec {
    fn default() -> Self {
        Self {
            sea_states_per_sector: 1,
            duration_s: None,
        }
    }
}

/// Most sea states a sector's screening may run.
pub const MAX_SCREENED_PER_SECTOR: usize = 16;

/// A hot spot found by the screening: where, its proxy and what set it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScreenedHotSpot {
    /// Line id.
    pub line: u32,
    /// Arc length from the fairlead (m): the rope node of the largest proxy.
    pub arc_length_m: f64,
    /// Equivalent strain range ε_eq there (module docs).
    pub equivalent_strain_range: f64,
    /// The screened sea state of the largest weighted contribution there: its sector (label,
    /// or `None` for a campaign of one table), Hs (m), Tp (s).
    pub governing_sector: Option<String>,
    /// Hs of the governing screened sea state (m).
    pub governing_hs_m: f64,
    /// Tp of the governing screened sea state (s).
    pub governing_tp_s: f64,
}

impl ScreenedHotSpot {
    /// The hot spot as a campaign lists it.
    pub fn hot_spot(&self) -> HotSpotSpec {
        HotSpotSpec {
            line: self.line,
            arc_length_m: self.arc_length_m,
        }
    }
}

/// One screening run: a sea state of a sector and its weight.
#[derive(Debug, Clone)]
struct ScreeningRun {
    sector: Option<String>,
    heading_deg: f64,
    hs_m: f64,
    tp_s: f64,
    weight: f64,
}

/// The screening runs of `tables` (each with its source): per table the `per_sector` planned
/// cells of largest Hs (the most frequent first among equal Hs), each weighing its sector's
/// share of the year divided among them.
fn screening_runs(
    inputs: &CampaignInputs,
    tables: &[(&ScatterTable, &ScatterSource)],
    per_sector: usize,
) -> Vec<ScreeningRun> {
    let mut runs = Vec::new();
    for (table, source) in tables {
        let share = match source.reading {
            ScatterReading::Sector { share_percent } => share_percent / 100.0,
            _ => 1.0,
        };
        let mut cells: Vec<(f64, f64, f64)> = table
            .cells()
            .into_iter()
            .filter(|c| c.value > 0.0)
            .map(|c| (0.5 * (c.hs_lower_m + c.hs_upper_m), c.tp_s, c.value))
            .filter(|&(hs, tp, _)| {
                sea_limits::check(inputs, hs, tp).is_ok_and(|l| l.faults.is_empty())
            })
            .collect();
        cells.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.2.total_cmp(&a.2)));
        cells.truncate(per_sector);
        let n = cells.len() as f64;
        for (hs_m, tp_s, _) in cells {
            runs.push(ScreeningRun {
                sector: source.label.clone(),
                heading_deg: source.heading_deg,
                hs_m,
                tp_s,
                weight: share / n,
            });
        }
    }
    runs
}

/// The global case of one screening run (the campaign's seed, the screening's duration).
fn screening_case(inputs: &CampaignInputs, run: &ScreeningRun, duration_s: f64) -> CaseSpec {
    let mut case = inputs.case_at(run.hs_m, run.tp_s, inputs.spec.seed, run.heading_deg);
    case.name = format!(
        "{}_screening_hs{}_tp{}",
        inputs.spec.name, run.hs_m, run.tp_s
    );
    case.timing.duration_s = duration_s;
    case.hot_spots.clear();
    case
}

/// Runs one screening case.
fn run_screening_case(inputs: &CampaignInputs, case: &CaseSpec) -> Result<GlobalResult, String> {
    let floater = match &inputs.floater {
        FloaterContent::RigidBody(spec) => FloaterInput::RigidBody(spec.clone()),
        FloaterContent::PrescribedMotionCsv(text) => FloaterInput::Prescribed(
            PrescribedMotion::from_csv_str(text).map_err(|e| e.to_string())?,
        ),
    };
    let model = GlobalModel::new(case, floater, None).map_err(|e| e.to_string())?;
    let result = run(&model, &RunParams::default(), |_, _| {}).map_err(|e| e.to_string())?;
    result.check_finite().map_err(|e| e.to_string())?;
    Ok(result)
}

/// Per line, the rope node of the largest ε_eq over the screening runs: `envelopes[j]` holds
/// each line's id and envelope in run `runs[j]` (lines in the same order in every run);
/// `outer_wire_radius_m` is r_w.
fn hot_spots_of(
    case: &CaseSpec,
    runs: &[ScreeningRun],
    envelopes: &[Vec<(u32, &Envelope)>],
    outer_wire_radius_m: f64,
) -> Vec<ScreenedHotSpot> {
    let total_weight: f64 = runs.iter().map(|r| r.weight).sum();
    let mut found = Vec::new();
    let Some(first) = envelopes.first() else {
        return found;
    };
    for (k, &(line, envelope)) in first.iter().enumerate() {
        let mut best: Option<ScreenedHotSpot> = None;
        for (i, &s) in envelope.arc_length_m.iter().enumerate() {
            let Some(line_type) = hot_spot_line_type(case, s) else {
                continue;
            };
            if !line_type.is_rope() || junction_with_rope(case, segment_end_near(case, s)).is_some()
            {
                continue;
            }
            let mut sum = 0.0;
            let mut governing = (f64::NEG_INFINITY, 0usize);
            for (j, (r, lines)) in runs.iter().zip(envelopes).enumerate() {
                let e = lines[k].1;
                let range = (e.tension_max_n[i] - e.tension_min_n[i]) / line_type.axial_stiffness_n
                    + outer_wire_radius_m * (e.curvature_max_per_m[i] - e.curvature_min_per_m[i]);
                let term = r.weight * range.max(0.0).powf(PROXY_EXPONENT);
                if term > governing.0 {
                    governing = (term, j);
                }
                sum += term;
            }
            let eq = (sum / total_weight).powf(1.0 / PROXY_EXPONENT);
            if !eq.is_finite() {
                continue;
            }
            if best.as_ref().is_none_or(|b| eq > b.equivalent_strain_range) {
                let g = &runs[governing.1];
                best = Some(ScreenedHotSpot {
                    line,
                    arc_length_m: s,
                    equivalent_strain_range: eq,
                    governing_sector: g.sector.clone(),
                    governing_hs_m: g.hs_m,
                    governing_tp_s: g.tp_s,
                });
            }
        }
        found.extend(best);
    }
    found
}

/// The end of a segment within a micrometre of `arc_length_m` (a node the mesh put at a
/// junction by summing segment lengths in its own order), else `arc_length_m` itself.
fn segment_end_near(case: &CaseSpec, arc_length_m: f64) -> f64 {
    let mut end = 0.0;
    for seg in &case.mooring.segments {
        end += seg.length_m;
        if (arc_length_m - end).abs() < 1e-6 {
            return end;
        }
    }
    arc_length_m
}

/// Finds a hot spot on every line of `inputs`' global case that has a rope (module docs),
/// running the screening cases on up to the cores this process may use.
pub fn screen(
    inputs: &CampaignInputs,
    tables: &[(&ScatterTable, &ScatterSource)],
    outer_wire_radius_m: f64,
) -> Result<Vec<ScreenedHotSpot>, CampaignError> {
    let settings = inputs.spec.hot_spot_screening.clone().unwrap_or_default();
    let duration_s = settings
        .duration_s
        .unwrap_or(inputs.spec.simulation.duration_s);
    let runs = screening_runs(inputs, tables, settings.sea_states_per_sector);
    let failed = |reason: String| CampaignError::Invalid {
        field: "hot_spots".into(),
        value: "auto".into(),
        reason,
    };
    if runs.iter().map(|r| r.weight).sum::<f64>() <= 0.0 {
        return Err(failed(
            "no planned sea state with a share of the year to screen".into(),
        ));
    }
    let cases: Vec<CaseSpec> = runs
        .iter()
        .map(|r| screening_case(inputs, r, duration_s))
        .collect();
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(cases.len());
    tracing::info!(
        runs = cases.len(),
        duration_s,
        threads,
        "screening every line for its hot spot"
    );
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut results: Vec<Option<Result<GlobalResult, String>>> =
        (0..cases.len()).map(|_| None).collect();
    let slots = std::sync::Mutex::new(&mut results);
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| loop {
                let j = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(case) = cases.get(j) else {
                    break;
                };
                let result = run_screening_case(inputs, case);
                slots.lock().unwrap_or_else(|e| e.into_inner())[j] = Some(result);
            });
        }
    });
    let mut done = Vec::with_capacity(results.len());
    for (r, result) in runs.iter().zip(results) {
        match result {
            Some(Ok(result)) => done.push(result),
            Some(Err(e)) => {
                return Err(failed(format!(
                    "the screening run of Hs {} m, Tp {} s at {}° failed: {e}",
                    r.hs_m, r.tp_s, r.heading_deg
                )))
            }
            None => return Err(failed("a screening run did not run".into())),
        }
    }
    let envelopes: Vec<Vec<(u32, &Envelope)>> = done
        .iter()
        .map(|r| r.lines.iter().map(|l| (l.id, &l.envelope)).collect())
        .collect();
    let found = hot_spots_of(&cases[0], &runs, &envelopes, outer_wire_radius_m);
    if found.is_empty() {
        return Err(failed(
            "no line of the global case has a rope segment".into(),
        ));
    }
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hot_spots_read_as_a_list_or_auto_and_a_list_writes_back_unchanged() {
        let text = r#"[{"line":1,"arc_length_m":79.0},{"line":2,"arc_length_m":80.5}]"#;
        let listed: HotSpots = serde_json::from_str(text).unwrap();
        assert_eq!(listed.len(), 2);
        assert_eq!((listed[1].line, listed[1].arc_length_m), (2, 80.5));
        // the stored form (and with it every cache key) is the list as before
        assert_eq!(serde_json::to_string(&listed).unwrap(), text);
        let auto: HotSpots = serde_json::from_str(r#""auto""#).unwrap();
        assert!(auto.is_auto() && auto.is_empty());
        assert_eq!(serde_json::to_string(&auto).unwrap(), r#""auto""#);
        for bad in [r#""automatic""#, "7", r#"{"line":1}"#] {
            let e = serde_json::from_str::<HotSpots>(bad)
                .unwrap_err()
                .to_string();
            assert!(e.contains("or \"auto\""), "{bad}: {e}");
        }
        // a listed hot spot's own fields are still checked
        let e = serde_json::from_str::<HotSpots>(r#"[{"line":1,"arc":3}]"#).unwrap_err();
        assert!(e.to_string().contains("unknown field `arc`"), "{e}");
    }

    /// The paper's case: each line a chain from 0 to 30 m, then the rope.
    fn paper_case() -> CaseSpec {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../campaigns/paper_case.json");
        CaseSpec::from_json_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    fn envelope(s: &[f64], dt_n: &[f64], dk_per_m: &[f64]) -> Envelope {
        Envelope {
            arc_length_m: s.to_vec(),
            tension_min_n: vec![1.0e6; s.len()],
            tension_max_n: dt_n.iter().map(|d| 1.0e6 + d).collect(),
            curvature_min_per_m: vec![0.01; s.len()],
            curvature_max_per_m: dk_per_m.iter().map(|d| 0.01 + d).collect(),
        }
    }

    #[test]
    fn the_hot_spot_is_the_rope_node_of_the_largest_equivalent_strain_range() {
        let case = paper_case();
        let rope = hot_spot_line_type(&case, 79.0).unwrap();
        assert!(rope.is_rope() && !hot_spot_line_type(&case, 10.0).unwrap().is_rope());
        let ea = rope.axial_stiffness_n;
        let r_w = 2.5e-3;
        // nodes: on the chain, at the chain-rope junction, three on the rope; the chain and
        // the junction have the largest ranges but are not rope
        let s = [10.0, 30.0, 50.0, 79.0, 120.0];
        let severe = envelope(&s, &[9e6, 9e6, 2e5, 1e5, 1e5], &[0.5, 0.5, 0.001, 0.2, 0.0]);
        let mild = envelope(
            &s,
            &[9e6, 9e6, 1e5, 0.5e5, 0.2e5],
            &[0.5, 0.5, 0.0, 0.03, 0.0],
        );
        let run = |hs_m: f64, weight: f64| ScreeningRun {
            sector: Some("S0".into()),
            heading_deg: 0.0,
            hs_m,
            tp_s: 12.0,
            weight,
        };
        let runs = [run(8.0, 0.3), run(3.0, 0.1)];
        let envelopes = vec![vec![(1, &severe)], vec![(1, &mild)]];
        let found = hot_spots_of(&case, &runs, &envelopes, r_w);
        assert_eq!(found.len(), 1);
        let strain = |dt: f64, dk: f64| dt / ea + r_w * dk;
        let eq = |a: f64, b: f64| ((0.3 * a.powf(4.8) + 0.1 * b.powf(4.8)) / 0.4).powf(1.0 / 4.8);
        let expected: Vec<f64> = [
            (2e5, 0.001, 1e5, 0.0),
            (1e5, 0.2, 0.5e5, 0.03),
            (1e5, 0.0, 0.2e5, 0.0),
        ]
        .iter()
        .map(|&(t1, k1, t2, k2)| eq(strain(t1, k1), strain(t2, k2)))
        .collect();
        // the largest of the three rope nodes, by the formula written out
        let (at, largest) =
            expected
                .iter()
                .enumerate()
                .fold((0, 0.0), |b, (i, &v)| if v > b.1 { (i, v) } else { b });
        assert_eq!(found[0].arc_length_m, s[2 + at]);
        assert!((found[0].equivalent_strain_range / largest - 1.0).abs() < 1e-12);
        assert_eq!(found[0].arc_length_m, 79.0, "the bending node wins here");
        // the severe run contributes most there: 0.3 × (1e5/EA + r_w 0.2)^m against
        // 0.1 × (0.5e5/EA + r_w 0.03)^m
        assert_eq!(found[0].governing_hs_m, 8.0);
        // the mild run alone: ε_eq is its strain range, largest where its tension range is
        let one = hot_spots_of(&case, &runs[1..], &envelopes[1..], r_w);
        assert_eq!(one[0].arc_length_m, 50.0);
        assert!((one[0].equivalent_strain_range / strain(1e5, 0.0) - 1.0).abs() < 1e-12);
    }
}
