//! Wire numbering of a strand: [`WireId`] 0 is the core, then the wires of layer 0, layer 1, …
//! in order of their phase (wire i of layer k has phase φₖ + 2π i / nₖ).

use std::f64::consts::PI;

use super::helix::Helix;
use super::profile::Strand;

/// Index of a wire in the strand (0 = core).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct WireId(pub usize);

/// One wire: where it sits and its centreline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wire {
    /// Its id.
    pub id: WireId,
    /// Helical layer index, `None` for the core.
    pub layer: Option<usize>,
    /// Index within the layer.
    pub index: usize,
    /// Wire radius (m).
    pub radius_m: f64,
    /// Centreline.
    pub helix: Helix,
}

impl Strand {
    /// Every wire, core first.
    pub fn wires(&self) -> Vec<Wire> {
        let mut out = Vec::with_capacity(self.wire_count());
        out.push(Wire {
            id: WireId(0),
            layer: None,
            index: 0,
            radius_m: self.core_wire_radius_m,
            helix: Helix::straight(),
        });
        for (k, l) in self.layers.iter().enumerate() {
            for i in 0..l.wires {
                let phase = l.phase_rad + 2.0 * PI * i as f64 / l.wires as f64;
                out.push(Wire {
                    id: WireId(out.len()),
                    layer: Some(k),
                    index: i,
                    radius_m: l.wire_radius_m,
                    helix: Helix::new(l.helix_radius_m, l.lay_angle_rad, l.hand, phase),
                });
            }
        }
        out
    }

    /// Id of the first wire of helical layer `layer`.
    pub fn first_wire_of_layer(&self, layer: usize) -> WireId {
        WireId(
            1 + self
                .layers
                .iter()
                .take(layer)
                .map(|l| l.wires)
                .sum::<usize>(),
        )
    }
}
