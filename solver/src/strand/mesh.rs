//! Finite-element mesh of the strand wires: nodes on the exact centrelines at every contact
//! point, contact points of one wire closer than a merge tolerance (arc length) sharing a node,
//! end nodes at z = 0 and z = L, and intermediate nodes so that no element is longer than a
//! maximum length (arc length, equal subdivision). Two-node elements join consecutive nodes of a
//! wire; each contact joins its inner and outer wire nodes.
//!
//! Merged clusters take the z of an end node if they contain one, else the mean z of their
//! points, so a merged contact node lies off its exact contact point by at most the merge
//! tolerance; [`MeshContact::offset_m`] reports it.

use nalgebra::Vector3;

use super::contacts::{ContactKind, ContactSet, GeometryError};
use super::profile::Strand;
use super::wires::WireId;

/// Index of a mesh node.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct NodeId(pub usize);

/// Index of a contact element (same order as the contact points it comes from).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct ContactId(pub usize);

/// Meshing settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshParameters {
    /// Contact points of one wire closer than this arc length share a node (m).
    pub merge_tolerance_m: f64,
    /// Maximum element arc length (m).
    pub max_element_length_m: f64,
}

impl Default for MeshParameters {
    fn default() -> Self {
        Self {
            merge_tolerance_m: 1e-4,
            max_element_length_m: 1e-2,
        }
    }
}

/// A node on a wire centreline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshNode {
    /// Wire it belongs to.
    pub wire: WireId,
    /// Axial coordinate (m).
    pub z_m: f64,
    /// Position on the centreline (m).
    pub position: Vector3<f64>,
    /// Unit centreline tangent.
    pub tangent: Vector3<f64>,
}

/// A two-node wire element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshElement {
    /// Wire.
    pub wire: WireId,
    /// End nodes, increasing z.
    pub nodes: [NodeId; 2],
    /// Arc length between the nodes along the helix (m).
    pub length_m: f64,
}

/// A contact element between two nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshContact {
    /// Id.
    pub id: ContactId,
    /// Kind of the contact point.
    pub kind: ContactKind,
    /// Inner and outer node.
    pub nodes: [NodeId; 2],
    /// Largest distance between a node and its exact contact point (m).
    pub offset_m: f64,
}

/// Counts reported by the mesher.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct MeshStats {
    /// Wires.
    pub wires: usize,
    /// Nodes.
    pub nodes: usize,
    /// Wire elements.
    pub elements: usize,
    /// Contact elements.
    pub contacts: usize,
    /// Trellis contacts.
    pub trellis_contacts: usize,
    /// Core line contact points.
    pub core_line_contacts: usize,
    /// Same-hand crossing contacts.
    pub same_hand_contacts: usize,
    /// Contact-point nodes saved by merging.
    pub merged_points: usize,
    /// Shortest element (m).
    pub min_element_length_m: f64,
    /// Longest element (m).
    pub max_element_length_m: f64,
}

/// The mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct StrandMesh {
    /// Nodes, wire by wire in increasing z.
    pub nodes: Vec<MeshNode>,
    /// Wire elements.
    pub elements: Vec<MeshElement>,
    /// Contact elements, in the order of the contact set.
    pub contacts: Vec<MeshContact>,
    /// First node of each wire and one past its last.
    pub wire_nodes: Vec<std::ops::Range<usize>>,
    /// Counts.
    pub stats: MeshStats,
}

/// A contact point on a wire: z and, unless it is an end node, (contact index, side 0 = inner,
/// 1 = outer).
type WirePoint = (f64, Option<(usize, usize)>);

/// Meshes `strand` with nodes at the contact points of `contacts`.
pub fn build_mesh(
    strand: &Strand,
    contacts: &ContactSet,
    params: &MeshParameters,
) -> Result<StrandMesh, GeometryError> {
    let (tol, hmax) = (params.merge_tolerance_m, params.max_element_length_m);
    if !(tol >= 0.0 && tol.is_finite()) {
        return Err(GeometryError::InvalidParameter {
            field: "merge_tolerance_m",
            value: tol,
            reason: "must be finite and >= 0",
        });
    }
    if !(hmax > tol && hmax.is_finite()) {
        return Err(GeometryError::InvalidParameter {
            field: "max_element_length_m",
            value: hmax,
            reason: "must be finite and larger than merge_tolerance_m",
        });
    }
    let length = strand.model_length_m;
    let wires = strand.wires();
    // Per wire: (z, Some((contact index, side))) with side 0 = inner, 1 = outer.
    let mut points: Vec<Vec<WirePoint>> = vec![Vec::new(); wires.len()];
    for (c, p) in contacts.contacts.iter().enumerate() {
        points[p.inner.0].push((p.z_m, Some((c, 0))));
        points[p.outer.0].push((p.z_m, Some((c, 1))));
    }
    let mut contact_nodes = vec![[NodeId(0); 2]; contacts.contacts.len()];
    let mut nodes = Vec::new();
    let mut elements = Vec::new();
    let mut wire_nodes = Vec::with_capacity(wires.len());
    let mut merged = 0;
    for (w, pts) in wires.iter().zip(points.iter_mut()) {
        pts.push((0.0, None));
        pts.push((length, None));
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let cos_b = w.helix.lay_angle_rad.cos();
        // Clusters of points within the merge tolerance (arc length) of the cluster's first.
        let mut clusters: Vec<(f64, Vec<WirePoint>)> = Vec::new();
        for &p in pts.iter() {
            match clusters.last_mut() {
                Some((_, members)) if (p.0 - members[0].0) / cos_b <= tol => members.push(p),
                _ => clusters.push((0.0, vec![p])),
            }
        }
        for (z, members) in clusters.iter_mut() {
            let ends: Vec<f64> = members
                .iter()
                .filter(|m| m.1.is_none())
                .map(|m| m.0)
                .collect();
            *z = match ends.first() {
                Some(&e) => e,
                None => members.iter().map(|m| m.0).sum::<f64>() / members.len() as f64,
            };
            merged += members
                .iter()
                .filter(|m| m.1.is_some())
                .count()
                .saturating_sub(1);
        }
        let first = nodes.len();
        let push_node = |z: f64, nodes: &mut Vec<MeshNode>| {
            nodes.push(MeshNode {
                wire: w.id,
                z_m: z,
                position: w.helix.position(z),
                tangent: w.helix.tangent(z),
            });
            NodeId(nodes.len() - 1)
        };
        for (ci, (z, members)) in clusters.iter().enumerate() {
            if ci > 0 {
                let z_prev = clusters[ci - 1].0;
                let sub = (((z - z_prev) / cos_b) / hmax).ceil().max(1.0) as usize;
                for q in 1..sub {
                    push_node(z_prev + (z - z_prev) * q as f64 / sub as f64, &mut nodes);
                }
            }
            let id = push_node(*z, &mut nodes);
            for m in members.iter() {
                if let Some((c, side)) = m.1 {
                    contact_nodes[c][side] = id;
                }
            }
        }
        for i in first..nodes.len().saturating_sub(1) {
            let dz = nodes[i + 1].z_m - nodes[i].z_m;
            elements.push(MeshElement {
                wire: w.id,
                nodes: [NodeId(i), NodeId(i + 1)],
                length_m: dz / cos_b,
            });
        }
        wire_nodes.push(first..nodes.len());
    }
    let mesh_contacts: Vec<MeshContact> = contacts
        .contacts
        .iter()
        .enumerate()
        .map(|(c, p)| {
            let [a, b] = contact_nodes[c];
            let offset_m = (nodes[a.0].position - p.inner_position)
                .norm()
                .max((nodes[b.0].position - p.outer_position).norm());
            MeshContact {
                id: ContactId(c),
                kind: p.kind,
                nodes: [a, b],
                offset_m,
            }
        })
        .collect();
    let stats = MeshStats {
        wires: wires.len(),
        nodes: nodes.len(),
        elements: elements.len(),
        contacts: mesh_contacts.len(),
        trellis_contacts: contacts.count(ContactKind::Trellis),
        core_line_contacts: contacts.count(ContactKind::CoreLine),
        same_hand_contacts: contacts.count(ContactKind::SameHandCrossing),
        merged_points: merged,
        min_element_length_m: elements
            .iter()
            .map(|e| e.length_m)
            .fold(f64::INFINITY, f64::min),
        max_element_length_m: elements.iter().map(|e| e.length_m).fold(0.0, f64::max),
    };
    Ok(StrandMesh {
        nodes,
        elements,
        contacts: mesh_contacts,
        wire_nodes,
        stats,
    })
}
