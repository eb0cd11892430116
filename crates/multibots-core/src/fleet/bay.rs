//! Bays: the recess beside an aisle where a robot stands out of the traffic (spread
//! placement's parked robots, and robots waiting there for a charger). A bay is a physical
//! place: its robot stands one contact distance to the right of the lane (as a car pulls
//! over), so a robot driving the lane passes it without touching, and the contact count,
//! which reads positions only, sees that. The point on the lane where the robot stepped
//! aside is kept, to the bit: routes are planned from it, and the robot returns to it when
//! it leaves the bay.

use crate::fleet::robot::Robots;
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

/// Robots whose bay flag (`bay[i]`, decided by the step) differs from where they stand step
/// aside into their bay, `depth` px to the right of their edge, or back onto their lane.
/// Stepping aside or back takes no time of its own (a robot that steps back drives on in the
/// same step: the bay's depth, about six steps' travel, is not driven). A robot on a node
/// has no side to step to, and a robot whose destination a person stands too near to
/// (`clear(x, y, radius)` says no) stays where it is this step: `bay[i]` then says where it
/// is.
pub(crate) fn settle(r: &mut Robots, g: &HighwayGraph, bay: &mut [bool], depth: f64, clear: impl Fn(f64, f64, f64) -> bool) {
    let n = r.len();
    if bay.is_empty() || (r.lane_x.is_empty() && !bay[..n].contains(&true)) {
        return;
    }
    if r.lane_x.len() < n {
        r.lane_x.resize(n, f64::NAN);
        r.lane_y.resize(n, f64::NAN);
    }
    for (i, aside) in bay[..n].iter_mut().enumerate() {
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
