//! How people walk: the social-force model (Helbing and Molnár, 1995, "Social force model
//! for pedestrian dynamics"), the model most crowd simulators start from, with one hard rule
//! added for safety.
//!
//! A person accelerates towards its desired velocity (walking speed towards the next
//! waypoint) with relaxation time `TAU`, and is pushed away from other people and from robots
//! by forces that fall off exponentially with the gap between bodies. It stays within the
//! aisle it walks (its centre at most half the aisle width off the line of its path), and it
//! never steps to a point closer to a robot than the sum of their radii: when the step the
//! forces give would touch a robot, it tries the same step turned by ±45°, ±90° and ±135°
//! (its right first, as people keep right), and otherwise waits.
//!
//! Everything is in pixels and steps; the constants are the published ones converted with
//! `px_per_m` and `step_seconds`.

use super::{People, Phase};
use crate::fleet::robot::Robots;
use crate::world::buckets::at_least;

/// Relaxation time, seconds (Helbing and Molnár: 0.5 s).
const TAU: f64 = 0.5;
/// Strength of the repulsion between people, m/s² (Helbing et al. 2000: A = 2000 N on 80 kg).
const PEOPLE_A: f64 = 25.0;
/// Its range, m (B = 0.08 m).
const PEOPLE_B: f64 = 0.08;
/// Repulsion from robots: people give machines a wider berth, m/s² and m.
const ROBOT_A: f64 = 10.0;
const ROBOT_B: f64 = 0.3;
/// Of the repulsion from a body ahead, this share also pushes sideways, to the walker's
/// right: without it two bodies head-on on one line stand in a balance of forces for ever
/// (the "evasive" force of later social-force models, and the keep-right habit).
const EVADE: f64 = 0.6;
/// The push to the side of the aisle when a robot comes, in units of the driving force.
const STEP_ASIDE: f64 = 3.0;
/// Steps without getting closer to its waypoint after which a person gives way: walks back
/// to its last waypoint and stays there for `GIVE_WAY` steps, so robots waiting for it can go.
const PATIENCE: u32 = 40;
const GIVE_WAY: u32 = 60;
/// Past this gap, m, a robot exerts no force (the exponential is below 0.1% of A).
pub(super) const ROBOT_RANGE: f64 = 2.0;
/// A person walks at most this factor of its desired speed.
const MAX_SPEED: f64 = 1.3;
/// The gap people keep to robots beyond touching, px (4 cm at 25 px/m): contact is `d < r_i + r_j`.
pub(super) const CLEAR: f64 = 1.0;

/// Turns tried, radians, when a step would touch a robot: right first (y grows downwards
/// in layout coordinates, so a positive angle turns right).
const TURNS: [f64; 6] = [
    std::f64::consts::FRAC_PI_4,
    -std::f64::consts::FRAC_PI_4,
    std::f64::consts::FRAC_PI_2,
    -std::f64::consts::FRAC_PI_2,
    2.356_194_490_192_345,
    -2.356_194_490_192_345,
];

/// The model's constants in pixels and steps.
#[derive(Clone, Copy, Debug)]
pub(super) struct Forces {
    tau: f64,
    people_a: f64,
    people_b: f64,
    robot_a: f64,
    robot_b: f64,
    robot_range: f64,
}

impl Forces {
    pub(super) fn new(px_per_m: f64, step_seconds: f64) -> Forces {
        let accel = px_per_m * step_seconds * step_seconds;
        Forces {
            tau: TAU / step_seconds,
            people_a: PEOPLE_A * accel,
            people_b: PEOPLE_B * px_per_m,
            robot_a: ROBOT_A * accel,
            robot_b: ROBOT_B * px_per_m,
            robot_range: ROBOT_RANGE * px_per_m,
        }
    }
}

impl People {
    /// Phase of the people, after the robots moved: each person picks, rests or walks one
    /// step. Returns the person-steps spent blocked by robots this step.
    pub(super) fn walk_people(&mut self, robots: &Robots, forces: &Forces) -> u64 {
        let n = self.len();
        let rh = self.radius;
        let rr_max = robots.radius.iter().copied().fold(0.0, f64::max);
        let speed_max = robots.speed.iter().copied().fold(0.0, f64::max);
        let mut blocked = 0;
        for k in 0..n {
            match self.phase[k] {
                Phase::Pick(0) | Phase::Rest(0) => {
                    self.tours.depart(k);
                    self.seg_x[k] = self.x[k];
                    self.seg_y[k] = self.y[k];
                    self.phase[k] = Phase::Walk;
                }
                Phase::Pick(s) => {
                    self.phase[k] = Phase::Pick(s - 1);
                    continue;
                }
                Phase::Rest(s) => {
                    self.phase[k] = Phase::Rest(s - 1);
                    continue;
                }
                Phase::Walk => {}
            }
            let Some((mut gx, mut gy)) = self.tours.waypoint(k) else { continue };
            self.walk_steps += 1;
            let (px, py) = (self.x[k], self.y[k]);
            if self.retreat[k] > 0 {
                self.give_way_steps += 1;
                // Giving way: back to the last waypoint, out of the robots' way, for a while.
                self.retreat[k] -= 1;
                (gx, gy) = (self.ret_x[k], self.ret_y[k]);
                if (gx - px).hypot(gy - py) <= self.v0 {
                    self.vx[k] = 0.0;
                    self.vy[k] = 0.0;
                    continue;
                }
            } else {
                let d = (gx - px).hypot(gy - py);
                // A crossing on the way counts as passed within a quarter of the aisle width
                // (people cut corners); the service and pick points are stepped onto.
                if !self.tours.last_two(k) && d <= (self.half_aisle / 2.0).max(self.v0) {
                    self.seg_x[k] = gx;
                    self.seg_y[k] = gy;
                    self.best[k] = f64::INFINITY;
                    self.tours.reached(k);
                    let Some(next) = self.tours.waypoint(k) else { continue };
                    (gx, gy) = next;
                } else if self.tours.last_two(k) && d <= self.v0.max(0.5) {
                    if self.clear_of_robots(robots, gx, gy, rr_max, speed_max) {
                        self.x[k] = gx;
                        self.y[k] = gy;
                        self.seg_x[k] = gx;
                        self.seg_y[k] = gy;
                        self.vx[k] = 0.0;
                        self.vy[k] = 0.0;
                        self.best[k] = f64::INFINITY;
                        if let Some(next) = self.tours.reached(k) {
                            self.phase[k] = next;
                        }
                    } else {
                        blocked += 1;
                    }
                    continue;
                }
                // No progress for a while (a robot stands in the way, and the robot waits for
                // this person): give way.
                let d = (gx - px).hypot(gy - py);
                if d < self.best[k] - 0.05 * self.v0 {
                    self.best[k] = d;
                    self.stuck[k] = 0;
                } else {
                    self.stuck[k] += 1;
                    if self.stuck[k] >= PATIENCE {
                        self.stuck[k] = 0;
                        self.best[k] = f64::INFINITY;
                        self.retreat[k] = GIVE_WAY;
                        // Back along the way it came, to the latest point outside every robot's
                        // warning zone (or the start of the leg).
                        let w = self.zones.warning;
                        let (grid, aside) = (&self.robot_grid, self.aside);
                        let free = |(x, y): (f64, f64)| {
                            let mut ok = true;
                            grid.near(x, y, w + speed_max + aside, |i| ok = ok && at_least(robots.x[i] - x, robots.y[i] - y, w));
                            ok
                        };
                        let back = self.tours.passed(k).find(|&q| free(q)).or_else(|| self.tours.passed(k).last()).unwrap_or((self.seg_x[k], self.seg_y[k]));
                        (self.ret_x[k], self.ret_y[k]) = back;
                    }
                }
            }
            let (dx, dy) = (gx - px, gy - py);
            let d = dx.hypot(dy).max(1e-9);
            // The driving force, then repulsion from people and robots (positions at the
            // start of the step for people, after the robots' moves for robots).
            let (ex, ey) = (dx / d, dy / d);
            let mut fx = (self.v0 * ex - self.vx[k]) / forces.tau;
            let mut fy = (self.v0 * ey - self.vy[k]) / forces.tau;
            let reach_p = 2.0 * rh + 6.0 * forces.people_b;
            let (xs, ys) = (&self.x, &self.y);
            self.crowd.near(px, py, reach_p, |j| {
                if j != k {
                    let (ox, oy) = (px - xs[j], py - ys[j]);
                    if at_least(ox, oy, reach_p) {
                        return;
                    }
                    let dd = ox.hypot(oy);
                    if dd < reach_p && dd > 1e-9 {
                        let f = forces.people_a * ((2.0 * rh - dd) / forces.people_b).exp();
                        let (nx, ny) = (ox / dd, oy / dd);
                        let side = if nx * ex + ny * ey < 0.0 { EVADE * f } else { 0.0 };
                        fx += f * nx - side * ey;
                        fy += f * ny + side * ex;
                    }
                }
            });
            // Stepping aside: a person in the path of a robot coming within its warning zone
            // moves to the side of the aisle, where the robot can pass it.
            let (w, corridor) = (self.zones.warning, self.zones.corridor);
            self.robot_grid.near(px, py, w + speed_max + self.aside, |i| {
                if !(robots.routing[i] && robots.state[i].travels()) {
                    return;
                }
                let (ox, oy) = (px - robots.x[i], py - robots.y[i]);
                if at_least(ox, oy, w) {
                    return;
                }
                let (hx, hy) = (robots.wp_x[i] - robots.x[i], robots.wp_y[i] - robots.y[i]);
                let len = hx.hypot(hy);
                if len <= 1e-9 {
                    return;
                }
                let (hx, hy) = (hx / len, hy / len);
                let along = ox * hx + oy * hy;
                let across = ox * hy - oy * hx; // > 0: the robot's left... either way, away from its line
                if along > -(robots.radius[i] + rh) && across.abs() < robots.radius[i] + rh + corridor + 1.0 {
                    // Away from the robot's line; a person right on it goes to the robot's right.
                    let side = if across.abs() < 1e-6 { -1.0 } else { across.signum() };
                    fx += STEP_ASIDE * self.v0 / forces.tau * side * hy;
                    fy -= STEP_ASIDE * self.v0 / forces.tau * side * hx;
                }
            });
            let reach_r = rr_max + rh + forces.robot_range;
            self.robot_grid.near(px, py, reach_r + speed_max + self.aside, |i| {
                let (ox, oy) = (px - robots.x[i], py - robots.y[i]);
                if at_least(ox, oy, reach_r) {
                    return;
                }
                let dd = ox.hypot(oy);
                if dd < reach_r && dd > 1e-9 {
                    let f = forces.robot_a * ((robots.radius[i] + rh - dd) / forces.robot_b).exp().min(1e3);
                    let (nx, ny) = (ox / dd, oy / dd);
                    let side = if nx * ex + ny * ey < 0.0 { EVADE * f } else { 0.0 };
                    fx += f * nx - side * ey;
                    fy += f * ny + side * ex;
                }
            });
            let (mut vx, mut vy) = (self.vx[k] + fx, self.vy[k] + fy);
            let v = vx.hypot(vy);
            let vmax = MAX_SPEED * self.v0;
            if v > vmax {
                vx *= vmax / v;
                vy *= vmax / v;
            }
            // The step, or the first turned step that is clear of robots.
            let mut moved = false;
            for turn in std::iter::once(0.0).chain(TURNS) {
                let (c, s) = (turn.cos(), turn.sin());
                let (tx, ty) = (vx * c - vy * s, vx * s + vy * c);
                let (nx, ny) = self.in_aisle(k, px + tx, py + ty);
                if self.clear_of_robots(robots, nx, ny, rr_max, speed_max) {
                    self.vx[k] = nx - px;
                    self.vy[k] = ny - py;
                    self.x[k] = nx;
                    self.y[k] = ny;
                    moved = true;
                    break;
                }
            }
            if !moved {
                self.vx[k] = 0.0;
                self.vy[k] = 0.0;
                blocked += 1;
            }
        }
        blocked
    }

    /// A point moved back into the aisle person `k` walks: its centre at most half the
    /// aisle width off the line from its last waypoint to its next one.
    fn in_aisle(&self, k: usize, x: f64, y: f64) -> (f64, f64) {
        let Some((bx, by)) = self.tours.waypoint(k) else { return (x, y) };
        let (ax, ay) = (self.seg_x[k], self.seg_y[k]);
        let (dx, dy) = (bx - ax, by - ay);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            return (x, y);
        }
        let (ux, uy) = (dx / len, dy / len);
        let off = (x - ax) * -uy + (y - ay) * ux;
        if off.abs() <= self.half_aisle {
            return (x, y);
        }
        let back = off - self.half_aisle.copysign(off);
        (x + back * uy, y - back * ux)
    }

    /// Whether a person at `(x, y)` touches no robot (robots at their current positions).
    fn clear_of_robots(&self, robots: &Robots, x: f64, y: f64, rr_max: f64, speed_max: f64) -> bool {
        let rh = self.radius;
        let mut clear = true;
        // The grid holds positions from before the robots' moves: reach one step further.
        self.robot_grid.near(x, y, rr_max + rh + CLEAR + speed_max + self.aside, |i| {
            clear = clear && at_least(robots.x[i] - x, robots.y[i] - y, robots.radius[i] + rh + CLEAR);
        });
        clear
    }
}
