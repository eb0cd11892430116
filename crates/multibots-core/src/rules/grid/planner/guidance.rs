//! Highways: a cost for every move that makes traffic flow one way along each row and each
//! column, so that robots on a corridor mostly face the same way and rarely meet head-on.
//! The planner's distance tables are searched with these costs ([`Distances::weighted`]);
//! a move along the row's or column's direction costs [`WITH`], against it [`AGAINST`].
//!
//! ## Where it comes from
//! Guidance graphs for lifelong MAPF (Zhang et al., "Guidance Graph Optimization for
//! Lifelong Multi-Agent Path Finding", IJCAI 2024) and the League of Robot Runners entries
//! that used them: the 2024 winner (ssfc/LORR24, `graph_guidance.cpp`: moves along a lane
//! cost 20, against it 200) and the 2023 test-round leader on `warehouse_large` (Team
//! Pikachu, near one-way lanes). We read them and chose our own costs and layout:
//! - rows alternate east and west from one corridor row to the next (the first one east),
//!   whatever the rows between them;
//! - columns follow a period of 8, `N S N S S N S N` from column 0, so that the vertical
//!   aisles of a warehouse (one every 4 columns on the archive's maps) alternate too, and
//!   each direction has two lanes in every 8 columns;
//! - against the lane costs 20 times a move along it: a detour round a block of shelves is
//!   cheaper than a few cells against the flow, but a robot whose goal is only reachable
//!   against it still gets there.
//!
//! ## What it changes
//! Measured with `benchmarks/lorr.py` (docs/benchmarks.md): on the archive's warehouse and
//! sortation maps, two thirds more tasks to twice as many; on the small random maps (32×32), 5-15 %
//! fewer, since their short corridors gain nothing from a direction and lose the detours.
//! The planner `pibt-no-highways` is PIBT without them.
//!
//! [`Distances::weighted`]: super::Distances::weighted

use crate::input::lorr::GridMap;

/// The cost of a move along its row's or column's direction.
pub const WITH: u8 = 10;
/// The cost of a move against it.
pub const AGAINST: u8 = 200;

/// Columns whose lane runs north, one bit per column modulo 8 (bit 0: column 0).
const NORTHBOUND: u32 = 0b1010_0101;

/// Per free cell, the cost of leaving it in each heading (0 east, 1 south, 2 west, 3 north),
/// as [`super::Distances::weighted`] takes it.
///
/// A row's direction alternates from one corridor row to the next: a row where at least
/// half the free cells have a free neighbour east. Counting rows by their index instead puts
/// every corridor of a map whose corridors are every other row (the archive's sortation maps)
/// on one direction, and the robots going the other way then detour round the whole map.
#[must_use]
pub fn highway_costs(map: &GridMap) -> Vec<[u8; 4]> {
    let (rows, cols) = (map.rows as usize, map.cols as usize);
    let free = |r: usize, c: usize| map.free[r * cols + c];
    let mut corridors_above = 0u32;
    let mut out = vec![[AGAINST; 4]; map.cells()];
    for r in 0..rows {
        let east = corridors_above % 2 == 0;
        let (mut cells, mut ways_east) = (0, 0);
        for c in 0..cols {
            if !free(r, c) {
                continue;
            }
            cells += 1;
            ways_east += usize::from(c + 1 < cols && free(r, c + 1));
            let north = (NORTHBOUND >> (c % 8)) & 1 == 1;
            let along = [east, !north, !east, north];
            out[r * cols + c] = along.map(|a| if a { WITH } else { AGAINST });
        }
        if cells > 0 && 2 * ways_east >= cells {
            corridors_above += 1;
        }
    }
    out
}

/// The cost of a move along an open band: a tenth more than [`WITH`].
pub const ALONG_BAND: u8 = WITH + 1;

/// Whether the map's obstacles stand in blocks (shelves, buildings, walls) rather than
/// scattered: at least half of the obstacle cells have two obstacle cells or more among their
/// four neighbours. About a fifth do on the archive's 32×32 random maps (a fifth of the cells
/// blocked at random), every one on `warehouse_small`, `warehouse_large`, `Paris_1_256` and
/// `brc202d`, none on the sortation maps (single-cell obstacles). Counted on neighbours alone,
/// so a map transposed, mirrored or turned gives the same answer.
#[must_use]
pub fn obstacles_in_blocks(map: &GridMap) -> bool {
    let (rows, cols) = (map.rows as usize, map.cols as usize);
    let blocked = |r: usize, c: usize| !map.free[r * cols + c];
    let (mut obstacles, mut in_blocks) = (0usize, 0usize);
    for r in 0..rows {
        for c in 0..cols {
            if !blocked(r, c) {
                continue;
            }
            obstacles += 1;
            let around = usize::from(r > 0 && blocked(r - 1, c))
                + usize::from(r + 1 < rows && blocked(r + 1, c))
                + usize::from(c > 0 && blocked(r, c - 1))
                + usize::from(c + 1 < cols && blocked(r, c + 1));
            in_blocks += usize::from(around >= 2);
        }
    }
    obstacles > 0 && in_blocks * 2 >= obstacles
}

/// Raises to [`ALONG_BAND`] the cost of each move along the lane that runs the long way of
/// an open band: from a cell whose eight neighbours are free, in the direction (row or
/// column) in which the open cells around it run further.
///
/// A band of open floor in front of stations is crossed by every robot bound for them; a
/// robot that also travels along it, when a corridor beside the shelves is as short, fills
/// it. The tenth only breaks ties between routes of equal length, so that the travel along
/// goes through the corridors and the band is only crossed (the 2023 League of Robot Runners
/// entry of Team Pikachu weighted its warehouse map's bands by the same idea).
///
/// Only where open cells are at most half the free cells: on a map that is mostly open floor
/// (the archive's city and game maps) there is no band to keep clear, and the tenth only
/// bends routes (MR23-I-01 on `Paris_1_256`: 8,599 errands against 9,865 without it).
pub fn open_band_costs(map: &GridMap, costs: &mut [[u8; 4]]) {
    let (rows, cols) = (map.rows as usize, map.cols as usize);
    let open: Vec<bool> = (0..rows * cols)
        .map(|cell| {
            let (r, c) = ((cell / cols) as i64, (cell % cols) as i64);
            (-1..=1i64).all(|dr| {
                (-1..=1i64).all(|dc| {
                    let (rr, cc) = (r + dr, c + dc);
                    rr >= 0 && cc >= 0 && (rr as usize) < rows && (cc as usize) < cols && map.free[rr as usize * cols + cc as usize]
                })
            })
        })
        .collect();
    let free_cells = map.free.iter().filter(|&&f| f).count();
    if 2 * open.iter().filter(|&&o| o).count() > free_cells {
        return;
    }
    // The length of the run of open cells through each cell, along its row and its column:
    // lines of `len` cells, the `i`th cell of line `line` at `at(line, i)`.
    let runs = |lines: usize, len: usize, at: &dyn Fn(usize, usize) -> usize| {
        let mut out = vec![0u32; rows * cols];
        for line in 0..lines {
            let mut i = 0;
            while i < len {
                let start = i;
                while i < len && open[at(line, i)] {
                    i += 1;
                }
                for k in start..i {
                    out[at(line, k)] = (i - start) as u32;
                }
                i += 1;
            }
        }
        out
    };
    let along_row = runs(rows, cols, &|r, c| r * cols + c);
    let along_col = runs(cols, rows, &|c, r| r * cols + c);
    for cell in (0..rows * cols).filter(|&cell| open[cell]) {
        let headings: &[usize] = match along_row[cell].cmp(&along_col[cell]) {
            std::cmp::Ordering::Greater => &[0, 2],
            std::cmp::Ordering::Less => &[1, 3],
            std::cmp::Ordering::Equal => &[],
        };
        for &h in headings {
            if costs[cell][h] == WITH {
                costs[cell][h] = ALONG_BAND;
            }
        }
    }
}

/// The free cells that moves along the lanes connect both ways (each reaches every other
/// without a step against a lane): the largest strongly connected component of the lanes'
/// graph, if it holds at least half the free cells, else none.
///
/// Between these cells a robot never needs to go against a lane, so `pibt-one-way` bars
/// it there ([`super::BARRED`]); elsewhere (a dead end, a pocket the lanes only run into,
/// a smaller component) the step against the lane stays open, at its cost.
///
/// Kosaraju's two passes, each an explicit stack: O(cells), whatever the map.
#[must_use]
pub fn lanes_core(map: &GridMap, costs: &[[u8; 4]]) -> Vec<bool> {
    use crate::rules::grid::action::ahead;
    const NONE: u32 = u32::MAX;
    let cells = map.cells();
    let free_cells = map.free.iter().filter(|&&f| f).count();
    let along = |p: u32, h: u8| ahead(map, p, h).filter(|&q| map.free[q as usize] && costs[p as usize][h as usize] < AGAINST);
    // Into `p` along a lane, from its neighbour in heading `h`.
    let into = |p: u32, h: u8| ahead(map, p, h).filter(|&q| map.free[q as usize] && along(q, (h + 2) % 4) == Some(p));
    // First pass: cells in the order their depth-first search finishes.
    let mut finished = Vec::with_capacity(free_cells);
    let mut seen = vec![false; cells];
    let mut stack: Vec<(u32, u8)> = Vec::new();
    for root in (0..cells as u32).filter(|&c| map.free[c as usize]) {
        if seen[root as usize] {
            continue;
        }
        seen[root as usize] = true;
        stack.push((root, 0));
        while let Some(top) = stack.last_mut() {
            let (p, h) = *top;
            if h == 4 {
                finished.push(p);
                stack.pop();
                continue;
            }
            top.1 += 1;
            if let Some(q) = along(p, h).filter(|&q| !seen[q as usize]) {
                seen[q as usize] = true;
                stack.push((q, 0));
            }
        }
    }
    // Second pass, on the reversed moves, latest finished first: each search is one component.
    let mut component = vec![NONE; cells];
    let (mut best, mut best_size) = (NONE, 0);
    let mut queue = Vec::new();
    for (id, &root) in finished.iter().rev().enumerate() {
        if component[root as usize] != NONE {
            continue;
        }
        component[root as usize] = id as u32;
        queue.push(root);
        let mut size = 0;
        while let Some(p) = queue.pop() {
            size += 1;
            for h in 0..4u8 {
                if let Some(q) = into(p, h).filter(|&q| component[q as usize] == NONE) {
                    component[q as usize] = id as u32;
                    queue.push(q);
                }
            }
        }
        if size > best_size {
            (best, best_size) = (id as u32, size);
        }
    }
    if 2 * best_size < free_cells {
        return vec![false; cells];
    }
    component.iter().map(|&c| c == best).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corridors_alternate_down_each_column_and_columns_follow_the_period() {
        // Rows 0, 1 and 3 are corridors; row 2 has no east-west move (a lattice row).
        let map = GridMap::parse("type octile\nheight 4\nwidth 9\nmap\n.........\n.........\n.@.@.@.@.\n.........\n").unwrap();
        let costs = highway_costs(&map);
        let east = |cell: u32| costs[cell as usize][0] == WITH && costs[cell as usize][2] == AGAINST;
        let west = |cell: u32| costs[cell as usize][2] == WITH && costs[cell as usize][0] == AGAINST;
        assert!((0..9).all(&east) && (9..18).all(&west));
        assert!((27..36).all(&east), "the third corridor runs east though its row is odd");
        let north: Vec<bool> = (0..9).map(|c| costs[c][3] == WITH).collect();
        assert_eq!(north, [true, false, true, false, false, true, false, true, true]);
        for cell in (0..36).filter(|&c| map.free[c]) {
            assert_ne!(costs[cell][1] == WITH, costs[cell][3] == WITH, "one way per column");
        }
    }

    /// An open `rows` × `cols` floor's costs with open bands weighted, checked cell by cell:
    /// with-lane moves out of the open cells (one cell in from the edge) along `axis` (0: the
    /// rows, 1: the columns) cost [`ALONG_BAND`], every other move as before.
    fn assert_band(rows: usize, cols: usize, axis: usize) {
        let map = GridMap::parse(&format!("type octile\nheight {rows}\nwidth {cols}\nmap\n{}", format!("{}\n", ".".repeat(cols)).repeat(rows))).unwrap();
        let plain = highway_costs(&map);
        let mut costs = plain.clone();
        open_band_costs(&map, &mut costs);
        for cell in 0..map.cells() {
            let (r, c) = (cell / cols, cell % cols);
            let open = (1..rows - 1).contains(&r) && (1..cols - 1).contains(&c);
            for h in 0..4 {
                let raised = open && h % 2 == axis && plain[cell][h] == WITH;
                assert_eq!(costs[cell][h], if raised { ALONG_BAND } else { plain[cell][h] }, "{rows}×{cols}: cell {cell} heading {h}");
            }
        }
    }

    #[test]
    fn moves_along_an_open_band_cost_a_tenth_more_and_crossing_it_does_not() {
        // 5×10: rows 1-3, columns 1-8 are open cells (all eight neighbours free), their runs
        // along the rows (8) longer than across (3); 10×5 is the same band standing up.
        assert_band(5, 10, 0);
        assert_band(10, 5, 1);
        // A map that is mostly open floor has no band: nothing changes.
        // (10×14: 96 of its 140 cells are open, and the open runs are longer along the rows.)
        let floor = GridMap::parse(&format!("type octile\nheight 10\nwidth 14\nmap\n{}", "..............\n".repeat(10))).unwrap();
        let mut open_costs = highway_costs(&floor);
        open_band_costs(&floor, &mut open_costs);
        assert_eq!(open_costs, highway_costs(&floor));
    }

    /// Cells reachable from `root` along the lanes, forwards or backwards.
    fn along_from(map: &GridMap, costs: &[[u8; 4]], root: u32, back: bool) -> Vec<bool> {
        use crate::rules::grid::action::ahead;
        let mut seen = vec![false; map.cells()];
        let mut stack = vec![root];
        seen[root as usize] = true;
        while let Some(p) = stack.pop() {
            for q in 0..map.cells() as u32 {
                let edge = |a: u32, b: u32| (0..4u8).any(|h| ahead(map, a, h) == Some(b) && map.free[b as usize] && costs[a as usize][h as usize] < AGAINST);
                let linked = if back { edge(q, p) } else { edge(p, q) };
                if map.free[q as usize] && linked && !seen[q as usize] {
                    seen[q as usize] = true;
                    stack.push(q);
                }
            }
        }
        seen
    }

    #[test]
    fn the_core_is_what_the_lanes_connect_both_ways() {
        // A dead end hangs below an open block; its column's lane runs south.
        let spur = GridMap::parse("type octile\nheight 6\nwidth 8\nmap\n........\n........\n........\n........\n@.@@@@@@\n@.@@@@@@\n").unwrap();
        let costs = highway_costs(&spur);
        let core = lanes_core(&spur, &costs);
        let members: Vec<u32> = (0..spur.cells() as u32).filter(|&c| core[c as usize]).collect();
        // The block but two corners: (0, 7), which the lanes cannot leave (row 0 runs east,
        // column 7 north), and (3, 7), which they cannot enter.
        assert_eq!(members, (0..32).filter(|&c| c != 7 && c != 31).collect::<Vec<u32>>());
        assert!(!core[33] && !core[41], "the dead end is not in the core");
        // Exactly the component of its first member: everything reached both ways from it.
        let (fwd, bwd) = (along_from(&spur, &costs, members[0], false), along_from(&spur, &costs, members[0], true));
        for c in 0..spur.cells() {
            assert_eq!(core[c], fwd[c] && bwd[c], "cell {c}");
        }
        // No component is half the map when the lanes only run into a corridor.
        let line = GridMap::parse("type octile\nheight 1\nwidth 6\nmap\n......\n").unwrap();
        assert!(lanes_core(&line, &highway_costs(&line)).iter().all(|&c| !c));
    }
}
