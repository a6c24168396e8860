//! Contact samples of the whole model and the monitor channels of a history run (the paper's Figs.
//! 19-22).
//!
//! Slip convention: the scalar slip of a contact is the total relative tangential displacement
//! of its two wires since the reference configuration (contact element, [`crate::contact`])
//! projected on the current axis of the outer wire, t₂ = Λ₂ T₂. In bending, the wires of a
//! layer slide along their own axis over the layer underneath (Papailiou's model), so this is
//! the component that carries the fretting; the tangential force is projected on the same axis.
//!
//! Angle θ: measured from the bending neutral axis as in `crate::fretting::record`; a point of
//! reference cross-section coordinates (X, Y) has X = −R sin θ, Y = R cos θ, so that its bending
//! strain is κ R sin θ ([`crate::strand::loading`]). A contact's position is the midpoint of its
//! two nodes.
//!
//! Default monitors: for every layer interface, the contact at the neutral axis and the one at the
//! outer arc (normal force, tangential force, slip); for every helical layer, the wire element at
//! the neutral axis and the one at the outer arc (axial force); and a ring: for every wire of the
//! outermost layer, its contact with the layer underneath nearest mid-length.
//!
//! "At the outer arc" means nearest θ = +π/2, the stretched side; "at the neutral axis" nearest
//! θ = 0 or π. The angle comes first, the axial position second: among the sites whose angular
//! distance to the target is within one element's angular span of the closest one, the one
//! nearest mid-length is taken. A layer with many wires therefore has its monitors near
//! mid-length; a layer of one wire (the 1+6+1 benchmark) reaches the outer arc only at the
//! model ends, and its outer-arc monitor sits there. Each channel records its θ and z.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::beam::frame::{FrameError, FrameState};
use crate::contact::ContactResponse;
use crate::fretting::ContactSample;
use crate::strand::model::StrandModel;

/// Where a contact sits: layer interface, angle from the neutral axis, axial coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactSite {
    /// Layer interface: 0 for layer 1 on the core, i for layer i+1 on layer i.
    pub interface: usize,
    /// Angle from the bending neutral axis (rad), in (−π, π].
    pub theta_rad: f64,
    /// Reference axial coordinate (m).
    pub z_m: f64,
}

/// Angle from the neutral axis of a point of reference coordinates (x, y) (see module docs).
pub(crate) fn theta_from_neutral_axis(x: f64, y: f64) -> f64 {
    (-x).atan2(y)
}

/// Site of every contact of `model`, mesh contact order.
pub fn contact_sites(model: &StrandModel) -> Vec<ContactSite> {
    let wires = model.strand.wires();
    model
        .mesh
        .contacts
        .iter()
        .map(|mc| {
            let [a, b] = mc.nodes;
            let (na, nb) = (&model.mesh.nodes[a.0], &model.mesh.nodes[b.0]);
            let mid: Vector3<f64> = 0.5 * (na.position + nb.position);
            let interface = wires[na.wire.0].layer.map_or(0, |k| k + 1);
            ContactSite {
                interface,
                theta_rad: theta_from_neutral_axis(mid.x, mid.y),
                z_m: 0.5 * (na.z_m + nb.z_m),
            }
        })
        .collect()
}

/// The fretting sample of contact `c` from its response at `state` (module docs).
pub(crate) fn contact_sample(
    model: &StrandModel,
    state: &FrameState,
    c: usize,
    response: Option<&ContactResponse>,
) -> ContactSample {
    let Some(r) = response else {
        return ContactSample {
            slip_m: 0.0,
            normal_force_n: 0.0,
            tangential_force_n: 0.0,
        };
    };
    let b = model.mesh.contacts[c].nodes[1].0;
    let t2 = (state.rotations[b] * model.mesh.nodes[b].tangent).normalize();
    ContactSample {
        slip_m: r.total_slip.dot(&t2),
        normal_force_n: r.normal_force_n,
        tangential_force_n: r.tangential_force.dot(&t2),
    }
}

/// Quantity of a monitor channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MonitorQuantity {
    /// Axial force of a wire element (N).
    WireAxialForce,
    /// Contact normal force (N).
    NormalForce,
    /// Contact tangential force along the outer wire axis (N).
    TangentialForce,
    /// Slip along the outer wire axis (m).
    Slip,
}

impl MonitorQuantity {
    /// Stable lower-case name with unit.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::WireAxialForce => "wire_axial_force_n",
            Self::NormalForce => "normal_force_n",
            Self::TangentialForce => "tangential_force_n",
            Self::Slip => "slip_m",
        }
    }
}

/// What a channel monitors: a wire element or a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MonitorTarget {
    /// Wire element index (mesh order).
    Element(usize),
    /// Contact index (mesh order).
    Contact(usize),
}

/// Group a channel belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MonitorGroup {
    /// Nearest the neutral axis.
    NeutralAxis,
    /// Nearest the outer arc.
    OuterArc,
    /// Ring of contacts around the circumference at mid-length.
    Ring,
}

/// One monitored time series on the original time axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MonitorChannel {
    /// Quantity.
    pub quantity: MonitorQuantity,
    /// Element or contact.
    pub target: MonitorTarget,
    /// Group.
    pub group: MonitorGroup,
    /// Layer interface for contacts, helical layer index (0 = layer 1) for wire elements.
    pub layer: usize,
    /// Angle from the neutral axis (rad).
    pub theta_rad: f64,
    /// Reference axial coordinate (m).
    pub z_m: f64,
    /// Values, one per history sample.
    pub values: Vec<f64>,
}

/// Monitor time series of a history run, on the original time axis.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MonitorSeries {
    /// Sample times (s).
    pub time_s: Vec<f64>,
    /// Imposed axial strain.
    pub strain: Vec<f64>,
    /// Imposed curvature (1/m).
    pub curvature_per_m: Vec<f64>,
    /// Channels.
    pub channels: Vec<MonitorChannel>,
}

/// Index of the element minimising `score` among `candidates`.
fn best<I: Iterator<Item = usize>>(candidates: I, score: impl Fn(usize) -> f64) -> Option<usize> {
    candidates.min_by(|&a, &b| score(a).total_cmp(&score(b)))
}

/// Angular distance of an angle θ to a monitor's target angle.
type AngularDistance = fn(f64) -> f64;

/// Angular distance (rad, in [0, π]) from θ to the outer arc θ = π/2.
fn from_outer_arc(theta: f64) -> f64 {
    let d = (theta - std::f64::consts::FRAC_PI_2).rem_euclid(std::f64::consts::TAU);
    d.min(std::f64::consts::TAU - d)
}

/// Angular distance (rad, in [0, π/2]) from θ to the neutral axis θ ∈ {0, π}.
fn from_neutral_axis(theta: f64) -> f64 {
    let d = theta.rem_euclid(std::f64::consts::PI);
    d.min(std::f64::consts::PI - d)
}

/// The site at angle `target` (module docs): among `candidates` of angle `theta` and axial
/// coordinate `z`, those within `span` (rad) of the smallest angular distance, then the one
/// nearest `mid`; ties to the smaller index.
fn at_angle(
    candidates: &[usize],
    target: AngularDistance,
    span: f64,
    theta: impl Fn(usize) -> f64,
    z: impl Fn(usize) -> f64,
    mid: f64,
) -> Option<usize> {
    let closest = candidates
        .iter()
        .map(|&i| target(theta(i)))
        .min_by(f64::total_cmp)?;
    best(
        candidates
            .iter()
            .copied()
            .filter(|&i| target(theta(i)) <= closest + span),
        |i| (z(i) - mid).abs(),
    )
}

/// Angular span (rad) about the strand axis of the longest element of every helical layer.
fn element_angular_spans(model: &StrandModel) -> Vec<f64> {
    let wires = model.strand.wires();
    let mut spans = vec![0.0f64; model.strand.layers.len()];
    for el in &model.mesh.elements {
        let Some(layer) = wires[el.wire.0].layer else {
            continue;
        };
        let span = {
            let (a, b) = (
                &model.mesh.nodes[el.nodes[0].0].position,
                &model.mesh.nodes[el.nodes[1].0].position,
            );
            let (ta, tb) = (a.y.atan2(a.x), b.y.atan2(b.x));
            let d = (tb - ta).rem_euclid(std::f64::consts::TAU);
            d.min(std::f64::consts::TAU - d)
        };
        spans[layer] = spans[layer].max(span);
    }
    spans
}

/// The default monitor channels of `model` (module docs), with empty series.
pub(crate) fn default_channels(model: &StrandModel, sites: &[ContactSite]) -> Vec<MonitorChannel> {
    let mid = 0.5 * model.strand.model_length_m;
    let wires = model.strand.wires();
    let layers = model.strand.layers.len();
    let mut out = Vec::new();
    let contact_channels = |out: &mut Vec<MonitorChannel>, c: usize, group| {
        for quantity in [
            MonitorQuantity::NormalForce,
            MonitorQuantity::TangentialForce,
            MonitorQuantity::Slip,
        ] {
            out.push(MonitorChannel {
                quantity,
                target: MonitorTarget::Contact(c),
                group,
                layer: sites[c].interface,
                theta_rad: sites[c].theta_rad,
                z_m: sites[c].z_m,
                values: Vec::new(),
            });
        }
    };
    // interface i is that of helical layer i on the layer underneath
    let spans = element_angular_spans(model);
    let groups: [(MonitorGroup, AngularDistance); 2] = [
        (MonitorGroup::NeutralAxis, from_neutral_axis),
        (MonitorGroup::OuterArc, from_outer_arc),
    ];
    // contacts: neutral axis and outer arc of every interface
    for (interface, &span) in spans.iter().enumerate() {
        let candidates: Vec<usize> = (0..sites.len())
            .filter(|&c| sites[c].interface == interface)
            .collect();
        for (group, target) in groups {
            let theta = |c: usize| sites[c].theta_rad;
            if let Some(c) = at_angle(&candidates, target, span, theta, |c| sites[c].z_m, mid) {
                contact_channels(&mut out, c, group);
            }
        }
    }
    // wire elements: neutral axis and outer arc of every helical layer
    let element_sites: Vec<(f64, f64)> = model
        .mesh
        .elements
        .iter()
        .map(|el| {
            let (a, b) = (
                &model.mesh.nodes[el.nodes[0].0],
                &model.mesh.nodes[el.nodes[1].0],
            );
            let p = 0.5 * (a.position + b.position);
            (theta_from_neutral_axis(p.x, p.y), 0.5 * (a.z_m + b.z_m))
        })
        .collect();
    let element_layers: Vec<Option<usize>> = model
        .mesh
        .elements
        .iter()
        .map(|el| wires[el.wire.0].layer)
        .collect();
    for (layer, &span) in spans.iter().enumerate() {
        let candidates: Vec<usize> = (0..element_sites.len())
            .filter(|&e| element_layers[e] == Some(layer))
            .collect();
        for (group, target) in groups {
            let theta = |e: usize| element_sites[e].0;
            if let Some(e) = at_angle(
                &candidates,
                target,
                span,
                theta,
                |e| element_sites[e].1,
                mid,
            ) {
                let (theta_rad, z_m) = element_sites[e];
                out.push(MonitorChannel {
                    quantity: MonitorQuantity::WireAxialForce,
                    target: MonitorTarget::Element(e),
                    group,
                    layer,
                    theta_rad,
                    z_m,
                    values: Vec::new(),
                });
            }
        }
    }
    // ring: every wire of the outermost layer, its inner contact nearest mid-length
    if layers > 0 {
        let outer = layers - 1;
        for w in wires.iter().filter(|w| w.layer == Some(outer)) {
            let candidates = (0..sites.len()).filter(|&c| {
                let b = model.mesh.contacts[c].nodes[1].0;
                model.mesh.nodes[b].wire == w.id && sites[c].interface == outer
            });
            if let Some(c) = best(candidates, |c| (sites[c].z_m - mid).abs()) {
                contact_channels(&mut out, c, MonitorGroup::Ring);
            }
        }
    }
    out
}

/// Axial force of wire element `e` at `state` (N).
pub fn element_axial_force(
    model: &StrandModel,
    state: &FrameState,
    e: usize,
) -> Result<f64, FrameError> {
    let el = &model.frame.elements()[e];
    let [a, b] = el.nodes;
    el.beam
        .local_forces(
            &state.positions[a.0],
            &state.positions[b.0],
            &state.rotations[a.0],
            &state.rotations[b.0],
        )
        .map(|f| f.axial_n)
        .map_err(|source| FrameError::Element { element: e, source })
}
