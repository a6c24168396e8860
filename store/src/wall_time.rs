//! Wall-time budget of a worker whose allocation ends at a known time (Slurm `--time`, a
//! Kubernetes `activeDeadlineSeconds`, a reservation): which jobs still fit.
//!
//! A worker never starts a job whose expected cost exceeds its remaining wall time
//! (`deploy/README.md`). The budget turns "time left" into the number the store filters on,
//! [`ClaimFilter::max_expected_cost_s`]:
//!
//! `max_expected_cost_s(t) = max(0, t_end − t − reserve)`,
//!
//! where the reserve covers what follows a job: storing its results and, when the scheduler's
//! stop signal comes first, releasing the lease. Times are seconds on the worker's monotonic
//! clock, so a change of the system clock does not move the end.

use std::time::{Duration, Instant};

use super::error::StoreError;
use super::model::ClaimFilter;

/// Time left to a worker and the reserve it keeps for finishing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WallTimeBudget {
    ends_at: Instant,
    reserve: Duration,
}

impl WallTimeBudget {
    /// A budget of `wall_time_s` seconds from `started`, of which the last `reserve_s` are kept
    /// for finishing. Both must be finite; the wall time positive, the reserve non-negative and
    /// shorter than the wall time.
    pub fn new(wall_time_s: f64, reserve_s: f64, started: Instant) -> Result<Self, StoreError> {
        let invalid = |field: &'static str, value: f64, reason: &'static str| {
            Err(StoreError::InvalidParameter {
                field,
                value: value.to_string(),
                reason,
            })
        };
        if !(wall_time_s.is_finite() && wall_time_s > 0.0) {
            return invalid(
                "wall_time_s",
                wall_time_s,
                "must be a positive number of seconds",
            );
        }
        if !(reserve_s.is_finite() && reserve_s >= 0.0) {
            return invalid(
                "reserve_s",
                reserve_s,
                "must be a non-negative number of seconds",
            );
        }
        if reserve_s >= wall_time_s {
            return invalid("reserve_s", reserve_s, "must be shorter than wall_time_s");
        }
        Ok(Self {
            ends_at: started + Duration::from_secs_f64(wall_time_s),
            reserve: Duration::from_secs_f64(reserve_s),
        })
    }

    /// Wall time left at `now` (zero once the end has passed).
    pub fn remaining(&self, now: Instant) -> Duration {
        self.ends_at.saturating_duration_since(now)
    }

    /// Longest expected cost, s, of a job that may still be started at `now`.
    pub fn max_expected_cost_s(&self, now: Instant) -> f64 {
        self.remaining(now)
            .saturating_sub(self.reserve)
            .as_secs_f64()
    }

    /// `filter` further limited to the jobs that fit at `now` (a tighter limit already in
    /// `filter` is kept).
    pub fn restrict(&self, filter: &ClaimFilter, now: Instant) -> ClaimFilter {
        let fits = self.max_expected_cost_s(now);
        ClaimFilter {
            kinds: filter.kinds.clone(),
            max_expected_cost_s: Some(filter.max_expected_cost_s.map_or(fits, |m| m.min(fits))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budget_shrinks_with_elapsed_time_and_keeps_the_reserve() {
        let start = Instant::now();
        let budget = WallTimeBudget::new(3_600.0, 120.0, start).unwrap();
        assert_eq!(budget.max_expected_cost_s(start), 3_480.0);
        let later = start + Duration::from_secs(3_000);
        assert_eq!(budget.remaining(later), Duration::from_secs(600));
        assert_eq!(budget.max_expected_cost_s(later), 480.0);
        // Inside the reserve and past the end nothing fits.
        assert_eq!(
            budget.max_expected_cost_s(start + Duration::from_secs(3_500)),
            0.0
        );
        assert_eq!(
            budget.max_expected_cost_s(start + Duration::from_secs(9_999)),
            0.0
        );
    }

    #[test]
    fn restriction_keeps_kinds_and_the_tighter_limit() {
        let start = Instant::now();
        let budget = WallTimeBudget::new(1_000.0, 100.0, start).unwrap();
        let filter = ClaimFilter {
            kinds: vec![crate::JobKind::Strand],
            max_expected_cost_s: Some(300.0),
        };
        let early = budget.restrict(&filter, start);
        assert_eq!(early.kinds, filter.kinds);
        assert_eq!(early.max_expected_cost_s, Some(300.0));
        let late = budget.restrict(&filter, start + Duration::from_secs(750));
        assert_eq!(late.max_expected_cost_s, Some(150.0));
        let open = budget.restrict(&ClaimFilter::default(), start);
        assert_eq!(open.max_expected_cost_s, Some(900.0));
    }

    #[test]
    fn bad_budgets_name_the_field() {
        let now = Instant::now();
        for (wall, reserve, field) in [
            (0.0, 0.0, "wall_time_s"),
            (f64::NAN, 0.0, "wall_time_s"),
            (f64::INFINITY, 0.0, "wall_time_s"),
            (100.0, -1.0, "reserve_s"),
            (100.0, 100.0, "reserve_s"),
        ] {
            match WallTimeBudget::new(wall, reserve, now) {
                Err(StoreError::InvalidParameter { field: f, .. }) => assert_eq!(f, field),
                other => panic!("({wall}, {reserve}) gave {other:?}"),
            }
        }
    }
}
