//! linalg (module under construction).
