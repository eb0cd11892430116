//! A frame: what a run shows of itself after a step, in the units of a replay
//! (`docs/replay-format.md`), whatever its rules. Every rule set emits its state as a
//! [`Frame`] through the run contract (`crate::rules::Run`), and whatever records or draws a
//! run (a replay file, the live viewer) is a [`FrameSink`] that reads frames and nothing
//! of the run itself. The scales below are defined here only: the codec, the binding and the
//! viewer's page take them from here.

use crate::error::Result;
use crate::record::resources::{Bottleneck, Queues, ResourceUse};
use std::f64::consts::TAU;

/// The state byte's flag: marked by the threshold rule to charge after unloading.
pub const MARKED: u8 = 0x80;
/// The state byte's bits that hold the state code (all but [`MARKED`]).
pub const STATE_MASK: u8 = !MARKED;
/// Heading steps in a full turn: the heading byte counts turns in 256ths.
pub const HEADING_STEPS: u32 = 256;
/// The energy word of a full battery: energy is a fraction of full times this.
pub const ENERGY_SCALE: u16 = u16::MAX;

/// Heading angle (radians) as one byte: round(α / 2π × [`HEADING_STEPS`]) mod [`HEADING_STEPS`].
#[must_use]
pub fn heading_byte(a: f64) -> u8 {
    ((a / TAU * f64::from(HEADING_STEPS)).round() as i64).rem_euclid(i64::from(HEADING_STEPS)) as u8
}

/// Energy as a fraction of full, in 16 bits: × [`ENERGY_SCALE`], rounded.
#[must_use]
pub fn energy_word(e: f64, full: f64) -> u16 {
    ((e / full).clamp(0.0, 1.0) * f64::from(ENERGY_SCALE)).round() as u16
}

/// One frame: the counters, one value per robot in each column, the events of the step that
/// led to it and where people stand. The buffers are kept between frames, so a run that
/// emits into the same frame every step allocates nothing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// S, C and delivered (what they count under each rule set: `docs/replay-format.md`).
    pub counters: [u32; 3],
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    /// Energy words ([`energy_word`]).
    pub energy: Vec<u16>,
    /// Heading bytes ([`heading_byte`]).
    pub heading: Vec<u8>,
    /// State codes, `| MARKED` where marked to charge.
    pub state: Vec<u8>,
    /// The step's events as (kind, robot, cell); a sink numbers them by its frame.
    pub events: Vec<[u32; 3]>,
    /// People on the floor (none where the rules have none).
    pub people_x: Vec<f32>,
    pub people_y: Vec<f32>,
    /// The queues of the step, where the rules report resources.
    pub queues: Option<Queues>,
}

impl Frame {
    /// Empties every column, keeping the buffers.
    pub fn clear(&mut self) {
        self.counters = [0; 3];
        self.x.clear();
        self.y.clear();
        self.energy.clear();
        self.heading.clear();
        self.state.clear();
        self.events.clear();
        self.people_x.clear();
        self.people_y.clear();
        self.queues = None;
    }

    /// Robots in the frame.
    #[must_use]
    pub fn robots(&self) -> usize {
        self.x.len()
    }
}

/// What records or draws a run: frames one per step, in order.
pub trait FrameSink {
    /// The frame after the next step.
    fn frame(&mut self, frame: &Frame) -> Result<()>;
    /// A step in which nothing moved or happened: the last frame again, without its events
    /// (a League of Robot Runners step lost to the plan time limit).
    fn repeat(&mut self) -> Result<()>;
}

/// What a run says of itself when a recording of it ends: a replay's footer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Task time T, once known.
    pub t: Option<u64>,
    /// The counters S and C (as the frames count them).
    pub s: u64,
    pub c: u64,
    /// How the run ended (`running` while it goes on; `horizon` where the rules have no end).
    pub outcome: &'static str,
    /// Goods delivered, or tasks finished.
    pub delivered: u64,
    /// Steps per throughput window, and what each complete window delivered.
    pub window: u64,
    pub windows: Vec<u64>,
    /// The resources the run reports, and the bottleneck among them.
    pub resources: Vec<ResourceUse>,
    pub bottleneck: Option<Bottleneck>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heading_and_energy_encodings() {
        assert_eq!(heading_byte(0.0), 0);
        assert_eq!(heading_byte(std::f64::consts::FRAC_PI_2), 64);
        assert_eq!(heading_byte(std::f64::consts::PI), 128);
        assert_eq!(heading_byte(-std::f64::consts::FRAC_PI_2), 192);
        assert_eq!(energy_word(10.0, 10.0), 65535);
        assert_eq!(energy_word(0.0, 10.0), 0);
        assert_eq!(energy_word(5.0, 10.0), 32768);
        // The format's numbers (docs/replay-format.md): readers in other languages use them.
        assert_eq!((MARKED, STATE_MASK, HEADING_STEPS, ENERGY_SCALE), (0x80, 0x7f, 256, 65535));
    }
}
