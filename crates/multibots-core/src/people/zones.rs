//! The zones robots keep around people, after ISO 3691-4 practice, and the safety figures.
//!
//! - **Protective zone**: the robot's and the person's radii, plus the robot's stopping
//!   distance at full speed (v² / 2a), one step of travel and a margin. A robot with a person
//!   inside it, ahead of the robot or beside it, stops: a *protective stop*, counted apart from
//!   the collisions S. A person within one step of travel stops it from any side.
//! - **Warning zone**: the protective zone plus a further distance; a robot with a person
//!   inside it moves at a fraction of its speed.
//!
//! The figures are measured on the positions after each step (people moved last): the
//! smallest gap between a person and a robot (surface to surface), its 1st percentile over
//! the robot-steps with a person inside the warning zone, contacts (a gap below zero:
//! never, by construction), protective stops and the steps robots spend stopped, robot-steps
//! in warning zones, and person-steps spent blocked by robots.

use super::walk::CLEAR;
use super::People;
use crate::fleet::robot::Robots;
use crate::input::scenario::Humans;
use crate::world::buckets::at_least;

/// Width of the histogram's bins, px: the 1st percentile is known to this.
const BIN: f64 = 0.25;
/// Most bins; wider zones get wider bins.
const MAX_BINS: usize = 8192;

/// The safety and cost figures of a run with people.
#[derive(Clone, Debug, PartialEq)]
pub struct PeopleFigures {
    /// People on the floor.
    pub count: u32,
    /// The smallest person–robot gap seen after a step, px (surface to surface); `None` if
    /// no person came inside a robot's warning zone.
    pub min_gap: Option<f64>,
    /// The 1st percentile of the gap over robot-steps with a person inside the warning zone,
    /// px (to 0.25 px, rounded down); `None` without such a step.
    pub gap_p1: Option<f64>,
    /// Person–robot contacts after a step (gap below zero).
    pub contacts: u64,
    /// Stops for a person that began (a robot that wanted to move and stopped).
    pub protective_stops: u64,
    /// Robot-steps spent stopped for a person.
    pub stopped_steps: u64,
    /// Robot-steps with a person inside the warning zone.
    pub warning_steps: u64,
    /// Person-steps in which a person could not step because of a robot.
    pub person_wait_steps: u64,
    /// Person-steps in all.
    pub person_steps: u64,
    /// Pick tours finished, and picks done.
    pub tours: u64,
    pub picks: u64,
    /// Person-steps spent walking (not picking or resting).
    pub walk_steps: u64,
    /// Walking person-steps held up: hard stops for robots (`person_wait_steps`) and steps
    /// giving way after no progress for a while (walking back out of the way, or standing
    /// there), which robots in the way cause, and now and then a crowd of people.
    pub blocked_steps: u64,
    /// The same people over the same steps with the fleet removed (same stations, tours and
    /// seed): what they do without robots. `None` in the figures of that run itself.
    pub alone: Option<Box<PeopleFigures>>,
    /// The zones' radii, px, centre to centre: protective and warning.
    pub protective_radius: f64,
    pub warning_radius: f64,
    /// Pixels per metre, to read the gaps in metres.
    pub px_per_m: f64,
    /// Seconds per step (docs/model.md, Units), to read steps as hours.
    pub step_seconds: f64,
}

#[derive(Clone, Debug)]
pub(super) struct Zones {
    /// Radii, centre to centre, px.
    pub(super) protective: f64,
    pub(super) warning: f64,
    /// How far beyond touching the protective field reaches to each side of a robot's path, px.
    pub(super) corridor: f64,
    /// A robot stopped for a person last step.
    was_stopped: Vec<bool>,
    /// Each robot's nearest gap this step (`INFINITY`: none in reach), and the robots touched.
    gap: Vec<f64>,
    touched: Vec<u32>,
    bins: Vec<u64>,
    bin: f64,
    samples: u64,
    min_gap: f64,
    contacts: u64,
    protective_stops: u64,
    stopped_steps: u64,
    pub(super) person_wait_steps: u64,
    px_per_m: f64,
    step_seconds: f64,
}

impl Zones {
    pub(super) fn new(h: &Humans, rr: f64, speed: f64, rh: f64, robots: usize) -> Zones {
        let v = speed / h.px_per_m / h.step_seconds; // m/s
        let stopping = v * v / (2.0 * h.decel); // m
        let protective = rr + rh + (stopping + h.protective) * h.px_per_m + speed;
        let warning = protective + h.warning * h.px_per_m;
        let span = (warning - rr - rh).max(BIN);
        // Truncation is intended: a bin count from a bounded, positive ratio.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let bins = ((span / BIN) as usize + 1).min(MAX_BINS);
        #[allow(clippy::cast_precision_loss)]
        let bin = span / (bins - 1).max(1) as f64;
        Zones {
            protective,
            warning,
            corridor: h.protective * h.px_per_m,
            was_stopped: vec![false; robots],
            gap: vec![f64::INFINITY; robots],
            touched: Vec::new(),
            bins: vec![0; bins],
            bin: bin.max(BIN.min(span)),
            samples: 0,
            min_gap: f64::INFINITY,
            contacts: 0,
            protective_stops: 0,
            stopped_steps: 0,
            person_wait_steps: 0,
            px_per_m: h.px_per_m,
            step_seconds: h.step_seconds,
        }
    }

    pub(super) fn figures(&self, person_steps: u64, tours: u64, picks: u64) -> PeopleFigures {
        let p1 = (self.samples > 0).then(|| {
            // Nearest rank: the smallest gap with at least 1% of the samples at or below it.
            let rank = self.samples.div_ceil(100).max(1);
            let mut seen = 0;
            let mut k = 0;
            for (b, &c) in self.bins.iter().enumerate() {
                seen += c;
                if seen >= rank {
                    k = b;
                    break;
                }
            }
            #[allow(clippy::cast_precision_loss)]
            let v = k as f64 * self.bin;
            v
        });
        #[allow(clippy::cast_possible_truncation)]
        PeopleFigures {
            count: 0,
            min_gap: self.min_gap.is_finite().then_some(self.min_gap),
            gap_p1: p1,
            contacts: self.contacts,
            protective_stops: self.protective_stops,
            stopped_steps: self.stopped_steps,
            warning_steps: self.samples,
            person_wait_steps: self.person_wait_steps,
            person_steps,
            tours,
            picks,
            walk_steps: 0,
            blocked_steps: 0,
            alone: None,
            protective_radius: self.protective,
            warning_radius: self.warning,
            px_per_m: self.px_per_m,
            step_seconds: self.step_seconds,
        }
    }
}

impl People {
    /// Before the robots move: which robots stop for a person and which slow down. `wants`:
    /// robots that want to move this step (heading from their position to their waypoint).
    pub(crate) fn guard(&mut self, robots: &Robots, wants: &[bool]) {
        let n = robots.len();
        self.stop[..n].fill(false);
        self.slow[..n].fill(false);
        self.robot_grid.build(&robots.x, &robots.y, |_| true);
        self.crowd.build(&self.x, &self.y, |_| true);
        let (p, w, rh, corridor) = (self.zones.protective, self.zones.warning, self.radius, self.zones.corridor);
        for k in 0..self.len() {
            let (qx, qy) = (self.x[k], self.y[k]);
            let (stop, slow) = (&mut self.stop, &mut self.slow);
            self.robot_grid.near(qx, qy, w, |i| {
                if !wants[i] {
                    return;
                }
                let (dx, dy) = (qx - robots.x[i], qy - robots.y[i]);
                if at_least(dx, dy, w) {
                    return;
                }
                let d = dx.hypot(dy);
                slow[i] = true;
                if d < p {
                    // The protective field covers the robot's path ahead: a person whose centre
                    // is within the robot's and its own radius plus the margin of the line the
                    // robot drives. One within a step of travel stops it from any side.
                    let (hx, hy) = (robots.wp_x[i] - robots.x[i], robots.wp_y[i] - robots.y[i]);
                    let len = hx.hypot(hy);
                    let reach = robots.radius[i] + rh;
                    let in_path = len <= 1e-9 || {
                        let along = (dx * hx + dy * hy) / len;
                        let across = (dx * hy - dy * hx).abs() / len;
                        along > -reach && across < reach + corridor
                    };
                    if in_path || d < reach + robots.speed[i] + CLEAR {
                        stop[i] = true;
                    }
                }
            });
        }
        let z = &mut self.zones;
        for i in 0..n {
            if self.stop[i] {
                z.stopped_steps += 1;
                if !z.was_stopped[i] {
                    z.protective_stops += 1;
                }
            }
            z.was_stopped[i] = self.stop[i];
        }
    }

    /// After everyone moved: the gaps between people and robots.
    pub(crate) fn measure(&mut self, robots: &Robots) {
        let rh = self.radius;
        let speed_max = robots.speed.iter().copied().fold(0.0, f64::max);
        let reach = self.zones.warning + speed_max + self.aside;
        let z = &mut self.zones;
        for k in 0..self.x.len() {
            let (qx, qy) = (self.x[k], self.y[k]);
            let (gap, touched) = (&mut z.gap, &mut z.touched);
            self.robot_grid.near(qx, qy, reach, |i| {
                let (dx, dy) = (qx - robots.x[i], qy - robots.y[i]);
                if at_least(dx, dy, z.warning) {
                    return;
                }
                let d = dx.hypot(dy);
                // `d < warning`, not `!(d >= warning)`: a NaN is left out, as it always was.
                if d < z.warning {
                    let g = d - robots.radius[i] - rh;
                    if gap[i].is_infinite() {
                        #[allow(clippy::cast_possible_truncation)]
                        touched.push(i as u32);
                    }
                    gap[i] = gap[i].min(g);
                }
            });
        }
        for &i in &z.touched {
            let g = z.gap[i as usize];
            z.gap[i as usize] = f64::INFINITY;
            z.samples += 1;
            z.min_gap = z.min_gap.min(g);
            if g < 0.0 {
                z.contacts += 1;
            }
            // Truncation is intended: the bin of a gap, clamped into the histogram.
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let b = ((g.max(0.0) / z.bin) as usize).min(z.bins.len() - 1);
            z.bins[b] += 1;
        }
        z.touched.clear();
    }
}
