//! Learning environments, engine side: what `multibots.envs` (Gymnasium and PettingZoo) runs.
//!
//! A run pauses at its decision points ([`crate::rules::paper::decision_point`]); there every idle robot
//! takes one *action*: the goods in one of the first `max_queue` slots of the queue, "charge
//! now", or "wait". The engine keeps everything between two actions: the order robots decide
//! in, which goods robots before them took, the observation features, the action mask, the
//! reward and how an episode ends. The Python package only shapes the arrays into spaces.
//!
//! | module | what it holds |
//! | --- | --- |
//! | this one | [`Settings`] (queue slots, reward weights) and [`Action`] (an action's code and meaning) |
//! | `round` | one decision point's actions, robot by robot: order, taken slots, masks, forced waits |
//! | [`observation`] | the features a decider sees, the action mask, the global state, their bounds |
//! | [`reward`] | reward weights, the reward of a stretch of the run, and how an episode ends |
//! | [`dispatcher`] | one robot's action per call: the single-agent environment |
//! | [`fleet`] | every robot's action per call: the multi-agent environment |
//! | [`vector`] | many dispatchers stepped in one call, on threads |
//!
//! The paper rules only: the original rules hand out goods inside the authors' code and
//! take no decisions ([`crate::rules::paper::decision_point`]).

pub mod dispatcher;
pub mod fleet;
pub mod observation;
pub mod reward;
mod round;
pub mod vector;

pub use dispatcher::Dispatcher;
pub use fleet::Fleet;
pub use observation::{Encoder, ObsMut};
pub use reward::{Ending, Failure, RewardWeights};
pub use round::decide_each;
pub use vector::VectorDispatch;

use crate::error::{Error, Result};
use crate::input::scenario::{Rules, Scenario};

/// Queue slots an observation shows by default: the paper's task lists hold 10 goods.
pub const DEFAULT_MAX_QUEUE: usize = 10;
/// The most queue slots an environment may show.
pub const MAX_QUEUE_LIMIT: usize = 1024;

/// What an environment takes besides its scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Queue slots an observation shows and an action can pick from (the front of the queue).
    pub max_queue: usize,
    /// How the reward is made.
    pub reward: RewardWeights,
    /// What a masked-out action does.
    pub invalid: InvalidAction,
}

/// What an action the mask does not allow does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InvalidAction {
    /// It is refused with [`Error::Decision`], naming the action, the robot and why; nothing
    /// changes. The default.
    #[default]
    Refuse,
    /// It counts as "wait", and the step says so. For tools that sample actions without the
    /// mask (Gymnasium's `check_env`, PettingZoo's `parallel_seed_test`, a plain random agent).
    Wait,
}

impl Settings {
    /// The defaults for a scenario: [`DEFAULT_MAX_QUEUE`] slots, and the reward of
    /// Cost_total with the scenario's `[cost]` weights.
    #[must_use]
    pub fn of(scenario: &Scenario) -> Settings {
        Settings { max_queue: DEFAULT_MAX_QUEUE, reward: RewardWeights::cost(&scenario.cost), invalid: InvalidAction::Refuse }
    }

    /// One-line errors naming the setting and its value.
    pub fn check(&self) -> Result<()> {
        if self.max_queue == 0 || self.max_queue > MAX_QUEUE_LIMIT {
            return Err(Error::scenario("max_queue", self.max_queue, format!("must be 1 to {MAX_QUEUE_LIMIT}")));
        }
        self.reward.check()
    }

    /// Actions per decision: one per queue slot, then "charge now" and "wait".
    #[must_use]
    pub fn actions(&self) -> usize {
        self.max_queue + 2
    }
}

/// Refuses a scenario whose rules take no decisions.
pub(crate) fn check_rules(scenario: &Scenario) -> Result<()> {
    if scenario.rules == Rules::Original {
        return Err(crate::rules::paper::decision_point::no_decisions());
    }
    Ok(())
}

/// What an action means. Codes: `0..max_queue` take the goods in that queue slot (front
/// first), `max_queue` is "charge now", `max_queue + 1` is "wait".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// The goods in this queue slot.
    Take(usize),
    /// Go to charge now (the charging rule picks the charger).
    Charge,
    /// Stay idle until the next decision point.
    Wait,
}

impl Action {
    /// The action a code means with `max_queue` slots, if the code is one.
    #[must_use]
    pub fn decode(code: i64, max_queue: usize) -> Option<Action> {
        let q = max_queue as i64;
        match code {
            c if (0..q).contains(&c) => Some(Action::Take(c as usize)),
            c if c == q => Some(Action::Charge),
            c if c == q + 1 => Some(Action::Wait),
            _ => None,
        }
    }

    /// The code of this action with `max_queue` slots.
    #[must_use]
    pub fn code(self, max_queue: usize) -> i64 {
        match self {
            Action::Take(k) => k as i64,
            Action::Charge => max_queue as i64,
            Action::Wait => max_queue as i64 + 1,
        }
    }

    /// A few words on what it does, for error messages.
    #[must_use]
    pub fn describe(self) -> String {
        match self {
            Action::Take(k) => format!("take the goods in queue slot {k}"),
            Action::Charge => "charge now".into(),
            Action::Wait => "wait".into(),
        }
    }
}

/// The one-line error for an action code that is not one.
pub(crate) fn bad_code(step: u64, code: i64, max_queue: usize) -> Error {
    Error::Decision {
        step,
        reason: format!(
            "action = {code}: out of range 0..={} (0..={} take the goods in that queue slot, {} charge now, {} wait)",
            max_queue + 1,
            max_queue - 1,
            max_queue,
            max_queue + 1
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_bad_ones_are_none() {
        for code in 0..12 {
            assert_eq!(Action::decode(code, 10).unwrap().code(10), code);
        }
        assert_eq!(Action::decode(10, 10), Some(Action::Charge));
        assert_eq!(Action::decode(11, 10), Some(Action::Wait));
        assert_eq!((Action::decode(12, 10), Action::decode(-1, 10)), (None, None));
        assert_eq!(
            bad_code(3, 12, 10).to_string(),
            "decision at step 3: action = 12: out of range 0..=11 (0..=9 take the goods in that queue slot, 10 charge now, 11 wait)"
        );
    }

    #[test]
    fn settings_are_checked_naming_the_field() {
        let s = Scenario::paper(3, &[1]);
        let mut st = Settings::of(&s);
        assert_eq!((st.max_queue, st.actions()), (10, 12));
        st.max_queue = 0;
        assert_eq!(st.check().unwrap_err().to_string(), "max_queue = 0: must be 1 to 1024");
    }
}
