//! One robot as the original keeps it (`Models.agent`), and how it moves
//! (`Models.agent.stepToGoal` and `move`, `Strategy.dummyTeleporter`).
//!
//! The original's flags are kept one for one, under names that say what they mean; each
//! field's doc names the original's attribute. Display-only attributes (colours, battery
//! bar, timers) are left out: no decision reads them.
//!
//! **Motion.** A step of length `s` towards a goal moves along an axis when the goal is
//! straight ahead (`dx == 0` or `dy == 0`; both zero counts as "west"), and otherwise along
//! `atan2(-dy, dx)` with the sine's sign as written (a diagonal that never occurs on the
//! warehouse's axis-aligned aisles). The heading is `atan2(-offset_y, offset_x)` in degrees,
//! in the mathematical frame (y up). Where Python mixes `int` and `float`, the signs of zero
//! follow Python: an axis-aligned offset carries an integer 0, whose negation stays +0, so a
//! zero-length step heads 180° (west). A teleport puts the robot on a point's integer
//! coordinates; we record whether `y` is still a Python `int`, because the collision test
//! negates `y_j − y_i`, and `-(0)` is +0 for integers but −0.0 for floats (bearing +180°
//! versus −180°: see `collision.rs`).

use super::map::{self, Plan, NOWHERE};

/// `agent.status`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Status {
    /// 0: idle (also: going home, charging, and before the first step).
    Idle = 0,
    /// 1: going to fetch goods (also: going to charge after putting goods back).
    Fetching = 1,
    /// 2: at the shelf or carrying goods.
    Carrying = 2,
}

/// One robot.
#[derive(Clone, Debug)]
#[allow(clippy::struct_excessive_bools)] // the original's flags, kept one for one so that each can be checked against it
pub struct Agent {
    /// Position, original frame.
    pub x: f64,
    pub y: f64,
    /// Whether `y` holds a Python `int` (set by a teleport, kept by horizontal steps).
    pub y_int: bool,
    /// `angle.theta`: heading in degrees, y up, not folded.
    pub theta: f64,
    pub status: Status,
    /// `currentOverallPlans[id]`.
    pub plan: Plan,
    /// `nextIntemediateGoal` (`NOWHERE` for `'x'` and the initial `''`).
    pub next: u8,
    /// `withStepPlan`: heading for `next`.
    pub stepping: bool,
    /// `goodnum`: the cell of the goods fetched or carried.
    pub goods: u8,
    /// Whether `goods` is still this robot's job (false once delivered or put back).
    pub holds: bool,
    /// `getgood`: loaded.
    pub loaded: bool,
    /// `waiting`: ticks counted at the shelf or the unloading crossing.
    pub dwell: u32,
    /// `goodforwardletter`: at the shelf's forward crossing, driving to the loading point.
    pub to_shelf: bool,
    /// `goodbackwardletter`: left the shelf by its backward crossing, route to M planned.
    pub to_drop: bool,
    /// `out`: at M, unloading.
    pub unloading: bool,
    /// `debug`: reached the loading point of the current goods (cleared on delivery).
    pub reached_shelf: bool,
    /// `stopmark`: stopped by the collision rule.
    pub stopped: bool,
    /// `agentcolmark`: this stop has been counted in S.
    pub counted: bool,
    /// `steptimes`: ticks of consumption since the last full charge.
    pub use_ticks: u64,
    /// `currentenergy`.
    pub energy: f64,
    /// `needchargemark`: the threshold rule asked this robot to charge.
    pub needs_charge: bool,
    /// `firsttime`: the threshold rule has fired since the last charge.
    pub low_seen: bool,
    /// `currentstatus`: the status when the threshold rule fired (1 again after a delivery).
    pub low_status: Status,
    /// `backtocharge`: put its goods back and heading to charge.
    pub to_charge: bool,
    /// `backhomemark`: nothing left for it, heading home.
    pub to_home: bool,
    /// `chargemark`: at its charging position.
    pub at_charger: bool,
    /// `fullenergymark`.
    pub full: bool,
    /// `stopwait`: charged and settled at the charger.
    pub settled: bool,
    /// `readymark`: charged and waiting to be sent out.
    pub ready: bool,
    /// `startletter`, and `chargingposition`.
    pub start: u8,
    pub charger: u8,
    /// The point last stood on (for viewers: the edge a robot is inside).
    pub from: u8,
    /// `collisioncnt[id]` and `chargecnts`.
    pub collisions: u64,
    pub charges: u64,
}

impl Agent {
    /// Robot `k` as `Controller.__init__` and `InitStartGoal` make it: start letter k,
    /// charging position k, heading 270°.
    #[must_use]
    pub fn new(k: u8, full_energy: f64) -> Agent {
        Agent {
            x: 0.0,
            y: 0.0,
            y_int: true,
            theta: 270.0,
            status: Status::Idle,
            plan: Plan::EMPTY,
            next: NOWHERE,
            stepping: false,
            goods: 0,
            holds: false,
            loaded: false,
            dwell: 0,
            to_shelf: false,
            to_drop: false,
            unloading: false,
            reached_shelf: false,
            stopped: false,
            counted: false,
            use_ticks: 0,
            energy: full_energy,
            needs_charge: false,
            low_seen: false,
            low_status: Status::Idle,
            to_charge: false,
            to_home: false,
            at_charger: false,
            full: false,
            settled: false,
            ready: false,
            start: k,
            charger: map::CHARGER_0 + k,
            from: map::CHARGER_0 + k,
            collisions: 0,
            charges: 0,
        }
    }

    /// `Strategy.dummyTeleporterToNode`: onto point `p`'s integer coordinates, heading `theta`.
    pub fn teleport(&mut self, p: u8, theta: f64) -> f64 {
        let (x, y) = map::point(p);
        let jump = ((self.x - x) * (self.x - x) + (self.y - y) * (self.y - y)).sqrt();
        self.x = x;
        self.y = y;
        self.y_int = true;
        self.theta = theta;
        self.from = p;
        jump
    }

    /// Euclidean distance to `(gx, gy)` (`math.sqrt(dx**2 + dy**2)`; on the integer
    /// coordinates robots keep, squaring is exact either way).
    #[inline]
    #[must_use]
    pub fn distance_to(&self, gx: f64, gy: f64) -> f64 {
        let (dx, dy) = (self.x - gx, self.y - gy);
        (dx * dx + dy * dy).sqrt()
    }

    /// `stepToGoal(goal, min(step, distance))` as the callers write it: `step > distance`
    /// moves by `distance`. Returns the length moved.
    #[inline]
    pub fn step_towards(&mut self, gx: f64, gy: f64, step: f64) -> f64 {
        let distance = self.distance_to(gx, gy);
        let s = if step > distance { distance } else { step };
        self.step_to_goal(gx, gy, s);
        s
    }

    /// `Models.agent.stepToGoal` followed by `move`.
    fn step_to_goal(&mut self, gx: f64, gy: f64, step: f64) {
        let dy = gy - self.y;
        let dx = gx - self.x;
        // (offset x, offset y, Python's -offset[1]).
        let (ox, oy, up) = if dy == 0.0 {
            // Also dx == 0: the original's second test overrides the first, heading west.
            (if dx > 0.0 { step } else { -step }, 0.0, 0.0)
        } else if dx == 0.0 {
            let oy = if dy > 0.0 { step } else { -step };
            (0.0, oy, -oy)
        } else {
            let theta = (-dy).atan2(dx);
            let oy = step * theta.sin();
            (step * theta.cos(), oy, -oy)
        };
        self.x += ox;
        if dy != 0.0 {
            // A horizontal step adds the integer 0 to y; any other adds a float.
            self.y += oy;
            self.y_int = false;
        }
        self.theta = up.atan2(ox) * 180.0 / std::f64::consts::PI;
    }
}
