//! The fleet as the rest of the engine sees it: [`crate::fleet::robot::Robots`] in the paper
//! layout's frame, the original's flags mapped onto [`State`], and the per-tick statistics.
//!
//! States: at the charger, CHARGING until full, then PARKED (charged, waiting to be sent out);
//! going home for want of work TO_HOME; going to charge after putting goods back TO_CHARGER;
//! at M UNLOADING; at the shelf before the goods is taken LOADING; carrying TO_DROP;
//! otherwise TO_PICKUP (including the first tick, before the original sets status 1). A
//! stopped robot keeps its state and counts a wait step. The original never strands a
//! robot, so STRANDED does not occur.

use super::agent::{Agent, Status};
use super::map::{self, FRAME_DX, FRAME_DY, NOWHERE};
use super::{Original, RADIUS, STEP};
use crate::fleet::robot::State;
use crate::ids::{NodeId, NONE};

/// The state a viewer shows for a robot.
fn state_of(a: &Agent) -> State {
    if a.at_charger {
        if a.full {
            State::Parked
        } else {
            State::Charging
        }
    } else if a.to_home {
        State::ToHome
    } else if a.to_charge {
        State::ToCharger
    } else if a.unloading {
        State::Unloading
    } else if a.status == Status::Carrying {
        if a.loaded {
            State::ToDrop
        } else {
            State::Loading
        }
    } else {
        State::ToPickup
    }
}

impl Original {
    /// Fills the columns once, at the start.
    pub(super) fn init_view(&mut self) {
        for a in &self.agents {
            let home = NodeId(u32::from(a.charger));
            let (x, y) = (a.x - FRAME_DX, a.y - FRAME_DY);
            self.view.push(home, (x, y), home, RADIUS, STEP, a.energy);
        }
        self.sync_view();
    }

    /// Copies the robots into the columns and counts this tick's state and wait steps.
    pub(super) fn sync_view(&mut self) {
        let v = &mut self.view;
        let counting = self.t > 0;
        for (i, a) in self.agents.iter().enumerate() {
            v.x[i] = a.x - FRAME_DX;
            v.y[i] = a.y - FRAME_DY;
            v.heading[i] = -a.theta.to_radians();
            let state = state_of(a);
            v.state[i] = state;
            v.energy[i] = a.energy;
            let (fx, fy) = map::point(a.from);
            let on_point = a.x == fx && a.y == fy;
            v.at_node[i] = if on_point { u32::from(a.from) } else { NONE };
            let shelf = map::shelf(a.goods);
            // Heading for the next crossing, or (next = 'x') along the shelf's edge.
            let towards = if a.next == NOWHERE { shelf.backward } else { a.next };
            let inside = !on_point && !a.at_charger;
            v.edge_u[i] = if inside { u32::from(a.from) } else { NONE };
            v.edge_v[i] = if inside { u32::from(towards) } else { NONE };
            v.routing[i] = state.travels();
            v.goal[i] = match a.plan.last() {
                NOWHERE => NONE,
                g => u32::from(g),
            };
            let to_shelf = a.to_shelf || (a.status == Status::Carrying && !a.loaded);
            v.has_final[i] = to_shelf;
            v.final_x[i] = shelf.x - FRAME_DX;
            v.final_y[i] = shelf.y - FRAME_DY;
            v.final_v[i] = u32::from(shelf.backward);
            let (wx, wy) = if to_shelf || a.next == NOWHERE { (shelf.x, shelf.y) } else { map::point(a.next) };
            v.wp_x[i] = wx - FRAME_DX;
            v.wp_y[i] = wy - FRAME_DY;
            v.wp_node[i] = if to_shelf || a.next == NOWHERE { NONE } else { u32::from(a.next) };
            v.goods[i] = if a.holds { self.goods_of_cell[usize::from(a.goods)] } else { NONE };
            v.cell[i] = if a.holds { u32::from(a.goods) } else { NONE };
            v.carrying[i] = a.loaded;
            v.dwell[i] = a.dwell;
            v.marked[i] = a.needs_charge && !a.to_charge;
            v.waited[i] = a.stopped;
            if counting {
                self.stats.state_steps[i][state as usize] += 1;
                if a.stopped && !a.at_charger {
                    self.stats.wait_steps[i] += 1;
                }
            }
        }
    }
}
