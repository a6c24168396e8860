//! fatigue (module under construction).
