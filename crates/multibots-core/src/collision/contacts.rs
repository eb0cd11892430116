//! Contacts: pairs of robots closer than r_i + r_j after a move (docs/metrics.md), found
//! among the step's candidates.

use super::Collisions;

impl Collisions {
    /// Contacts after this step's moves: pairs closer than `r_i + r_j` of which at least one
    /// robot moved (`moved`), counted once each, and the smallest centre distance among the
    /// pairs looked at, or `f64::INFINITY`. A pair is looked at from the robot `i` that moved
    /// (the larger id if both did) when the other robot, where it stood before the moves, is
    /// within `r_i + r_max + slack / 2` of where `i` stands after them. `x`, `y` are the
    /// positions after the moves; `slack` is twice the farthest a robot moves in a step.
    /// Robots in bays (spread placement's parked robots) stand beside the aisle: they are not
    /// looked at, as they do not block.
    /// Call it after [`Collisions::resolve`] (or [`Collisions::build_grid`]) in the same step.
    #[must_use]
    pub fn contacts(&mut self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], slack: f64) -> (u64, f64) {
        let r_max = radius[..x.len()].iter().copied().fold(0.0, f64::max);
        self.contacts_within(x, y, radius, moved, r_max, slack)
    }

    /// [`Collisions::contacts`] with the fleet's largest radius `r_max` given (it is the
    /// same every step: the caller keeps it).
    #[must_use]
    pub fn contacts_within(&mut self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        let n = x.len();
        let (y, radius, moved) = (&y[..n], &radius[..n], &moved[..n]);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        if self.tiny {
            let (by_cell, sx, sy) = (&self.by_cell[..self.placed], &self.sx[..self.placed], &self.sy[..self.placed]);
            for i in 0..n {
                if !moved[i] {
                    continue;
                }
                let (xi, yi, ri) = (x[i], y[i], radius[i]);
                // A robot within contact of `i` after the moves stood within contact plus half
                // the slack of it before them: test the copied (pre-move) positions first, and
                // only the few near ones by id.
                let near = radius[i] + r_max + 0.5 * slack;
                let near2 = near * near * 1.000_001;
                // Far is `d² > near2`, and the rest near (NaN included, as ever); flagged
                // without a branch each.
                let mut mask = 0u64;
                for k in 0..by_cell.len() {
                    let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                    let far = dx * dx + dy * dy > near2;
                    mask |= (u64::from(!far) & u64::from(by_cell[k] as usize != i)) << k;
                }
                while mask != 0 {
                    let j = by_cell[mask.trailing_zeros() as usize] as usize;
                    mask &= mask - 1;
                    if moved[j] && j < i {
                        continue;
                    }
                    let d = crate::route::axis_dist(x[j] - xi, y[j] - yi);
                    closest = closest.min(d);
                    count += u64::from(d < ri + radius[j]);
                }
            }
            return (count, closest);
        }
        // The widest pair looked at: the other robot before the moves within `near` of `i`
        // after them (a hair more for `near2`'s slack and rounding), so within `near` plus how
        // far `i` moved of `i` before them. `slack` bounds that move; each robot's own move
        // is checked below all the same.
        let need = (self.r_max.max(r_max) + r_max + 0.5 * slack) * 1.000_001 + slack * (1.0 + 1e-9) + 1e-9;
        if need > self.contact_need {
            self.contact_need = need;
        }
        if need > self.near.cover {
            // The list was not built for contacts this wide: build it now, at the positions
            // before the moves, for which it answers.
            let (px, py) = (&self.px[..], &self.py[..]);
            self.near.build(px, py, need * 2.0);
        }
        let (px, py, out) = (&self.px[..n], &self.py[..n], &self.out[..]);
        let (start, list, cover) = (&self.near.start[..=n], &self.near.list[..], self.near.cover);
        let mut all: Vec<u32> = Vec::new();
        for i in 0..n {
            if !moved[i] {
                continue;
            }
            let (xi, yi, ri) = (x[i], y[i], radius[i]);
            let near = radius[i] + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            // `i`'s neighbours before the moves are every robot this test can pass, unless
            // `i` moved farther than the list allows: then every robot is looked at.
            let moved_by = crate::route::axis_dist(xi - px[i], yi - py[i]);
            let candidates = if near * 1.000_001 + moved_by * (1.0 + 1e-9) + 1e-9 <= cover {
                &list[start[i] as usize..start[i + 1] as usize]
            } else {
                if all.is_empty() {
                    all.extend(0..n as u32);
                }
                &all[..]
            };
            for &j in candidates {
                let j = j as usize;
                if j == i || (!out.is_empty() && out[j]) || (moved[j] && j < i) {
                    continue;
                }
                let (dx, dy) = (px[j] - xi, py[j] - yi);
                if dx * dx + dy * dy > near2 {
                    continue;
                }
                let d = crate::route::axis_dist(x[j] - xi, y[j] - yi);
                closest = closest.min(d);
                count += u64::from(d < ri + radius[j]);
            }
        }
        (count, closest)
    }
}
