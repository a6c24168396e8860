//! io (module under construction).
