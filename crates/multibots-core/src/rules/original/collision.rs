//! Phase 2, collisions (`Controller.checkCollisionsAndStop`), and when a run is deadlocked.
//!
//! **The rule.** For every ordered pair (i, j), i ≠ j, in the order `for i: for j:`, on the
//! positions after phase 1:
//!
//! - *contact* is `sqrt(dx² + dy²) <= r_i + r_j + 8` = 32 px (the radius is `L / 4` = 12 by
//!   Python 2's integer division);
//! - in contact, with the bearing β = `atan2(-(y_j − y_i), x_j − x_i)` in degrees (y up),
//!   robot i *meets* j when `|β − θ_i| < 30` on the **unfolded** angles (a heading of 180°
//!   and a bearing of −179° are 359° apart, not 1°), or when 133 < β < 137 whatever its
//!   heading (the **extra stop**: j up and to the left of i, near the diagonal). When it
//!   meets j, the pair (i, j) joins the end of the list of stops unless it is there
//!   already, and only then is i stopped; and i's S count grows by one unless this stop
//!   was counted already. A robot's "counted" mark is cleared in phase 1 of every tick on
//!   which it is not stopped, so a robot released while still meeting another robot whose
//!   pair is in the list is counted again on every tick, without being stopped.
//! - out of contact: if (i, j) is the **first** pair in the list, it leaves the list and i
//!   is released. Only the first pair can leave, so a stop ends only when every stop
//!   before it has ended.
//!
//! β is −180° or +180° for a robot straight to the west, depending on the sign of zero in
//! `-(y_j − y_i)`: Python gives +0 when both `y` are integers and −0.0 when either is a
//! float (see `agent.rs`). Against a heading of 180° the first counts as meeting, the second
//! does not.
//!
//! **Deadlock.** Stopped robots never move (phase 1 skips them, and only a robot at its
//! charger is teleported), and only the first pair of the list can release anyone. So once
//! the first pair is two stopped robots, neither at its charger, that are in contact, that
//! pair stays first and in contact for ever: no stopped robot is released again, and the
//! first robot of the pair never reaches its charger, so the run can never be complete.
//! [`Original::deadlocked`] tests exactly that, after every tick; the run ends then with
//! [`Outcome::Deadlock`](crate::record::metrics::Outcome::Deadlock), where the original would go on
//! ticking for ever.

use super::agent::Agent;
use super::{Original, RADIUS};
use crate::ids::NONE;
use crate::record::events::EventKind;

/// `r_i + r_j + 8`.
const CONTACT: f64 = RADIUS + RADIUS + 8.0;
/// `param.th_close_angle`.
const CLOSE_ANGLE: f64 = 30.0;

/// `Controller.collisionBetweenAgents`.
#[inline]
fn in_contact(a: &Agent, b: &Agent) -> bool {
    let (dx, dy) = (a.x - b.x, a.y - b.y);
    // Beyond CONTACT + 1 on either axis the distance exceeds CONTACT whatever the rounding.
    if dx.abs() > CONTACT + 1.0 || dy.abs() > CONTACT + 1.0 {
        return false;
    }
    (dx * dx + dy * dy).sqrt() <= CONTACT
}

/// The bearing from `a` to `b` in degrees, y up, with Python's sign of zero.
#[inline]
fn bearing(a: &Agent, b: &Agent) -> f64 {
    let dy = b.y - a.y;
    let up = if dy == 0.0 && a.y_int && b.y_int { 0.0 } else { -dy };
    up.atan2(b.x - a.x) * 180.0 / std::f64::consts::PI
}

impl Original {
    /// `Controller.checkCollisionsAndStop`.
    pub(super) fn check_collisions(&mut self) {
        let n = self.agents.len();
        for i in 0..n {
            for j in 0..n {
                if i == j {
                    continue;
                }
                let (a, b) = (&self.agents[i], &self.agents[j]);
                let pair = (i as u8, j as u8);
                if in_contact(a, b) {
                    let beta = bearing(a, b);
                    if (beta - a.theta).abs() < CLOSE_ANGLE || (beta > 133.0 && beta < 137.0) {
                        if !self.pairs.contains(&pair) {
                            self.pairs.push_back(pair);
                            self.agents[i].stopped = true;
                        }
                        if !self.agents[i].counted {
                            self.agents[i].counted = true;
                            self.agents[i].collisions += 1;
                            self.stats.collisions[i] += 1;
                            self.event(EventKind::Wait, i, NONE);
                        }
                    }
                } else if self.pairs.front() == Some(&pair) {
                    self.agents[i].stopped = false;
                    self.pairs.pop_front();
                }
            }
        }
    }

    /// Whether stopped robots can never be released again (see the module docs).
    pub(super) fn deadlocked(&self) -> bool {
        let Some(&(i, j)) = self.pairs.front() else {
            return false;
        };
        let (a, b) = (&self.agents[usize::from(i)], &self.agents[usize::from(j)]);
        let frozen = |r: &Agent| r.stopped && !r.at_charger;
        frozen(a) && frozen(b) && in_contact(a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, y: f64, y_int: bool) -> Agent {
        let mut a = Agent::new(0, 10.0);
        a.x = x;
        a.y = y;
        a.y_int = y_int;
        a
    }

    #[test]
    fn contact_is_at_32_px() {
        assert!(in_contact(&at(100.0, 100.0, true), &at(132.0, 100.0, true)));
        assert!(!in_contact(&at(100.0, 100.0, true), &at(133.0, 100.0, true)));
        // 20² + 25² = 1025 > 32²
        assert!(!in_contact(&at(100.0, 100.0, true), &at(120.0, 125.0, true)));
        assert!(in_contact(&at(100.0, 100.0, true), &at(120.0, 124.0, true)));
    }

    #[test]
    fn a_robot_due_west_bears_180_or_minus_180_as_python_does() {
        let i = at(100.0, 625.0, true);
        assert_eq!(bearing(&i, &at(80.0, 625.0, true)), 180.0);
        assert_eq!(bearing(&i, &at(80.0, 625.0, false)), -180.0);
        assert_eq!(bearing(&i, &at(120.0, 625.0, false)), 0.0);
        assert_eq!(bearing(&i, &at(100.0, 605.0, false)), 90.0);
        assert_eq!(bearing(&i, &at(100.0, 645.0, true)), -90.0);
        let b = bearing(&i, &at(80.0, 605.0, true));
        assert!(b > 133.0 && b < 137.0, "{b}");
    }
}
