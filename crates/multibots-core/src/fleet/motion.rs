//! How a robot travels: [`Motion`], the view of the fleet's columns that a move reads and
//! writes, built here from [`Robots`] and used by the step's pass and by cruising; headings
//! (`bearing`, `folded_angle`); and the exact arithmetic of a move along an axis-parallel
//! aisle.

use crate::fleet::robot::{Robots, State};
use crate::ids::{NodeId, NONE};
use crate::world::graph::HighwayGraph;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// `atan2(dy, dx)`, with the axis-parallel directions of aisles answered without the library
/// call. The shortcuts return exactly what IEEE 754 specifies for `atan2` there (±0, ±π,
/// ±π/2, signs included), so headings are bit-identical either way.
#[inline]
#[must_use]
pub(crate) fn bearing(dx: f64, dy: f64) -> f64 {
    if dy == 0.0 && dx > 0.0 {
        dy
    } else if dy == 0.0 && dx < 0.0 {
        PI.copysign(dy)
    } else if dx == 0.0 && dy != 0.0 {
        FRAC_PI_2.copysign(dy)
    } else {
        dy.atan2(dx)
    }
}

/// The angle between two directions, folded into [0, π].
#[inline]
#[must_use]
pub(crate) fn folded_angle(a: f64, b: f64) -> f64 {
    // `x % TAU` is `x` below TAU: the common case skips the slow `fmod`.
    let d = (a - b).abs();
    let d = if d < TAU { d } else { d % TAU };
    if d > PI {
        TAU - d
    } else {
        d
    }
}

/// `√(dx² + dy²)`, without the square root along the axes, where aisles run. There
/// `√(dx²)` is exactly `|dx|` in IEEE 754 arithmetic, as long as `dx²` neither overflows nor
/// loses precision to underflow: the range checked here.
#[inline]
#[must_use]
pub fn axis_dist(dx: f64, dy: f64) -> f64 {
    const NORMAL: std::ops::RangeInclusive<f64> = 1e-150..=1e150;
    if dy == 0.0 && NORMAL.contains(&dx.abs()) {
        dx.abs()
    } else if dx == 0.0 && NORMAL.contains(&dy.abs()) {
        dy.abs()
    } else {
        (dx * dx + dy * dy).sqrt()
    }
}

/// `(dx / d * budget, dy / d * budget)`, `d` being [`axis_dist`]`(dx, dy)`. Along the axes `d`
/// is `|dx|` (or `|dy|`), so the first is `±budget` and the second, `dy` being a zero, is
/// `dy * budget`, bit for bit: no division there.
#[inline]
fn along(dx: f64, dy: f64, d: f64, budget: f64) -> (f64, f64) {
    if dy == 0.0 && d == dx.abs() && d > 0.0 {
        (if dx > 0.0 { budget } else { -budget }, dy * budget)
    } else if dx == 0.0 && d == dy.abs() && d > 0.0 {
        (dx * budget, if dy > 0.0 { budget } else { -budget })
    } else {
        (dx / d * budget, dy / d * budget)
    }
}

/// Motion's columns of a fleet `$r`, each sliced to `$n`: one list for [`Robots::split`],
/// which borrows other columns beside them, and [`Robots::motion`]. Detours are empty, or as
/// long as the fleet.
macro_rules! motion_of {
    ($r:expr, $n:expr) => {
        Motion {
            x: &mut $r.x[..$n],
            y: &mut $r.y[..$n],
            at_node: &mut $r.at_node[..$n],
            edge_u: &mut $r.edge_u[..$n],
            edge_v: &mut $r.edge_v[..$n],
            routing: &mut $r.routing[..$n],
            goal: &$r.goal[..$n],
            has_final: &$r.has_final[..$n],
            final_x: &$r.final_x[..$n],
            final_y: &$r.final_y[..$n],
            final_v: &$r.final_v[..$n],
            wp_x: &mut $r.wp_x[..$n],
            wp_y: &mut $r.wp_y[..$n],
            wp_node: &mut $r.wp_node[..$n],
            via: {
                let via = $r.via.len().min($n);
                &mut $r.via[..via]
            },
        }
    };
}

/// The columns of phases 3 to 6 beside motion's, each a slice of the fleet's length.
pub(crate) struct Pass<'a> {
    pub state: &'a [State],
    /// Phase 2's heading: written only by cruising steps (`crate::rules::paper::cruise`), which do phase
    /// 2 in the same pass.
    pub heading: &'a mut [f64],
    pub waited: &'a mut [bool],
    /// Read by cruising steps only (`crate::rules::paper::cruise`).
    pub marked: &'a [bool],
    pub speed: &'a [f64],
    pub dwell: &'a mut [u32],
    pub energy: &'a mut [f64],
}

impl Robots {
    /// The columns the step's pass over the robots (phases 3 to 6) reads and writes, each a
    /// slice of the fleet's length: motion's (see [`Motion`]), then the rest of the pass's.
    #[allow(clippy::inline_always)] // measured: inlined, the passes know every slice's length
    #[inline(always)]
    pub(crate) fn split(&mut self) -> (Motion<'_>, Pass<'_>) {
        let n = self.x.len();
        let pass = Pass {
            state: &self.state[..n],
            heading: &mut self.heading[..n],
            waited: &mut self.waited[..n],
            marked: &self.marked[..n],
            speed: &self.speed[..n],
            dwell: &mut self.dwell[..n],
            energy: &mut self.energy[..n],
        };
        (motion_of!(self, n), pass)
    }

    /// Motion's columns alone (other columns may be shorter: a hand-built fleet in a test
    /// need not fill them).
    #[cfg(test)]
    pub(crate) fn motion(&mut self) -> Motion<'_> {
        let n = self.x.len();
        motion_of!(self, n)
    }
}

/// The columns that motion reads and writes, each a slice of the fleet's length: the step's
/// pass over the robots indexes them with no bounds check per access (on the whole `Vec`s
/// those checks were a third of that pass's instructions at the paper's sizes).
pub(crate) struct Motion<'a> {
    pub(crate) x: &'a mut [f64],
    pub(crate) y: &'a mut [f64],
    pub(crate) at_node: &'a mut [u32],
    pub(crate) edge_u: &'a mut [u32],
    pub(crate) edge_v: &'a mut [u32],
    pub(crate) routing: &'a mut [bool],
    pub(crate) goal: &'a [u32],
    pub(crate) has_final: &'a [bool],
    pub(crate) final_x: &'a [f64],
    pub(crate) final_y: &'a [f64],
    pub(crate) final_v: &'a [u32],
    pub(crate) wp_x: &'a mut [f64],
    pub(crate) wp_y: &'a mut [f64],
    pub(crate) wp_node: &'a mut [u32],
    /// Detours: empty, or as long as the fleet (robots past its end have none).
    pub(crate) via: &'a mut [u32],
}

#[cfg(test)]
impl<'a> Motion<'a> {
    pub(crate) fn of(r: &'a mut Robots) -> Motion<'a> {
        r.motion()
    }
}

impl Motion<'_> {
    /// [`advance`], for robot `i` of this view. Inlined into both passes that move robots
    /// (the step's and cruising's): a call costs a fifth of a move.
    #[allow(clippy::inline_always)] // measured: left to `#[inline]`, both passes called it
    #[inline(always)]
    pub(crate) fn advance(&mut self, g: &HighwayGraph, i: usize, mut budget: f64) -> f64 {
        let mut moved = 0.0;
        while self.routing[i] {
            let (dx, dy) = (self.wp_x[i] - self.x[i], self.wp_y[i] - self.y[i]);
            let d = axis_dist(dx, dy);
            if budget < d {
                // dx / d is exactly ±1 or 0 on axis-parallel aisles, so positions stay exact.
                let (mx, my) = along(dx, dy, d, budget);
                self.x[i] += mx;
                self.y[i] += my;
                self.at_node[i] = NONE;
                moved += budget;
                break;
            }
            self.x[i] = self.wp_x[i];
            self.y[i] = self.wp_y[i];
            budget -= d;
            moved += d;
            let n = self.wp_node[i];
            if n == NONE {
                // The final point: strictly inside its edge, which the robot keeps for planning.
                self.at_node[i] = NONE;
                self.edge_u[i] = self.goal[i];
                self.edge_v[i] = self.final_v[i];
                self.routing[i] = false;
                break;
            }
            self.at_node[i] = n;
            if n == self.goal[i] {
                if self.has_final[i] {
                    self.wp_x[i] = self.final_x[i];
                    self.wp_y[i] = self.final_y[i];
                    self.wp_node[i] = NONE;
                    self.edge_u[i] = n;
                    self.edge_v[i] = self.final_v[i];
                } else {
                    self.routing[i] = false;
                    break;
                }
            } else {
                let via = self.via.get_mut(i).map_or(NONE, |v| std::mem::replace(v, NONE));
                let next = if via == NONE { g.next_hop(NodeId(n), NodeId(self.goal[i])).map_or(NONE, |v| v.0) } else { via };
                let (x, y) = g.pos(next);
                self.wp_x[i] = x;
                self.wp_y[i] = y;
                self.wp_node[i] = next;
                self.edge_u[i] = n;
                self.edge_v[i] = next;
            }
            if budget <= 0.0 {
                break;
            }
        }
        moved
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn along_the_axes_without_division_agrees_bit_for_bit() {
        let mut v = 1e-200_f64;
        while v < 1e200 {
            for a in [v, -v, v * 1.000_000_1, -v * 0.999_999_9] {
                for z in [0.0, -0.0] {
                    for (dx, dy) in [(a, z), (z, a)] {
                        let d = axis_dist(dx, dy);
                        for budget in [0.0, -0.0, 4.0, 0.3, 1e-300, d * 0.5, -1.0] {
                            let (mx, my) = along(dx, dy, d, budget);
                            assert_eq!((mx.to_bits(), my.to_bits()), ((dx / d * budget).to_bits(), (dy / d * budget).to_bits()), "{dx} {dy} {budget}");
                        }
                    }
                }
            }
            v *= 7.3;
        }
        let (mx, my) = along(3.0, 4.0, 5.0, 2.0);
        assert_eq!((mx, my), (3.0 / 5.0 * 2.0, 4.0 / 5.0 * 2.0));
    }
}
