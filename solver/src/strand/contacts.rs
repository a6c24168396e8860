//! Geometric detection of the fixed contact pairs of a strand (the paper's Sec. 2.2).
//!
//! - Trellis contacts between adjacent helical layers k, k+1 of opposite hand: wire i of layer k
//!   (θ = aᵢ + ωₖ z) and wire j of layer k+1 (θ = bⱼ + ωₖ₊₁ z) are radially aligned where
//!   (ωₖ − ωₖ₊₁) z = bⱼ − aᵢ + 2π m, m ∈ ℤ — solved exactly. There the segment between the two
//!   axes is radial, hence normal to both tangents, of length Rₖ₊₁ − Rₖ = rₖ + rₖ₊₁: the closest
//!   points of the two axes, at contact. Over a length L the interface holds
//!   nₖ nₖ₊₁ |ωₖ − ωₖ₊₁| L / 2π crossings.
//! - Adjacent layers of the same hand cross at a shallow angle (long line-like contacts); their
//!   crossings are solved the same way and reported as [`ContactKind::SameHandCrossing`].
//! - Line contact of layer 0 on the straight core: represented by points along each wire at a
//!   spacing (arc length) no larger than the requested one, uniformly over [0, L).
//!
//! Contacts are kept in z ∈ [0, L) (a crossing within 1e-9 L of L belongs to the next period).
//! Wire 1 of a pair is the inner wire; the contact normal points outwards.

use std::f64::consts::PI;

use nalgebra::Vector3;

use super::profile::Strand;
use super::wires::{Wire, WireId};

/// Kind of contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ContactKind {
    /// Crossing of wires of adjacent layers of opposite hand.
    Trellis,
    /// Point of the line contact between layer 0 and the core.
    CoreLine,
    /// Crossing of wires of adjacent layers of the same hand.
    SameHandCrossing,
}

/// One geometric contact point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// Kind.
    pub kind: ContactKind,
    /// Inner wire.
    pub inner: WireId,
    /// Outer wire.
    pub outer: WireId,
    /// Outer layer index of the interface (0 = core / layer 0).
    pub outer_layer: usize,
    /// Axial coordinate (m), the same on both wires.
    pub z_m: f64,
    /// Angular position of the contact in the cross section, wrapped to (−π, π] (rad).
    pub theta_rad: f64,
    /// Angle between the two wire tangents (rad).
    pub crossing_angle_rad: f64,
    /// Point on the inner wire axis.
    pub inner_position: Vector3<f64>,
    /// Point on the outer wire axis.
    pub outer_position: Vector3<f64>,
}

/// Counts of one layer interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceSummary {
    /// Outer layer index (inner is the core for 0, else layer − 1).
    pub outer_layer: usize,
    /// Kind of its contacts.
    pub kind: ContactKind,
    /// Number of contacts found.
    pub contacts: usize,
    /// Crossing count predicted by nₖ nₖ₊₁ |Δω| L / 2π (trellis and same-hand only).
    pub predicted: f64,
}

/// Contact detection settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSearchParameters {
    /// Maximum arc-length spacing of the core line contact points (m).
    pub core_line_spacing_m: f64,
}

impl Default for ContactSearchParameters {
    fn default() -> Self {
        Self {
            core_line_spacing_m: 5e-3,
        }
    }
}

/// Geometry errors.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// A parameter is out of range.
    #[error("{field} = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Field.
        field: &'static str,
        /// Value.
        value: f64,
        /// Why.
        reason: &'static str,
    },
    /// Adjacent layers with identical angular rate never cross: a true line contact this model
    /// does not represent.
    #[error("layers {inner} and {outer} have the same angular rate (same hand and lay length): parallel line contact not supported")]
    ParallelLayers {
        /// Inner layer.
        inner: usize,
        /// Outer layer.
        outer: usize,
    },
}

/// All contacts of a strand with per-interface counts.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSet {
    /// Contact points, grouped by interface, then inner wire, outer wire, z.
    pub contacts: Vec<ContactPoint>,
    /// Per-interface summary, innermost first.
    pub interfaces: Vec<InterfaceSummary>,
}

impl ContactSet {
    /// Number of contacts of a kind.
    pub fn count(&self, kind: ContactKind) -> usize {
        self.contacts.iter().filter(|c| c.kind == kind).count()
    }
}

fn wrap(theta: f64) -> f64 {
    let t = theta.rem_euclid(2.0 * PI);
    if t > PI {
        t - 2.0 * PI
    } else {
        t
    }
}

fn point(kind: ContactKind, a: &Wire, b: &Wire, outer_layer: usize, z: f64) -> ContactPoint {
    let (ta, tb) = (a.helix.tangent(z), b.helix.tangent(z));
    ContactPoint {
        kind,
        inner: a.id,
        outer: b.id,
        outer_layer,
        z_m: z,
        theta_rad: wrap(b.helix.angle(z)),
        crossing_angle_rad: ta.cross(&tb).norm().atan2(ta.dot(&tb)),
        inner_position: a.helix.position(z),
        outer_position: b.helix.position(z),
    }
}

/// Finds every contact of `strand` over its model length.
pub fn find_contacts(
    strand: &Strand,
    params: &ContactSearchParameters,
) -> Result<ContactSet, GeometryError> {
    let s = params.core_line_spacing_m;
    if !(s > 0.0 && s.is_finite()) {
        return Err(GeometryError::InvalidParameter {
            field: "core_line_spacing_m",
            value: s,
            reason: "must be finite and > 0",
        });
    }
    let length = strand.model_length_m;
    let tol = 1e-9 * length;
    let wires = strand.wires();
    let mut contacts = Vec::new();
    let mut interfaces = Vec::new();
    let layer_wires = |k: usize| wires.iter().filter(move |w| w.layer == Some(k));
    if let Some(l0) = strand.layers.first() {
        let dz = s * l0.lay_angle_rad.cos();
        let count = (length / dz).ceil().max(1.0) as usize;
        let before = contacts.len();
        for w in layer_wires(0) {
            for j in 0..count {
                contacts.push(point(
                    ContactKind::CoreLine,
                    &wires[0],
                    w,
                    0,
                    length * j as f64 / count as f64,
                ));
            }
        }
        interfaces.push(InterfaceSummary {
            outer_layer: 0,
            kind: ContactKind::CoreLine,
            contacts: contacts.len() - before,
            predicted: 0.0,
        });
    }
    for k in 1..strand.layers.len() {
        let (li, lo) = (&strand.layers[k - 1], &strand.layers[k]);
        let kind = if li.hand == lo.hand {
            ContactKind::SameHandCrossing
        } else {
            ContactKind::Trellis
        };
        let inner = layer_wires(k - 1)
            .next()
            .map(|w| w.helix.rate_rad_per_m)
            .unwrap_or(0.0);
        let outer = layer_wires(k)
            .next()
            .map(|w| w.helix.rate_rad_per_m)
            .unwrap_or(0.0);
        let dw = inner - outer;
        if dw.abs() * length < 1e-9 {
            return Err(GeometryError::ParallelLayers {
                inner: k - 1,
                outer: k,
            });
        }
        let period = 2.0 * PI / dw.abs();
        let before = contacts.len();
        for a in layer_wires(k - 1) {
            for b in layer_wires(k) {
                let z0 = (b.helix.phase_rad - a.helix.phase_rad) / dw;
                let mut m = ((-tol - z0) / period).ceil();
                loop {
                    let z = z0 + m * period;
                    if z >= length - tol {
                        break;
                    }
                    contacts.push(point(kind, a, b, k, z.max(0.0)));
                    m += 1.0;
                }
            }
        }
        interfaces.push(InterfaceSummary {
            outer_layer: k,
            kind,
            contacts: contacts.len() - before,
            predicted: (li.wires * lo.wires) as f64 * dw.abs() * length / (2.0 * PI),
        });
    }
    Ok(ContactSet {
        contacts,
        interfaces,
    })
}
