//! Contacts: pairs of robots closer than r_i + r_j after a move (docs/metrics.md), found
//! with the step's collision grid.

use super::Collisions;

/// Tiny fleets: how far apart, before the moves, two robots must stand for the contact count
/// (with the fleet's largest radius `r_max` and moves of at most `slack`) to pass them by.
pub(super) fn contact_need(r_max: f64, slack: f64) -> f64 {
    (2.0 * r_max + 0.5 * slack) * 1.000_001 + slack * (1.0 + 1e-9) + 1e-9
}

impl Collisions {
    /// Contacts after this step's moves: pairs closer than `r_i + r_j` of which at least one
    /// robot moved (`moved`), counted once each, and the smallest centre distance among the
    /// pairs looked at (within `r_i + r_j + slack`, or `f64::INFINITY`). `x`, `y` are the
    /// positions after the moves; `slack` is at least the farthest any robot moved this step
    /// (twice a step), so this step's grid (built before the moves) still finds every pair.
    /// Robots in bays (spread placement's parked robots) stand beside the aisle and are not in
    /// the grid: they are not counted, as they do not block.
    /// Call it after [`Collisions::resolve`] in a step where someone wanted to move.
    #[must_use]
    pub fn contacts(&mut self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], slack: f64) -> (u64, f64) {
        let r_max = radius[..x.len()].iter().copied().fold(0.0, f64::max);
        self.contacts_within(x, y, radius, moved, r_max, slack)
    }

    /// [`Collisions::contacts`] with the fleet's largest radius `r_max` given (it is the
    /// same every step: the caller keeps it).
    #[must_use]
    pub fn contacts_within(&mut self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        if x.len() < 2 {
            // No pairs (and `resolve` built no grid for a robot alone).
            return (0, f64::INFINITY);
        }
        if self.space.tiny {
            return self.contacts_tiny(x, y, radius, moved, r_max, slack);
        }
        if self.space.dense {
            if let Some(found) = self.contacts_by_cell_pairs(x, y, radius, moved, r_max, slack) {
                return found;
            }
        }
        self.contacts_by_boxes(x, y, radius, moved, r_max, slack)
    }

    /// Contacts after this step's moves, from positions alone (docs/metrics.md): every pair
    /// of robots closer than `r_i + r_j`, whatever their state (in a bay, still, queued),
    /// counted once; and the smallest distance among pairs within `r_i + r_j + margin`
    /// (`f64::INFINITY` if none). `slack` is at least twice the farthest any robot moved; the
    /// grid is this step's, built before the moves (as for [`Collisions::contacts`]).
    ///
    /// Robots in the grid are counted as [`Collisions::contacts_within`] counts them with
    /// every one of them marked as moved (each pair once, from the smaller id); robots in
    /// bays, out of the grid, against the grid from their own side (a box around each), and
    /// against one another by a sort of their cells (cells are at least `2 r_max + margin`
    /// wide, so a pair within that stands in neighbouring cells). Widening `slack` by
    /// `2 margin` makes every pair within `r_i + r_j + margin` one that is looked at.
    #[allow(clippy::too_many_arguments)]
    pub fn contacts_of_every_pair(&mut self, x: &[f64], y: &[f64], radius: &[f64], r_max: f64, slack: f64, margin: f64) -> (u64, f64) {
        let n = x.len();
        if n < 2 {
            return (0, f64::INFINITY);
        }
        self.closest_within = margin;
        let slack = slack + 2.0 * margin;
        let mut in_grid = std::mem::take(&mut self.in_grid);
        let mut in_bay = std::mem::take(&mut self.in_bay);
        in_grid.clear();
        in_bay.clear();
        let cell_of = &self.space.cell_of[..n];
        in_grid.extend(cell_of.iter().map(|&c| c != u32::MAX));
        in_bay.extend(cell_of.iter().map(|&c| c == u32::MAX));
        let (mut count, mut closest) = self.contacts_within(x, y, radius, &in_grid, r_max, slack);
        if in_bay.contains(&true) {
            // Robots in bays against the grid: each bay robot looks from its own side (the
            // grid's robots are never "moved" here, so each pair is seen once).
            let (c, d) = if self.space.tiny {
                self.contacts_tiny(x, y, radius, &in_bay, r_max, slack)
            } else {
                self.contacts_by_boxes(x, y, radius, &in_bay, r_max, slack)
            };
            count += c;
            closest = closest.min(d);
            let (c, d) = self.bays_among_themselves(x, y, radius, &in_bay, margin);
            count += c;
            closest = closest.min(d);
        }
        self.in_grid = in_grid;
        self.in_bay = in_bay;
        (count, closest)
    }

    /// Pairs of robots in bays, by their positions now: sorted by cell, each robot looks at
    /// the neighbouring cells for robots with a larger id.
    fn bays_among_themselves(&mut self, x: &[f64], y: &[f64], radius: &[f64], in_bay: &[bool], margin: f64) -> (u64, f64) {
        let grid = self.space.grid;
        let cols = grid.cols as u64;
        let key = |i: usize| {
            let (tx, ty) = grid.scaled(x[i], y[i]);
            let (c, r) = grid.cell(tx, ty);
            u64::from(r) * cols + u64::from(c)
        };
        let list = &mut self.bays_by_cell;
        list.clear();
        list.extend((0..in_bay.len()).filter(|&i| in_bay[i]).map(|i| (key(i), i as u32)));
        list.sort_unstable();
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        for &(k, i) in list.iter() {
            let i = i as usize;
            let (row, col) = (k / cols, k % cols);
            for r in row.saturating_sub(1)..=row + 1 {
                let (lo, hi) = (r * cols + col.saturating_sub(1), r * cols + col + 1);
                let start = list.partition_point(|e| e.0 < lo);
                for &(kj, j) in &list[start..] {
                    if kj > hi {
                        break;
                    }
                    let j = j as usize;
                    if j <= i {
                        continue;
                    }
                    let d = crate::fleet::motion::axis_dist(x[j] - x[i], y[j] - y[i]);
                    if d <= radius[i] + radius[j] + margin {
                        closest = closest.min(d);
                    }
                    count += u64::from(d < radius[i] + radius[j]);
                }
            }
        }
        (count, closest)
    }

    /// [`Collisions::contacts_within`] for tiny fleets: the robots flagged near each robot
    /// that moved, by the step's pass over pairs (see `Collisions::tiny`).
    fn contacts_tiny(&mut self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        let within = self.closest_within;
        let n = x.len();
        let (y, radius, moved) = (&y[..n], &radius[..n], &moved[..n]);
        // The widest pair looked at: the other robot before the moves within `near` of `i`
        // after them (a hair more for `near2`'s slack and rounding), so within `near` plus how
        // far `i` moved of `i` before them; `slack` bounds that move. Each robot's own move is
        // checked below all the same.
        let need = contact_need(r_max, slack);
        if need > self.contact_need {
            // From the next step on, the pass over pairs flags this wide.
            self.contact_need = need;
        }
        let placed = self.space.placed;
        let cell_of = &self.space.cell_of[..n];
        let (by_cell, sx, sy, bits, cover) =
            (&self.space.by_cell[..placed], &self.space.sx[..placed], &self.space.sy[..placed], &self.space.bits[..placed], self.space.cover);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        // Robots in the grid are placed in id order: `p` is the place of robot `i`, as in
        // `Collisions::resolve`.
        let mut p = 0;
        for i in 0..n {
            let here = cell_of[i] != u32::MAX;
            p += usize::from(here);
            if !moved[i] {
                continue;
            }
            let (xi, yi, ri) = (x[i], y[i], radius[i]);
            // A robot within contact of `i` after the moves stood within contact plus half the
            // slack of it before them: test the copied (pre-move) positions, and only the
            // near ones by id.
            let near = radius[i] + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            let far = |k: usize| {
                let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                dx * dx + dy * dy > near2
            };
            // The others flagged near `i` hold every robot this test can pass, unless `i`
            // moved farther than the flags allow (or stands in a bay): then every robot in the
            // grid is looked at.
            let mut mask = 0u64;
            if here && near * 1.000_001 + crate::fleet::motion::axis_dist(xi - sx[p - 1], yi - sy[p - 1]) * (1.0 + 1e-9) + 1e-9 <= cover {
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
                let d = crate::fleet::motion::axis_dist(x[j] - xi, y[j] - yi);
                if d <= ri + radius[j] + within {
                    closest = closest.min(d);
                }
                count += u64::from(d < ri + radius[j]);
            }
        }
        (count, closest)
    }

    /// [`Collisions::contacts_within`] robot by robot: the cells of a box around each robot
    /// that moved.
    fn contacts_by_boxes(&self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        let within = self.closest_within;
        let n = x.len();
        let (y, radius, moved) = (&y[..n], &radius[..n], &moved[..n]);
        let grid = self.space.grid;
        let (by_cell, sx, sy) = (&self.space.by_cell[..], &self.space.sx[..], &self.space.sy[..]);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        for i in 0..n {
            if !moved[i] {
                continue;
            }
            let (xi, yi) = (x[i], y[i]);
            // A robot within contact of `i` after the moves stood within contact plus half the
            // slack of it before them: test the sorted (pre-move) positions first, read in
            // order, and only the few near ones by id.
            let near = radius[i] + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            let ri = radius[i];
            let mut pair = |k: usize| {
                let j = by_cell[k] as usize;
                if moved[j] && j < i {
                    return;
                }
                let d = crate::fleet::motion::axis_dist(x[j] - xi, y[j] - yi);
                if d <= ri + radius[j] + within {
                    closest = closest.min(d);
                }
                count += u64::from(d < ri + radius[j]);
            };
            // Far is `d² > near2`, and the rest near (NaN included, as ever).
            let near_k = |k: usize| {
                let (dx, dy) = (sx[k] - xi, sy[k] - yi);
                let far = dx * dx + dy * dy > near2;
                u64::from(!far) & u64::from(by_cell[k] as usize != i)
            };
            // The cells of a box around `i`. Every position that passes the test above lies
            // within `near` (and a hair, from `near2`'s slack and rounding) of `i` along each
            // axis; which cells the box covers changes only what is read, never what is
            // counted.
            let hw = (near * 1.000_1 + 1e-9) * grid.inv_size + 1e-6;
            let (tx, ty) = grid.scaled(xi, yi);
            let (c0, r0) = grid.cell(tx - hw, ty - hw);
            let (c1, r1) = grid.cell(tx + hw, ty + hw);
            let (c0, r0, c1, r1) = (c0 as usize, r0 as usize, c1 as usize, r1 as usize);
            for row in r0..=r1 {
                let (mut k0, k1) = {
                    let base = row * grid.cols;
                    self.runs().of(base + c0, base + c1)
                };
                // Most candidates are far: flag the near ones without a branch each, 64 at a
                // time, then look at those.
                while k0 < k1 {
                    let end = k1.min(k0 + 64);
                    let mut mask = 0u64;
                    for k in k0..end {
                        mask |= near_k(k) << (k - k0);
                    }
                    while mask != 0 {
                        pair(k0 + mask.trailing_zeros() as usize);
                        mask &= mask - 1;
                    }
                    k0 = end;
                }
            }
        }
        (count, closest)
    }

    /// [`Collisions::contacts_within`] for dense grids: each pair of neighbouring robots is
    /// found once, from the cell of the first in grid order (the rest of its cell, the next
    /// cell of its row and the three cells below), instead of once from each robot's box.
    /// The pairs the collision test collected this step are read again where they reach
    /// far enough; else the count collects its own (`pairs.rs`).
    /// Each pair found is then judged exactly as the box scan judges it, from the same robot
    /// (the one that moved; of two that moved, the smaller id), so the pairs looked at, the
    /// count and the closest approach are the same to the bit. `None` where that cannot be
    /// promised: a neighbour could lie beyond the next cell, or a robot that moved stands
    /// in a bay, out of the grid.
    fn contacts_by_cell_pairs(&mut self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> Option<(u64, f64)> {
        let within = self.closest_within;
        let n = x.len();
        let (y, radius, moved, cell_of) = (&y[..n], &radius[..n], &moved[..n], &self.space.cell_of[..n]);
        // A pair the box scan looks at stood (before the moves) within its `near` (at most
        // `2 r_max + slack / 2`) plus one robot's move (at most `slack / 2`): within `span`.
        let span = (2.0 * r_max + slack) * 1.000_1 + 1e-9;
        let fits = span * 1.001 < 1.0 / self.space.grid.inv_size;
        if !fits || (0..n).any(|i| moved[i] && cell_of[i] == u32::MAX) {
            return None;
        }
        let span2 = span * span;
        // From the next step on, the collision test collects its pairs this wide too.
        self.near.contact_span2 = self.near.contact_span2.max(span2);
        let half = 0.5 * slack;
        if span2 > self.near.pairs_r2 && !self.collect_pairs(span2) {
            // The collision test did not collect them this step, or not this wide, and there
            // are too many to keep: the boxes count without keeping them.
            return None;
        }
        let placed = self.space.placed;
        let (by_cell, sx, sy) = (&self.space.by_cell[..placed], &self.space.sx[..placed], &self.space.sy[..placed]);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        for &(k, m) in &self.near.pairs[..self.near.pairs_len] {
            let (k, m) = (k as usize, m as usize);
            let (dx, dy) = (sx[m] - sx[k], sy[m] - sy[k]);
            if dx * dx + dy * dy > span2 {
                continue;
            }
            let (i, j) = (by_cell[k] as usize, by_cell[m] as usize);
            let (mi, mj) = (moved[i], moved[j]);
            if !(mi || mj) {
                continue;
            }
            // The robot the box scan would look from, and the other, by its place.
            let (l, o, ko) = if mi && (!mj || i < j) { (i, j, m) } else { (j, i, k) };
            let near = radius[l] + r_max + half;
            let near2 = near * near * 1.000_001;
            let (ex, ey) = (sx[ko] - x[l], sy[ko] - y[l]);
            if ex * ex + ey * ey > near2 {
                continue;
            }
            let d = crate::fleet::motion::axis_dist(x[o] - x[l], y[o] - y[l]);
            if d <= radius[l] + radius[o] + within {
                closest = closest.min(d);
            }
            count += u64::from(d < radius[l] + radius[o]);
        }
        Some((count, closest))
    }
}

#[cfg(test)]
mod tests {
    use super::Collisions;

    /// A small deterministic generator (no dependency for one test).
    fn lcg(state: &mut u64) -> f64 {
        *state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn cell_pairs_count_what_boxes_count_to_the_bit() {
        let mut seed = 7;
        let mut found = 0;
        for case in 0..200 {
            let n = 300 + case * 7;
            // Crowded: about 6 cells per robot, so the grid is dense.
            let side = (n as f64 * 6.0).sqrt() * 50.0;
            let mut c = Collisions::new([0.0, 0.0, side, side], 25.0, n);
            assert!(c.space.dense);
            let (mut x, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
            for _ in 0..n {
                // Some on an aisle's line, some anywhere, a few on top of each other.
                let on_line = lcg(&mut seed) < 0.5;
                x.push(if on_line { (lcg(&mut seed) * 10.0).floor() * 50.0 + 25.0 } else { lcg(&mut seed) * side });
                y.push(lcg(&mut seed) * side);
            }
            let radius: Vec<f64> = (0..n).map(|i| if case % 3 == 0 { 12.5 } else { 10.0 + (i % 5) as f64 }).collect();
            let (px, py) = (x.clone(), y.clone());
            c.build_grid(&x, &y, &radius, &[]);
            let moved: Vec<bool> = (0..n).map(|_| lcg(&mut seed) < 0.6).collect();
            for i in 0..n {
                if moved[i] {
                    let a = lcg(&mut seed) * std::f64::consts::TAU;
                    x[i] += 4.0 * a.cos();
                    y[i] += 4.0 * a.sin();
                }
            }
            let r_max = radius.iter().copied().fold(0.0, f64::max);
            let pairs = c.contacts_by_cell_pairs(&x, &y, &radius, &moved, r_max, 8.0).expect("fits the grid");
            let boxes = c.contacts_by_boxes(&x, &y, &radius, &moved, r_max, 8.0);
            assert_eq!((pairs.0, pairs.1.to_bits()), (boxes.0, boxes.1.to_bits()), "case {case}");
            // A grid as the simulation builds it (reaching the widest contact distance)
            // through the collision test, which collects the pairs as wide as the count
            // asked for once: the count reads them instead of collecting its own.
            let mut k = Collisions::new([0.0, 0.0, side, side], 2.0 * r_max, n);
            k.build_grid(&px, &py, &radius, &[]);
            let _ = k.contacts_by_cell_pairs(&x, &y, &radius, &moved, r_max, 8.0).expect("fits the grid");
            let heading = vec![0.0; n];
            k.resolve(&px, &py, &radius, &vec![true; n], &heading, &[], 0.0, 0.5);
            assert!(k.near.pairs_r2 > 0.0, "case {case}: the collision test collected pairs");
            let kept = k.contacts_by_cell_pairs(&x, &y, &radius, &moved, r_max, 8.0).expect("fits the grid");
            assert_eq!((kept.0, kept.1.to_bits()), (boxes.0, boxes.1.to_bits()), "case {case}, pairs kept");
            found += pairs.0;
        }
        assert!(found > 1000, "the cases hold contacts: {found}");
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
                let d = crate::fleet::motion::axis_dist(x[j] - x[i], y[j] - y[i]);
                closest = closest.min(d);
                count += u64::from(d < radius[i] + radius[j]);
            }
        }
        (count, closest)
    }

    #[test]
    fn contacts_count_what_the_definition_counts_to_the_bit() {
        // Tiny fleets (the pass over pairs, from its first step with nothing flagged for
        // contacts yet) and larger ones (sparse and dense grids), over several steps, with
        // robots in bays in some cases.
        let mut seed = 7;
        let mut found = 0;
        for case in 0..160 {
            let n = [1, 2, 6, 20, 32, 33, 60, 300][case % 8];
            let side = (n as f64 * 3.0).sqrt() * 50.0;
            let radius: Vec<f64> = (0..n).map(|i| if case % 3 == 0 { 12.5 } else { 10.0 + (i % 5) as f64 }).collect();
            let r_max = radius.iter().copied().fold(0.0, f64::max);
            let mut c = Collisions::new([-50.0, -50.0, side + 50.0, side + 50.0], 2.0 * r_max, n);
            let (mut x, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
            for _ in 0..n {
                // Some on an aisle's line, some anywhere.
                let on_line = lcg(&mut seed) < 0.5;
                x.push(if on_line { (lcg(&mut seed) * 10.0).floor() * 50.0 + 25.0 } else { lcg(&mut seed) * side });
                y.push(lcg(&mut seed) * side);
            }
            // Bays in every other round of fleet sizes, so tiny fleets get them too.
            let bay: Vec<bool> = (0..n).map(|_| (case / 8) % 2 == 1 && lcg(&mut seed) < 0.15).collect();
            for step in 0..4 {
                let (px, py) = (x.clone(), y.clone());
                c.build_grid(&x, &y, &radius, &bay);
                let moved: Vec<bool> = (0..n).map(|_| lcg(&mut seed) < 0.6).collect();
                for i in 0..n {
                    if moved[i] {
                        let a = lcg(&mut seed) * std::f64::consts::TAU;
                        // Now and then a tiny fleet's robot jumps far beyond `slack`, past
                        // what the flags cover: the count must look at every robot for it.
                        // (The grids' cell pairs rely on moves within `slack / 2`.)
                        let len = if n <= 32 && lcg(&mut seed) < 0.1 { 40.0 } else { 4.0 };
                        x[i] += len * a.cos();
                        y[i] += len * a.sin();
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
