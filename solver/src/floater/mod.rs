//! The floating platform: a rigid 6-DOF body with strip-theory (Morison) hydrodynamics on
//! cylindrical members, hydrostatics from the member geometry, gravity, rotor thrust and optional
//! linear damping; or, alternatively, a prescribed 6-DOF motion read from a table.
//!
//! - `spec`: serde description (`campaigns/data/oc4_semi_floater.json`) and validation.
//! - `members`: members, strips and their Morison loads and added mass.
//! - [`diffraction`]: optional MacCamy–Fuchs correction of the inertia for large members.
//! - `hydrostatics`: submerged volume, centre of buoyancy, waterplane, restoring matrix.
//! - `body`: rigid-body state, mass matrix, inertial terms, point kinematics.
//! - `model`: [`Floater`], the interface a coupled implicit integrator calls.
//! - [`dynamics`]: a generalised-α integrator of the floater alone with linear moorings.
//! - [`prescribed`]: prescribed motion from a time table, interpolated by cubic splines.
//!
//! Units SI; global frame z up, still water level z = 0; rotations follow
//! [`crate::beam::rotation`] (Λ ← exp(θ̂) Λ, spatial increments).

pub(crate) mod body;
pub mod diffraction;
pub mod dynamics;
pub(crate) mod error;
pub(crate) mod hydrostatics;
pub(crate) mod members;
pub(crate) mod model;
pub mod prescribed;
pub(crate) mod spec;

pub use body::{
    fairlead_body_points, fairlead_load, BodyState, MassProperties, PointKinematics, Wrench,
};
pub use error::FloaterError;
pub use model::{Floater, JacobianSteps, LoadBreakdown, LoadJacobians};
pub use spec::FloaterSpec;
