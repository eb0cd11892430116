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
            let need = (2.0 * r_max + 0.5 * slack) * 1.000_001 + slack * (1.0 + 1e-9) + 1e-9;
            if need > self.contact_need {
                // From the next step on, the pass over pairs flags this wide.
                self.contact_need = need;
            }
            let placed = self.placed;
            let (by_cell, sx, sy, bits, cover) = (&self.by_cell[..placed], &self.sx[..placed], &self.sy[..placed], &self.bits[..placed], self.cover);
            // Robots in the traffic are placed in id order: `p` is the place of robot `i`.
            let mut p = 0;
            for i in 0..n {
                let here = p < placed && by_cell[p] as usize == i;
                p += usize::from(here);
                if !moved[i] {
                    continue;
                }
                let (xi, yi, ri) = (x[i], y[i], radius[i]);
                // A robot within contact of `i` after the moves stood within contact plus half
                // the slack of it before them: test the copied (pre-move) positions, and only
                // the near ones by id.
                let near = radius[i] + r_max + 0.5 * slack;
                let near2 = near * near * 1.000_001;
                let far = |k: usize| {
                    let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                    dx * dx + dy * dy > near2
                };
                // The others near `i` before the moves hold every robot this test can pass,
                // unless `i` moved farther than they allow (or stands in a bay): then every
                // robot in the traffic is looked at.
                let mut mask = 0u64;
                if here && near * 1.000_001 + crate::route::axis_dist(xi - sx[p - 1], yi - sy[p - 1]) * (1.0 + 1e-9) + 1e-9 <= cover {
                    mask = u64::from(bits[p - 1]);
                } else {
                    // Flagged without a branch each (NaN counts as near, as ever).
                    for (k, &j) in by_cell.iter().enumerate() {
                        mask |= (u64::from(!far(k)) & u64::from(j as usize != i)) << k;
                    }
                }
                while mask != 0 {
                    let k = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let j = by_cell[k] as usize;
                    if far(k) || (moved[j] && j < i) {
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

#[cfg(test)]
mod tests {
    use super::Collisions;
    use crate::route::axis_dist;

    /// A small deterministic generator (no dependency for one test).
    fn lcg(state: &mut u64) -> f64 {
        *state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The count's definition over every pair (`px`, `py` before the moves, `x`, `y` after).
    #[allow(clippy::too_many_arguments)]
    fn brute(px: &[f64], py: &[f64], x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], bay: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        let (mut count, mut closest) = (0, f64::INFINITY);
        for i in 0..x.len() {
            if !moved[i] {
                continue;
            }
            let near = radius[i] + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            for j in 0..x.len() {
                if j == i || bay[j] || (moved[j] && j < i) {
                    continue;
                }
                let (dx, dy) = (px[j] - x[i], py[j] - y[i]);
                if dx * dx + dy * dy > near2 {
                    continue;
                }
                let d = axis_dist(x[j] - x[i], y[j] - y[i]);
                closest = closest.min(d);
                count += u64::from(d < radius[i] + radius[j]);
            }
        }
        (count, closest)
    }

    #[test]
    fn contacts_count_what_the_definition_counts_to_the_bit() {
        // Tiny fleets (the pass over pairs, from its first step with nothing flagged for
        // contacts yet), and larger ones (the neighbour list, kept over several steps), with
        // robots in bays in some cases.
        let mut seed = 7;
        let mut found = 0;
        for case in 0..160 {
            let n = [1, 2, 6, 20, 32, 33, 60, 300][case % 8];
            let side = (n as f64 * 3.0).sqrt() * 50.0;
            let mut c = Collisions::new([0.0, 0.0, side, side], 25.0, n);
            let (mut x, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
            for _ in 0..n {
                // Some on an aisle's line, some anywhere.
                let on_line = lcg(&mut seed) < 0.5;
                x.push(if on_line { (lcg(&mut seed) * 10.0).floor() * 50.0 + 25.0 } else { lcg(&mut seed) * side });
                y.push(lcg(&mut seed) * side);
            }
            let radius: Vec<f64> = (0..n).map(|i| if case % 3 == 0 { 12.5 } else { 10.0 + (i % 5) as f64 }).collect();
            let bay: Vec<bool> = (0..n).map(|_| case % 4 == 1 && lcg(&mut seed) < 0.15).collect();
            if bay.contains(&true) {
                c.bay.clone_from(&bay);
            }
            let r_max = radius.iter().copied().fold(0.0, f64::max);
            for step in 0..4 {
                let (px, py) = (x.clone(), y.clone());
                c.build_grid(&x, &y, &radius);
                let moved: Vec<bool> = (0..n).map(|_| lcg(&mut seed) < 0.6).collect();
                for i in 0..n {
                    if moved[i] {
                        let a = lcg(&mut seed) * std::f64::consts::TAU;
                        x[i] += 4.0 * a.cos();
                        y[i] += 4.0 * a.sin();
                    }
                }
                let got = c.contacts_within(&x, &y, &radius, &moved, r_max, 8.0);
                let want = brute(&px, &py, &x, &y, &radius, &moved, &bay, r_max, 8.0);
                assert_eq!((got.0, got.1.to_bits()), (want.0, want.1.to_bits()), "case {case} (n = {n}), step {step}");
                found += got.0;
            }
        }
        assert!(found > 1000, "the cases hold contacts: {found}");
    }
}
