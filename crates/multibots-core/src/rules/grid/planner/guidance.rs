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
//! - rows alternate, even rows east, odd rows west;
//! - columns follow a period of 8, `N S N S S N S N` from column 0, so that the vertical
//!   aisles of a warehouse (one every 4 columns on the archive's maps) alternate too, and
//!   each direction has two lanes in every 8 columns;
//! - against the lane costs 20 times a move along it: a detour round a block of shelves is
//!   cheaper than a few cells against the flow, but a robot whose goal is only reachable
//!   against it still gets there.
//!
//! ## What it changes
//! Measured with `benchmarks/lorr.py` (docs/benchmarks.md): on the archive's warehouse and
//! sortation maps, one to two thirds more tasks; on the small random maps (32×32), 5-15 %
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

/// The cost of leaving `cell` in `heading` (0 east, 1 south, 2 west, 3 north).
#[must_use]
pub fn highway_cost(map: &GridMap, cell: u32, heading: u8) -> u8 {
    let (row, col) = map.row_col(cell);
    let north = (NORTHBOUND >> (col % 8)) & 1 == 1;
    let along = match heading {
        0 => row % 2 == 0,
        2 => row % 2 == 1,
        1 => !north,
        _ => north,
    };
    if along {
        WITH
    } else {
        AGAINST
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_alternate_and_columns_follow_the_period() {
        let map = GridMap::parse("type octile\nheight 2\nwidth 9\nmap\n.........\n.........\n").unwrap();
        assert_eq!((highway_cost(&map, 0, 0), highway_cost(&map, 0, 2)), (WITH, AGAINST));
        assert_eq!((highway_cost(&map, 9, 0), highway_cost(&map, 9, 2)), (AGAINST, WITH));
        let north: Vec<bool> = (0..9).map(|c| highway_cost(&map, c, 3) == WITH).collect();
        assert_eq!(north, [true, false, true, false, false, true, false, true, true]);
        for c in 0..18 {
            assert_ne!(highway_cost(&map, c, 1) == WITH, highway_cost(&map, c, 3) == WITH, "one way per column");
        }
    }
}
