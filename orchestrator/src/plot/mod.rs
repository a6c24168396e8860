//! SVG plots of run results (plotters, SVG backend only).
//!
//! - [`hotspots_svg`]: tension T(t) (kN) and curvature κ(t) (1/m) of every hot spot, one pair
//!   of stacked panels per hot spot, as the seed's Fig. 17.
//! - [`static_shapes_svg`]: static line profiles, depth versus horizontal distance from the
//!   fairlead, one curve per line.

mod global;

pub(crate) use global::{bounds, panel, plot_err};
pub use global::{hotspots_svg, static_shapes_svg};
