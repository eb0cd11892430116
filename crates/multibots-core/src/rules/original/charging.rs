//! Phase 3, energy (`Controller.chargeController`, `ChargeThreshold.AgentCharge`).
//!
//! Robot by robot:
//!
//! - **Away from its charger** (`eleconsume`): every tick costs energy, whatever the robot
//!   does (moving, stopped, loading, going home). The energy is recomputed, not decremented:
//!   `10 − 0.005 · ticks`, where `ticks` counts from the last full charge (the same float
//!   operations as the original, so the threshold fires on the same tick). At or below 3.5
//!   the **threshold rule** fires once per charge, for a robot whose status is not 0
//!   (robots going home have status 0 and are never marked): it is marked to charge, and
//!   remembers its status (1 fetching, 2 carrying). A robot fetching turns back in phase 1;
//!   one carrying delivers first. At or below 0 the original asks for Enter and carries on:
//!   the robot keeps working, with negative energy (it is listed in `stranded`).
//! - **At its charger** (`charging`): +0.05 a tick until the energy is at least 10 (sums of
//!   0.05 in floats, as the original). Once full it is *ready*, with status 0. A ready robot
//!   released by phase 4 goes back to work on the next tick: **C counts here**, for every
//!   robot that leaves its charger again, whether it came to charge or had gone home for
//!   want of work. It **jumps** from its charging position to its start crossing, heading
//!   0° (east), takes the goods at the front of the list (`GOOD_NUM[0]`: an empty list is
//!   [`Fault::EmptyQueueAtRedispatch`]), and plans to its shelf.

use super::agent::Status;
use super::map;
use super::{Fault, Original, CHARGE_RATE, CONSUMPTION, FULL, THRESHOLD};
use crate::ids::NONE;
use crate::record::events::EventKind;

impl Original {
    /// `Controller.chargeController`.
    pub(super) fn charge_and_consume(&mut self) -> Result<(), Fault> {
        for i in 0..self.agents.len() {
            let a = &mut self.agents[i];
            if !a.at_charger {
                // `eleconsume`.
                a.use_ticks += 1;
                a.energy = FULL - CONSUMPTION * a.use_ticks as f64;
                self.stats.energy_used[i] += CONSUMPTION;
                if a.energy <= THRESHOLD {
                    if a.energy <= 0.0 {
                        self.ran_flat[i] = true;
                    } else if a.status != Status::Idle && !a.to_charge && !a.low_seen {
                        a.low_seen = true;
                        a.low_status = a.status;
                        a.needs_charge = true;
                    }
                }
                continue;
            }
            // `charging`.
            if !a.full {
                a.energy += CHARGE_RATE;
                if a.energy >= FULL {
                    a.full = true;
                }
            }
            if !a.full {
                continue;
            }
            if !a.settled {
                a.settled = true;
                a.status = Status::Idle;
                a.to_home = false;
                a.ready = true;
                a.use_ticks = 0;
            }
            if !a.ready {
                self.back_to_work(i)?;
            }
        }
        Ok(())
    }

    /// A released robot leaves its charger: C counts, and it takes the next goods.
    fn back_to_work(&mut self, i: usize) -> Result<(), Fault> {
        let a = &mut self.agents[i];
        a.charges += 1;
        a.full = false;
        a.at_charger = false;
        a.use_ticks = 0;
        a.low_seen = false;
        a.to_charge = false;
        a.needs_charge = false;
        a.status = Status::Fetching;
        a.stepping = false;
        a.settled = false;
        let start = a.start;
        a.teleport(start, 0.0);
        self.stats.charges[i] += 1;
        self.event(EventKind::Charge, i, NONE);
        let g = self.queue.pop_front().ok_or(Fault::EmptyQueueAtRedispatch)?;
        let a = &mut self.agents[i];
        a.goods = g;
        a.holds = true;
        a.plan = self.routes.plan(start, map::shelf(g).forward);
        self.event(EventKind::Assign, i, u32::from(g));
        Ok(())
    }
}
