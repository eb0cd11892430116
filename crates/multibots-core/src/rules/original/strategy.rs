//! Phase 1, driving (`Strategy.computeStartToGood` and the functions it calls).
//!
//! Each robot that is neither stopped nor at its charger does one of four things, chosen in
//! this order:
//!
//! - **to the shelf** (`travelTogood`): from the forward crossing towards the loading point.
//!   Within 5 px it counts as arrived (status 2), *and* still moves the rest of the way on
//!   the same tick, so it ends exactly on the point; an arrival from 0 px away is a step of
//!   length 0, which heads it west (180°).
//! - **loading** (`pickupgoods`): 10 ticks, then the cell is empty and the robot heads for
//!   the backward crossing.
//! - **unloading** (`takeoffgoods`): heading −90° at M, 20 ticks, then the delivery. The robot
//!   takes the next goods only if the goods left, less those being carried, outnumber the
//!   robots fetching (those marked to charge not counted); otherwise it plans home. A robot
//!   about to put its goods back is counted in neither, so the list can be empty when the
//!   counts ask for more ([`Fault::EmptyQueueAfterDelivery`]).
//! - **along its plan** (`travelToNextNode` and the plan logic): a robot heads for its next
//!   crossing at 4 px a tick; within 5 px it **snaps** onto the crossing (a teleport of up to
//!   4 px) and stops for that tick, and it takes the next crossing as its goal on the tick
//!   after, without moving either. When the plan is used up it is at the shelf's forward
//!   crossing, at M (unloading begins next tick), or at its start crossing after going home
//!   or to charge, from where it **jumps to its charging position** (heading −90°).
//!
//! A robot marked by the threshold rule while fetching (and before it reached the shelf)
//! puts its goods back at the front of the list, and plans from its next crossing to its
//! start crossing. When that crossing is `'x'` (it reached the end of its plan on the tick
//! before), the original raises `KeyError` ([`Fault::ChargeRouteFromNowhere`]).

use super::agent::Status;
use super::map::{self, NOWHERE};
use super::{Fault, Original, LOAD_TICKS, STEP, UNLOAD_TICKS};
use crate::record::events::EventKind;

impl Original {
    /// `Strategy.computeStartToGood`.
    pub(super) fn drive(&mut self) -> Result<(), Fault> {
        for i in 0..self.agents.len() {
            let a = &mut self.agents[i];
            if a.stopped || a.at_charger {
                continue;
            }
            a.counted = false;
            match a.status {
                Status::Fetching if a.to_shelf => self.travel_to_shelf(i),
                Status::Carrying if !a.to_drop => self.load(i),
                Status::Carrying if a.unloading => self.unload(i)?,
                _ => self.follow_plan(i)?,
            }
        }
        Ok(())
    }

    /// `Strategy.travelTogood`.
    fn travel_to_shelf(&mut self, i: usize) {
        let a = &mut self.agents[i];
        let s = map::shelf(a.goods);
        if a.distance_to(s.x, s.y) < 5.0 {
            a.to_shelf = false;
            a.status = Status::Carrying;
            a.reached_shelf = true;
        }
        self.stats.distance[i] += a.step_towards(s.x, s.y, STEP);
    }

    /// `Strategy.pickupgoods`.
    fn load(&mut self, i: usize) {
        let a = &mut self.agents[i];
        if a.loaded {
            self.travel_to_next(i);
            return;
        }
        a.dwell += 1;
        if a.dwell == LOAD_TICKS {
            a.dwell = 0;
            a.loaded = true;
            a.next = map::shelf(a.goods).backward;
            let cell = a.goods;
            self.cells_full[usize::from(cell)] = false;
            self.event(EventKind::Pickup, i, u32::from(cell));
        }
    }

    /// `Strategy.takeoffgoods`.
    fn unload(&mut self, i: usize) -> Result<(), Fault> {
        let a = &mut self.agents[i];
        a.theta = -90.0;
        a.dwell += 1;
        if a.dwell != UNLOAD_TICKS {
            return Ok(());
        }
        a.dwell = 0;
        a.unloading = false;
        a.to_shelf = false;
        a.to_drop = false;
        a.loaded = false;
        a.low_status = Status::Fetching;
        a.status = Status::Idle;
        a.reached_shelf = false;
        a.holds = false;
        let cell = a.goods;
        self.delivered += 1;
        self.stats.delivered[i] += 1;
        self.event(EventKind::Deliver, i, u32::from(cell));
        let (mut fetching, mut carrying) = (0, 0);
        for b in &self.agents {
            match b.status {
                Status::Fetching if !b.needs_charge => fetching += 1,
                Status::Carrying => carrying += 1,
                _ => {}
            }
        }
        if self.remaining() - carrying > fetching {
            let g = self.queue.pop_front().ok_or(Fault::EmptyQueueAfterDelivery)?;
            let a = &mut self.agents[i];
            a.goods = g;
            a.holds = true;
            a.plan = self.routes.plan(map::UNLOAD, map::shelf(g).forward);
            a.status = Status::Fetching;
            self.event(EventKind::Assign, i, u32::from(g));
        } else {
            // `agentbackhome`.
            let a = &mut self.agents[i];
            a.to_home = true;
            a.plan = self.routes.plan(map::UNLOAD, a.start);
        }
        self.agents[i].stepping = false;
        Ok(())
    }

    /// The last branch of `computeStartToGood`: turn back to charge, follow the plan, or act
    /// on its end.
    fn follow_plan(&mut self, i: usize) -> Result<(), Fault> {
        let a = &mut self.agents[i];
        let next = a.plan.front();
        if a.needs_charge && !a.to_charge && !a.to_home && a.low_status == Status::Fetching && !a.reached_shelf && self.delivered != self.total {
            debug_assert!(a.holds, "a robot turning back to charge holds goods");
            a.holds = false;
            let cell = a.goods;
            self.queue.push_front(cell);
            self.event(EventKind::PutBack, i, u32::from(cell));
            let a = &mut self.agents[i];
            if next == NOWHERE {
                return Err(Fault::ChargeRouteFromNowhere);
            }
            a.plan = self.routes.plan(next, a.start);
            a.to_charge = true;
        }
        let a = &mut self.agents[i];
        if a.stepping {
            self.travel_to_next(i);
            return Ok(());
        }
        if next == NOWHERE {
            if a.to_charge || a.to_home {
                // `agentcharging`: the jump from the start crossing to the charging position.
                a.at_charger = true;
                a.needs_charge = false;
                a.status = Status::Idle;
                let charger = a.charger;
                a.teleport(charger, -90.0);
            } else if !a.to_shelf && !a.loaded && !a.unloading {
                a.to_shelf = true;
            } else {
                a.unloading = true;
            }
        }
        a.next = next;
        a.stepping = true;
        Ok(())
    }

    /// `Strategy.travelToNextNode`.
    fn travel_to_next(&mut self, i: usize) {
        let a = &mut self.agents[i];
        if a.status != Status::Carrying && !a.to_home {
            a.status = Status::Fetching;
        }
        if a.next == NOWHERE {
            return;
        }
        let (gx, gy) = map::point(a.next);
        if a.distance_to(gx, gy) < 5.0 {
            if a.loaded && !a.to_drop {
                a.plan = self.routes.plan(a.next, map::UNLOAD);
                a.to_drop = true;
            }
            a.plan.pop_front();
            a.stepping = false;
            let (next, theta) = (a.next, a.theta);
            self.stats.distance[i] += a.teleport(next, theta);
            return;
        }
        self.stats.distance[i] += a.step_towards(gx, gy, STEP);
    }
}
