//! Bays: the recess beside an aisle where a robot stands out of the traffic (spread
//! placement's parked robots, and robots waiting there for a charger; docs/model.md section
//! 7). The whole rule is here: who should stand in a bay this step ([`Bays::choose`], phase
//! 2), stepping aside and back ([`Bays::settle`], which the traffic decision calls in phase
//! 3), and that a robot in its bay does not move ([`Bays::holds`], phase 4). Collision
//! waiting and the traffic policies only read the flags they are given.
//!
//! A bay is a physical place: its robot stands one contact distance to the right of the lane
//! (as a car pulls over), so a robot driving the lane passes it without touching, and the
//! contact count, which reads positions only, sees that. The point on the lane where the
//! robot stepped aside is kept, to the bit: routes are planned from it, and the robot returns
//! to it when it leaves the bay.

use crate::fleet::robot::{Robots, State};
use crate::ids::NONE;
use crate::world::graph::HighwayGraph;

impl Robots {
    /// Whether robot `i` stands aside in a bay.
    #[inline]
    #[must_use]
    pub fn in_bay(&self, i: usize) -> bool {
        self.lane_x.get(i).is_some_and(|x| !x.is_nan())
    }

    /// Where robot `i` stands on its lane: its position, or the point it stepped aside from.
    #[inline]
    #[must_use]
    pub fn on_lane(&self, i: usize) -> (f64, f64) {
        if self.in_bay(i) {
            (self.lane_x[i], self.lane_y[i])
        } else {
            (self.x[i], self.y[i])
        }
    }
}

/// Who stands in a bay this step: one flag per robot, decided in phase 2 and settled in
/// phase 3. Without spread placement nobody ever does, and the column stays empty (the
/// paper): every reader then skips it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bays {
    flags: Vec<bool>,
    /// Robots whose flag may differ from where they stand, for [`Bays::settle`]: set by
    /// [`Bays::choose`] and [`Bays::keep`] (each robot's settling reads only itself, so
    /// their order does not matter, and a robot listed twice is settled once).
    differ: Vec<u32>,
    /// How far beside its lane a robot in a bay stands: one contact distance of the largest
    /// robots, so that robots driving the lane pass it without touching.
    depth: f64,
}

impl Bays {
    /// The bays of a fleet of `robots` (`spread`: under spread placement; else none), for
    /// robots of at most `r_max` px with the collision `margin`.
    pub fn new(spread: bool, robots: usize, r_max: f64, margin: f64) -> Bays {
        Bays { flags: if spread { vec![false; robots] } else { Vec::new() }, differ: Vec::new(), depth: 2.0 * r_max + margin }
    }

    /// The flags, robot by robot; empty without bays.
    #[inline]
    pub fn flags(&self) -> &[bool] {
        &self.flags
    }

    /// Whether there are bays at all (spread placement).
    #[inline]
    pub fn exist(&self) -> bool {
        !self.flags.is_empty()
    }

    /// Whether robot `i` stands in its bay this step: it does not move, whatever it wants
    /// (a robot that could not step out, a person in the way, waits there).
    #[inline]
    pub fn holds(&self, i: usize) -> bool {
        self.flags.get(i).is_some_and(|&b| b)
    }

    /// Phase 2: who should stand in a bay. Parked robots, and robots waiting for a charger
    /// once at their slot, stand out of the traffic; a robot that ran flat in its bay stays
    /// there (it strands where it stands).
    pub fn choose(&mut self, r: &Robots) {
        let n = self.flags.len();
        let (state, routing) = (&r.state[..n], &r.routing[..n]);
        self.differ.clear();
        // Nobody has stood in a bay yet: the robots flagged are the ones to step aside.
        let lane_x: &[f64] = if r.lane_x.len() >= n { &r.lane_x[..n] } else { &[] };
        for (i, ((b, s), &routing)) in self.flags.iter_mut().zip(state).zip(routing).enumerate() {
            let aside = !lane_x.is_empty() && !lane_x[i].is_nan();
            *b = match s {
                State::Parked => true,
                State::WaitCharger => !routing,
                State::Stranded => aside,
                _ => false,
            };
            if *b != aside {
                self.differ.push(i as u32);
            }
        }
    }

    /// Robots whose flag differs from where they stand step aside into their bay, to the
    /// right of their edge, or back onto their lane. Stepping aside or back takes no time of
    /// its own (a robot that steps back drives on in the same step: the bay's depth, about
    /// six steps' travel, is not driven). A robot on a node has no side to step to, and a
    /// robot whose destination a person stands too near to (`clear(x, y, radius)` says no)
    /// stays where it is this step: its flag then says where it is.
    pub fn settle(&mut self, r: &mut Robots, g: &HighwayGraph, clear: impl Fn(f64, f64, f64) -> bool) {
        let (bay, depth) = (&mut self.flags, self.depth);
        let n = r.len();
        if self.differ.is_empty() {
            return;
        }
        if r.lane_x.len() < n {
            r.lane_x.resize(n, f64::NAN);
            r.lane_y.resize(n, f64::NAN);
        }
        for &i in &self.differ {
            let i = i as usize;
            let aside = &mut bay[i];
            if *aside == r.in_bay(i) {
                continue;
            }
            if *aside {
                if r.at_node[i] != NONE {
                    *aside = false;
                    continue;
                }
                let ((ux, uy), (vx, vy)) = (g.pos(r.edge_u[i]), g.pos(r.edge_v[i]));
                let len = crate::fleet::motion::axis_dist(vx - ux, vy - uy);
                // The right of the direction of travel, in screen coordinates (y grows down).
                let (x, y) = (r.x[i] - (vy - uy) / len * depth, r.y[i] + (vx - ux) / len * depth);
                if !clear(x, y, r.radius[i]) {
                    *aside = false;
                    continue;
                }
                (r.lane_x[i], r.lane_y[i]) = (r.x[i], r.y[i]);
                (r.x[i], r.y[i]) = (x, y);
            } else {
                if !clear(r.lane_x[i], r.lane_y[i], r.radius[i]) {
                    *aside = true;
                    continue;
                }
                (r.x[i], r.y[i]) = (r.lane_x[i], r.lane_y[i]);
                (r.lane_x[i], r.lane_y[i]) = (f64::NAN, f64::NAN);
            }
        }
    }

    /// The traffic policy `reserve`'s hold on robots leaving a bay: robot `i` stays in it
    /// this step (no room on its lane yet), or may go.
    #[inline]
    pub fn keep(&mut self, i: usize, stay: bool) {
        self.flags[i] = stay;
        self.differ.push(i as u32);
    }
}
