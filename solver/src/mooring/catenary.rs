//! Placeholder (local only) until the catenary module lands.
