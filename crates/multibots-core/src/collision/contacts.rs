//! Contacts: pairs of robots closer than r_i + r_j after a move (docs/metrics.md), found
//! with the step's pass over pairs (tiny fleets) or the index (larger ones).
//!
//! The count after every step is a function of the positions alone: every pair closer than
//! r_i + r_j, and the smallest distance among pairs within r_i + r_j + margin. Larger fleets
//! keep the pairs in contact from the last count ([`Touching`]) and look again only at the
//! pairs of robots that moved since: the others' distances are what they were. The
//! smallest distance is then that of the pairs looked at, which is all the tally needs: it
//! keeps the smallest over the run, and every other pair's distance was looked at when one
//! of its robots last moved (a full count comes first).

use super::index::Index;
use super::{grid::Grid, Collisions};
use crate::fleet::motion::axis_dist;

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
        self.catch_up_index();
        self.index.ready_rows(&self.space.grid);
        self.contacts_by_index(x, y, radius, moved, r_max, slack)
    }

    /// Contacts after this step's moves, from positions alone (docs/metrics.md): every pair
    /// of robots closer than `r_i + r_j`, whatever their state (in a bay, still, queued),
    /// counted once; and the smallest distance among pairs within `r_i + r_j + margin`
    /// (`f64::INFINITY` if none). `slack` is at least twice the farthest any robot moved; the
    /// grid is this step's, built before the moves (as for [`Collisions::contacts`]).
    ///
    /// Tiny fleets: robots in the pass are counted as [`Collisions::contacts_within`] counts
    /// them with every one of them marked as moved (each pair once, from the smaller id);
    /// robots in bays against the others from their own side, and against one another by a
    /// sort of their cells (cells are at least `2 r_max + margin` wide, so a pair within that
    /// stands in neighbouring cells). Widening `slack` by `2 margin` makes every pair within
    /// `r_i + r_j + margin` one that is looked at. Larger fleets: [`Touching`], from the index
    /// brought to the positions after the moves (so `slack` is not needed); the smallest
    /// distance is then that of the pairs of robots that moved since the last count (module
    /// doc), `f64::INFINITY` if none.
    #[allow(clippy::too_many_arguments)]
    pub fn contacts_of_every_pair(&mut self, x: &[f64], y: &[f64], radius: &[f64], r_max: f64, slack: f64, margin: f64) -> (u64, f64) {
        let n = x.len();
        if n < 2 {
            return (0, f64::INFINITY);
        }
        // Lists serve where they can (positions not finite: the index's way). The index is
        // left as it stands, for `contacts_within` and for the index's next count (a full
        // one: `count_listed`).
        if !self.space.tiny && self.listed(r_max, margin) && self.lists.as_deref_mut().expect("listed").ready(x, y, 2.0 * r_max + margin) {
            let lists = self.lists.as_deref().expect("listed");
            return self.touching.count_listed(&lists.pairs, x, y, &radius[..n], margin);
        }
        if !self.space.tiny {
            self.catch_up_index();
            let span = ((2.0 * r_max + margin) + slack) * (1.0 + 1e-6) + 1e-9;
            // The collision test's pairs, if it collected them this step, wide enough.
            let kept = self.graph.near_generation == Some(self.index.generation) && self.graph.near_span >= span;
            // From the next step on, the pass over pairs collects them this wide.
            self.graph.contact_span = span;
            // The index follows the moves where the count reads it: without the collision
            // test's pairs. With them the count reads positions alone, and the next refresh
            // notes this step's moves for both the test and the next count all the same.
            if !kept {
                self.index.refresh(&self.space.grid, x, y, None, None);
            }
            let near = kept.then_some(&self.graph.near[..]);
            return self.touching.count(&mut self.index, &self.space.grid, near, (x, y), &radius[..n], r_max, margin);
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
            let (c, d) = self.contacts_tiny(x, y, radius, &in_bay, r_max, slack);
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

    /// [`Collisions::contacts_within`] for larger fleets, robot by robot: the slots of a box
    /// around each robot that moved, by their places before the moves (robots in bays are
    /// not counted).
    fn contacts_by_index(&self, x: &[f64], y: &[f64], radius: &[f64], moved: &[bool], r_max: f64, slack: f64) -> (u64, f64) {
        let within = self.closest_within;
        let n = x.len();
        let (y, radius, moved) = (&y[..n], &radius[..n], &moved[..n]);
        let (grid, slots) = (&self.space.grid, &self.index.slots);
        let (mut count, mut closest) = (0u64, f64::INFINITY);
        for i in 0..n {
            if !moved[i] {
                continue;
            }
            let (xi, yi, ri) = (x[i], y[i], radius[i]);
            // A robot within contact of `i` after the moves stood within contact plus half the
            // slack of it before them: test the slots' (pre-move) positions first.
            let near = ri + r_max + 0.5 * slack;
            let near2 = near * near * 1.000_001;
            self.index.visit(grid, xi, yi, near * 1.000_1 + 1e-9, |k| {
                let s = &slots[k];
                let j = s.robot();
                let (dx, dy) = (s.x - xi, s.y - yi);
                if j == i || s.in_bay() || dx * dx + dy * dy > near2 || (moved[j] && j < i) {
                    return;
                }
                let d = axis_dist(x[j] - xi, y[j] - yi);
                if d <= ri + radius[j] + within {
                    closest = closest.min(d);
                }
                count += u64::from(d < ri + radius[j]);
            });
        }
        (count, closest)
    }
}

/// A pass over every pair beats looking again robot by robot when more than one robot in
/// this many moved since the last count (as for the collision test's rows, `blocking.rs`).
const RECOUNT_BELOW: usize = 8;

/// Larger fleets' contacts as of the last count: the pairs closer than `r_i + r_j`.
#[derive(Clone, Debug, Default)]
pub(super) struct Touching {
    /// The pairs `(i, j)`, `i < j`, in contact at the last count.
    pairs: Vec<(u32, u32)>,
    /// Pairs to look at, for a full count without the collision test's (reused).
    near: Vec<(u32, u32)>,
    /// What they were counted with (the margin, the fleet's one radius or `None` for mixed,
    /// then `radii`); `None` before the first count.
    inputs: Option<(u64, Option<u64>)>,
    radii: Vec<f64>,
    /// Robots moved since the last count, and a mark per robot id for them.
    shifted: Vec<u32>,
    mark: Vec<bool>,
}

impl Touching {
    /// The contacts at the positions after the moves (where the index stands now), and the
    /// smallest distance among the pairs looked at: every pair at the first count, after a
    /// change of radii or margin, or when many robots moved (from `near`, the collision
    /// test's pairs within the count's reach before the moves, when it kept them this step);
    /// else the pairs of robots that moved since the last count.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn count(
        &mut self,
        index: &mut Index,
        grid: &Grid,
        near: Option<&[(u32, u32)]>,
        (x, y): (&[f64], &[f64]),
        radius: &[f64],
        r_max: f64,
        margin: f64,
    ) -> (u64, f64) {
        let n = radius.len();
        let (x, y) = (&x[..n], &y[..n]);
        let uniform = radius.iter().all(|&r| r.to_bits() == radius[0].to_bits());
        let inputs = (margin.to_bits(), uniform.then(|| radius[0].to_bits()));
        // Radii are the same for the life of a run; a caller that changes them gets a full
        // count.
        let mut all = index.take_shifted(&mut self.shifted) || self.inputs != Some(inputs) || self.mark.len() != n;
        if !uniform {
            all |= self.radii.len() != n || self.radii.iter().zip(radius).any(|(a, b)| a.to_bits() != b.to_bits());
            self.radii.clear();
            self.radii.extend_from_slice(radius);
        }
        self.inputs = Some(inputs);
        if self.mark.len() != n {
            self.mark.clear();
            self.mark.resize(n, false);
        }
        // The collision test's pairs, when given, are this step's: a full count from them
        // (the index was not brought to the moves for the pairs of the moved).
        if let Some(near) = near {
            return self.count_pairs(near.iter().copied(), x, y, radius, margin);
        }
        if !all && self.shifted.is_empty() {
            return (self.pairs.len() as u64, f64::INFINITY);
        }
        let widest = 2.0 * r_max + margin;
        if (all || self.shifted.len() * RECOUNT_BELOW > n) && (widest * 1.000_001 + 1e-9) * 1.001 < grid.size() {
            let mut near = std::mem::take(&mut self.near);
            near.clear();
            let slots = &index.slots[..];
            index.pairs(grid, widest * widest * 1.000_001, |k, m| near.push((slots[k].robot() as u32, slots[m].robot() as u32)));
            let found = self.count_pairs(near.iter().copied(), x, y, radius, margin);
            self.near = near;
            return found;
        }
        if all {
            self.pairs.clear();
            self.shifted.clear();
            self.shifted.extend(0..n as u32);
        }
        index.ready_rows(grid);
        let mark = &mut self.mark[..];
        for &i in &self.shifted {
            mark[i as usize] = true;
        }
        self.pairs.retain(|&(a, b)| !mark[a as usize] && !mark[b as usize]);
        let (slots, pairs) = (&index.slots, &mut self.pairs);
        let mut closest = f64::INFINITY;
        // Each pair of a moved robot once: from the smaller id where both moved.
        for &i in &self.shifted {
            let i = i as usize;
            let (xi, yi, ri) = (x[i], y[i], radius[i]);
            let h = (ri + r_max + margin) * 1.000_001 + 1e-9;
            index.visit(grid, xi, yi, h, |k| {
                let s = &slots[k];
                let j = s.robot();
                if j == i || (mark[j] && j < i) {
                    return;
                }
                let d = axis_dist(s.x - xi, s.y - yi);
                let touch = ri + radius[j];
                if d <= touch + margin {
                    closest = closest.min(d);
                }
                if d < touch {
                    pairs.push((i.min(j) as u32, i.max(j) as u32));
                }
            });
        }
        for &i in &self.shifted {
            mark[i as usize] = false;
        }
        (pairs.len() as u64, closest)
    }

    /// Every pair in contact, from pairs that hold all of them (each pair once). What is
    /// kept of this count is not one the index's way may go on from: its next count is a
    /// full one.
    pub(super) fn count_listed(&mut self, near: &[(u32, u32)], x: &[f64], y: &[f64], radius: &[f64], margin: f64) -> (u64, f64) {
        self.inputs = None;
        self.count_pairs(near.iter().copied(), x, y, radius, margin)
    }

    /// Every pair in contact, from pairs that hold all of them (each pair once).
    fn count_pairs(&mut self, near: impl Iterator<Item = (u32, u32)>, x: &[f64], y: &[f64], radius: &[f64], margin: f64) -> (u64, f64) {
        let pairs = &mut self.pairs;
        pairs.clear();
        let mut closest = f64::INFINITY;
        for (i, j) in near {
            let (i, j) = (i as usize, j as usize);
            let (dx, dy) = (x[j] - x[i], y[j] - y[i]);
            let touch = radius[i] + radius[j];
            // Clearly beyond both distances that count (a slack far above rounding): most
            // pairs given are, and need no distance.
            let reach = touch + margin.max(0.0);
            if dx * dx + dy * dy > reach * reach * 1.000_001 {
                continue;
            }
            let d = axis_dist(dx, dy);
            if d <= touch + margin {
                closest = closest.min(d);
            }
            if d < touch {
                pairs.push((i.min(j) as u32, i.max(j) as u32));
            }
        }
        (pairs.len() as u64, closest)
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

    /// Every pair closer than touching, and the smallest distance within `+ margin`.
    fn every_pair_brute(x: &[f64], y: &[f64], radius: &[f64], margin: f64) -> (u64, f64) {
        let (mut count, mut closest) = (0, f64::INFINITY);
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let d = crate::fleet::motion::axis_dist(x[j] - x[i], y[j] - y[i]);
                if d <= radius[i] + radius[j] + margin {
                    closest = closest.min(d);
                }
                count += u64::from(d < radius[i] + radius[j]);
            }
        }
        (count, closest)
    }

    #[test]
    fn a_kept_count_of_every_pair_counts_what_the_definition_counts_to_the_bit() {
        // A crowded floor walked for many steps: in some steps most robots move (the pass
        // over pairs), in others a few (the pairs of those only), some step into bays and out
        // (robots in bays count too), and now and then the margin changes (a fresh count).
        // The count must be the definition's every step, and the smallest distance so far
        // (all the tally keeps) too; a full count's smallest distance is the definition's.
        let mut seed = 11;
        let (mut found, mut passes, mut kept) = (0, 0, 0);
        for case in 0..24 {
            let n = [40, 300, 1000][case % 3];
            let side = (n as f64 * 4.0).sqrt() * 50.0;
            let radius: Vec<f64> = (0..n).map(|i| if case % 4 == 3 { 10.0 + (i % 5) as f64 } else { 12.5 }).collect();
            let r_max = radius.iter().copied().fold(0.0, f64::max);
            let mut c = Collisions::new([-50.0, -50.0, side + 50.0, side + 50.0], 2.0 * r_max + 3.0, n);
            let (mut x, mut y): (Vec<f64>, Vec<f64>) = (0..n).map(|_| ((lcg(&mut seed) * side).round(), (lcg(&mut seed) * 10.0).floor() * 50.0)).unzip();
            let mut bay = vec![false; n];
            let (mut lowest_got, mut lowest_want) = (f64::INFINITY, f64::INFINITY);
            for step in 0..60 {
                let margin = if step % 20 < 10 { 0.0 } else { 3.0 };
                let share = if step % 7 == 0 { 0.9 } else { 0.02 };
                for i in 0..n {
                    if lcg(&mut seed) < share {
                        if lcg(&mut seed) < 0.1 {
                            bay[i] = !bay[i];
                            y[i] += if bay[i] { 25.0 } else { -25.0 };
                        } else {
                            x[i] = (x[i] + [4.0, -4.0, 1.5][(lcg(&mut seed) * 3.0) as usize]).clamp(0.0, side);
                        }
                    }
                }
                c.build_grid(&x, &y, &radius, &bay);
                let got = c.contacts_of_every_pair(&x, &y, &radius, r_max, 8.0, margin);
                let want = every_pair_brute(&x, &y, &radius, margin);
                assert_eq!(got.0, want.0, "case {case} (n = {n}), step {step}");
                (lowest_got, lowest_want) = (lowest_got.min(got.1), lowest_want.min(want.1));
                assert_eq!(lowest_got.to_bits(), lowest_want.to_bits(), "case {case}, step {step}");
                if share > 0.5 || step % 10 == 0 {
                    assert_eq!(got.1.to_bits(), want.1.to_bits(), "case {case}, step {step}: a full count");
                    passes += 1;
                } else {
                    kept += 1;
                }
                found += got.0;
            }
        }
        assert!(found > 1000 && passes > 100 && kept > 100, "{found} contacts, {passes} full counts, {kept} kept");
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
