//! contact (module under construction).
