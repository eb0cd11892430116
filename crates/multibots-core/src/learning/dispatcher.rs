//! The dispatcher: one idle robot's action per call (the single-agent environment,
//! `multibots/Dispatch-v0`).
//!
//! An episode is one run. `reset` starts it and runs to the first decision point; each
//! `step` takes the action of the robot deciding now ([`super::round`] gives the order), and
//! when the point's last robot has decided the engine carries the decisions out and runs on
//! to the next decision point, or to the end. The reward covers the steps the call ran (0
//! while the robots of one point decide), so an episode's rewards add up to the whole run's.

use super::observation::{Encoder, ObsMut};
use super::reward::{Account, Ending};
use super::round::Round;
use super::{check_rules, Settings};
use crate::alloc::{Decisions, InTurn};
use crate::error::{Error, Result};
use crate::ids::RobotId;
use crate::input::csv::Tables;
use crate::input::scenario::Scenario;
use crate::record::metrics::{Outcome, RunResult};
use crate::rules::paper::Paper;
use crate::rules::Engine;
use crate::world::World;
use std::sync::Arc;

/// What one action did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transition {
    /// The reward of the steps the action's call ran.
    pub reward: f64,
    /// The run completed, or can do nothing more (a failed end).
    pub terminated: bool,
    /// The run reached its step limit or horizon.
    pub truncated: bool,
    /// The action was masked out and taken as "wait" ([`super::InvalidAction::Wait`]).
    pub invalid: bool,
}

/// The run's counts, for the environment's info.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    pub t: u64,
    pub s: u64,
    pub c: u64,
    pub delivered: u64,
    pub goods_total: u64,
    /// Px driven by the fleet.
    pub distance: f64,
    /// Actions taken in this episode.
    pub decisions: u64,
}

impl Progress {
    /// The counts of `paper` so far, with `decisions` actions taken.
    pub(crate) fn of(paper: &Paper, decisions: u64) -> Progress {
        Progress {
            t: paper.t(),
            s: paper.s(),
            c: paper.c(),
            delivered: paper.delivered(),
            goods_total: paper.goods_total(),
            distance: paper.stats().distance.iter().sum(),
            decisions,
        }
    }
}

/// The single-agent environment's engine.
pub struct Dispatcher {
    scenario: Scenario,
    world: Arc<World>,
    /// The CSV tables of the scenario: read once, reused by every `reset()` until a new
    /// scenario comes, whose files are read anew.
    tables: Tables,
    settings: Settings,
    enc: Encoder,
    paper: Box<Paper>,
    round: Round,
    account: Account,
    /// The robot that decided last: the terminal observation is its.
    last: RobotId,
    ended: bool,
    decisions: u64,
}

/// The world of `scenario`, the one given when it is on the same layout with the same routes
/// (`reserve` has its own, `World::of`).
pub(crate) fn world_for(world: &Arc<World>, old: &Scenario, new: &Scenario) -> Result<Arc<World>> {
    // The traffic the run will play: "auto" resolved for this layout's departure zones.
    let departures = world.layout.departure.len();
    let reserve = |s: &Scenario| s.resolved(departures).traffic == crate::input::scenario::Traffic::Reserve;
    if new.layout == old.layout && new.layout_generate == old.layout_generate && reserve(new) == reserve(old) {
        Ok(Arc::clone(world))
    } else {
        World::of(new)
    }
}

/// Checks a scenario for an environment whose spaces are for `robots` robots.
pub(crate) fn check_scenario(scenario: &Scenario, robots: Option<usize>) -> Result<()> {
    scenario.check_values()?;
    check_rules(scenario)?;
    if let Some(n) = robots.filter(|&n| n != scenario.robots as usize) {
        return Err(Error::scenario("robots", scenario.robots, format!("the environment's spaces are for {n} robots")));
    }
    Ok(())
}

impl Dispatcher {
    /// An environment on `scenario`, at its first decision point.
    pub fn new(scenario: &Scenario, settings: Settings) -> Result<Dispatcher> {
        check_scenario(scenario, None)?;
        let world = World::of(scenario)?;
        settings.check()?;
        Dispatcher::build(world, scenario, settings)
    }

    /// The same on an already built world.
    pub fn with_world(world: Arc<World>, scenario: &Scenario, settings: Settings) -> Result<Dispatcher> {
        settings.check()?;
        check_scenario(scenario, None)?;
        Dispatcher::build(world, scenario, settings)
    }

    /// The one way in, for checked settings and scenario.
    fn build(world: Arc<World>, scenario: &Scenario, settings: Settings) -> Result<Dispatcher> {
        let tables = Tables::default();
        let paper = Box::new(Paper::build(Arc::clone(&world), &tables, scenario, Box::new(InTurn))?);
        let n = paper.robots().len();
        let mut d = Dispatcher {
            enc: Encoder::new(&world, scenario, settings.max_queue),
            scenario: scenario.clone(),
            world,
            tables,
            settings,
            paper,
            round: Round::default(),
            account: Account::new(n),
            last: RobotId(0),
            ended: false,
            decisions: 0,
        };
        d.advance()?;
        Ok(d)
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
        self.last = RobotId(0);
        self.ended = false;
        self.decisions = 0;
        self.advance()
    }

    /// Runs to the next decision point with a robot to ask, or to the end.
    fn advance(&mut self) -> Result<()> {
        loop {
            if !self.paper.advance_to_decision()? {
                self.ended = true;
                return Ok(());
            }
            self.round.start(&self.paper.pending_view_unchecked(), &self.enc);
            if !self.round.finished() {
                return Ok(());
            }
            self.decide()?;
        }
    }

    /// Hands the point's decisions to the engine, which finishes the step.
    fn decide(&mut self) -> Result<()> {
        let d: Decisions = std::mem::take(&mut self.round.decisions);
        let r = self.paper.decide(&d);
        self.round.decisions = d;
        r
    }

    /// Checks an action of the robot deciding now without taking it.
    pub fn check(&self, code: i64) -> Result<()> {
        self.ensure_running()?;
        self.round.resolve(&self.paper.pending_view_unchecked(), &self.enc, code, self.settings.invalid).map(|_| ())
    }

    fn ensure_running(&self) -> Result<()> {
        if self.ended {
            return Err(Error::Decision { step: self.paper.t(), reason: "the episode has ended: reset() starts the next".into() });
        }
        Ok(())
    }

    /// Takes the action of the robot deciding now.
    ///
    /// # Errors
    /// [`Error::Decision`] for an action code that is not one, a masked-out action (unless
    /// masked-out actions count as "wait"), or a step after the end; nothing changes then.
    pub fn step(&mut self, code: i64) -> Result<Transition> {
        self.ensure_running()?;
        let view = self.paper.pending_view_unchecked();
        let (action, invalid) = self.round.resolve(&view, &self.enc, code, self.settings.invalid)?;
        self.last = self.round.current().expect("a robot decides while running");
        self.round.apply(&view, &self.enc, action);
        self.decisions += 1;
        if self.round.finished() {
            self.decide()?;
            self.advance()?;
        }
        let reward = self.account.pay(&self.paper, &self.settings.reward, None);
        let e = Ending::of(self.paper.outcome());
        Ok(Transition { reward, terminated: e.terminated, truncated: e.truncated, invalid })
    }

    /// Writes the observation: the deciding robot's, or at the end the last decider's, with
    /// only "wait" allowed.
    pub fn observe(&mut self, out: ObsMut<'_>) {
        if self.ended {
            let n = self.robots();
            self.round.marks.none(n, self.settings.max_queue);
            let view = self.paper.final_view();
            self.enc.observe(&view, self.last, &self.round.marks, false, out);
        } else {
            self.round.observe(&self.paper.pending_view_unchecked(), &self.enc, out);
        }
    }

    /// The robot deciding now (`None` once the episode has ended).
    #[must_use]
    pub fn robot(&self) -> Option<RobotId> {
        if self.ended {
            None
        } else {
            self.round.current()
        }
    }

    /// Whether the episode has ended.
    #[must_use]
    pub fn ended(&self) -> bool {
        self.ended
    }

    /// The run's outcome, once it has ended.
    #[must_use]
    pub fn outcome(&self) -> Option<Outcome> {
        self.paper.outcome()
    }

    /// The run's result so far (docs/metrics.md).
    #[must_use]
    pub fn result(&self) -> RunResult {
        self.paper.result()
    }

    /// The run's counts.
    #[must_use]
    pub fn progress(&self) -> Progress {
        Progress::of(&self.paper, self.decisions)
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

    /// The scenario of the current episode.
    #[must_use]
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The world.
    #[must_use]
    pub fn world(&self) -> &Arc<World> {
        &self.world
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scenario::PAPER_TASKS;
    use crate::learning::observation::Observation;
    use crate::learning::{Action, InvalidAction};
    use crate::Simulation;

    /// In-turn as actions: each robot takes the front open slot.
    fn in_turn_code(obs: &Observation, q: usize) -> i64 {
        (0..q).find(|&k| obs.mask[k] == 1).map_or(Action::Wait.code(q), |k| k as i64)
    }

    #[test]
    fn in_turn_actions_reproduce_in_turn_and_rewards_add_up_to_minus_cost_total() {
        for n in 1..=6 {
            for cells in &PAPER_TASKS {
                let s = Scenario::paper(n, cells);
                let mut d = Dispatcher::new(&s, Settings::of(&s)).unwrap();
                let mut obs = Observation::zeros(n as usize, 10);
                let mut total = 0.0;
                while !d.ended() {
                    d.observe(obs.as_mut());
                    let tr = d.step(in_turn_code(&obs, 10)).unwrap();
                    total += tr.reward;
                    assert_eq!(tr.terminated, d.ended());
                }
                let want = Simulation::new(&s).unwrap().run().unwrap();
                assert_eq!(d.result(), want);
                assert!((total + want.cost.unwrap()).abs() < 1e-6, "{total} {:?}", want.cost);
            }
        }
    }

    #[test]
    fn masked_out_actions_are_refused_or_taken_as_wait() {
        let s = Scenario::paper(3, &PAPER_TASKS[0]);
        let mut d = Dispatcher::new(&s, Settings::of(&s)).unwrap();
        // Robot 0 is full: "charge now" is masked out.
        let e = d.step(10).unwrap_err().to_string();
        assert_eq!(e, "decision at step 1: action = 10 (charge now): not allowed for robot 0: robot 0 is full (energy 10)");
        assert_eq!(d.step(12).unwrap_err().to_string().split(": ").nth(1), Some("action = 12"));
        d.step(4).unwrap();
        let e = d.step(4).unwrap_err().to_string();
        assert_eq!(e, "decision at step 1: action = 4 (take the goods in queue slot 4): not allowed for robot 1: robot 0 took the goods in queue slot 4 at this decision point");
        let mut st = Settings::of(&s);
        st.invalid = InvalidAction::Wait;
        let mut w = Dispatcher::new(&s, st).unwrap();
        let tr = w.step(10).unwrap();
        // The first call pays for step 1, the step the first decision point came in.
        assert!(tr.invalid && !tr.terminated && tr.reward == -1.0, "{tr:?}");
        assert_eq!(w.step(11).unwrap().reward, 0.0);
        assert_eq!(w.robot(), Some(RobotId(2)));
    }

    #[test]
    fn observations_stay_in_bounds_every_mask_allows_wait_and_the_last_allows_only_wait() {
        let s = Scenario::paper(4, &PAPER_TASKS[1]);
        let mut d = Dispatcher::new(&s, Settings::of(&s)).unwrap();
        let mut obs = Observation::zeros(4, 10);
        let mut k = 0u64;
        let within = |v: &[f32], table: &[crate::learning::observation::Feature]| {
            for (k, x) in v.iter().enumerate() {
                let f = table[k % table.len()];
                assert!((f.low..=f.high).contains(x), "{} = {x}", f.name);
            }
        };
        while !d.ended() {
            d.observe(obs.as_mut());
            within(&obs.robot, &crate::learning::observation::ROBOT);
            within(&obs.fleet, &crate::learning::observation::FLEET);
            within(&obs.queue, &crate::learning::observation::GOODS);
            assert_eq!(obs.mask[11], 1);
            // A crude deterministic choice among the allowed actions.
            let allowed: Vec<i64> = (0..12).filter(|&a| obs.mask[a as usize] == 1).collect();
            k = k.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            d.step(allowed[(k >> 33) as usize % allowed.len()]).unwrap();
        }
        d.observe(obs.as_mut());
        assert_eq!(obs.mask.iter().map(|&m| u32::from(m)).sum::<u32>(), 1);
        assert_eq!(obs.mask[11], 1);
        assert!(d.step(11).unwrap_err().to_string().ends_with("the episode has ended: reset() starts the next"));
        d.reset(None).unwrap();
        assert!(!d.ended() && d.progress().t == 1);
    }

    #[test]
    fn the_original_rules_and_another_fleet_size_are_refused() {
        let mut s = Scenario::paper(3, &PAPER_TASKS[0]);
        let mut d = Dispatcher::new(&s, Settings::of(&s)).unwrap();
        s.robots = 4;
        assert_eq!(d.reset(Some(&s)).unwrap_err().to_string(), "robots = 4: the environment's spaces are for 3 robots");
        s.robots = 3;
        s.rules = crate::input::scenario::Rules::Original;
        assert!(Dispatcher::new(&s, Settings::of(&s)).err().unwrap().to_string().starts_with("rules = \"original\""));
    }
}
