//! Phase 4, readiness (`Controller.agentsRunagain`): how many charged robots waiting at
//! their chargers go back to work.
//!
//! Goods are handed out **in turn**: at the start every robot takes the next goods of the
//! list (`Strategy.__init__`), after a delivery a robot takes the next one when the counts
//! ask for it (`strategy.rs`), and a robot released here takes the front of the list on the
//! next tick (`charging.rs`). The readiness rule, with the original's counts:
//!
//! - *ready*: robots charged and waiting at their chargers;
//! - *working*: robots not marked to charge whose status is not 0;
//! - *on board*: robots marked to charge that are carrying (status 2);
//! - *wanted* = goods not yet delivered − working − on board, at most 10 − working
//!   (`Strategy.num_agents_threshold` is 10).
//!
//! When goods not yet delivered outnumber the working robots, and some robots are ready and
//! *wanted* is not 0, the first *wanted* ready robots (in id order) are released; if more
//! are wanted than are ready, all are. *Wanted* can be negative (robots on board count
//! twice over once goods run low); the original's loop then counts down past zero and
//! releases every ready robot, and so does this one.

use super::agent::Status;
use super::Original;

/// `Strategy.num_agents_threshold`, as `Controller.responsemodel` sets it on every tick.
const WORKERS: i64 = 10;

impl Original {
    /// `Controller.agentsRunagain`.
    pub(super) fn release_ready(&mut self) {
        let (mut ready, mut working, mut on_board) = (0i64, 0i64, 0i64);
        for a in &self.agents {
            if a.ready {
                ready += 1;
            }
            if a.needs_charge {
                if a.status == Status::Carrying {
                    on_board += 1;
                }
            } else if a.status != Status::Idle {
                working += 1;
            }
        }
        if ready == 0 {
            return;
        }
        let remaining = self.remaining();
        let mut wanted = if working < WORKERS { (remaining - working - on_board).min(WORKERS - working) } else { 0 };
        if remaining <= working || wanted == 0 {
            return;
        }
        if wanted <= ready {
            for a in &mut self.agents {
                if a.ready {
                    a.ready = false;
                    wanted -= 1;
                }
                if wanted == 0 {
                    break;
                }
            }
        } else {
            for a in &mut self.agents {
                a.ready = false;
            }
        }
    }
}
