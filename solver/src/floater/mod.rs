//! floater (module under construction).
