//! Analytical elastic catenary with seabed contact (under construction).
