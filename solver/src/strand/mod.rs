//! strand (module under construction).
