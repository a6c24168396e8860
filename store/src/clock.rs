//! Where the store takes "now" from: lease expiry, heartbeats, backoff and timestamps.
//!
//! Times are integer milliseconds since the Unix epoch (UTC). Hosts sharing one PostgreSQL
//! server should use [`Clock::Database`] so that every lease is measured on one clock; tests use
//! [`Clock::Manual`] to expire leases without sleeping.

use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Arc;
use std::time::{SystemTime, UNIX_EPOCH};

/// Source of the current time for the store.
#[derive(Debug, Clone, Default)]
pub enum Clock {
    /// This process's system clock.
    #[default]
    System,
    /// The database server's clock (one extra query per operation).
    Database,
    /// A clock moved by hand.
    Manual(ManualClock),
}

/// A shared, hand-driven clock; clones see the same time.
#[derive(Debug, Clone, Default)]
pub struct ManualClock {
    now_ms: Arc<AtomicI64>,
}

impl ManualClock {
    /// A clock reading `now_ms`.
    pub fn new(now_ms: i64) -> Self {
        Self {
            now_ms: Arc::new(AtomicI64::new(now_ms)),
        }
    }

    /// Current reading.
    pub fn now_ms(&self) -> i64 {
        self.now_ms.load(Ordering::SeqCst)
    }

    /// Moves the clock forward by `delta_ms` (backwards if negative).
    pub fn advance_ms(&self, delta_ms: i64) {
        self.now_ms.fetch_add(delta_ms, Ordering::SeqCst);
    }

    /// Sets the reading.
    pub fn set_ms(&self, now_ms: i64) {
        self.now_ms.store(now_ms, Ordering::SeqCst);
    }
}

/// Milliseconds since the Unix epoch on this host's clock (0 if the clock is before 1970).
pub fn system_now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manual_clock_clones_share_one_reading() {
        let clock = ManualClock::new(1_000);
        let other = clock.clone();
        other.advance_ms(250);
        assert_eq!(clock.now_ms(), 1_250);
        clock.set_ms(5);
        assert_eq!(other.now_ms(), 5);
    }
}
