//! The HTML page: inline SVG and tables, no scripts and no external resources.

use std::fmt::Write;

use super::data::ReportData;
use super::plots;
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
            Some(x) if n.is_f64() && x != 0.0 && !(1e-3..1e6).contains(&x.abs()) => {
                format!("{x:.4e}")
            }
            Some(x) if n.is_f64() => format!("{x:.6}"),
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
        let _ = write!(out, "<th>{}</th>", escape(c));
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
        planned,
        covered
    );
    body += "<h2>Scatter diagram: share of the annual damage per sea state</h2>\n";
    match &data.critical {
        Some(c) => {
            let _ = writeln!(
                body,
                "<p>Fretting: critical contact class hot spot {}, layer interface {}, {} \
                 (annual damage of its most damaged contact {:.4e}).</p>",
                c.hot_spot_index,
                c.layer_interface,
                c.angular_position.as_str(),
                c.annual_damage
            );
            body += "<div class=\"fig\">";
            body += &plots::scatter_svg(
                &data.sea_states,
                &data.fretting_share,
                "share of annual fretting damage",
            )?;
            body += "</div>\n";
        }
        None => body += "<p class=\"empty\">No fretting results stored yet.</p>\n",
    }
    match &data.tn_share {
        Some((measure, share)) => {
            let _ = writeln!(body, "<p>T-N damage, measure {}.</p>", escape(measure));
            body += "<div class=\"fig\">";
            body += &plots::scatter_svg(
                &data.sea_states,
                share,
                &format!("share of annual T-N damage ({measure})"),
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
    body += "<h2>Slip amplitude per layer interface</h2>\n";
    if data.histograms.is_empty() {
        body += "<p class=\"empty\">No cycle histograms stored yet.</p>\n";
    }
    for h in &data.histograms {
        body += "<div class=\"fig\">";
        body += &plots::histogram_svg(h)?;
        body += "</div>\n";
    }
    body += "<h2>Lifetime damage per year</h2>\n";
    body += &table_html(&data.lifetime);
    body += "<h2>Damage inputs per sea state and contact class (fretting_max)</h2>\n";
    body += &table_html(&data.damage_inputs);
    Ok(format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>moorfret report: {name}</title>\n<style>\n\
         body {{ font-family: sans-serif; margin: 1.5em; color: #222; }}\n\
         table {{ border-collapse: collapse; font-size: 12px; margin-bottom: 1.5em; }}\n\
         th, td {{ border: 1px solid #bbb; padding: 2px 6px; text-align: right; }}\n\
         th {{ background: #eee; }}\n .fig {{ display: inline-block; margin: 4px; }}\n\
         .empty {{ color: #888; font-style: italic; }}\n</style>\n</head>\n<body>\n{body}\
         </body>\n</html>\n"
    ))
}
