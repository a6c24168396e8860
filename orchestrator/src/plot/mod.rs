//! SVG plots of run results (plotters, SVG backend only).
//!
//! - [`hotspots_svg`]: tension T(t) (kN) and curvature κ(t) (1/m) of every hot spot, one pair
//!   of stacked panels per hot spot, as the paper's Fig. 17.
//! - [`static_shapes_svg`]: static line profiles, depth versus horizontal distance from the
//!   fairlead, one curve per line.
//! - [`strand_history_svgs`]: monitors of a strand history run (wire axial force, contact
//!   normal and tangential force, slip against time per layer or interface, neutral axis and
//!   outer arc) and its load, as the paper's Figs. 19-22.

mod global;
mod strand;

pub(crate) use global::{bounds, panel, plot_err};
pub use global::{hotspots_svg, static_shapes_svg};
pub use strand::{strand_history_svgs, LoadPlot};
