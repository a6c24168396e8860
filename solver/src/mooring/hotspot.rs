//! Line outputs: tension T and curvature κ at hot spots (arc length from the fairlead),
//! interpolated from the element fields, envelopes along the line per node, and the fairlead
//! tension, sampled at a requested output interval.
//!
//! On a rope element T = EA (|r'| − 1) and κ = |r' × r''| / |r'|³ at the local coordinate of the
//! point; on a chain bar T is the bar force and κ = 0. At a node shared by two elements the node
//! value averages both sides (the cubic interpolation is C¹, so κ may jump slightly at nodes).
//! Samples at the output times t_k = k Δt_out are linear interpolations between the two time
//! steps around t_k; envelopes are updated at every step.

use nalgebra::Vector3;

use super::bar_element::bar_tension;
use super::cable_element::cable_tension_curvature;
use super::error::LineError;
use super::line::{ElementId, ElementKind, LineModel};

fn vec3(x: &[f64], d: usize) -> Vector3<f64> {
    Vector3::new(x[d], x[d + 1], x[d + 2])
}

/// Tension (N) and curvature (1/m) at local coordinate `xi` of element `e` in state `q`.
pub(crate) fn element_tension_curvature(
    model: &LineModel,
    q: &[f64],
    e: ElementId,
    xi: f64,
) -> (f64, f64) {
    let el = &model.elements()[e.0];
    let sec = model.section(el);
    let d = model.element_dofs(el);
    match el.kind {
        ElementKind::Cable => cable_tension_curvature(sec, &d.map(|i| vec3(q, i)), el.length_m, xi),
        ElementKind::Bar => (
            bar_tension(sec.ea_n, el.length_m, &[vec3(q, d[0]), vec3(q, d[1])]),
            0.0,
        ),
    }
}

/// Tension (N) and curvature (1/m) at arc length `s` (m) from the fairlead.
pub fn tension_curvature_at(
    model: &LineModel,
    q: &[f64],
    arc_length_m: f64,
) -> Result<(f64, f64), LineError> {
    let (e, xi) = model.locate(arc_length_m)?;
    Ok(element_tension_curvature(model, q, e, xi))
}

/// Tension and curvature at every node (averaging the adjacent elements; element k joins
/// nodes k and k + 1).
pub fn node_values(model: &LineModel, q: &[f64], tension: &mut [f64], curvature: &mut [f64]) {
    tension.fill(0.0);
    curvature.fill(0.0);
    let elements = model.elements();
    for (k, el) in elements.iter().enumerate() {
        for (side, xi) in [(0, 0.0), (1, 1.0)] {
            let n = el.nodes[side].0;
            let (t, c) = element_tension_curvature(model, q, ElementId(k), xi);
            tension[n] += t;
            curvature[n] += c;
        }
    }
    let last = tension.len() - 1;
    for n in 0..=last {
        let left = (n > 0).then(|| elements[n - 1].kind);
        let right = (n < last).then(|| elements[n].kind);
        let count_t = usize::from(left.is_some()) + usize::from(right.is_some());
        let count_k = usize::from(left == Some(ElementKind::Cable))
            + usize::from(right == Some(ElementKind::Cable));
        tension[n] /= count_t.max(1) as f64;
        curvature[n] /= count_k.max(1) as f64;
    }
}

/// Extremes over time at every node.
#[derive(Debug, Clone, PartialEq)]
pub struct Envelope {
    /// Arc length of each node (m).
    pub arc_length_m: Vec<f64>,
    /// Smallest tension (N).
    pub tension_min_n: Vec<f64>,
    /// Largest tension (N).
    pub tension_max_n: Vec<f64>,
    /// Smallest curvature magnitude (1/m).
    pub curvature_min_per_m: Vec<f64>,
    /// Largest curvature magnitude (1/m).
    pub curvature_max_per_m: Vec<f64>,
}

impl Envelope {
    /// Curvature range max |κ| − min |κ| per node (1/m).
    pub fn curvature_range_per_m(&self) -> Vec<f64> {
        self.curvature_max_per_m
            .iter()
            .zip(&self.curvature_min_per_m)
            .map(|(a, b)| a - b)
            .collect()
    }
}

/// Sampled history at one hot spot.
#[derive(Debug, Clone, PartialEq)]
pub struct HotSpotRecord {
    /// Arc length from the fairlead (m).
    pub arc_length_m: f64,
    /// Tension samples (N).
    pub tension_n: Vec<f64>,
    /// Curvature samples (1/m).
    pub curvature_per_m: Vec<f64>,
}

impl HotSpotRecord {
    /// max − min of the tension samples (N).
    pub fn tension_range_n(&self) -> f64 {
        range(&self.tension_n)
    }
    /// max − min of the curvature samples (1/m).
    pub fn curvature_range_per_m(&self) -> f64 {
        range(&self.curvature_per_m)
    }
}

fn range(x: &[f64]) -> f64 {
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if x.is_empty() {
        0.0
    } else {
        hi - lo
    }
}

/// Everything recorded over a run.
#[derive(Debug, Clone, PartialEq)]
pub struct LineOutputs {
    /// Sample times (s).
    pub time_s: Vec<f64>,
    /// Fairlead tension |F| (N) at the sample times.
    pub fairlead_tension_n: Vec<f64>,
    /// Hot-spot histories.
    pub hot_spots: Vec<HotSpotRecord>,
    /// Envelopes along the line, from `record_from_s` on.
    pub envelope: Envelope,
}

/// Time, fairlead tension and hot-spot (tension, curvature) of the previous step.
type Observation = (f64, f64, Vec<(f64, f64)>);

/// Collects [`LineOutputs`] from successive states.
#[derive(Debug, Clone)]
pub struct LineRecorder {
    spots: Vec<(ElementId, f64)>,
    interval_s: f64,
    record_from_s: f64,
    next_sample: u64,
    previous: Option<Observation>,
    scratch: Vec<(f64, f64)>,
    node_t: Vec<f64>,
    node_k: Vec<f64>,
    outputs: LineOutputs,
}

impl LineRecorder {
    /// Recorder of the hot spots at `arc_lengths_m`, sampled every `interval_s` from
    /// `record_from_s` on (envelopes too, so a start-up transient can be excluded).
    pub fn new(
        model: &LineModel,
        arc_lengths_m: &[f64],
        interval_s: f64,
        record_from_s: f64,
    ) -> Result<Self, LineError> {
        if interval_s.is_nan() || interval_s <= 0.0 {
            return Err(LineError::invalid(
                "output_interval_s",
                interval_s,
                "must be > 0",
            ));
        }
        let spots = arc_lengths_m
            .iter()
            .map(|&s| model.locate(s))
            .collect::<Result<Vec<_>, _>>()?;
        let n = model.nodes().len();
        Ok(LineRecorder {
            spots,
            interval_s,
            record_from_s,
            next_sample: (record_from_s / interval_s).ceil().max(0.0) as u64,
            previous: None,
            scratch: Vec::new(),
            node_t: vec![0.0; n],
            node_k: vec![0.0; n],
            outputs: LineOutputs {
                time_s: Vec::new(),
                fairlead_tension_n: Vec::new(),
                hot_spots: arc_lengths_m
                    .iter()
                    .map(|&s| HotSpotRecord {
                        arc_length_m: s,
                        tension_n: Vec::new(),
                        curvature_per_m: Vec::new(),
                    })
                    .collect(),
                envelope: Envelope {
                    arc_length_m: model.nodes().iter().map(|n| n.arc_length_m).collect(),
                    tension_min_n: vec![f64::INFINITY; n],
                    tension_max_n: vec![f64::NEG_INFINITY; n],
                    curvature_min_per_m: vec![f64::INFINITY; n],
                    curvature_max_per_m: vec![f64::NEG_INFINITY; n],
                },
            },
        })
    }

    /// Takes the state `q` at time `t_s` with fairlead force `fairlead_force_n`.
    pub fn observe(
        &mut self,
        model: &LineModel,
        t_s: f64,
        q: &[f64],
        fairlead_force_n: &Vector3<f64>,
    ) {
        let mut spots = std::mem::take(&mut self.scratch);
        spots.clear();
        spots.extend(
            self.spots
                .iter()
                .map(|&(e, xi)| element_tension_curvature(model, q, e, xi)),
        );
        let tf = fairlead_force_n.norm();
        if t_s >= self.record_from_s - 1e-9 * self.interval_s {
            node_values(model, q, &mut self.node_t, &mut self.node_k);
            let env = &mut self.outputs.envelope;
            for i in 0..self.node_t.len() {
                env.tension_min_n[i] = env.tension_min_n[i].min(self.node_t[i]);
                env.tension_max_n[i] = env.tension_max_n[i].max(self.node_t[i]);
                env.curvature_min_per_m[i] = env.curvature_min_per_m[i].min(self.node_k[i]);
                env.curvature_max_per_m[i] = env.curvature_max_per_m[i].max(self.node_k[i]);
            }
        }
        let eps = 1e-9 * self.interval_s;
        loop {
            let ts = self.next_sample as f64 * self.interval_s;
            if ts > t_s + eps {
                break;
            }
            // Weight of the current state at the sample time.
            let (w, prev) = match &self.previous {
                Some((t0, f0, p0)) if ts < t_s - eps && t_s > *t0 => {
                    ((ts - t0) / (t_s - t0), Some((*f0, p0)))
                }
                _ => (1.0, None),
            };
            let mix = |a: f64, b: f64| a + w * (b - a);
            self.outputs.time_s.push(ts);
            self.outputs
                .fairlead_tension_n
                .push(prev.map_or(tf, |(f0, _)| mix(f0, tf)));
            for (k, series) in self.outputs.hot_spots.iter_mut().enumerate() {
                let (t1, k1) = spots[k];
                let (t0, k0) = prev.map_or((t1, k1), |(_, p)| p[k]);
                series.tension_n.push(mix(t0, t1));
                series.curvature_per_m.push(mix(k0, k1));
            }
            self.next_sample += 1;
        }
        if let Some((_, _, old)) = self.previous.replace((t_s, tf, spots)) {
            self.scratch = old;
        }
    }

    /// The recorded outputs.
    pub fn finish(self) -> LineOutputs {
        self.outputs
    }
}
