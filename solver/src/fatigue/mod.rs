//! Classical tension-tension fatigue of mooring components and lifetime aggregation
//! (`docs/damage.md`).
//!
//! - `tn`: T-N curves of DNV-OS-E301 and API RP 2SK with their nominal areas / strengths;
//! - `miner`: Palmgren-Miner damage from rainflow cycles, histograms and tension series;
//! - `lifetime`: occurrence-weighted sum over sea states and seeds, with the covered fraction
//!   of the year reported, never renormalised.
//!
//! Units: N, m², s; damage is dimensionless.

pub(crate) mod error;
pub(crate) mod lifetime;
pub(crate) mod miner;
pub(crate) mod tn;

pub use error::FatigueError;
pub use lifetime::{lifetime_damage, LifetimeDamage, SeaStateDamage, SeedDamage, SECONDS_PER_YEAR};
pub use miner::{histogram_damage, miner_damage, sea_state_tension_damage, TensionDamage};
pub use tn::{chain_nominal_area_m2, rope_nominal_area_m2, ApiComponent, DnvComponent, TnCurve};
