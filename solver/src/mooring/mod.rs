//! mooring (module under construction).
