//! The competition's action model (`MAPF_T`, the Start-Kit's `ActionModel.cpp`): a robot has
//! a cell and a heading (0 east, 1 south, 2 west, 3 north); `F` goes one cell ahead, `R`
//! turns clockwise, `C` counter-clockwise, `W` waits; `T` is the wait the system writes when
//! the planner ran out of time. A joint action is checked robot by robot in id order, and the
//! first fault found is the one recorded: a move off the map or into an obstacle ("unallowed
//! move"), a cell another robot (of lower id) already ends on ("vertex conflict"), or the
//! reverse of another robot's move ("edge conflict", a swap).

use crate::input::lorr::GridMap;
use crate::record::grid::ActionError;

/// One robot's action for one step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Action {
    /// Forward one cell.
    F = 0,
    /// Turn clockwise.
    R = 1,
    /// Turn counter-clockwise.
    C = 2,
    /// Wait.
    W = 3,
    /// A wait forced by a planner timeout (the Start-Kit's `NA`).
    T = 4,
}

impl Action {
    /// The letter the result file uses.
    #[must_use]
    pub fn letter(self) -> char {
        ['F', 'R', 'C', 'W', 'T'][self as usize]
    }

    /// The heading after this action from `heading`.
    #[must_use]
    pub fn turned(self, heading: u8) -> u8 {
        match self {
            Action::R => (heading + 1) % 4,
            Action::C => (heading + 3) % 4,
            _ => heading,
        }
    }
}

/// The cell one step ahead of `cell` facing `heading`, or `None` off the map.
#[must_use]
pub fn ahead(map: &GridMap, cell: u32, heading: u8) -> Option<u32> {
    ahead_on(map.rows, map.cols, cell, heading)
}

/// The cell one step ahead of `cell` facing `heading` on a grid of `rows` × `cols`, or `None`
/// off it.
#[must_use]
pub fn ahead_on(rows: u32, cols: u32, cell: u32, heading: u8) -> Option<u32> {
    let (r, c) = (cell / cols, cell % cols);
    match heading {
        0 if c + 1 < cols => Some(cell + 1),
        1 if r + 1 < rows => Some(cell + cols),
        2 if c > 0 => Some(cell - 1),
        3 if r > 0 => Some(cell - cols),
        _ => None,
    }
}

/// The heading that goes from `from` to its neighbour `to`.
#[must_use]
pub fn heading_to(map: &GridMap, from: u32, to: u32) -> u8 {
    if to == from + 1 {
        0
    } else if to == from + map.cols {
        1
    } else if to + 1 == from {
        2
    } else {
        3
    }
}

/// Checks joint actions; owns the buffers so a check costs no allocation.
#[derive(Default)]
pub struct Validator {
    owner: Vec<u32>,
    stamp: Vec<u32>,
    now: u32,
    next: Vec<u32>,
}

impl Validator {
    /// The first fault of `actions` from `loc` and `heading`, robots in id order, or `None`;
    /// `next` (the cells after the step) is filled when there is none.
    pub fn check(&mut self, map: &GridMap, loc: &[u32], heading: &[u8], actions: &[Action], timestep: u32) -> Option<ActionError> {
        if self.stamp.len() != map.cells() {
            self.stamp = vec![0; map.cells()];
            self.owner = vec![0; map.cells()];
            self.now = 0;
        }
        self.now = self.now.wrapping_add(1);
        if self.now == 0 {
            self.stamp.fill(0);
            self.now = 1;
        }
        self.next.clear();
        let fault = |kind, agent: usize, other: i64| Some(ActionError { kind, agent: agent as i64, other, timestep });
        for (i, (&p, &a)) in loc.iter().zip(actions).enumerate() {
            let q = if a == Action::F {
                match ahead(map, p, heading[i]) {
                    Some(q) if map.free[q as usize] => q,
                    _ => return fault("unallowed move", i, -1),
                }
            } else {
                p
            };
            if self.stamp[q as usize] == self.now {
                return fault("vertex conflict", i, i64::from(self.owner[q as usize]));
            }
            // A swap: a robot checked earlier ends where this one starts, and started where
            // this one ends. At most one robot ends on a cell, or the vertex check fired.
            if q != p && self.stamp[p as usize] == self.now {
                let j = self.owner[p as usize] as usize;
                if loc[j] == q {
                    return fault("edge conflict", i, j as i64);
                }
            }
            self.stamp[q as usize] = self.now;
            self.owner[q as usize] = i as u32;
            self.next.push(q);
        }
        None
    }

    /// The cells after the last joint action found valid.
    #[must_use]
    pub fn next(&self) -> &[u32] {
        &self.next
    }
}
