//! Phase 2 (spec section 4): who wants to move, and where each is heading; and who stands in
//! a bay ([`Bays::choose`]), for the collision phase that follows.

use crate::fleet::bay::Bays;
use crate::fleet::motion::bearing;
use crate::fleet::robot::Robots;

/// Phase 2: who wants to move (`wants`), and where each is heading (`robots.heading`).
pub(crate) fn intend(robots: &mut Robots, wants: &mut [bool], bays: &mut Bays) {
    let n = robots.len();
    let r = robots;
    // Slices of exactly `n` (here and in the phases below): indexing by `i < n` needs no
    // bounds checks.
    let (routing, state, x, y, wp_x, wp_y) = (&r.routing[..n], &r.state[..n], &r.x[..n], &r.y[..n], &r.wp_x[..n], &r.wp_y[..n]);
    // The heading is the collision test's direction too (`resolve` reads it only where a
    // robot wants to move, and so was set just now): no column of its own.
    let (wants, head) = (&mut wants[..n], &mut r.heading[..n]);
    for i in 0..n {
        let w = routing[i] && state[i].travels();
        wants[i] = w;
        if w {
            head[i] = bearing(wp_x[i] - x[i], wp_y[i] - y[i]);
        }
    }
    bays.choose(r);
}
