//! SVG plots of the report, rendered to strings for inlining (plotters SVG backend).

use std::collections::BTreeMap;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;

use super::data::{GlobalJobSeries, SlipHistogram};
use crate::plot::{bounds, panel, plot_err};
use moorfret_store::SeaStateStatus;

/// Colour of a share in [0, 1]: pale yellow (0) to dark red (1), linear in RGB.
pub(crate) fn share_colour(share: f64) -> RGBColor {
    let s = share.clamp(0.0, 1.0);
    let mix = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * s).round() as u8;
    RGBColor(mix(255, 165), mix(247, 0), mix(188, 38))
}

/// Scatter diagram (Tp, Hs) with every sea state as a disc coloured by its share of the
/// total, scaled so the largest share is darkest, and labelled in percent. When the strand
/// results come from more than one fidelity, the sea states with FE results (`fe`, or `mixed`:
/// an FE first seed and reduced extra seeds) get a thick blue ring.
pub(crate) fn scatter_svg(
    states: &[SeaStateStatus],
    share: &BTreeMap<i64, f64>,
    title: &str,
    fidelity: &BTreeMap<i64, String>,
) -> anyhow::Result<String> {
    let label = |v: f64| (v >= 0.005).then(|| format!("{:.0}%", 100.0 * v));
    let tick = |v: f64| format!("{}%", tick_text(100.0 * v));
    value_map_svg(states, share, title, fidelity, &label, &tick)
}

/// A colour-bar tick: at most two decimals from 0.01 to 10⁴, else one digit and an exponent.
pub(crate) fn tick_text(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_owned()
    } else if (0.01..1e4).contains(&a) {
        let t = format!("{v:.2}");
        t.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        format!("{v:.0e}")
    }
}

/// Steps of a colour bar.
const BAR_STEPS: usize = 48;

/// A vertical colour bar in `area`: the colours of [`share_colour`] from `lo` (bottom) to `hi`
/// (top), linear or logarithmic in the value, its ticks written by `tick`.
pub(crate) fn colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    lo: f64,
    hi: f64,
    log: bool,
    tick: &dyn Fn(f64) -> String,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let (lo, hi) = match (lo.is_finite() && hi.is_finite(), log) {
        (false, true) => (1e-3, 1.0),
        (false, false) => (0.0, 1.0),
        (true, true) if lo <= 0.0 || hi <= 0.0 => (1e-3, 1.0),
        (true, true) if hi <= lo => (lo / 10f64.sqrt(), lo * 10f64.sqrt()),
        (true, false) if hi <= lo => (lo, lo + 1.0),
        _ => (lo, hi),
    };
    let value_at = |t: f64| {
        if log {
            lo * (hi / lo).powf(t)
        } else {
            lo + (hi - lo) * t
        }
    };
    let steps: Vec<(f64, f64, RGBColor)> = (0..BAR_STEPS)
        .map(|k| {
            let (t0, t1) = (
                k as f64 / BAR_STEPS as f64,
                (k + 1) as f64 / BAR_STEPS as f64,
            );
            (value_at(t0), value_at(t1), share_colour(0.5 * (t0 + t1)))
        })
        .collect();
    let mut builder = ChartBuilder::on(area);
    builder
        .margin_top(40)
        .margin_bottom(52)
        .margin_right(6)
        .set_label_area_size(LabelAreaPosition::Left, 54);
    if log {
        // a log axis labels powers of ten only: the ends are written above and below the bar
        let (_, height) = area.dim_in_pixel();
        let font = ("sans-serif", 12).into_font().color(&BLACK);
        area.draw(&Text::new(
            format!("max {}", tick(hi)),
            (4, 24),
            font.clone(),
        ))
        .map_err(plot_err)?;
        area.draw(&Text::new(
            format!("min {}", tick(lo)),
            (4, height as i32 - 40),
            font,
        ))
        .map_err(plot_err)?;
        bar_steps(&mut builder, (lo..hi).log_scale(), &steps, tick)
    } else {
        bar_steps(&mut builder, lo..hi, &steps, tick)
    }
}

/// A colour bar's `steps` (from, to, colour) on a chart whose value axis is `y`, linear or
/// logarithmic, its ticks written by `tick`.
fn bar_steps<DB, Y>(
    builder: &mut ChartBuilder<'_, '_, DB>,
    y: Y,
    steps: &[(f64, f64, RGBColor)],
    tick: &dyn Fn(f64) -> String,
) -> anyhow::Result<()>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let mut chart = builder.build_cartesian_2d(0.0..1.0, y).map_err(plot_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(8)
        .y_label_style(("sans-serif", 12))
        .y_label_formatter(&|v| tick(*v))
        .draw()
        .map_err(plot_err)?;
    chart
        .draw_series(
            steps
                .iter()
                .map(|&(a, b, c)| Rectangle::new([(0.0, a), (1.0, b)], c.filled())),
        )
        .map_err(plot_err)?;
    Ok(())
}

/// Scatter diagram (Tp, Hs) with every sea state as a disc coloured by its value (the largest
/// darkest; grey without a value) and labelled by `label`, with a colour bar from 0 to the
/// largest value (ticks written by `tick`); FE sea states ringed as in [`scatter_svg`].
pub(crate) fn value_map_svg(
    states: &[SeaStateStatus],
    share: &BTreeMap<i64, f64>,
    title: &str,
    fidelity: &BTreeMap<i64, String>,
    label: &dyn Fn(f64) -> Option<String>,
    tick: &dyn Fn(f64) -> String,
) -> anyhow::Result<String> {
    let mark_fe = fidelity.values().any(|f| f != "fe");
    let mut svg = String::new();
    {
        let full = SVGBackend::with_string(&mut svg, (730, 480)).into_drawing_area();
        full.fill(&WHITE).map_err(plot_err)?;
        let (root, bar) = full.split_horizontally(640);
        let top = share.values().copied().fold(0.0, f64::max);
        colour_bar(&bar, 0.0, top, false, tick)?;
        let tp: Vec<f64> = states.iter().map(|s| s.tp_s).collect();
        let hs: Vec<f64> = states.iter().map(|s| s.hs_m).collect();
        let (x0, x1) = bounds(&tp);
        let (y0, y1) = bounds(&hs);
        let (x0, x1) = (x0 - 0.5, x1 + 0.5);
        let (y0, y1) = ((y0 - 0.5).max(0.0), y1 + 0.5);
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("Tp (s)")
            .y_desc("Hs (m)")
            .draw()
            .map_err(plot_err)?;
        for s in states {
            let value = share.get(&s.sea_state_index).copied();
            let colour = match value {
                Some(v) if top > 0.0 => share_colour(v / top),
                Some(_) => share_colour(0.0),
                None => RGBColor(220, 220, 220),
            };
            chart
                .draw_series([Circle::new((s.tp_s, s.hs_m), 9, colour.filled())])
                .map_err(plot_err)?;
            // the FE result counts in an `fe` sea state, and in a `mixed` one (FE first seed,
            // reduced extra seeds)
            let fe = mark_fe
                && matches!(
                    fidelity.get(&s.sea_state_index).map(String::as_str),
                    Some("fe" | "mixed")
                );
            let ring = if fe {
                RGBColor(20, 80, 220).stroke_width(4)
            } else {
                BLACK.stroke_width(1)
            };
            chart
                .draw_series([Circle::new((s.tp_s, s.hs_m), 9, ring)])
                .map_err(plot_err)?;
        }
        // labels over every disc, not under the next one
        for s in states {
            let value = share.get(&s.sea_state_index).copied();
            if let Some(text) = value.and_then(label) {
                chart
                    .draw_series([EmptyElement::at((s.tp_s, s.hs_m))
                        + Text::new(text, (8, -16), ("sans-serif", 11).into_font().color(&BLACK))])
                    .map_err(plot_err)?;
            }
        }
        full.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// Smallest positive spacing of `values`, or `default` when there is none.
fn spacing(values: impl Iterator<Item = f64>, default: f64) -> f64 {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let d = v
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 1e-9)
        .fold(f64::INFINITY, f64::min);
    if d.is_finite() {
        d
    } else {
        default
    }
}

/// One scatter map (Tp, Hs) per directional sector, on the same axes: every sea state of the
/// sector a cell coloured by its value on a logarithmic scale shared by all sectors (grey
/// without a value), with the colour bar of that scale; the sea states in `crossed` (failed or
/// skipped) are crossed out. `what` names the value in the caption, `tick` writes it.
pub(crate) fn sector_maps_svg(
    states: &[SeaStateStatus],
    values: &BTreeMap<i64, f64>,
    what: &str,
    crossed: &std::collections::BTreeSet<i64>,
    tick: &dyn Fn(f64) -> String,
) -> anyhow::Result<Vec<(String, String)>> {
    let mut sectors: Vec<(String, f64)> = Vec::new();
    for s in states {
        if let Some(label) = &s.sector {
            if !sectors.iter().any(|(l, _)| l == label) {
                sectors.push((label.clone(), s.heading_deg.unwrap_or(0.0)));
            }
        }
    }
    let positive: Vec<f64> = values.values().copied().filter(|v| *v > 0.0).collect();
    let hi = positive.iter().copied().fold(0.0, f64::max);
    let lo = positive.iter().copied().fold(f64::INFINITY, f64::min);
    // at least a decade, at most six below the largest
    let lo = if hi > 0.0 {
        lo.min(hi / 10.0).max(hi * 1e-6)
    } else {
        1e-3
    };
    let hi = if hi > 0.0 { hi } else { 1.0 };
    let fraction = |v: f64| ((v / lo).log10() / (hi / lo).log10()).clamp(0.0, 1.0);
    let dx = spacing(states.iter().map(|s| s.tp_s), 1.0);
    let dy = spacing(states.iter().map(|s| s.hs_m), 0.5);
    let tp: Vec<f64> = states.iter().map(|s| s.tp_s).collect();
    let hs: Vec<f64> = states.iter().map(|s| s.hs_m).collect();
    let (x0, x1) = bounds(&tp);
    let (y0, y1) = bounds(&hs);
    let (x0, x1) = (x0 - 0.5 * dx, x1 + 0.5 * dx);
    let (y0, y1) = ((y0 - 0.5 * dy).max(0.0), y1 + 0.5 * dy);
    let mut out = Vec::new();
    for (label, heading) in sectors {
        let mut svg = String::new();
        {
            let full = SVGBackend::with_string(&mut svg, (530, 400)).into_drawing_area();
            full.fill(&WHITE).map_err(plot_err)?;
            let (root, bar) = full.split_horizontally(440);
            colour_bar(&bar, lo, hi, true, tick)?;
            let mut chart = ChartBuilder::on(&root)
                .caption(
                    format!("sector {label} (heading {heading}°): {what}"),
                    ("sans-serif", 15),
                )
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(50)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(plot_err)?;
            chart
                .configure_mesh()
                .x_desc("Tp (s)")
                .y_desc("Hs (m)")
                .draw()
                .map_err(plot_err)?;
            for s in states
                .iter()
                .filter(|s| s.sector.as_deref() == Some(label.as_str()))
            {
                let colour = match values.get(&s.sea_state_index) {
                    Some(&v) if v > 0.0 => share_colour(fraction(v)),
                    _ => RGBColor(220, 220, 220),
                };
                let corners = [
                    (s.tp_s - 0.5 * dx, s.hs_m - 0.5 * dy),
                    (s.tp_s + 0.5 * dx, s.hs_m + 0.5 * dy),
                ];
                chart
                    .draw_series([Rectangle::new(corners, colour.filled())])
                    .map_err(plot_err)?;
                chart
                    .draw_series([Rectangle::new(corners, BLACK.stroke_width(1))])
                    .map_err(plot_err)?;
                if crossed.contains(&s.sea_state_index) {
                    let (a, b) = (corners[0], corners[1]);
                    chart
                        .draw_series([
                            PathElement::new(vec![a, b], BLACK.stroke_width(2)),
                            PathElement::new(vec![(a.0, b.1), (b.0, a.1)], BLACK.stroke_width(2)),
                        ])
                        .map_err(plot_err)?;
                }
            }
            full.present().map_err(plot_err)?;
        }
        out.push((label, svg));
    }
    Ok(out)
}

/// Slip amplitude histogram (µm) in cycles per hour of the year, on logarithmic axes: slips
/// and cycle rates span decades. A first bin from 0 is drawn from a tenth of its upper edge.
pub(crate) fn histogram_svg(h: &SlipHistogram) -> anyhow::Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (640, 360)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let bins: Vec<(f64, f64, f64)> = h
            .edges_m
            .windows(2)
            .zip(&h.cycles_per_hour)
            .filter(|(e, &c)| e[1] > 0.0 && c > 0.0)
            .map(|(e, &c)| {
                let hi = e[1] * 1e6;
                let lo = if e[0] > 0.0 { e[0] * 1e6 } else { 0.1 * hi };
                (lo, hi, c)
            })
            .collect();
        let x0 = bins.iter().map(|b| b.0).fold(f64::INFINITY, f64::min);
        let x1 = bins.iter().map(|b| b.1).fold(0.0, f64::max);
        let (x0, x1) = if bins.is_empty() {
            (0.1, 1000.0)
        } else {
            (x0, x1)
        };
        let top = bins.iter().map(|b| b.2).fold(0.0, f64::max);
        let low = bins.iter().map(|b| b.2).fold(f64::INFINITY, f64::min);
        let (y0, y1) = if bins.is_empty() {
            (1e-3, 1.0)
        } else {
            (0.5 * low, 2.0 * top)
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!(
                    "hot spot {}, layer interface {}",
                    h.hot_spot_index, h.layer_interface
                ),
                ("sans-serif", 16),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc("slip amplitude (µm)")
            .y_desc("cycles per hour of the year")
            .x_labels(6)
            .x_label_formatter(&|v| format!("{v}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(plot_err)?;
        chart
            .draw_series(
                bins.iter().map(|&(lo, hi, c)| {
                    Rectangle::new([(lo, y0), (hi, c)], BLUE.mix(0.6).filled())
                }),
            )
            .map_err(plot_err)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// Tension (kN) and curvature (1/m) of every hot spot of one global job.
pub(crate) fn series_svg(series: &GlobalJobSeries) -> anyhow::Result<String> {
    let mut svg = String::new();
    {
        let n = series.hot_spots.len().max(1);
        let root = SVGBackend::with_string(&mut svg, (900, 260 * 2 * n as u32)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let areas = root.split_evenly((2 * n, 1));
        for (i, h) in series.hot_spots.iter().enumerate() {
            let kn: Vec<f64> = h.tension_n.iter().map(|t| t * 1e-3).collect();
            panel(
                &areas[2 * i],
                &format!("hot spot {i}: tension"),
                "T (kN)",
                &h.time_s,
                &kn,
            )?;
            panel(
                &areas[2 * i + 1],
                &format!("hot spot {i}: curvature"),
                "κ (1/m)",
                &h.time_s,
                &h.curvature_per_m,
            )?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// One compass rose per mooring line: a wedge per directional sector, centred on the heading
/// its waves travel towards (model frame, counter-clockwise from +x, drawn with +x to the right
/// and +y up), its length the sector's annual damage on a log scale spanning four decades below
/// the line's largest, its colour the sector's share of the line's damage. Plain SVG: plotters
/// has no polar axes.
pub(crate) fn direction_roses_svg(
    sectors: &[crate::design::SectorDamage],
) -> anyhow::Result<String> {
    use std::fmt::Write;
    const SIZE: f64 = 220.0;
    const RADIUS: f64 = 80.0;
    const DECADES: f64 = 4.0;
    const BAR_WIDTH: f64 = 60.0;
    let mut lines: Vec<u32> = sectors.iter().map(|s| s.line).collect();
    lines.dedup();
    let mut out = String::new();
    for line in lines {
        let of_line: Vec<_> = sectors
            .iter()
            .filter(|s| s.line == line && s.sector != "all")
            .collect();
        let total: f64 = of_line.iter().map(|s| s.annual_damage).sum();
        let largest = of_line.iter().map(|s| s.annual_damage).fold(0.0, f64::max);
        // half width of a wedge: half the smallest spacing of the headings, at most 22.5°
        let mut headings: Vec<f64> = of_line
            .iter()
            .map(|s| s.heading_deg.rem_euclid(360.0))
            .collect();
        headings.sort_by(f64::total_cmp);
        let mut spacing: f64 = 45.0;
        for (i, h) in headings.iter().enumerate() {
            let next = headings.get(i + 1).copied().unwrap_or(headings[0] + 360.0);
            if next - h > 1e-9 {
                spacing = spacing.min(next - h);
            }
        }
        let half = 0.5 * spacing;
        let c = SIZE / 2.0;
        let _ = write!(
            out,
            "<svg class=\"fig map rose\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" \
             height=\"{h}\" viewBox=\"0 0 {w} {h}\">\
             <text x=\"{c}\" y=\"16\" text-anchor=\"middle\" font-size=\"14\">line {line}</text>",
            w = SIZE + BAR_WIDTH,
            h = SIZE + 20.0
        );
        // the colour bar of the shares, 0 % at the bottom to 100 % at the top
        let (bx, by, bh) = (SIZE + 6.0, 40.0, SIZE - 50.0);
        for k in 0..BAR_STEPS {
            let t = (k as f64 + 0.5) / BAR_STEPS as f64;
            let colour = share_colour(t);
            let step = bh / BAR_STEPS as f64;
            let y = by + bh - (k + 1) as f64 * step;
            let _ = write!(
                out,
                "<rect x=\"{bx}\" y=\"{y:.2}\" width=\"14\" height=\"{h:.2}\" \
                 fill=\"rgb({},{},{})\"/>",
                colour.0,
                colour.1,
                colour.2,
                h = step + 0.3
            );
        }
        let _ = write!(
            out,
            "<rect x=\"{bx}\" y=\"{by}\" width=\"14\" height=\"{bh}\" fill=\"none\" \
             stroke=\"#333\"/>"
        );
        for (share, text) in [(0.0, "0 %"), (0.5, "50 %"), (1.0, "100 %")] {
            let _ = write!(
                out,
                "<text x=\"{x}\" y=\"{y:.1}\" font-size=\"10\">{text}</text>",
                x = bx + 18.0,
                y = by + bh * (1.0 - share) + 3.0
            );
        }
        let _ = write!(
            out,
            "<text x=\"{bx}\" y=\"{y}\" font-size=\"10\">share</text>",
            y = by - 8.0
        );
        let cy = c + 10.0;
        for k in 1..=DECADES as usize {
            let r = RADIUS * k as f64 / DECADES;
            let _ = write!(
                out,
                "<circle cx=\"{c}\" cy=\"{cy}\" r=\"{r:.1}\" fill=\"none\" stroke=\"#ccc\"/>"
            );
        }
        let _ = write!(
            out,
            "<text x=\"{x:.1}\" y=\"{cy}\" font-size=\"10\" fill=\"#666\">+x</text>\
             <text x=\"{c}\" y=\"{y:.1}\" font-size=\"10\" fill=\"#666\">+y</text>",
            x = c + RADIUS + 4.0,
            y = cy - RADIUS - 4.0
        );
        for s in &of_line {
            if s.annual_damage <= 0.0 || largest <= 0.0 {
                continue;
            }
            let decades_below = (largest / s.annual_damage).log10();
            let r = RADIUS * (1.0 - decades_below / DECADES).clamp(0.02, 1.0);
            let (a0, a1) = (
                (s.heading_deg - half).to_radians(),
                (s.heading_deg + half).to_radians(),
            );
            // SVG y grows downwards: +y of the model is up
            let p = |a: f64| (c + r * a.cos(), cy - r * a.sin());
            let ((x0, y0), (x1, y1)) = (p(a0), p(a1));
            let colour = share_colour(s.annual_damage / total);
            let _ = write!(
                out,
                "<path d=\"M {c} {cy} L {x0:.1} {y0:.1} A {r:.1} {r:.1} 0 0 0 {x1:.1} {y1:.1} Z\" \
                 fill=\"rgb({},{},{})\" stroke=\"#333\"><title>{}: heading {} deg, {:.3e} per year \
                 ({:.1} % of the line's)</title></path>",
                colour.0,
                colour.1,
                colour.2,
                super::html::escape(&s.sector),
                s.heading_deg,
                s.annual_damage,
                100.0 * s.annual_damage / total
            );
        }
        let _ = write!(
            out,
            "<text x=\"{c}\" y=\"{y:.1}\" text-anchor=\"middle\" font-size=\"10\">rings: \
             decades below {largest:.2e}/yr</text></svg>",
            y = SIZE + 16.0
        );
    }
    Ok(out)
}
