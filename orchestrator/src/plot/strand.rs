//! Plots of a strand history run (the paper's Figs. 19-22): one file per quantity, one panel per
//! helical layer (wire axial force) or layer interface (contact forces, slip), each with the
//! neutral-axis and outer-arc monitors against time; and the load, T or ε, and κ against time.

use std::path::Path;

use anyhow::Context;
use moorfret_solver::strand::history::monitors::{
    MonitorGroup, MonitorQuantity, MonitorSeries, MonitorTarget,
};
use plotters::prelude::*;

use super::global::{panel, panel_curves, plot_err};

/// What the load plot shows besides κ: the tension when the history was given as one.
#[derive(Clone, Copy, Debug)]
pub struct LoadPlot<'a> {
    /// Tension per sample (N), if the history was a tension history.
    pub tension_n: Option<&'a [f64]>,
}

/// The plotted quantities: file stem, title, axis label, scale of the values.
const QUANTITIES: [(MonitorQuantity, &str, &str, &str, f64); 4] = [
    (
        MonitorQuantity::WireAxialForce,
        "wire_axial_force",
        "wire axial force",
        "F (kN)",
        1e-3,
    ),
    (
        MonitorQuantity::NormalForce,
        "contact_normal_force",
        "contact normal force",
        "f_N (N)",
        1.0,
    ),
    (
        MonitorQuantity::TangentialForce,
        "contact_tangential_force",
        "contact tangential force",
        "f_T (N)",
        1.0,
    ),
    (
        MonitorQuantity::Slip,
        "slip",
        "inter-wire slip",
        "slip (µm)",
        1e6,
    ),
];

/// Title of a panel: helical layer for wire elements, interface for contacts.
fn place(target: MonitorTarget, layer: usize) -> String {
    match (target, layer) {
        (MonitorTarget::Element(_), l) => format!("layer {}", l + 1),
        (MonitorTarget::Contact(_), 0) => "layer 1 on core".into(),
        (MonitorTarget::Contact(_), l) => format!("layer {} on layer {l}", l + 1),
    }
}

/// Writes `load.svg`, `wire_axial_force.svg`, `contact_normal_force.svg`,
/// `contact_tangential_force.svg` and `slip.svg` into `dir`.
pub fn strand_history_svgs(
    m: &MonitorSeries,
    load: &LoadPlot<'_>,
    dir: &Path,
) -> anyhow::Result<()> {
    load_svg(m, load, &dir.join("load.svg"))?;
    for (quantity, stem, title, y_label, scale) in QUANTITIES {
        let mut layers: Vec<usize> = m
            .channels
            .iter()
            .filter(|c| c.quantity == quantity && c.group != MonitorGroup::Ring)
            .map(|c| c.layer)
            .collect();
        layers.sort_unstable();
        layers.dedup();
        let path = dir.join(format!("{stem}.svg"));
        let n = layers.len().max(1);
        let root = SVGBackend::new(&path, (1000, 300 * n as u32)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let areas = root.split_evenly((n, 1));
        for (area, &layer) in areas.iter().zip(&layers) {
            let curves: Vec<(&str, RGBColor, Vec<f64>, MonitorTarget)> = m
                .channels
                .iter()
                .filter(|c| c.quantity == quantity && c.layer == layer)
                .filter_map(|c| {
                    let (name, color) = match c.group {
                        MonitorGroup::NeutralAxis => ("neutral axis", BLUE),
                        MonitorGroup::OuterArc => ("outer arc", RED),
                        MonitorGroup::Ring => return None,
                    };
                    let v = c.values.iter().map(|x| x * scale).collect();
                    Some((name, color, v, c.target))
                })
                .collect();
            let Some(target) = curves.first().map(|c| c.3) else {
                continue;
            };
            let curves: Vec<(&str, RGBColor, &[f64])> = curves
                .iter()
                .map(|(name, color, values, _)| (*name, *color, values.as_slice()))
                .collect();
            panel_curves(
                area,
                &format!("{title}, {}", place(target, layer)),
                y_label,
                &m.time_s,
                &curves,
            )?;
        }
        root.present()
            .map_err(plot_err)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// T (kN) or ε, and κ against time.
fn load_svg(m: &MonitorSeries, load: &LoadPlot<'_>, path: &Path) -> anyhow::Result<()> {
    let root = SVGBackend::new(path, (1000, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let areas = root.split_evenly((2, 1));
    match load.tension_n {
        Some(t) => {
            let kn: Vec<f64> = t.iter().map(|v| v * 1e-3).collect();
            panel(&areas[0], "tension", "T (kN)", &m.time_s, &kn)?;
        }
        None => panel(&areas[0], "axial strain", "ε", &m.time_s, &m.strain)?,
    }
    panel(
        &areas[1],
        "curvature",
        "κ (1/m)",
        &m.time_s,
        &m.curvature_per_m,
    )?;
    root.present()
        .map_err(plot_err)
        .with_context(|| format!("writing {}", path.display()))
}
