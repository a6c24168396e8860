//! # moorfret-studies
//!
//! What the study binaries (`src/bin/`) share: the directional finite-difference check of a
//! strand tangent, an irregular (ε, κ) load history, the reading of load files and the log
//! subscriber. The studies measure
//! the solver (convergence, cost, tolerances, tangents); `README.md` lists them with their
//! commands.

pub mod directional;
pub mod irregular;
pub mod load_file;
pub mod logging;
