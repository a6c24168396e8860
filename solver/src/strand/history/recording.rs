//! What a history run keeps between segments besides the solver state: the outputs of one
//! solved state ([`Snapshot`], interpolated between sub-steps back to the original samples) and
//! the streaming consumers of those samples ([`Recorder`]: per-contact rainflow counters, closed
//! cycles, peak normal forces, monitor series), with the contact records they finally give.
//!
//! Both are part of a history checkpoint, so they live apart from the run loop that fills them
//! and from the checkpoint that stores them.

use super::monitors::{
    contact_sites, MonitorChannel, MonitorQuantity, MonitorSeries, MonitorTarget,
};
use super::{HistoryError, LoadSample};
use crate::fretting::{ContactCycleAccumulator, ContactRecord, ContactSample, SlipCycle};
use crate::strand::model::StrandModel;

/// Everything the outputs need of one solved state: every contact's sample and the wire
/// element channels' values (in channel order, contact channels skipped).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub(super) struct Snapshot {
    pub(super) contacts: Vec<ContactSample>,
    pub(super) elements: Vec<f64>,
}

impl Snapshot {
    /// (1 − f) a + f b, field by field (exactly b at f = 1).
    pub(super) fn blend(a: &Self, b: &Self, f: f64, out: &mut Self) {
        let mix = |x: f64, y: f64| (1.0 - f) * x + f * y;
        for ((o, x), y) in out.contacts.iter_mut().zip(&a.contacts).zip(&b.contacts) {
            *o = ContactSample {
                slip_m: mix(x.slip_m, y.slip_m),
                normal_force_n: mix(x.normal_force_n, y.normal_force_n),
                tangential_force_n: mix(x.tangential_force_n, y.tangential_force_n),
            };
        }
        for ((o, x), y) in out.elements.iter_mut().zip(&a.elements).zip(&b.elements) {
            *o = mix(*x, *y);
        }
    }
}

/// Streaming consumers of the interpolated samples: rainflow counters and monitor series.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub(super) struct Recorder {
    accumulators: Vec<ContactCycleAccumulator>,
    cycles: Vec<Vec<SlipCycle>>,
    max_normal: Vec<f64>,
    pub(super) monitors: MonitorSeries,
}

impl Recorder {
    pub(super) fn new(
        contacts: usize,
        gate: f64,
        channels: Vec<MonitorChannel>,
    ) -> Result<Self, HistoryError> {
        let acc = ContactCycleAccumulator::new(gate).map_err(|e| HistoryError::InvalidOption {
            field: "slip_gate_m",
            value: gate,
            reason: e.to_string(),
        })?;
        Ok(Self {
            accumulators: vec![acc; contacts],
            cycles: vec![Vec::new(); contacts],
            max_normal: vec![0.0; contacts],
            monitors: MonitorSeries {
                channels,
                ..MonitorSeries::default()
            },
        })
    }

    /// Consumes the state of original sample `sample`.
    pub(super) fn push(
        &mut self,
        sample: &LoadSample,
        snap: &Snapshot,
    ) -> Result<(), HistoryError> {
        for (c, s) in snap.contacts.iter().enumerate() {
            self.accumulators[c]
                .push(*s, &mut self.cycles[c])
                .map_err(|source| HistoryError::Fretting { contact: c, source })?;
            self.max_normal[c] = self.max_normal[c].max(s.normal_force_n);
        }
        let m = &mut self.monitors;
        m.time_s.push(sample.time_s);
        m.strain.push(sample.strain);
        m.curvature_per_m.push(sample.curvature_per_m);
        let mut element = 0;
        for ch in &mut m.channels {
            let v = match ch.target {
                MonitorTarget::Element(_) => {
                    element += 1;
                    snap.elements[element - 1]
                }
                MonitorTarget::Contact(c) => {
                    let s = &snap.contacts[c];
                    match ch.quantity {
                        MonitorQuantity::NormalForce => s.normal_force_n,
                        MonitorQuantity::TangentialForce => s.tangential_force_n,
                        _ => s.slip_m,
                    }
                }
            };
            ch.values.push(v);
        }
        Ok(())
    }

    /// The contact records (residue closed as half cycles).
    pub(super) fn records(&self, model: &StrandModel) -> Vec<ContactRecord> {
        let sites = contact_sites(model);
        sites
            .iter()
            .enumerate()
            .map(|(c, site)| {
                let mut cycles = self.cycles[c].clone();
                self.accumulators[c].finish(&mut cycles);
                ContactRecord {
                    interface: site.interface,
                    theta_rad: site.theta_rad,
                    z_m: site.z_m,
                    max_normal_force_n: self.max_normal[c],
                    cycles,
                }
            })
            .collect()
    }
}
