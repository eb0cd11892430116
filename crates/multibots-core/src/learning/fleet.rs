//! The fleet: every robot is an agent, and each call takes the actions of all of them at one
//! decision point (the multi-agent environment, `multibots.envs.parallel_env`).
//!
//! At a decision point the idle robots decide, all at once; the other robots' masks allow
//! only "wait" (their action changes nothing). Two robots that pick the same goods: the lower
//! id takes them, the other waits, and the step says it met a conflict. Rewards are per
//! robot: its own distance, collisions, charges and deliveries, and an equal share of the
//! time and of a failure penalty, so that they add up to the dispatcher's reward.

use super::dispatcher::{check_scenario, world_for, Progress};
use super::observation::{Encoder, Marks, ObsMut};
use super::reward::{Account, Ending};
use super::{Action, InvalidAction, Settings};
use crate::alloc::{Assignment, Decisions, InTurn};
use crate::error::{Error, Result};
use crate::ids::{RobotId, NONE};
use crate::input::csv::Tables;
use crate::input::scenario::Scenario;
use crate::record::metrics::RunResult;
use crate::rules::paper::Paper;
use crate::rules::Engine;
use crate::world::World;
use std::sync::Arc;

/// What a robot's action did at one call.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AgentStep {
    /// Its reward.
    pub reward: f64,
    /// Its action was masked out (or missing) and taken as "wait".
    pub invalid: bool,
    /// A robot with a lower id took the goods it picked: it waits.
    pub conflict: bool,
}

/// The multi-agent environment's engine.
pub struct Fleet {
    scenario: Scenario,
    world: Arc<World>,
    /// The CSV tables of the scenario: read once, reused by every `reset()` until a new
    /// scenario comes, whose files are read anew.
    tables: Tables,
    settings: Settings,
    enc: Encoder,
    paper: Box<Paper>,
    marks: Marks,
    account: Account,
    decisions: Decisions,
    shares: Vec<f64>,
    ended: bool,
    calls: u64,
}

/// The code of a missing action.
pub const NO_ACTION: i64 = -1;

impl Fleet {
    /// An environment on `scenario`, at its first decision point.
    pub fn new(scenario: &Scenario, settings: Settings) -> Result<Fleet> {
        settings.check()?;
        check_scenario(scenario, None)?;
        let world = World::of(scenario)?;
        let tables = Tables::default();
        let paper = Box::new(Paper::build(Arc::clone(&world), &tables, scenario, Box::new(InTurn))?);
        let n = paper.robots().len();
        let mut f = Fleet {
            enc: Encoder::new(&world, scenario, settings.max_queue),
            scenario: scenario.clone(),
            world,
            tables,
            settings,
            paper,
            marks: Marks::default(),
            account: Account::new(n),
            decisions: Decisions::new(),
            shares: vec![0.0; n],
            ended: false,
            calls: 0,
        };
        f.advance()?;
        Ok(f)
    }

    /// A new episode: the same scenario again, or `scenario` (with as many robots).
    pub fn reset(&mut self, scenario: Option<&Scenario>) -> Result<()> {
        if let Some(s) = scenario {
            check_scenario(s, Some(self.robots()))?;
            self.world = world_for(&self.world, &self.scenario, s)?;
            self.enc = Encoder::new(&self.world, s, self.settings.max_queue);
            self.scenario = s.clone();
            self.tables = Tables::default();
        }
        *self.paper = Paper::build(Arc::clone(&self.world), &self.tables, &self.scenario, Box::new(InTurn))?;
        self.account.restart(self.robots());
        self.ended = false;
        self.calls = 0;
        self.advance()
    }

    fn advance(&mut self) -> Result<()> {
        if self.paper.advance_to_decision()? {
            let view = self.paper.pending_view_unchecked();
            self.marks.start(&view, view.idle, self.settings.max_queue);
        } else {
            self.ended = true;
        }
        Ok(())
    }

    /// Whether robot `i` decides at the current point.
    #[must_use]
    pub fn deciding(&self, i: usize) -> bool {
        !self.ended && self.marks.robot.get(i) == Some(&1)
    }

    /// Robot `i`'s action, or the reason it is masked out (`Err(None)`: not an action code).
    fn judge(&self, i: usize, code: i64) -> std::result::Result<Action, Option<String>> {
        let q = self.settings.max_queue;
        let action = if code == NO_ACTION { None } else { Some(Action::decode(code, q).ok_or(None)?) };
        let view = self.paper.pending_view_unchecked();
        let r = RobotId(i as u32);
        if !self.deciding(i) {
            return match action {
                None | Some(Action::Wait) => Ok(Action::Wait),
                Some(_) => {
                    Err(Some(format!("robot {i} does not decide at this point (it is {}): only wait (code {}) is allowed", view.state(r).name(), q + 1)))
                }
            };
        }
        match action {
            None => Err(Some(format!("robot {i} decides at this point and has no action"))),
            Some(Action::Take(k)) if k >= view.goods.len() => Err(Some(format!("queue slot {k} is empty ({} goods open)", view.goods.len()))),
            Some(Action::Charge) if !self.enc.can_charge(&view, r) => Err(Some(format!("robot {i} is full (energy {})", view.energy(r)))),
            Some(a) => Ok(a),
        }
    }

    /// Checks every robot's action code (`NO_ACTION` for none) without taking them.
    pub fn check(&self, codes: &[i64]) -> Result<()> {
        self.resolve(codes).map(|_| ())
    }

    fn resolve(&self, codes: &[i64]) -> Result<Vec<(Action, bool)>> {
        let t = self.paper.t();
        if self.ended {
            return Err(Error::Decision { step: t, reason: "the episode has ended: reset() starts the next".into() });
        }
        let n = self.robots();
        if codes.len() != n {
            return Err(Error::Decision { step: t, reason: format!("actions: {} given, one per robot ({n}) expected", codes.len()) });
        }
        let mut out = Vec::with_capacity(n);
        for (i, &code) in codes.iter().enumerate() {
            match (self.judge(i, code), self.settings.invalid) {
                (Ok(a), _) => out.push((a, false)),
                (Err(None), _) => {
                    let e = super::bad_code(t, code, self.settings.max_queue);
                    let Error::Decision { reason, .. } = e else { unreachable!("bad_code is a decision error") };
                    return Err(Error::Decision { step: t, reason: format!("robot {i}: {reason}") });
                }
                (Err(Some(_)), InvalidAction::Wait) => out.push((Action::Wait, true)),
                (Err(Some(why)), InvalidAction::Refuse) => {
                    let what = Action::decode(code, self.settings.max_queue).map_or_else(|| "no action".into(), Action::describe);
                    return Err(Error::Decision { step: t, reason: format!("robot {i}: action = {code} ({what}): not allowed: {why}") });
                }
            }
        }
        Ok(out)
    }

    /// Takes every robot's action (`NO_ACTION` for none), runs to the next decision point or
    /// the end, and writes each robot's step to `out`.
    ///
    /// # Errors
    /// [`Error::Decision`] for a code that is not an action, a masked-out or missing action
    /// (unless they count as "wait"), or a call after the end; nothing changes then.
    pub fn step(&mut self, codes: &[i64], out: &mut [AgentStep]) -> Result<Ending> {
        let actions = self.resolve(codes)?;
        let view = self.paper.pending_view_unchecked();
        self.decisions.clear();
        let mut taken = vec![NONE; self.settings.max_queue];
        for (i, &(action, invalid)) in actions.iter().enumerate() {
            out[i] = AgentStep { reward: 0.0, invalid, conflict: false };
            let r = RobotId(i as u32);
            match action {
                Action::Take(k) if taken[k] == NONE => {
                    taken[k] = r.0;
                    self.decisions.assign.push(Assignment { robot: r, goods: view.goods[k].id });
                }
                Action::Take(_) => out[i].conflict = true,
                Action::Charge => self.decisions.charge.push(r),
                Action::Wait => {}
            }
        }
        let d = std::mem::take(&mut self.decisions);
        let decided = self.paper.decide(&d);
        self.decisions = d;
        decided?;
        self.calls += 1;
        self.advance()?;
        self.account.pay(&self.paper, &self.settings.reward, Some(&mut self.shares));
        for (o, &s) in out.iter_mut().zip(&self.shares) {
            o.reward = s;
        }
        Ok(Ending::of(self.paper.outcome()))
    }

    /// Writes robot `i`'s observation (at the end, with only "wait" allowed).
    pub fn observe(&mut self, i: usize, out: ObsMut<'_>) {
        let r = RobotId(i as u32);
        if self.ended {
            let n = self.robots();
            self.marks.none(n, self.settings.max_queue);
            let view = self.paper.final_view();
            self.enc.observe(&view, r, &self.marks, false, out);
        } else {
            let deciding = self.deciding(i);
            self.enc.observe(&self.paper.pending_view_unchecked(), r, &self.marks, deciding, out);
        }
    }

    /// Writes every robot's observation, robot `i` in the `i`-th row of each array.
    pub fn observe_all(&mut self, out: ObsMut<'_>) {
        let ObsMut { robot, fleet, queue, mask } = out;
        let n = self.robots();
        let (r, f, q, m) = (robot.len() / n, fleet.len() / n, queue.len() / n, mask.len() / n);
        for i in 0..n {
            self.observe(
                i,
                ObsMut {
                    robot: &mut robot[i * r..(i + 1) * r],
                    fleet: &mut fleet[i * f..(i + 1) * f],
                    queue: &mut queue[i * q..(i + 1) * q],
                    mask: &mut mask[i * m..(i + 1) * m],
                },
            );
        }
    }

    /// Writes which robots decide at the current point.
    pub fn deciders(&self, out: &mut [bool]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.deciding(i);
        }
    }

    /// Writes the global state.
    pub fn state(&self, out: &mut [f32]) {
        self.enc.state(&self.paper, out);
    }

    /// Length of the global state.
    #[must_use]
    pub fn state_len(&self) -> usize {
        self.enc.state_len(self.robots())
    }

    /// Whether the episode has ended.
    #[must_use]
    pub fn ended(&self) -> bool {
        self.ended
    }

    /// The run's result so far.
    #[must_use]
    pub fn result(&self) -> RunResult {
        self.paper.result()
    }

    /// The run's counts (`decisions` counts calls).
    #[must_use]
    pub fn progress(&self) -> Progress {
        Progress::of(&self.paper, self.calls)
    }

    /// Robots in the fleet.
    #[must_use]
    pub fn robots(&self) -> usize {
        self.paper.robots().len()
    }

    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &Settings {
        &self.settings
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scenario::PAPER_TASKS;

    #[test]
    fn front_slots_in_id_order_reproduce_in_turn_and_shares_add_up() {
        for n in [1, 3, 6] {
            let s = Scenario::paper(n, &PAPER_TASKS[3]);
            let mut f = Fleet::new(&s, Settings::of(&s)).unwrap();
            let mut out = vec![AgentStep::default(); n as usize];
            let mut total = 0.0;
            while !f.ended() {
                // Deciders in id order take the front slots; the rest wait.
                let mut next = 0;
                let goods = f.paper.pending_view_unchecked().goods.len();
                let codes: Vec<i64> = (0..n as usize)
                    .map(|i| {
                        if f.deciding(i) && next < goods {
                            next += 1;
                            next as i64 - 1
                        } else {
                            11
                        }
                    })
                    .collect();
                f.step(&codes, &mut out).unwrap();
                total += out.iter().map(|o| o.reward).sum::<f64>();
            }
            let want = crate::Simulation::new(&s).unwrap().run().unwrap();
            assert_eq!(f.result(), want);
            assert!((total + want.cost.unwrap()).abs() < 1e-6);
        }
    }

    #[test]
    fn conflicts_go_to_the_lower_id_and_bad_actions_are_named() {
        let s = Scenario::paper(3, &PAPER_TASKS[0]);
        let mut f = Fleet::new(&s, Settings::of(&s)).unwrap();
        let mut out = vec![AgentStep::default(); 3];
        let e = f.step(&[0, 0, 10], &mut out).unwrap_err().to_string();
        assert_eq!(e, "decision at step 1: robot 2: action = 10 (charge now): not allowed: robot 2 is full (energy 10)");
        let e = f.step(&[0, -1, 1], &mut out).unwrap_err().to_string();
        assert_eq!(e, "decision at step 1: robot 1: action = -1 (no action): not allowed: robot 1 decides at this point and has no action");
        f.step(&[0, 0, 1], &mut out).unwrap();
        assert_eq!(out.iter().map(|o| o.conflict).collect::<Vec<_>>(), vec![false, true, false]);
        // Robot 1 waited: it is idle at the next point (when a robot has delivered); a busy
        // robot may only wait.
        assert!(f.deciding(1));
        let busy = (0..3).find(|&i| !f.deciding(i)).unwrap();
        let codes: Vec<i64> = (0..3).map(|i| if i == busy { 0 } else { 11 }).collect();
        let e = f.step(&codes, &mut out).unwrap_err().to_string();
        assert!(
            e.contains(&format!("robot {busy}: action = 0 (take the goods in queue slot 0): not allowed: robot {busy} does not decide at this point (it is ")),
            "{e}"
        );
        assert!(e.ends_with("): only wait (code 11) is allowed"), "{e}");
    }
}
