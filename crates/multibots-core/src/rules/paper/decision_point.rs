//! Decision points: a run that pauses where phase 1 needs decisions and takes them from
//! outside the engine (a learning environment, a controller), without returning between two
//! of them.
//!
//! A *decision point* is an allocation event with idle robots and open goods: exactly where
//! the built-in strategies are asked (`goods_queue.rs`). [`Paper::advance_to_decision`] runs
//! steps until one comes, and stops inside that step, after phase 0 and the first half of
//! phase 1; [`Paper::pending_view`] shows what an allocator would see; [`Paper::decide`]
//! checks the [`Decisions`] exactly as an allocator's answer is checked, carries them out and
//! finishes the step (phases 2 to 8). A run driven this way makes the same moves as one whose
//! allocator gives the same answers: `step()` is the pipeline's `begin`, `hand_out` (the two
//! halves of phase 1 around the allocator) and `finish` (`pipeline.rs`), and the pause only
//! splits it.
//!
//! A refused answer changes nothing: the run stays paused at the same point and takes
//! another. Under the original rules (`rules = "original"`) goods are handed out in turn
//! inside the authors' code, with nothing to decide, so the run refuses to pause.

use crate::alloc::{AllocView, Decisions};
use crate::error::{Error, Result};
use crate::rules::paper::Paper;
use crate::rules::Simulation;

impl Paper {
    /// Runs until phase 1 needs decisions, and pauses there. Returns `true` when paused at a
    /// decision point (at once if already paused), `false` when the run ended first.
    pub fn advance_to_decision(&mut self) -> Result<bool> {
        if self.goods.pending {
            return Ok(true);
        }
        loop {
            if !self.begin_step()? {
                return Ok(false);
            }
            if self.begin_hand_out() {
                self.goods.pending = true;
                return Ok(true);
            }
            self.finish_hand_out().map_err(|reason| Error::Decision { step: self.record.tally.t, reason })?;
            self.finish_step();
        }
    }

    /// What an allocator would see at the pending decision point, if the run is paused.
    #[must_use]
    pub fn pending_view(&self) -> Option<AllocView<'_>> {
        self.goods.pending.then(|| self.pending_view_unchecked())
    }

    /// Takes the decisions of the pending decision point and finishes its step.
    ///
    /// # Errors
    /// [`Error::Decision`] when no decision is pending, or when the decisions break a rule
    /// of an allocator's answer (a robot that is not idle or decided twice, goods that are
    /// not open or handed out twice, a full robot sent to charge); the run is unchanged then.
    pub fn decide(&mut self, decisions: &Decisions) -> Result<()> {
        if !self.goods.pending {
            return Err(Error::Decision { step: self.record.tally.t, reason: "no decision is pending: call advance_to_decision() first".into() });
        }
        self.goods.decisions.clone_from(decisions);
        self.finish_hand_out().map_err(|reason| Error::Decision { step: self.record.tally.t, reason })?;
        self.goods.pending = false;
        self.finish_step();
        Ok(())
    }

    /// Whether the run is paused at a decision point.
    #[must_use]
    pub fn paused(&self) -> bool {
        self.goods.pending
    }

    /// An allocator's view of a run that is not paused (no idle robot listed), such as one
    /// that has ended: for a last observation.
    pub(crate) fn final_view(&mut self) -> AllocView<'_> {
        if !self.goods.pending {
            self.goods.idle.clear();
            self.goods.queue.make_contiguous();
        }
        self.pending_view_unchecked()
    }
}

/// Only the original rules have no decision points.
pub(crate) fn no_decisions() -> Error {
    Error::scenario(
        "rules",
        "\"original\"",
        "the original rules hand out goods in turn inside the authors' code and take no decisions; decision points need rules = \"paper\"",
    )
}

impl Simulation {
    /// Runs until phase 1 needs decisions and pauses there (see [`Paper::advance_to_decision`]).
    ///
    /// # Errors
    /// [`Error::Scenario`] under the original rules, which take no decisions.
    pub fn advance_to_decision(&mut self) -> Result<bool> {
        self.paper_mut().ok_or_else(no_decisions)?.advance_to_decision()
    }

    /// Takes the decisions of the pending decision point (see [`Paper::decide`]).
    ///
    /// # Errors
    /// As [`Paper::decide`]; [`Error::Scenario`] under the original rules.
    pub fn decide(&mut self, decisions: &Decisions) -> Result<()> {
        self.paper_mut().ok_or_else(no_decisions)?.decide(decisions)
    }

    /// What an allocator would see at the pending decision point, if the run is paused.
    #[must_use]
    pub fn pending_view(&self) -> Option<AllocView<'_>> {
        self.paper().and_then(Paper::pending_view)
    }

    /// Whether the run is paused at a decision point.
    #[must_use]
    pub fn paused(&self) -> bool {
        self.paper().is_some_and(Paper::paused)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::alloc::{self, Allocator};
    use crate::ids::RobotId;
    use crate::input::scenario::{Rules, Scenario, PAPER_TASKS};

    /// Drives a run through decision points with a built-in's answers.
    fn driven(s: &Scenario) -> crate::RunResult {
        let mut sim = Simulation::new(s).unwrap();
        let mut a = alloc::built_in(s).unwrap();
        let mut d = Decisions::new();
        while sim.advance_to_decision().unwrap() {
            d.clear();
            a.allocate(&sim.pending_view().unwrap(), &mut d).unwrap();
            sim.decide(&d).unwrap();
        }
        sim.result()
    }

    #[test]
    fn a_run_driven_through_decision_points_equals_the_run_with_its_allocator() {
        for name in alloc::BUILT_INS {
            for n in [1, 3, 6] {
                for cells in &PAPER_TASKS {
                    let mut s = Scenario::paper(n, cells);
                    s.allocator = (*name).to_string();
                    assert_eq!(driven(&s), Simulation::new(&s).unwrap().run().unwrap(), "{name} N={n}");
                }
            }
        }
    }

    #[test]
    fn refused_decisions_change_nothing_and_the_run_goes_on() {
        let s = Scenario::paper(3, &PAPER_TASKS[0]);
        let mut sim = Simulation::new(&s).unwrap();
        assert!(sim.advance_to_decision().unwrap());
        let t = sim.t();
        let goods = sim.pending_view().unwrap().goods[0].id;
        let twice = Decisions { assign: vec![crate::Assignment { robot: RobotId(0), goods }, crate::Assignment { robot: RobotId(1), goods }], charge: vec![] };
        let e = sim.decide(&twice).unwrap_err();
        assert_eq!(e.to_string(), format!("decision at step {t}: assignment 1: goods {goods} handed out twice"));
        let full = Decisions { assign: vec![], charge: vec![RobotId(2)] };
        assert_eq!(sim.decide(&full).unwrap_err().to_string(), format!("decision at step {t}: charge 0: robot 2 is full (energy 10)"));
        let both = Decisions { assign: vec![crate::Assignment { robot: RobotId(0), goods }], charge: vec![RobotId(0)] };
        assert_eq!(sim.decide(&both).unwrap_err().to_string(), format!("decision at step {t}: charge 0: robot 0 is given two decisions"));
        assert!(sim.paused());
        assert_eq!(sim.step().unwrap_err().to_string(), format!("decision at step {t}: decisions are pending: decide() finishes this step first"));
        // The same point takes a good answer, and the run finishes as in-turn's would.
        let mut d = Decisions::new();
        while sim.advance_to_decision().unwrap() {
            d.clear();
            alloc::InTurn.allocate(&sim.pending_view().unwrap(), &mut d).unwrap();
            sim.decide(&d).unwrap();
        }
        assert_eq!(sim.result(), Simulation::new(&s).unwrap().run().unwrap());
        assert_eq!(sim.decide(&d).unwrap_err().to_string(), format!("decision at step {}: no decision is pending: call advance_to_decision() first", sim.t()));
    }

    #[test]
    fn charge_now_sends_an_idle_robot_to_charge_and_counts_c() {
        // One robot, two goods: it takes the first, then at the next point goes to charge.
        let s = Scenario::paper(1, &[42, 11]);
        let mut sim = Simulation::new(&s).unwrap();
        let mut points = 0;
        while sim.advance_to_decision().unwrap() {
            let v = sim.pending_view().unwrap();
            let d = if points == 1 {
                Decisions { assign: vec![], charge: vec![RobotId(0)] }
            } else {
                Decisions { assign: vec![crate::Assignment { robot: RobotId(0), goods: v.goods[0].id }], charge: vec![] }
            };
            sim.decide(&d).unwrap();
            points += 1;
        }
        let r = sim.result();
        assert_eq!((r.outcome, r.c, r.delivered), (Some(crate::Outcome::Complete), 1, 2));
        // Without the charge: no charging at all.
        assert_eq!(Simulation::new(&s).unwrap().run().unwrap().c, 0);
    }

    #[test]
    fn the_original_rules_refuse_to_pause() {
        let mut s = Scenario::paper(2, &PAPER_TASKS[0]);
        s.rules = Rules::Original;
        let mut sim = Simulation::new(&s).unwrap();
        let e = sim.advance_to_decision().unwrap_err();
        assert!(e.to_string().starts_with("rules = \"original\": the original rules hand out goods in turn"), "{e}");
        assert!(sim.pending_view().is_none());
    }
}
