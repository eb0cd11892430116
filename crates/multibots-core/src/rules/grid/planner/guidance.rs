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
}
