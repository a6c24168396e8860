//! Contact samples of the whole model and the monitor channels of a history run (seed Figs.
//! 19-22).
//!
//! Slip convention: the scalar slip of a contact is the total relative tangential displacement
//! of its two wires since the reference configuration (contact element, [`crate::contact`])
//! projected on the current axis of the outer wire, t₂ = Λ₂ T₂. In bending, the wires of a
//! layer slide along their own axis over the layer underneath (Papailiou's model), so this is
//! the component that carries the fretting; the tangential force is projected on the same axis.
//!
//! Angle θ: measured from the bending neutral axis as in [`crate::fretting::record`]; a point of
//! reference cross-section coordinates (X, Y) has X = −R sin θ, Y = R cos θ, so that its bending
//! strain is κ R sin θ ([`crate::strand::loading`]). A contact's position is the midpoint of its
//! two nodes.
//!
//! Default monitors: for every layer interface, the contact nearest the neutral axis and the one
//! nearest the outer arc among those within a quarter of the model length of mid-length
//! (normal force, tangential force, slip); for every helical layer, the wire elements nearest the
//! neutral axis and the outer arc at mid-length (axial force); and a ring: for every wire of the
//! outermost layer, its contact with the layer underneath nearest mid-length.

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
pub fn theta_from_neutral_axis(x: f64, y: f64) -> f64 {
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
pub fn contact_sample(
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

/// The default monitor channels of `model` (module docs), with empty series.
pub fn default_channels(model: &StrandModel, sites: &[ContactSite]) -> Vec<MonitorChannel> {
    let length = model.strand.model_length_m;
    let mid = 0.5 * length;
    let window = 0.25 * length;
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
    let near = |z: f64| (z - mid).abs() <= window;
    // contacts: neutral axis and outer arc of every interface
    for interface in 0..layers {
        let candidates = || {
            (0..sites.len()).filter(move |&c| sites[c].interface == interface && near(sites[c].z_m))
        };
        let dz = |c: usize| 1e-3 * (sites[c].z_m - mid).abs() / length;
        if let Some(c) = best(candidates(), |c| sites[c].theta_rad.sin().abs() + dz(c)) {
            contact_channels(&mut out, c, MonitorGroup::NeutralAxis);
        }
        if let Some(c) = best(candidates(), |c| sites[c].theta_rad.cos().abs() + dz(c)) {
            contact_channels(&mut out, c, MonitorGroup::OuterArc);
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
    for layer in 0..layers {
        let candidates: Vec<usize> = (0..element_sites.len())
            .filter(|&e| element_layers[e] == Some(layer) && near(element_sites[e].1))
            .collect();
        let dz = |e: usize| 1e-3 * (element_sites[e].1 - mid).abs() / length;
        let groups: [(MonitorGroup, fn(f64) -> f64); 2] = [
            (MonitorGroup::NeutralAxis, |t: f64| t.sin().abs()),
            (MonitorGroup::OuterArc, |t: f64| t.cos().abs()),
        ];
        for (group, f) in groups {
            if let Some(e) = best(candidates.iter().copied(), |e| {
                f(element_sites[e].0) + dz(e)
            }) {
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
