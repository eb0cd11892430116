//! Phase 2 (spec section 4): who wants to move, and where each is heading; and who stands in
//! a bay ([`crate::fleet::bay::Bays::choose`]), for the collision phase that follows.

use crate::fleet::motion::bearing;
use crate::rules::paper::Paper;

impl Paper {
    /// Phase 2: who wants to move, and where each is heading.
    pub(super) fn intend(&mut self) {
        let n = self.robots.len();
        let r = &mut self.robots;
        // Slices of exactly `n` (here and in the phases below): indexing by `i < n` needs
        // no bounds checks.
        let (routing, state, x, y, wp_x, wp_y) = (&r.routing[..n], &r.state[..n], &r.x[..n], &r.y[..n], &r.wp_x[..n], &r.wp_y[..n]);
        // The heading is the collision test's direction too (`resolve` reads it only where
        // a robot wants to move, and so was set just now): no column of its own.
        let (wants, head) = (&mut self.wants[..n], &mut r.heading[..n]);
        for i in 0..n {
            let w = routing[i] && state[i].travels();
            wants[i] = w;
            if w {
                head[i] = bearing(wp_x[i] - x[i], wp_y[i] - y[i]);
            }
        }
        self.bays.choose(&self.robots);
    }
}
