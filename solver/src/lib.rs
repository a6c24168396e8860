//! # moorfret-solver
//!
//! All physics and numerics of moorfret, as pure computation (no I/O runtime, no database, no
//! printing): the global stage (waves, floater, mooring lines), the detailed strand stage (wire
//! beams, small-sliding frictional contact, periodic ends) and the fretting / fatigue statistics
//! that turn their histories into damage.
//!
//! Units are SI everywhere (m, s, kg, N, Pa, rad). Global frame: z up, still water level at
//! z = 0, seabed at z = -depth, waves travelling along +x unless a heading is given. Strand frame:
//! rope axis along z, bending about y (curvature κ > 0 bends the axis towards +x), wire angle θ
//! = +π/2 at the outer arc.
#![warn(missing_docs)]

pub mod beam;
pub mod contact;
pub mod damage;
pub mod fatigue;
pub mod floater;
pub mod fretting;
pub mod global;
pub mod io;
pub mod linalg;
pub mod mooring;
pub mod strand;
pub mod text;
pub mod waves;
