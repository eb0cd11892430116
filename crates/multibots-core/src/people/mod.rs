//! People in the aisles (docs/people.md): pickers who walk the aisles in either direction,
//! pick at storage cells and return to a station (their tours, `tours.rs`; how they walk,
//! `walk.rs`), and the safety zones robots keep around them (`zones.rs`, with the people
//! sorted into buckets by position, `buckets.rs`).
//!
//! Each step, around the robots' phases 3 and 4 (crate::rules::paper):
//! 1. [`People::guard`] (before robots move): a robot with a person ahead or beside it
//!    inside its protective zone stops (a protective stop, counted apart from S); one with a
//!    person inside its warning zone slows down ([`zones`]).
//! 2. The robots move.
//! 3. [`People::walk`] (after): each person walks towards the next point of its tour with
//!    the social-force model, and never steps into contact with a robot ([`walk`]); then
//!    the safety figures are measured on the positions after the step.
//!
//! With both rules no step can bring a person and a robot into contact: a robot moves only
//! when every person within its reach is behind it and further than one step, and a person
//! moves only to a point clear of every robot.

mod tours;
mod walk;
mod zones;

pub use zones::PeopleFigures;

use crate::error::Result;
use crate::fleet::robot::Robots;
use crate::input::csv::Tables;
use crate::input::scenario::Humans;
use crate::world::buckets::{self, Buckets};
use crate::world::World;
use tours::Tours;

/// What a person is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Phase {
    Walk,
    /// Steps left picking at a cell.
    Pick(u32),
    /// Steps left at the station between tours.
    Rest(u32),
}

/// The workers on the floor, struct of arrays.
#[derive(Clone, Debug)]
pub struct People {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    vx: Vec<f64>,
    vy: Vec<f64>,
    phase: Vec<Phase>,
    /// Radius, px.
    pub radius: f64,
    /// Walking speed, px per step.
    v0: f64,
    /// Half the aisle width: how far from the line of its path a person may stand.
    half_aisle: f64,
    /// The start of the segment each person walks (its last waypoint).
    seg_x: Vec<f64>,
    seg_y: Vec<f64>,
    /// The closest a person came to its waypoint, steps without getting closer, and steps
    /// left giving way (walk.rs).
    best: Vec<f64>,
    stuck: Vec<u32>,
    retreat: Vec<u32>,
    ret_x: Vec<f64>,
    ret_y: Vec<f64>,
    tours: Tours,
    zones: zones::Zones,
    /// People near each point, and robots near each point, at the start of the step.
    crowd: Buckets,
    robot_grid: Buckets,
    /// How far a robot can land beside its route in a step beyond its speed: stepping into
    /// or out of a bay (one contact distance, `fleet/bay.rs`). `robot_grid` holds the robots'
    /// places from before their moves, so every query after the moves reaches this much and
    /// a step further (without it, only the grid's wide cells found such a robot).
    aside: f64,
    /// Robots that stop for a person this step, and robots that slow down.
    pub(crate) stop: Vec<bool>,
    pub(crate) slow: Vec<bool>,
    /// The warning zone's speed factor.
    pub(crate) slow_factor: f64,
    forces: walk::Forces,
    /// Person-steps spent walking (not picking or resting), and walking steps spent giving
    /// way (walking back out of the way, or standing there).
    walk_steps: u64,
    give_way_steps: u64,
}

impl People {
    /// The people of a scenario's `[humans]` table; `None` when there are none.
    /// `margin`: the collision margin (a bay is one contact distance deep).
    pub(crate) fn new(h: &Humans, world: &World, tables: &Tables, robots: &Robots, margin: f64) -> Result<Option<People>> {
        if h.count == 0 {
            return Ok(None);
        }
        let n = h.count as usize;
        let radius = h.radius * h.px_per_m;
        let v0 = h.speed * h.step_seconds * h.px_per_m;
        let rr = robots.radius.iter().copied().fold(0.0, f64::max);
        let speed = robots.speed.iter().copied().fold(0.0, f64::max);
        let zones = zones::Zones::new(h, rr, speed, radius, robots.len());
        let tours = Tours::new(h, world, tables, robots, radius)?;
        let (x, y): (Vec<f64>, Vec<f64>) = (0..n).map(|k| tours.start(k)).unzip();
        let bounds = world.reach_bounds();
        let pad = zones.warning + rr + radius;
        let bounds = [bounds[0] - pad, bounds[1] - pad, bounds[2] + pad, bounds[3] + pad];
        // Cells as wide as the largest reach any query uses, so a query spans 3 x 3 cells.
        let reach = (zones.warning + speed + rr + radius).max(6.0 * radius + 4.0 * walk::ROBOT_RANGE * h.px_per_m);
        Ok(Some(People {
            seg_x: x.clone(),
            seg_y: y.clone(),
            x,
            y,
            best: vec![f64::INFINITY; n],
            stuck: vec![0; n],
            retreat: vec![0; n],
            ret_x: vec![0.0; n],
            ret_y: vec![0.0; n],
            vx: vec![0.0; n],
            vy: vec![0.0; n],
            phase: vec![Phase::Rest(h.rest); n],
            radius,
            v0,
            half_aisle: world.layout.aisle_width / 2.0,
            tours,
            zones,
            crowd: Buckets::new(bounds, reach),
            robot_grid: Buckets::new(bounds, reach),
            aside: 2.0 * rr + margin,
            stop: vec![false; robots.len()],
            slow: vec![false; robots.len()],
            slow_factor: h.slow,
            forces: walk::Forces::new(h.px_per_m, h.step_seconds),
            walk_steps: 0,
            give_way_steps: 0,
        }))
    }

    /// Number of people.
    #[must_use]
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are none (never, once built).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// The zones' radii around a robot, centre to centre, px: protective and warning.
    #[must_use]
    pub fn zone_radii(&self) -> [f64; 2] {
        [self.zones.protective, self.zones.warning]
    }

    /// Whether each person is walking (else picking or resting).
    pub fn walking(&self) -> impl Iterator<Item = bool> + '_ {
        self.phase.iter().map(|p| *p == Phase::Walk)
    }

    /// Whether a robot of `radius` may stand at `(x, y)`: no person within touching distance
    /// (and the gap people keep). Reads the positions of this step's [`People::guard`].
    pub(crate) fn clear_of(&self, x: f64, y: f64, radius: f64) -> bool {
        let reach = radius + self.radius + walk::CLEAR;
        let mut clear = true;
        self.crowd.near(x, y, reach, |k| clear = clear && buckets::at_least(self.x[k] - x, self.y[k] - y, reach));
        clear
    }

    /// After the robots moved: people walk, pick or rest, then the gaps are measured.
    pub(crate) fn step(&mut self, robots: &Robots) {
        let forces = self.forces;
        let blocked = self.walk_people(robots, &forces);
        self.zones.person_wait_steps += blocked;
        self.measure(robots);
    }

    /// The figures so far, after `steps` steps.
    #[must_use]
    pub fn figures(&self, steps: u64) -> PeopleFigures {
        #[allow(clippy::cast_possible_truncation)]
        let count = self.len() as u32;
        let f = self.zones.figures(self.len() as u64 * steps, self.tours.finished, self.tours.picked);
        let blocked_steps = f.person_wait_steps + self.give_way_steps;
        PeopleFigures { count, walk_steps: self.walk_steps, blocked_steps, ..f }
    }

    /// The same people with the fleet removed: their stations, tours and seed as they are
    /// now, on a floor with no robot. Stepped beside the run (`step_alone`), they give what
    /// robots cost people: the same workers, the same draws, nothing else changed.
    #[must_use]
    pub(crate) fn alone(&self) -> People {
        self.clone()
    }

    /// One step of people on a floor with no robot (`alone`).
    pub(crate) fn step_alone(&mut self) {
        let none = Robots::default();
        self.guard(&none, &[]);
        self.step(&none);
    }
}
