//! One decision point's actions, robot by robot: the dispatcher environment and a policy used
//! as an allocator ([`decide_each`]) go through this same code, so a policy sees and does the
//! same in both.
//!
//! Idle robots decide in ascending id. Goods a robot takes are gone for the robots after it
//! (their slots close). A robot whose only allowed action is "wait" (every visible slot taken
//! by robots before it, and a full battery) is not asked: it waits. The first robot always
//! has a choice (the front slot is open), so every decision point asks at least once. When
//! the last robot has decided, the point's [`Decisions`] go to the engine.

use super::observation::{Encoder, Marks, Observation};
use super::{Action, InvalidAction};
use crate::alloc::{AllocView, Assignment, Decisions};
use crate::error::{Error, Result};
use crate::ids::{RobotId, NONE};

/// The actions of one decision point so far.
#[derive(Clone, Debug, Default)]
pub(crate) struct Round {
    /// Idle robots, ascending; `order[cursor]` decides now.
    order: Vec<RobotId>,
    cursor: usize,
    pub marks: Marks,
    pub decisions: Decisions,
}

impl Round {
    /// A new decision point: its idle robots, none decided yet. Robots without a choice wait.
    pub fn start(&mut self, view: &AllocView<'_>, enc: &Encoder) {
        self.order.clear();
        self.order.extend_from_slice(view.idle);
        self.cursor = 0;
        self.marks.start(view, &self.order, enc.max_queue());
        self.decisions.clear();
        self.skip_forced(view, enc);
    }

    /// The robot deciding now.
    pub fn current(&self) -> Option<RobotId> {
        self.order.get(self.cursor).copied()
    }

    /// Whether every robot has decided.
    pub fn finished(&self) -> bool {
        self.cursor >= self.order.len()
    }

    fn has_choice(&self, view: &AllocView<'_>, enc: &Encoder, r: RobotId) -> bool {
        (0..enc.max_queue()).any(|k| Encoder::slot_open(view, &self.marks, k)) || enc.can_charge(view, r)
    }

    fn skip_forced(&mut self, view: &AllocView<'_>, enc: &Encoder) {
        while let Some(r) = self.current() {
            if self.has_choice(view, enc, r) {
                break;
            }
            self.marks.robot[r.index()] = 2;
            self.cursor += 1;
        }
    }

    /// Why robot `r` may not take `action` at this point, if it may not.
    pub fn refusal(&self, view: &AllocView<'_>, enc: &Encoder, r: RobotId, action: Action) -> Option<String> {
        match action {
            Action::Take(k) if k >= view.goods.len() => Some(format!("queue slot {k} is empty ({} goods open)", view.goods.len())),
            Action::Take(k) if self.marks.taken[k] != NONE => {
                Some(format!("robot {} took the goods in queue slot {k} at this decision point", self.marks.taken[k]))
            }
            Action::Charge if !enc.can_charge(view, r) => Some(format!("robot {r} is full (energy {})", view.energy(r))),
            _ => None,
        }
    }

    /// Records an allowed action of the robot deciding now, and moves on to the next robot
    /// with a choice.
    pub fn apply(&mut self, view: &AllocView<'_>, enc: &Encoder, action: Action) {
        let Some(r) = self.current() else { return };
        match action {
            Action::Take(k) => {
                self.marks.taken[k] = r.0;
                self.decisions.assign.push(Assignment { robot: r, goods: view.goods[k].id });
            }
            Action::Charge => self.decisions.charge.push(r),
            Action::Wait => {}
        }
        self.marks.robot[r.index()] = 2;
        self.cursor += 1;
        self.skip_forced(view, enc);
    }

    /// Checks an action code of the robot deciding now: the action to record, and whether a
    /// masked-out action was taken as "wait".
    pub fn resolve(&self, view: &AllocView<'_>, enc: &Encoder, code: i64, invalid: InvalidAction) -> Result<(Action, bool)> {
        let q = enc.max_queue();
        let Some(action) = Action::decode(code, q) else { return Err(super::bad_code(view.step, code, q)) };
        let r = self.current().expect("a robot decides");
        match (self.refusal(view, enc, r, action), invalid) {
            (None, _) => Ok((action, false)),
            (Some(_), InvalidAction::Wait) => Ok((Action::Wait, true)),
            (Some(why), InvalidAction::Refuse) => {
                Err(Error::Decision { step: view.step, reason: format!("action = {code} ({}): not allowed for robot {r}: {why}", action.describe()) })
            }
        }
    }

    /// The observation of the robot deciding now.
    pub fn observe(&self, view: &AllocView<'_>, enc: &Encoder, out: super::ObsMut<'_>) {
        let r = self.current().expect("a robot decides");
        enc.observe(view, r, &self.marks, true, out);
    }
}

/// A policy as an allocator: at a decision point, asks `policy` for each robot's action in
/// the dispatcher environment's order, with the observation that environment would show, and
/// returns the point's decisions. `policy` gets the robot and its observation and returns an
/// action code.
///
/// # Errors
/// The policy's own error, or [`Error::Decision`] for an action code that is not one, or (with
/// [`InvalidAction::Refuse`]) an action its mask does not allow.
pub fn decide_each(
    view: &AllocView<'_>,
    enc: &Encoder,
    invalid: InvalidAction,
    mut policy: impl FnMut(RobotId, &Observation) -> Result<i64>,
) -> Result<Decisions> {
    let mut round = Round::default();
    round.start(view, enc);
    let mut obs = Observation::zeros(view.robot_count(), enc.max_queue());
    while let Some(r) = round.current() {
        round.observe(view, enc, obs.as_mut());
        let code = policy(r, &obs)?;
        let (action, _) = round.resolve(view, enc, code, invalid)?;
        round.apply(view, enc, action);
    }
    Ok(round.decisions)
}
