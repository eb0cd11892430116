//! The reward, and how an episode ends.
//!
//! By default the reward is the negative of Cost_total's increment (`docs/metrics.md`):
//! over the steps an action covers, `−(w_d · px driven + w_t · steps + w_c · collisions)`
//! with the scenario's `[cost]` weights, so that the rewards of a complete episode add up to
//! `−Cost_total` exactly (up to float rounding). Two more terms are off by default:
//! `−charge` per arrival at a charger (C) and `+delivery` per delivery.
//!
//! Episodes end with the run:
//!
//! | outcome | ends as | reward at the end |
//! | --- | --- | --- |
//! | `complete` | terminated | the last increment |
//! | `incomplete` (step limit), `horizon` (lifelong) | truncated | the last increment |
//! | `gridlock`, `stalled`, `stranded`, `livelock` | terminated | the last increment and the failure penalty |
//!
//! The failure penalty keeps a jam from paying: with the cost reward, ending a run early
//! would otherwise save the time it did not run. By default ([`Failure::Clock`]) it is the
//! time weight times the steps left to the step limit (or the horizon), as if the clock ran
//! on to the limit; [`Failure::Fixed`] sets a constant instead.

use crate::error::{Error, Result};
use crate::input::scenario::CostWeights;
use crate::record::metrics::{Outcome, RobotStats};
use crate::rules::paper::Paper;
use crate::rules::Engine;

/// The failure penalty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Failure {
    /// `time` × the steps left to the step limit (or the lifelong horizon).
    Clock,
    /// This much (0 turns it off).
    Fixed(f64),
}

/// The weights of the reward's terms.
#[derive(Clone, Debug, PartialEq)]
pub struct RewardWeights {
    /// Per px driven by the fleet (w_d).
    pub distance: f64,
    /// Per step (w_t).
    pub time: f64,
    /// Per collision S (w_c).
    pub collision: f64,
    /// Per arrival at a charger (C); default 0.
    pub charge: f64,
    /// Gained per delivery; default 0.
    pub delivery: f64,
    /// At a failed end (gridlock, stalled, stranded, livelock).
    pub failure: Failure,
}

impl RewardWeights {
    /// The negative of Cost_total's increment, with the failure penalty of the clock.
    #[must_use]
    pub fn cost(w: &CostWeights) -> RewardWeights {
        RewardWeights { distance: w.distance, time: w.time, collision: w.collision, charge: 0.0, delivery: 0.0, failure: Failure::Clock }
    }

    /// Every weight must be a finite number.
    pub fn check(&self) -> Result<()> {
        let fixed = match self.failure {
            Failure::Fixed(v) => v,
            Failure::Clock => 0.0,
        };
        for (name, v) in [
            ("distance", self.distance),
            ("time", self.time),
            ("collision", self.collision),
            ("charge", self.charge),
            ("delivery", self.delivery),
            ("failure", fixed),
        ] {
            if !v.is_finite() {
                return Err(Error::scenario(format!("reward.{name}"), v, "must be a finite number"));
            }
        }
        Ok(())
    }
}

/// How an episode ends, from the run's outcome.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ending {
    /// The work is done, or the run can do nothing more.
    pub terminated: bool,
    /// Cut short by the step limit or the horizon.
    pub truncated: bool,
    /// One of the failed ends, which pay the failure penalty.
    pub failed: bool,
}

impl Ending {
    /// The ending of a run with this outcome (`None`: still running).
    #[must_use]
    pub fn of(outcome: Option<Outcome>) -> Ending {
        let (terminated, truncated, failed) = match outcome {
            None => (false, false, false),
            Some(Outcome::Complete) => (true, false, false),
            Some(Outcome::Incomplete | Outcome::Horizon) => (false, true, false),
            // The horizon ended it, with the fleet no longer delivering.
            Some(Outcome::Collapse) => (false, true, true),
            Some(Outcome::Gridlock | Outcome::Stalled | Outcome::Stranded | Outcome::Livelock | Outcome::Deadlock | Outcome::Fault) => (true, false, true),
        };
        Ending { terminated, truncated, failed }
    }
}

/// The run's totals when the last reward was paid.
#[derive(Clone, Debug, Default)]
pub(crate) struct Account {
    t: u64,
    distance: Vec<f64>,
    collisions: Vec<u32>,
    charges: Vec<u32>,
    delivered: Vec<u32>,
}

impl Account {
    /// Totals at the start of a run: zero.
    pub fn new(robots: usize) -> Account {
        Account { t: 0, distance: vec![0.0; robots], collisions: vec![0; robots], charges: vec![0; robots], delivered: vec![0; robots] }
    }

    /// Back to the start of a run.
    pub fn restart(&mut self, robots: usize) {
        self.t = 0;
        for v in [&mut self.collisions, &mut self.charges, &mut self.delivered] {
            v.clear();
            v.resize(robots, 0);
        }
        self.distance.clear();
        self.distance.resize(robots, 0.0);
    }

    /// Pays out the stretch of the run since the last call: the fleet's reward, and with
    /// `shares` each robot's part of it (its own distance, collisions, charges and
    /// deliveries, and an equal share of the time and the failure penalty). The parts add up
    /// to the fleet's reward up to float rounding.
    pub fn pay(&mut self, paper: &Paper, w: &RewardWeights, mut shares: Option<&mut [f64]>) -> f64 {
        let st: &RobotStats = paper.stats();
        let n = st.distance.len();
        let steps = (paper.t() - self.t) as f64;
        let mut common = -w.time * steps;
        if Ending::of(paper.outcome()).failed {
            common -= match w.failure {
                Failure::Clock => w.time * paper.limit().saturating_sub(paper.t()) as f64,
                Failure::Fixed(v) => v,
            };
        }
        self.t = paper.t();
        let mut total = common;
        for i in 0..n {
            let d = st.distance[i] - self.distance[i];
            let own = -w.distance * d - w.collision * f64::from(st.collisions[i] - self.collisions[i]) - w.charge * f64::from(st.charges[i] - self.charges[i])
                + w.delivery * f64::from(st.delivered[i] - self.delivered[i]);
            self.distance[i] = st.distance[i];
            self.collisions[i] = st.collisions[i];
            self.charges[i] = st.charges[i];
            self.delivered[i] = st.delivered[i];
            total += own;
            if let Some(out) = shares.as_deref_mut() {
                out[i] = own + common / n as f64;
            }
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endings_follow_the_outcome() {
        assert_eq!(Ending::of(Some(Outcome::Complete)), Ending { terminated: true, truncated: false, failed: false });
        assert_eq!(Ending::of(Some(Outcome::Horizon)), Ending { terminated: false, truncated: true, failed: false });
        assert_eq!(Ending::of(Some(Outcome::Incomplete)), Ending { terminated: false, truncated: true, failed: false });
        assert_eq!(Ending::of(Some(Outcome::Stalled)), Ending { terminated: true, truncated: false, failed: true });
        assert_eq!(Ending::of(None), Ending { terminated: false, truncated: false, failed: false });
    }

    #[test]
    fn weights_must_be_finite() {
        let mut w = RewardWeights::cost(&CostWeights::default());
        assert!(w.check().is_ok());
        w.delivery = f64::NAN;
        assert_eq!(w.check().unwrap_err().to_string(), "reward.delivery = NaN: must be a finite number");
    }
}
