//! Robot states and the fleet's columns (struct of arrays).

use crate::ids::{CellId, GoodsId, NodeId, NONE};

/// The ten states of the paper model (plus one for shared chargers), with the codes that
/// replays and the Python arrays use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum State {
    Idle = 0,
    ToPickup = 1,
    Loading = 2,
    ToDrop = 3,
    Unloading = 4,
    ToCharger = 5,
    Charging = 6,
    ToHome = 7,
    Parked = 8,
    Stranded = 9,
    /// Queued for a shared charger (never in the paper model).
    WaitCharger = 10,
}

impl State {
    pub const COUNT: usize = 11;
    pub const ALL: [State; State::COUNT] = [
        State::Idle,
        State::ToPickup,
        State::Loading,
        State::ToDrop,
        State::Unloading,
        State::ToCharger,
        State::Charging,
        State::ToHome,
        State::Parked,
        State::Stranded,
        State::WaitCharger,
    ];

    /// The upper-case name the spec uses.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            State::Idle => "IDLE",
            State::ToPickup => "TO_PICKUP",
            State::Loading => "LOADING",
            State::ToDrop => "TO_DROP",
            State::Unloading => "UNLOADING",
            State::ToCharger => "TO_CHARGER",
            State::Charging => "CHARGING",
            State::ToHome => "TO_HOME",
            State::Parked => "PARKED",
            State::Stranded => "STRANDED",
            State::WaitCharger => "WAIT_CHARGER",
        }
    }

    /// States in which a robot follows a route (when it has one: a robot waiting for a
    /// charger drives to its bay, under spread placement).
    #[inline]
    #[must_use]
    pub fn travels(self) -> bool {
        matches!(self, State::ToPickup | State::ToDrop | State::ToCharger | State::ToHome | State::WaitCharger)
    }

    /// Loading, unloading or charging: a step of it is progress, though the robot stands.
    #[inline]
    #[must_use]
    pub fn busy_in_place(self) -> bool {
        matches!(self, State::Loading | State::Unloading | State::Charging)
    }
}

/// Where a route ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// Standing on a node: an unloading zone, a charger, a highway node.
    Node(NodeId),
    /// A point strictly inside the directed edge `(u, v)`: a service point.
    Point { u: NodeId, v: NodeId, x: f64, y: f64 },
}

/// The fleet, one column per quantity. Index = robot id.
#[derive(Clone, Debug, Default)]
pub struct Robots {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub radius: Vec<f64>,
    pub speed: Vec<f64>,
    /// Direction of travel, radians, screen coordinates; kept while standing.
    pub heading: Vec<f64>,
    pub state: Vec<State>,
    pub energy: Vec<f64>,
    pub home: Vec<NodeId>,
    /// Node the robot stands exactly on, or `NONE`.
    pub at_node: Vec<u32>,
    /// When not on a node: the directed edge it is strictly inside (its travel direction,
    /// or the edge it stood on to load).
    pub edge_u: Vec<u32>,
    pub edge_v: Vec<u32>,
    /// Route: whether one is under way, the node path's goal, and an optional final point.
    pub routing: Vec<bool>,
    pub goal: Vec<u32>,
    pub has_final: Vec<bool>,
    pub final_x: Vec<f64>,
    pub final_y: Vec<f64>,
    /// The final point's edge head (the final point lies inside `goal -> final_v`).
    pub final_v: Vec<u32>,
    /// Current waypoint, and the node it is (`NONE` when it is the final point).
    pub wp_x: Vec<f64>,
    pub wp_y: Vec<f64>,
    pub wp_node: Vec<u32>,
    /// Goods the robot is fetching or carrying, and its cell.
    pub goods: Vec<u32>,
    pub cell: Vec<u32>,
    pub carrying: Vec<bool>,
    /// Steps counted in LOADING or UNLOADING.
    pub dwell: Vec<u32>,
    /// Marked by the threshold rule to charge after unloading.
    pub marked: Vec<bool>,
    pub waited: Vec<bool>,
    /// The charger a robot is heading to or charging at (its home in the paper model).
    pub charger: Vec<u32>,
    /// A detour (traffic policies): the node to take after the next node instead of the
    /// route's next hop, or `NONE`. Empty until a policy gives the first detour (robots
    /// past its end have none): most runs never take one.
    pub via: Vec<u32>,
    /// A robot standing aside in a bay (`fleet/bay.rs`): the point of its lane it stepped
    /// aside from; NaN on the lane. Empty until the first robot steps aside.
    pub lane_x: Vec<f64>,
    pub lane_y: Vec<f64>,
}

impl Robots {
    /// Robot count.
    #[must_use]
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether the fleet is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Adds a robot standing on `at`, idle, with full energy.
    pub fn push(&mut self, at: NodeId, pos: (f64, f64), home: NodeId, radius: f64, speed: f64, energy: f64) {
        self.x.push(pos.0);
        self.y.push(pos.1);
        self.radius.push(radius);
        self.speed.push(speed);
        self.heading.push(std::f64::consts::FRAC_PI_2);
        self.state.push(State::Idle);
        self.energy.push(energy);
        self.home.push(home);
        self.at_node.push(at.0);
        self.edge_u.push(NONE);
        self.edge_v.push(NONE);
        self.routing.push(false);
        self.goal.push(NONE);
        self.has_final.push(false);
        self.final_x.push(0.0);
        self.final_y.push(0.0);
        self.final_v.push(NONE);
        self.wp_x.push(pos.0);
        self.wp_y.push(pos.1);
        self.wp_node.push(NONE);
        self.goods.push(NONE);
        self.cell.push(NONE);
        self.carrying.push(false);
        self.dwell.push(0);
        self.marked.push(false);
        self.waited.push(false);
        self.charger.push(home.0);
    }

    /// Positions as `[x0, y0, x1, y1, …]`, for arrays of shape (N, 2).
    #[must_use]
    pub fn positions_flat(&self) -> Vec<f64> {
        self.x.iter().zip(&self.y).flat_map(|(&x, &y)| [x, y]).collect()
    }

    /// State codes (the replay codes).
    #[must_use]
    pub fn state_codes(&self) -> Vec<u8> {
        self.state.iter().map(|&s| s as u8).collect()
    }

    /// Home charger node ids.
    #[must_use]
    pub fn home_ids(&self) -> Vec<u32> {
        self.home.iter().map(|h| h.0).collect()
    }

    /// The cell each robot carries goods from, or -1.
    #[must_use]
    pub fn carried_cells(&self) -> Vec<i32> {
        (0..self.len()).map(|i| if self.carrying[i] { self.cell[i] as i32 } else { -1 }).collect()
    }

    /// The cell each robot fetches or carries goods from, or -1.
    #[must_use]
    pub fn task_cells(&self) -> Vec<i32> {
        (0..self.len()).map(|i| self.goods_of(i).map_or(-1, |(_, c)| c.0 as i32)).collect()
    }

    /// The goods robot `i` fetches or carries.
    #[must_use]
    pub fn goods_of(&self, i: usize) -> Option<(GoodsId, CellId)> {
        (self.goods[i] != NONE).then(|| (GoodsId(self.goods[i]), CellId(self.cell[i])))
    }
}
