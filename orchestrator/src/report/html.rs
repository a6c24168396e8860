//! The HTML page: inline SVG and tables, no scripts and no external resources.

use std::fmt::Write;

use super::data::{select_columns, CriticalClass, ReportData};
use super::plots;
use crate::query::significant as number;
use crate::query::Table;

/// Escapes text for HTML.
pub(crate) fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn cell(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Null => String::new(),
        serde_json::Value::String(s) => escape(s),
        serde_json::Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() => number(x),
            _ => n.to_string(),
        },
        other => escape(&other.to_string()),
    }
}

fn table_html(table: &Table) -> String {
    if table.rows.is_empty() {
        return "<p class=\"empty\">No rows stored yet.</p>\n".into();
    }
    let mut out = String::from("<table>\n<tr>");
    for c in &table.columns {
        // long snake_case names may break after their underscores
        let _ = write!(out, "<th>{}</th>", escape(c).replace('_', "_<wbr>"));
    }
    out += "</tr>\n";
    for row in &table.rows {
        out += "<tr>";
        for v in row {
            let _ = write!(out, "<td>{}</td>", cell(v));
        }
        out += "</tr>\n";
    }
    out + "</table>\n"
}

/// The hot spots a screening run found, one per line, with their proxy and what set it.
fn screening_html(
    found: &[moorfret_campaign::screening::ScreenedHotSpot],
) -> anyhow::Result<String> {
    let mut body = String::from(
        "<h3>Hot spots found by screening</h3>\n<p>On each line the rope node of the largest \
         equivalent strain range ε<sub>eq</sub> = (Σ w Δε<sup>4.8</sup> / Σ w)<sup>1/4.8</sup> \
         over screening runs of each sector's severest sea states (Δε = ΔT/EA + r<sub>w</sub> \
         Δκ, w the sector's share of the year): a ranking of positions, not a damage.</p>\n",
    );
    let table = Table::from_rows(
        &[
            "line",
            "arc_length_m",
            "equivalent_strain_range",
            "governing_sector",
            "governing_hs_m",
            "governing_tp_s",
        ],
        found,
    )?;
    body += &table_html(&table);
    Ok(body)
}

/// The design check: pass or fail per line with what governs it, the damage by direction of
/// each line's governing figure, and the design figures per hot spot.
fn design_section(data: &ReportData) -> anyhow::Result<String> {
    let mut body = String::from("<h2>Design check</h2>\n");
    let Some(d) = &data.design else {
        body += "<p class=\"empty\">The campaign is stored without its inputs: no design \
                 check.</p>\n";
        return Ok(body);
    };
    let _ = writeln!(
        body,
        "<p>Utilisation u = γ<sub>F</sub> · D<sub>year</sub> · T<sub>design</sub> with design \
         fatigue factor γ<sub>F</sub> = {} and design life {} years; a line passes when every \
         design figure of its hot spots (the fretting law on the most damaged contact of every \
         class, <code>fretting_max</code>, and the rope T-N curves of the tension) has u ≤ 1 \
         over the whole year. The climate covers {:.1} % of the year: a figure on less of it can \
         fail but not pass (INCOMPLETE).</p>",
        number(d.design_fatigue_factor),
        number(d.design_life_years),
        100.0 * d.year_planned
    );
    if !d.screening.is_empty() {
        body += &screening_html(&d.screening)?;
    }
    if !d.mild_seas.is_empty() {
        body += "<h3>Mild sea states skipped</h3>\n<p>Per hot spot, the first-seed sea states of \
                 the smallest fibre-strain measure x = σ<sub>T</sub>/EA + (D/2) σ<sub>κ</sub> \
                 whose tension-bending proxy w x<sup>4.8</sup>/T<sub>p</sub> together stays \
                 within <code>strand.skip_mild_share</code> of the hot spot's were not run \
                 through the strand model. For any damage growing with x at least as fast as \
                 x<sup>4.8</sup>, they hold at most the share q of the hot spot's damage: its \
                 strand figures are charged by 1/(1 − q) and count their year as covered.</p>\n";
        body += &table_html(&Table::from_rows(
            &[
                "hot_spot_index",
                "sea_states",
                "year_share",
                "proxy_share",
                "damage_factor",
            ],
            &d.mild_seas,
        )?);
    }
    if d.lines.is_empty() {
        body += "<p class=\"empty\">No damage figure stored yet.</p>\n";
        return Ok(body);
    }
    let verdicts: Vec<String> = d
        .lines
        .iter()
        .map(|l| {
            let class = match l.verdict {
                moorfret_campaign::design::Verdict::Pass => "pass",
                moorfret_campaign::design::Verdict::Fail => "fail",
                moorfret_campaign::design::Verdict::Incomplete => "incomplete",
            };
            format!(
                "<span class=\"verdict {class}\">line {}: {} (u = {})</span>",
                l.line,
                l.verdict.as_str(),
                number(l.utilisation)
            )
        })
        .collect();
    let _ = writeln!(body, "<p>{}</p>", verdicts.join(" "));
    body += "<h3>Governing figure and sea state of each line</h3>\n<p>Per line: the design \
             figure of largest utilisation, and the sector and sea state contributing most to \
             its annual damage (sea_state_share: that sea state's share of it).</p>\n";
    body += &table_html(&crate::query::lines_table(d)?);
    if d.sectors.iter().any(|s| s.sector != "all") {
        body += "<h3>Damage by wave direction of each line's governing figure</h3>\n";
        body += "<p>Each wedge is a sector at the heading its waves travel towards (model \
                 frame, counter-clockwise from +x); its length is the sector's annual damage \
                 on a log scale over four decades below the line's largest, its colour the \
                 sector's share of the line's annual damage.</p>\n";
        body += &plots::direction_roses_svg(&d.sectors)?;
    }
    let design_figures = Table::from_rows(
        &[
            "line",
            "hot_spot_index",
            "arc_length_m",
            "measure",
            "class",
            "annual_damage",
            "life_years",
            "utilisation",
            "year_covered",
            "verdict",
        ],
        &d.figures
            .iter()
            .filter(|f| f.check == "design")
            .collect::<Vec<_>>(),
    )?;
    body += "<h3>Design figures per hot spot, largest utilisation first</h3>\n";
    body += &table_html(&design_figures);
    Ok(body)
}

/// One scatter map per directional sector: occurrence, and the share of the critical class's
/// annual fretting damage where it is stored, each on a logarithmic colour scale shared by the
/// sectors; failed and skipped sea states crossed out.
fn sector_maps_section(
    data: &ReportData,
    occurrence: &std::collections::BTreeMap<i64, f64>,
) -> anyhow::Result<String> {
    if !data.sea_states.iter().any(|s| s.sector.is_some()) {
        return Ok(String::new());
    }
    let crossed: std::collections::BTreeSet<i64> = data
        .unfinished
        .iter()
        .filter(|u| u.status != "not run yet")
        .filter_map(|u| u.sea_state_index)
        .collect();
    let mut body = String::from(
        "<h3>Scatter diagram per wave sector</h3>\n<p>Every cell is a planned sea state of \
         the sector, coloured on a logarithmic scale shared by all sectors; failed and skipped \
         sea states are crossed out, grey cells have no value.</p>\n",
    );
    let percent = |v: f64| format!("{}%", plots::tick_text(v));
    for (_, svg) in plots::sector_maps_svg(
        &data.sea_states,
        occurrence,
        "occurrence (% of the year)",
        &crossed,
        &percent,
    )? {
        body += "<div class=\"fig map sector-map occurrence\">";
        body += &svg;
        body += "</div>\n";
    }
    if !data.fretting_share.is_empty() {
        let share: std::collections::BTreeMap<i64, f64> = data
            .fretting_share
            .iter()
            .map(|(&k, &v)| (k, 100.0 * v))
            .collect();
        for (_, svg) in plots::sector_maps_svg(
            &data.sea_states,
            &share,
            "% of the annual fretting damage",
            &crossed,
            &percent,
        )? {
            body += "<div class=\"fig map sector-map damage\">";
            body += &svg;
            body += "</div>\n";
        }
    }
    Ok(body)
}

/// The sea states of the climate without results: failed, skipped (left out of the plan or
/// cancelled) and not run yet, with why.
fn unfinished_section(data: &ReportData) -> String {
    let mut body = String::from("<h3>Failed or skipped sea states</h3>\n");
    if data.unfinished.is_empty() {
        body += "<p>Every sea state of the climate has its results.</p>\n";
        return body;
    }
    let share: f64 = data.unfinished.iter().map(|u| u.occurrence_fraction).sum();
    let _ = writeln!(
        body,
        "<p>{} sea state(s), {:.3} % of the year, without results: their damage is not in the \
         lifetime sums.</p>",
        data.unfinished.len(),
        100.0 * share
    );
    body += "<table class=\"unfinished\">\n<tr><th>status</th><th>sector</th><th>sea state</th>\
             <th>Hs (m)</th><th>Tp (s)</th><th>occurrence (% of the year)</th><th>reason</th>\
             </tr>\n";
    for u in &data.unfinished {
        let _ = writeln!(
            body,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td style=\"text-align: left\">{}</td></tr>",
            u.status,
            escape(u.sector.as_deref().unwrap_or("–")),
            u.sea_state_index
                .map_or_else(|| "not planned".to_owned(), |i| i.to_string()),
            number(u.hs_m),
            number(u.tp_s),
            number(100.0 * u.occurrence_fraction),
            escape(&u.reason)
        );
    }
    body + "</table>\n"
}

/// The run-in per sea state: where the slip monitors stopped drifting, on the scatter diagram.
fn run_in_section(data: &ReportData) -> anyhow::Result<String> {
    let mut body = String::from("<h2>Run-in per sea state</h2>\n");
    if data.run_in.is_empty() {
        body += "<p class=\"empty\">No strand results stored yet.</p>\n";
        return Ok(body);
    }
    let mut detected: Vec<f64> = data.run_in.values().filter_map(|r| r.0).collect();
    detected.sort_by(f64::total_cmp);
    let unstable = data.run_in.len() - detected.len();
    let excluded: Vec<f64> = data.run_in.values().map(|r| r.1).collect();
    let _ = write!(
        body,
        "<p>Detected where the mean of every slip monitor stops drifting: in {} of {} sea \
         states",
        detected.len(),
        data.run_in.len()
    );
    if let (Some(first), Some(last)) = (detected.first(), detected.last()) {
        let median = detected[detected.len() / 2];
        let _ = write!(
            body,
            " (from {} s to {} s, median {} s)",
            number(*first),
            number(*last),
            number(median)
        );
    }
    let _ = write!(
        body,
        "; {unstable} never stabilised or were too short to tell (grey)."
    );
    if excluded.windows(2).all(|w| w[0] == w[1]) {
        let _ = write!(
            body,
            " The statistics leave out the first {} s of every history.",
            number(excluded[0])
        );
    } else {
        body += " The statistics leave out each history's detected run-in, and nothing where \
                 none was detected.";
    }
    body += "</p>\n<div class=\"fig map\">";
    let values: std::collections::BTreeMap<i64, f64> = data
        .run_in
        .iter()
        .filter_map(|(&k, r)| r.0.map(|v| (k, v)))
        .collect();
    let label = |v: f64| Some(format!("{v:.0}"));
    let tick = |v: f64| format!("{} s", plots::tick_text(v));
    body += &plots::value_map_svg(
        &data.sea_states,
        &values,
        "detected run-in (s)",
        &data.fidelity,
        &label,
        &tick,
    )?;
    body += "</div>\n";
    Ok(body)
}

/// The strand fidelity of the results: how many sea states ran which model, the calibrations,
/// and the reduced-versus-FE comparison where both ran.
fn class_lives_section(data: &ReportData) -> String {
    if data.class_lives.is_empty() {
        return String::new();
    }
    let mut body = String::from(
        "<h3>Life of the most damaged contact per class, both fretting laws</h3>\n\
         <table><tr><th>hot spot</th><th>interface</th><th>position</th>\
         <th>life, campaign law (years)</th><th>life, rope S-N per slip cycle (years)</th>\
         <th>ratio</th><th>regime of most cycles</th><th>stick / partial / gross slip \
         cycles per hour</th></tr>\n",
    );
    let life = |d: f64| {
        if d > 0.0 {
            format!("{:.3e}", 1.0 / d)
        } else {
            "∞".to_owned()
        }
    };
    for c in &data.class_lives {
        let ratio = if c.annual_damage > 0.0 && c.rope_tn_annual_damage > 0.0 {
            format!("{:.3}", c.rope_tn_annual_damage / c.annual_damage)
        } else {
            "–".to_owned()
        };
        let [s, p, g] = c.regime_cycles_per_hour;
        body += &format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{:.3e} / {:.3e} / {:.3e}</td></tr>\n",
            c.hot_spot_index,
            c.layer_interface,
            c.angular_position.as_str(),
            life(c.annual_damage),
            life(c.rope_tn_annual_damage),
            ratio,
            c.dominant_regime(),
            s,
            p,
            g
        );
    }
    body + "</table>\n"
}

fn fidelity_section(data: &ReportData) -> String {
    let mut body = String::from("<h2>Strand fidelity</h2>\n");
    let count = |f: &str| data.fidelity.values().filter(|v| v.as_str() == f).count();
    let _ = writeln!(
        body,
        "<p>Counted strand results: {} sea states from the FE model, {} from the reduced \
         response, {} mixed.</p>",
        count("fe"),
        count("reduced"),
        count("mixed")
    );
    for c in &data.calibrations {
        if c["kept"].as_bool() == Some(true) {
            let _ = writeln!(
                body,
                "<p>Check of hot spot {}: the load of all {} global jobs (strain {} to {}) lies \
                 within the calibration above, which every reduced job uses.</p>",
                c["hot_spot_index"],
                c["global_jobs"],
                number(c["load_range"]["strain"][0].as_f64().unwrap_or(f64::NAN)),
                number(c["load_range"]["strain"][1].as_f64().unwrap_or(f64::NAN)),
            );
            continue;
        }
        let range = |k: &str, i: usize| c[k]["strain"][i].as_f64().unwrap_or(f64::NAN);
        let curv = |i: usize| {
            c["calibrated_range"]["curvature_per_m"][i]
                .as_f64()
                .unwrap_or(f64::NAN)
        };
        let _ = writeln!(
            body,
            "<p>Calibration of hot spot {}: strain {} to {}, curvature {} to {} 1/m (the load \
             range of {} global jobs widened by the margin); FE run of {} designed samples in \
             {} s.</p>",
            c["hot_spot_index"],
            number(range("calibrated_range", 0)),
            number(range("calibrated_range", 1)),
            number(curv(0)),
            number(curv(1)),
            c["global_jobs"],
            c["design_samples"],
            number(c["fe_wall_time_s"].as_f64().unwrap_or(f64::NAN)),
        );
    }
    if data.comparison.rows.is_empty() {
        body += "<p class=\"empty\">No sea state ran both fidelities.</p>\n";
        return body;
    }
    body += &agreement_paragraph(&class_agreement(&data.comparison), data.critical.as_ref());
    body += "<p>Reduced against FE on the sea states that ran both (relative difference = \
             (reduced − FE) / FE):</p>\n";
    body += &table_html(&select_columns(
        &data.comparison,
        &[
            "sea_state_index",
            "hs_m",
            "tp_s",
            "layer_interface",
            "angular_position",
            "fe_damage_rate_max_per_s",
            "reduced_damage_rate_max_per_s",
            "damage_max_rel_diff",
            "damage_mean_rel_diff",
            "fe_slip_amplitude_max_m",
            "slip_amplitude_rel_diff",
            "slip_cycles_rel_diff",
        ],
    ));
    body
}

/// A class whose reduced damage rate lies more than this factor from the FE's, on a sea state
/// that ran both, is named in the report: its lifetime figures rest on a reduced response the
/// FE check does not confirm. In the paper campaign (docs/paper-campaign.md) the rope S-N law
/// per slip cycle keeps every class within 1.23 of FE, the contact-stress law does not (up to
/// 8.1 at γ_e = 10 µm, 30.5 at 1 µm): a factor 2 lies beyond the first's scatter.
const AGREEMENT_FACTOR: f64 = 2.0;

/// Reduced against FE for one contact class over the sea states that ran both.
#[derive(Debug, Clone, PartialEq)]
struct ClassAgreement {
    hot_spot_index: i64,
    layer_interface: i64,
    angular_position: String,
    /// The largest factor between the two damage rates of the most damaged contact (≥ 1;
    /// infinite where one of them is zero and the other is not).
    factor_max: f64,
    /// The same for the class mean.
    factor_mean: f64,
}

/// A factor ≥ 1 with three significant digits ("∞" when infinite).
fn factor_text(x: f64) -> String {
    match x {
        x if x.is_infinite() => "∞".into(),
        x if x < 10.0 => format!("{x:.2}"),
        x if x < 100.0 => format!("{x:.1}"),
        x => format!("{x:.0}"),
    }
}

/// max(r, 1/r) of r = reduced / FE; 1 when both are equal (zero included), infinite when a
/// rate is missing (NaN): a class without both rates is not confirmed.
fn factor_between(fe: f64, reduced: f64) -> f64 {
    if fe == reduced {
        return 1.0;
    }
    let r = reduced / fe;
    if r.is_nan() {
        return f64::INFINITY;
    }
    r.max(1.0 / r)
}

/// Per contact class of the `query fidelity` rows, the largest factor between the reduced and
/// the FE damage rates over the sea states that ran both, largest first.
fn class_agreement(comparison: &Table) -> Vec<ClassAgreement> {
    let column = |name: &str| comparison.columns.iter().position(|c| c == name);
    let (
        Some(hot),
        Some(iface),
        Some(pos),
        Some(fe_max),
        Some(red_max),
        Some(fe_mean),
        Some(red_mean),
    ) = (
        column("hot_spot_index"),
        column("layer_interface"),
        column("angular_position"),
        column("fe_damage_rate_max_per_s"),
        column("reduced_damage_rate_max_per_s"),
        column("fe_damage_rate_mean_per_s"),
        column("reduced_damage_rate_mean_per_s"),
    )
    else {
        return Vec::new();
    };
    let mut classes: Vec<ClassAgreement> = Vec::new();
    for row in &comparison.rows {
        let int = |i: usize| row[i].as_i64().unwrap_or(-1);
        let real = |i: usize| row[i].as_f64().unwrap_or(f64::NAN);
        let position = row[pos].as_str().unwrap_or_default().to_owned();
        let (f_max, f_mean) = (
            factor_between(real(fe_max), real(red_max)),
            factor_between(real(fe_mean), real(red_mean)),
        );
        let key = (int(hot), int(iface), position);
        match classes.iter_mut().find(|c| {
            (c.hot_spot_index, c.layer_interface, &c.angular_position) == (key.0, key.1, &key.2)
        }) {
            Some(c) => {
                c.factor_max = c.factor_max.max(f_max);
                c.factor_mean = c.factor_mean.max(f_mean);
            }
            None => classes.push(ClassAgreement {
                hot_spot_index: key.0,
                layer_interface: key.1,
                angular_position: key.2,
                factor_max: f_max,
                factor_mean: f_mean,
            }),
        }
    }
    classes.sort_by(|a, b| {
        b.factor_max
            .max(b.factor_mean)
            .total_cmp(&a.factor_max.max(a.factor_mean))
    });
    classes
}

/// What the FE check says of the lifetime figures: every class within [`AGREEMENT_FACTOR`], or
/// the classes beyond it, largest factor first, the critical one marked.
fn agreement_paragraph(classes: &[ClassAgreement], critical: Option<&CriticalClass>) -> String {
    if classes.is_empty() {
        return String::new();
    }
    let worst = |c: &ClassAgreement| c.factor_max.max(c.factor_mean);
    let beyond: Vec<&ClassAgreement> = classes
        .iter()
        .filter(|c| worst(c) > AGREEMENT_FACTOR || worst(c).is_nan())
        .collect();
    if beyond.is_empty() {
        let largest = classes.iter().map(worst).fold(1.0, f64::max);
        return format!(
            "<p>FE check: on every contact class the reduced damage rates (most damaged contact \
             and class mean) lie within a factor {} of the FE's on the sea states that ran both \
             (largest {}).</p>\n",
            AGREEMENT_FACTOR,
            factor_text(largest)
        );
    }
    let is_critical = |c: &ClassAgreement| {
        critical.is_some_and(|k| {
            k.hot_spot_index == c.hot_spot_index
                && k.layer_interface == c.layer_interface
                && k.angular_position.as_str() == c.angular_position
        })
    };
    let names: Vec<String> = beyond
        .iter()
        .map(|c| {
            format!(
                "{}hot spot {}, interface {} / {} (most damaged contact ×{}, class mean ×{})",
                if is_critical(c) {
                    "<strong>the critical class</strong>, "
                } else {
                    ""
                },
                c.hot_spot_index,
                c.layer_interface,
                escape(&c.angular_position),
                factor_text(c.factor_max),
                factor_text(c.factor_mean)
            )
        })
        .collect();
    format!(
        "<p class=\"warning\">FE check: on {} of {} contact classes the reduced damage rate lies \
         more than a factor {} from the FE's on a sea state that ran both: {}. Their lifetime \
         figures rest on a reduced response that the FE check does not confirm.</p>\n",
        beyond.len(),
        classes.len(),
        AGREEMENT_FACTOR,
        names.join("; ")
    )
}

/// The energy every sea state's wave cut-off keeps: the least, and the sea states flagged
/// for keeping less than 90 % (`moorfret_campaign::sea_limits`), each with its occurrence.
fn wave_energy_section(data: &ReportData) -> String {
    let mut body = String::from("<h2>Wave energy kept per sea state</h2>\n");
    let known: Vec<_> = data
        .sea_states
        .iter()
        .filter_map(|s| s.wave_energy_kept.map(|k| (s, k)))
        .collect();
    if known.is_empty() {
        body += "<p class=\"empty\">The energy kept is not stored for this campaign's sea \
                 states (planned before it was stored; `moorfret query sea-states` computes \
                 it).</p>\n";
        return body;
    }
    let least = known.iter().map(|(_, k)| *k).fold(f64::INFINITY, f64::min);
    let flagged: Vec<_> = known
        .iter()
        .filter(|(_, k)| crate::query::energy_flagged(*k))
        .collect();
    let share: f64 = flagged.iter().map(|(s, _)| s.occurrence_fraction).sum();
    let _ = writeln!(
        body,
        "<p>The global stage keeps the wave components below its frequency cut-off (the time \
         step and the floater's kinematics table); every sea state keeps at least {:.1} % of \
         its spectrum's energy. {} sea state(s), {:.4} % of the year, keep less than {:.0} %: \
         their loads are those of their longer waves only.</p>",
        100.0 * least,
        flagged.len(),
        100.0 * share,
        100.0 * moorfret_campaign::sea_limits::FLAG_ENERGY_KEPT
    );
    if flagged.is_empty() {
        return body;
    }
    body += "<table>\n<tr><th>sea_state_index</th><th>hs_m</th><th>tp_s</th>\
             <th>occurrence_fraction</th><th>wave_energy_kept</th><th>kept_hs_m</th></tr>\n";
    for (s, k) in flagged {
        let _ = writeln!(
            body,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{}</td></tr>",
            s.sea_state_index,
            number(s.hs_m),
            number(s.tp_s),
            number(s.occurrence_fraction),
            k,
            number(s.hs_m * k.sqrt())
        );
    }
    body += "</table>\n";
    body
}

/// The page of `data`.
pub(crate) fn page(data: &ReportData) -> anyhow::Result<String> {
    let name = escape(&data.name);
    let mut body = String::new();
    let _ = writeln!(body, "<h1>moorfret report: campaign {name}</h1>");
    let covered: f64 = data
        .sea_states
        .iter()
        .filter(|s| s.jobs_total > 0 && s.jobs_done == s.jobs_total)
        .map(|s| s.occurrence_fraction)
        .sum();
    let planned: f64 = data.sea_states.iter().map(|s| s.occurrence_fraction).sum();
    let _ = writeln!(
        body,
        "<p>{} sea states, occurrence planned {:.5}, covered by completed sea states {:.5} \
         (fraction of the year; lifetime sums are not renormalised).</p>",
        data.sea_states.len(),
        // + 0.0: an empty sum is −0.0, shown as "-0.00000".
        planned + 0.0,
        covered + 0.0
    );
    body += &design_section(data)?;
    body += &unfinished_section(data);
    body += &wave_energy_section(data);
    body += "<h2>Scatter diagram: share of the annual damage per sea state</h2>\n";
    if data.fidelity.values().any(|f| f != "fe") {
        body += "<p>Every disc is a sea state; a thick blue ring marks the sea states whose \
                 strand results come from the FE model (with extra seeds of the reduced \
                 response where they ran), the others from the reduced strand response.</p>\n";
    }
    // the diagram itself: each sea state's occurrence, percent of the year
    let occurrence: std::collections::BTreeMap<i64, f64> = data
        .sea_states
        .iter()
        .map(|s| (s.sea_state_index, 100.0 * s.occurrence_fraction))
        .collect();
    // colour only: labels of neighbouring cells would overlap
    let largest = occurrence.values().copied().fold(0.0, f64::max);
    let no_label = |_: f64| None;
    let percent = |v: f64| format!("{}%", plots::tick_text(v));
    body += "<div class=\"fig map\">";
    body += &plots::value_map_svg(
        &data.sea_states,
        &occurrence,
        &format!("occurrence (% of the year; darkest {})", number(largest)),
        &data.fidelity,
        &no_label,
        &percent,
    )?;
    body += "</div>\n";
    body += &sector_maps_section(data, &occurrence)?;
    match &data.critical {
        Some(c) => {
            let _ = writeln!(
                body,
                "<p>Fretting: critical contact class hot spot {}, layer interface {}, {} \
                 (annual damage of its most damaged contact {}, life {} years).</p>",
                c.hot_spot_index,
                c.layer_interface,
                c.angular_position.as_str(),
                number(c.annual_damage),
                number(1.0 / c.annual_damage)
            );
            body += "<div class=\"fig map\">";
            body += &plots::scatter_svg(
                &data.sea_states,
                &data.fretting_share,
                "share of annual fretting damage",
                &data.fidelity,
            )?;
            body += "</div>\n";
        }
        None => body += "<p class=\"empty\">No fretting results stored yet.</p>\n",
    }
    match &data.tn_share {
        Some((measure, share)) => {
            let _ = writeln!(body, "<p>T-N damage, measure {}.</p>", escape(measure));
            body += "<div class=\"fig map\">";
            body += &plots::scatter_svg(
                &data.sea_states,
                share,
                &format!("share of annual T-N damage ({measure})"),
                &data.fidelity,
            )?;
            body += "</div>\n";
        }
        None => body += "<p class=\"empty\">No T-N results stored yet.</p>\n",
    }
    body += "<h2>Hot-spot tension and curvature</h2>\n";
    match &data.series {
        Some(s) => {
            let _ = writeln!(
                body,
                "<p>Global job of sea state {}.</p>",
                s.sea_state_index
            );
            body += "<div class=\"fig\">";
            body += &plots::series_svg(s)?;
            body += "</div>\n";
        }
        None => {
            body += "<p class=\"empty\">No hot-spot series artifact (hot-spot series of a global \
                     job) found.</p>\n"
        }
    }
    body += &run_in_section(data)?;
    body += "<h2>Slip amplitude per layer interface</h2>\n";
    if data.histograms.is_empty() {
        body += "<p class=\"empty\">No cycle histograms stored yet.</p>\n";
    }
    for h in &data.histograms {
        body += "<div class=\"fig\">";
        body += &plots::histogram_svg(h)?;
        body += "</div>\n";
    }
    body += "<h2>Lifetime damage per year and life in years</h2>\n";
    body += &class_lives_section(data);
    body += "<p>Annual damage: Σ over sea states of occurrence × seed-mean damage rate × one \
             year, not renormalised by the covered occurrence; life = 1 / annual damage \
             (Miner, failure at D = 1). `fretting_*`: the campaign's fretting law (by default \
             the life to crack initiation of each crossing from its contact stress field); \
             `rope_tn_*`: the DNV spiral-rope S-N curve charged per slip cycle on the wire's \
             stress range, kept for comparison. Seed band: D ± 2 SE, SE² = Σ (occurrence × year)² × \
             s² / n over the sea states with n ≥ 2 seeds (s their seed-to-seed standard \
             deviation of the damage rate); sea states with one seed add no spread and are \
             counted apart; effective_dof is the Welch–Satterthwaite count behind SE.</p>\n";
    body += &table_html(&select_columns(
        &data.lifetime,
        &[
            "hot_spot_index",
            "layer_interface",
            "angular_position",
            "measure",
            "annual_damage",
            "annual_damage_low",
            "annual_damage_high",
            "life_years",
            "life_years_low",
            "life_years_high",
            "occurrence_covered",
            "sea_states",
            "sea_states_with_spread",
            "sea_states_without_spread",
            "effective_dof",
        ],
    ));
    body += &fidelity_section(data);
    body += "<h2>Seed-to-seed spread of the critical contact class, most damaging sea states \
             (fretting_max)</h2>\n";
    body += "<p>Per sea state: seeds run, mean and standard deviation of the damage rate, \
             coefficient of variation, the sea state's annual damage and its standard error \
             (occurrence × year × s / √n; empty for one seed).</p>\n";
    body += &table_html(&select_columns(
        &data.seeds,
        &[
            "sea_state_index",
            "hs_m",
            "tp_s",
            "occurrence_fraction",
            "fidelity",
            "seeds",
            "damage_rate_per_s",
            "damage_rate_sd",
            "damage_rate_cv",
            "annual_damage",
            "annual_damage_se",
        ],
    ));
    body += "<h2>Damage inputs of the critical contact class, most damaging sea states \
             (fretting_max)</h2>\n";
    body += &table_html(&select_columns(
        &data.damage_inputs,
        &[
            "sea_state_index",
            "hs_m",
            "tp_s",
            "occurrence_fraction",
            "layer_interface",
            "angular_position",
            "fidelity",
            "damage_rate_per_s",
            "partial_slip_cycles_per_hour",
            "gross_slip_cycles_per_hour",
            "slip_amplitude_max_m",
            "peak_pressure_max_pa",
        ],
    ));
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>moorfret report: {name}</title>\n<style>\n\
         body {{ font-family: sans-serif; margin: 1.5em; color: #222; }}\n\
         table {{ border-collapse: collapse; font-size: 12px; margin-bottom: 1.5em; }}\n\
         th, td {{ border: 1px solid #bbb; padding: 2px 6px; text-align: right; }}\n\
         th {{ white-space: normal; max-width: 9em; }}\n\
         th {{ background: #eee; }}\n .fig {{ display: inline-block; margin: 4px; }}\n\
         .empty {{ color: #888; font-style: italic; }}\n\
         .verdict {{ display: inline-block; padding: 4px 10px; margin: 2px; font-weight: bold; \
         border-radius: 4px; color: white; }}\n\
         .pass {{ background: #2e7d32; }} .fail {{ background: #c62828; }} \
         .incomplete {{ background: #9e9e9e; }}\n\
         .warning {{ border-left: 4px solid #c62828; padding-left: 8px; }}\n</style>\n</head>\n<body>\n{body}\
         </body>\n</html>\n"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use moorfret_solver::fretting::AngularPosition;
    use moorfret_store::FidelityComparison;

    /// The `query fidelity` table of rows (sea state, interface, position, (FE max, reduced
    /// max, FE mean, reduced mean)) of hot spot 0.
    fn comparison(rows: &[(i64, i64, AngularPosition, Rates)]) -> Table {
        let rows: Vec<FidelityComparison> = rows
            .iter()
            .map(|r| FidelityComparison {
                sea_state_index: r.0,
                hs_m: 6.25,
                tp_s: 16.0,
                occurrence_fraction: 7.7e-4,
                seed_index: 0,
                hot_spot_index: 0,
                layer_interface: r.1,
                angular_position: r.2,
                reduced_damage_rate_max_per_s: r.3 .1,
                fe_damage_rate_max_per_s: r.3 .0,
                reduced_damage_rate_mean_per_s: r.3 .3,
                fe_damage_rate_mean_per_s: r.3 .2,
                reduced_slip_amplitude_max_m: 1e-6,
                fe_slip_amplitude_max_m: 1e-6,
                reduced_slip_cycles_per_hour: 1e3,
                fe_slip_cycles_per_hour: 1e3,
            })
            .collect();
        crate::query::fidelity_table(&rows).unwrap()
    }

    /// (FE max, reduced max, FE mean, reduced mean) damage rates of a class (1/s).
    type Rates = (f64, f64, f64, f64);

    /// Interface 1 near the neutral axis in the paper campaign at γ_e = 1 µm, Hs 6.25 m, Tp
    /// 16 s: (FE max, reduced max, FE mean, reduced mean).
    const INTERFACE_1: Rates = (4.481e-12, 1.368e-10, 7.087e-14, 1.067e-12);

    #[test]
    fn each_class_keeps_its_largest_factor_over_the_sea_states_either_way() {
        use AngularPosition::{Between, NeutralAxis, OuterArc};
        let table = comparison(&[
            (130, 1, NeutralAxis, INTERFACE_1),
            (
                135,
                1,
                NeutralAxis,
                (2.046e-11, 2.443e-10, 3.208e-13, 2.049e-12),
            ),
            (130, 4, Between, (4.537e-14, 2.269e-14, 4.258e-16, 4.0e-16)),
            (135, 4, Between, (8.0e-14, 8.8e-14, 0.0, 0.0)),
            (130, 0, OuterArc, (0.0, 1e-20, 1e-16, 1e-16)),
        ]);
        let classes = class_agreement(&table);
        assert_eq!(classes.len(), 3);
        // sorted largest first: the zero FE rate against a non-zero reduced one is infinite
        assert_eq!(classes[0].layer_interface, 0);
        assert_eq!(classes[0].factor_max, f64::INFINITY);
        assert_eq!(classes[0].factor_mean, 1.0);
        let i1 = &classes[1];
        assert_eq!(
            (i1.layer_interface, i1.angular_position.as_str()),
            (1, "neutral_axis")
        );
        assert!((i1.factor_max - INTERFACE_1.1 / INTERFACE_1.0).abs() < 1e-9);
        assert!((i1.factor_mean - INTERFACE_1.3 / INTERFACE_1.2).abs() < 1e-9);
        // a reduced rate below the FE's counts as FE / reduced; both zero is agreement
        let i4 = &classes[2];
        assert!((i4.factor_max - 4.537e-14 / 2.269e-14).abs() < 1e-12);
        assert!((i4.factor_mean - 4.258e-16 / 4.0e-16).abs() < 1e-12);
    }

    #[test]
    fn the_report_names_the_classes_the_fe_check_does_not_confirm() {
        use AngularPosition::{Between, NeutralAxis};
        let close = (130, 2, Between, (1.0e-12, 1.3e-12, 1.0e-14, 0.9e-14));
        let table = comparison(&[(130, 1, NeutralAxis, INTERFACE_1), close]);
        let critical = CriticalClass {
            hot_spot_index: 0,
            layer_interface: 1,
            angular_position: NeutralAxis,
            annual_damage: 1.2e-5,
        };
        let text = agreement_paragraph(&class_agreement(&table), Some(&critical));
        assert!(text.contains("on 1 of 2 contact classes"), "{text}");
        assert!(
            text.contains(
                "<strong>the critical class</strong>, hot spot 0, interface 1 / neutral_axis"
            ),
            "{text}"
        );
        assert!(!text.contains("interface 2"), "{text}");

        // within the factor everywhere: one sentence with the largest factor
        let text = agreement_paragraph(&class_agreement(&comparison(&[close])), Some(&critical));
        assert!(text.contains("within a factor 2"), "{text}");
        assert!(text.contains("largest 1.30"), "{text}");
        assert!(!text.contains("warning"), "{text}");
        assert_eq!(agreement_paragraph(&[], None), "");
    }
}
