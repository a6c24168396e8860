//! Plots of a global run.

use std::path::Path;

use anyhow::{anyhow, Context};
use moorfret_solver::global::GlobalResult;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

pub(crate) fn bounds(x: &[f64]) -> (f64, f64) {
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

pub(crate) fn plot_err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("plotting failed: {e:?}")
}

/// The legend of the labelled series of `chart`, boxed in its upper right corner.
fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(plot_err)
}

/// Buckets of a time panel's curve: a panel is about 1000 px wide, so two points (the lowest
/// and the highest) per half pixel draw the same line as every sample.
const PANEL_BUCKETS: usize = 2000;

/// The points of `y(t)` to draw: all of them up to `2 buckets`, else the lowest and the
/// highest sample of each of `buckets` runs of equal length, in time order, and the last
/// sample. The drawn envelope is that of every sample, and an SVG stays a few hundred kB
/// whatever the length of the series.
pub(crate) fn decimated(t: &[f64], y: &[f64], buckets: usize) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    if n <= 2 * buckets.max(1) {
        return t.iter().copied().zip(y.iter().copied()).take(n).collect();
    }
    let mut out = Vec::with_capacity(2 * buckets + 2);
    out.push((t[0], y[0]));
    for b in 0..buckets {
        let (lo, hi) = (
            b * n / buckets,
            ((b + 1) * n / buckets).max(b * n / buckets + 1),
        );
        let run = lo..hi.min(n);
        let lowest = run.clone().fold(lo, |m, i| if y[i] < y[m] { i } else { m });
        let highest = run.fold(lo, |m, i| if y[i] > y[m] { i } else { m });
        let (first, second) = (lowest.min(highest), lowest.max(highest));
        if first != 0 {
            out.push((t[first], y[first]));
        }
        if second != first {
            out.push((t[second], y[second]));
        }
    }
    if out.last().map(|p| p.0) != Some(t[n - 1]) {
        out.push((t[n - 1], y[n - 1]));
    }
    out
}

/// One panel: `y(t)`.
pub(crate) fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    y_label: &str,
    t: &[f64],
    y: &[f64],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    panel_curves(area, title, y_label, t, &[("", BLUE, y)])
}

/// One panel with several curves `(label, colour, y(t))`; a legend when any label is given.
pub(crate) fn panel_curves<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    y_label: &str,
    t: &[f64],
    curves: &[(&str, RGBColor, &[f64])],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let (t0, t1) = bounds(t);
    let all: Vec<f64> = curves.iter().flat_map(|c| c.2.iter().copied()).collect();
    let (y0, y1) = bounds(&all);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, y0..y1)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(y_label)
        .draw()
        .map_err(plot_err)?;
    for &(label, color, y) in curves {
        let series = chart
            .draw_series(LineSeries::new(decimated(t, y, PANEL_BUCKETS), color))
            .map_err(plot_err)?;
        if !label.is_empty() {
            series
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
    }
    if curves.iter().any(|c| !c.0.is_empty()) {
        draw_legend(&mut chart)?;
    }
    Ok(())
}

/// Tension and curvature histories of every hot spot.
pub fn hotspots_svg(result: &GlobalResult, path: &Path) -> anyhow::Result<()> {
    let n = result.hot_spots.len().max(1);
    let root = SVGBackend::new(path, (1000, 320 * 2 * n as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let areas = root.split_evenly((2 * n, 1));
    for (i, h) in result.hot_spots.iter().enumerate() {
        let tension_kn: Vec<f64> = h.tension_n.iter().map(|v| v * 1e-3).collect();
        panel(
            &areas[2 * i],
            &format!("line {}, s = {} m: tension", h.line, h.arc_length_m),
            "T (kN)",
            &result.time_s,
            &tension_kn,
        )?;
        panel(
            &areas[2 * i + 1],
            &format!("line {}, s = {} m: curvature", h.line, h.arc_length_m),
            "κ (1/m)",
            &result.time_s,
            &h.curvature_per_m,
        )?;
    }
    root.present()
        .map_err(plot_err)
        .with_context(|| format!("writing {}", path.display()))
}

/// Static profiles of all lines: elevation versus horizontal distance from the fairlead.
pub fn static_shapes_svg(result: &GlobalResult, path: &Path) -> anyhow::Result<()> {
    let curves: Vec<(u32, Vec<(f64, f64)>)> = result
        .lines
        .iter()
        .map(|l| {
            let p0 = l.static_position_m.first().copied().unwrap_or([0.0; 3]);
            let pts = l
                .static_position_m
                .iter()
                .map(|p| ((p[0] - p0[0]).hypot(p[1] - p0[1]), p[2]))
                .collect();
            (l.id, pts)
        })
        .collect();
    let xs: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.1.iter().map(|p| p.0))
        .collect();
    let zs: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.1.iter().map(|p| p.1))
        .collect();
    let (x0, x1) = bounds(&xs);
    let (z0, z1) = bounds(&zs);
    let root = SVGBackend::new(path, (1000, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{}: static line profiles", result.name),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, z0..z1)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc("horizontal distance from the fairlead (m)")
        .y_desc("z (m)")
        .draw()
        .map_err(plot_err)?;
    for (k, (id, pts)) in curves.into_iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        chart
            .draw_series(LineSeries::new(pts, color))
            .map_err(plot_err)?
            .label(format!("line {id}"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
    }
    draw_legend(&mut chart)?;
    root.present()
        .map_err(plot_err)
        .with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_keeps_every_extreme_in_time_order() {
        let n = 1_000_000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.001).collect();
        let mut y: Vec<f64> = t.iter().map(|t| (0.7 * t).sin()).collect();
        y[123_457] = 5.0; // a spike
        y[876_543] = -4.0;
        let d = decimated(&t, &y, 2000);
        assert!(d.len() <= 4002, "{}", d.len());
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
        let max = d.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let min = d.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert_eq!((max, min), (5.0, -4.0));
        assert_eq!(d[0], (t[0], y[0]));
        assert_eq!(*d.last().unwrap(), (t[n - 1], y[n - 1]));
        // Short series are drawn as they are.
        assert_eq!(decimated(&t[..10], &y[..10], 2000).len(), 10);
    }
}
