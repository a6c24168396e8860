//! Sea states: the JONSWAP spectrum (DNV-RP-C205), finite-depth dispersion, seeded random
//! realisations, Airy kinematics with Wheeler stretching, precomputed kinematics at fixed points,
//! steady wind loads on the rotor and the wave scatter diagram of a site, also as directional
//! diagrams built from a sea-state time series.
//!
//! Every consumer of water kinematics (Morison loads on lines and floater members) goes through
//! [`SeaKinematics`], so a still sea, a regular wave or an irregular realisation are
//! interchangeable.
//!
//! Files: `spectrum` (JONSWAP), `dispersion` (ω² = g k tanh kd), `kinematics` (Airy sums with
//! Wheeler stretching), `realisation` ([`IrregularSea`], [`RegularWave`]), `series`
//! ([`PointKinematicsSeries`]: FFT precomputation at fixed points), `table`
//! ([`PlaneKinematicsTable`]: FFT precomputation on a vertical-plane grid around a moving body),
//! `fft`, `wind` (rotor loads,
//! wind speed per sea state), `scatter` (scatter-diagram tables), `climate` (directional scatter
//! tables from a hindcast or buoy series), `sea` (the shared trait) and
//! `error`. Gravity is `dispersion::GRAVITY` = 9.81 m/s² throughout.

mod error;
mod sea;

mod chebyshev;
pub mod climate;
pub mod dispersion;
pub mod fft;
pub(crate) mod kinematics;
pub mod realisation;
pub mod scatter;
pub(crate) mod series;
pub(crate) mod spectrum;
pub(crate) mod table;
pub mod wind;

pub use error::WavesError;
pub use kinematics::{AiryField, WaveComponent};
pub use realisation::{IrregularSea, RealisationParams, RegularWave, RepeatPeriod};
pub use scatter::{ScatterCell, ScatterError, ScatterTable, TotalKind, TotalMismatch};
pub use sea::{FluidKinematics, SeaKinematics, StillWater};
pub use series::{PointKinematicsSeries, PointSample, SeriesParams, SeriesStats};
pub use spectrum::{Jonswap, PeakEnhancement};
pub use table::{PlaneKinematicsTable, TableParams, TableRegion, TimeSlice};
pub use wind::{RotorLoads, RotorTable, WindLaw};
