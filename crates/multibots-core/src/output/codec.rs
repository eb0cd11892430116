//! The replay frame codec (`docs/replay-format.md`): the one definition of how frames are
//! laid out in a chunk, used by the replay writer, the live viewer's frames and the Python
//! reader (through the binding). The viewer's page decodes the same layout in JavaScript and
//! takes the state and event names from the replay header, and the scales (the mark, the
//! state mask, the heading and energy scales, `crate::record::frame`) from the server, which
//! has them from the binding.
//!
//! A decompressed chunk holds `K` frames of `N` robots and `E` events:
//!
//! | section | type | count |
//! | --- | --- | --- |
//! | head: first frame, K, N, E | u32 | 4 |
//! | counters: S, C, delivered per frame | u32 | 3·K |
//! | x, then y, per frame and robot | f32 | K·N each |
//! | events: frame, kind, robot, cell | u32 | 4·E |
//! | energy: fraction of full × 65535 | u16 | K·N |
//! | heading: round(α / 2π × 256) mod 256 | u8 | K·N |
//! | state: code, +128 when marked to charge | u8 | K·N |
//! | people (only with `[humans]`): x, then y, per frame and person | f32 | K·P each |
//!
//! Every section starts at a multiple of its type's size without padding, all little-endian
//! (the sections before the people's add up to a multiple of 4 bytes). The number of people
//! P is not in the head: it is what the bytes after the robots' sections hold, 8·K bytes per
//! person, and the replay header's `humans` says it too.

use crate::record::frame::Frame;
pub use crate::record::frame::{ENERGY_SCALE, HEADING_STEPS, MARKED, STATE_MASK};
use flate2::read::ZlibDecoder;
use std::io::Read;

/// File magic.
pub const MAGIC: &[u8; 8] = b"MBREPLAY";
/// Format version.
pub const VERSION: u32 = 1;
/// Bytes per robot per frame before compression.
pub const BYTES_PER_ROBOT_STEP: usize = 12;
/// Byte offset and length of each section of a decompressed chunk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkLayout {
    pub counters: (usize, usize),
    pub x: (usize, usize),
    pub y: (usize, usize),
    pub events: (usize, usize),
    pub energy: (usize, usize),
    pub heading: (usize, usize),
    pub state: (usize, usize),
    pub people_x: (usize, usize),
    pub people_y: (usize, usize),
    pub total: usize,
}

impl ChunkLayout {
    /// The layout of `frames` frames of `robots` robots with `events` events; `None` when
    /// the sizes overflow (a corrupt head).
    #[must_use]
    pub fn new(frames: usize, robots: usize, events: usize, people: usize) -> Option<ChunkLayout> {
        let cells = frames.checked_mul(robots)?;
        let mut at = 16usize;
        let mut section = |bytes: usize| -> Option<(usize, usize)> {
            let s = (at, bytes);
            at = at.checked_add(bytes)?;
            Some(s)
        };
        let counters = section(frames.checked_mul(12)?)?;
        let x = section(cells.checked_mul(4)?)?;
        let y = section(cells.checked_mul(4)?)?;
        let events = section(events.checked_mul(16)?)?;
        let energy = section(cells.checked_mul(2)?)?;
        let heading = section(cells)?;
        let state = section(cells)?;
        let crowd = frames.checked_mul(people)?;
        let people_x = section(crowd.checked_mul(4)?)?;
        let people_y = section(crowd.checked_mul(4)?)?;
        Some(ChunkLayout { counters, x, y, events, energy, heading, state, people_x, people_y, total: at })
    }
}

/// Frames gathered column by column, ready to be encoded as one chunk.
#[derive(Clone, Debug, Default)]
pub struct Frames {
    robots: usize,
    count: usize,
    counters: Vec<u32>,
    x: Vec<f32>,
    y: Vec<f32>,
    events: Vec<u32>,
    energy: Vec<u16>,
    heading: Vec<u8>,
    state: Vec<u8>,
    people_x: Vec<f32>,
    people_y: Vec<f32>,
}

impl Frames {
    /// Room for `frames` frames of `robots` robots.
    #[must_use]
    pub fn with_capacity(robots: usize, frames: usize) -> Frames {
        let cells = robots * frames;
        Frames {
            robots,
            count: 0,
            counters: Vec::with_capacity(3 * frames),
            x: Vec::with_capacity(cells),
            y: Vec::with_capacity(cells),
            events: Vec::new(),
            energy: Vec::with_capacity(cells),
            heading: Vec::with_capacity(cells),
            state: Vec::with_capacity(cells),
            people_x: Vec::new(),
            people_y: Vec::new(),
        }
    }

    /// Frames gathered so far.
    #[must_use]
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether no frame is gathered.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Adds `f` as frame number `frame`, with its events when `with_events` (frame 0, the
    /// state before step 1, has none under the paper rules).
    pub fn push(&mut self, f: &Frame, frame: u64, with_events: bool) {
        debug_assert_eq!(f.robots(), self.robots);
        self.counters.extend_from_slice(&f.counters);
        self.x.extend_from_slice(&f.x);
        self.y.extend_from_slice(&f.y);
        self.energy.extend_from_slice(&f.energy);
        self.heading.extend_from_slice(&f.heading);
        self.state.extend_from_slice(&f.state);
        self.people_x.extend_from_slice(&f.people_x);
        self.people_y.extend_from_slice(&f.people_y);
        if with_events {
            for &[kind, robot, cell] in &f.events {
                self.events.extend_from_slice(&[frame as u32, kind, robot, cell]);
            }
        }
        self.count += 1;
    }

    /// Appends the decompressed chunk of the gathered frames, numbered from `first_frame`.
    pub fn encode(&self, first_frame: u64, out: &mut Vec<u8>) {
        let words = |out: &mut Vec<u8>, v: &[u32]| v.iter().for_each(|w| out.extend_from_slice(&w.to_le_bytes()));
        words(out, &[first_frame as u32, self.count as u32, self.robots as u32, (self.events.len() / 4) as u32]);
        words(out, &self.counters);
        self.x.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        self.y.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        words(out, &self.events);
        self.energy.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        out.extend_from_slice(&self.heading);
        out.extend_from_slice(&self.state);
        self.people_x.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        self.people_y.iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
    }

    /// Forgets the gathered frames, keeping the buffers.
    pub fn clear(&mut self) {
        self.count = 0;
        self.counters.clear();
        self.x.clear();
        self.y.clear();
        self.events.clear();
        self.energy.clear();
        self.heading.clear();
        self.state.clear();
        self.people_x.clear();
        self.people_y.clear();
    }
}

/// A decoded chunk.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Chunk {
    pub first_frame: u32,
    pub frames: u32,
    pub robots: u32,
    /// `(frames, 3)`: S, C, delivered.
    pub counters: Vec<u32>,
    /// `(frames, robots)` each.
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    /// `(events, 4)`: frame, kind, robot, cell.
    pub events: Vec<u32>,
    pub energy: Vec<u16>,
    pub heading: Vec<u8>,
    pub state: Vec<u8>,
    /// People on the floor (0 without `[humans]`), and `(frames, people)` positions each.
    pub people: u32,
    pub people_x: Vec<f32>,
    pub people_y: Vec<f32>,
}

/// Inflates a chunk's zlib stream, refusing to produce more than `limit` bytes (a small
/// stream can inflate to gigabytes: the caller knows how big a chunk can be).
pub fn inflate(compressed: &[u8], limit: usize) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let mut z = ZlibDecoder::new(compressed).take(limit as u64 + 1);
    z.read_to_end(&mut out).map_err(|e| format!("corrupt ({e})"))?;
    if out.len() > limit {
        return Err(format!("inflates to more than the {limit} bytes its frames can hold"));
    }
    Ok(out)
}

/// Decodes a decompressed chunk, checking that its sizes agree with its head.
pub fn decode(raw: &[u8]) -> Result<Chunk, String> {
    if raw.len() < 16 {
        return Err(format!("too short ({} bytes)", raw.len()));
    }
    let word = |k: usize| u32::from_le_bytes([raw[4 * k], raw[4 * k + 1], raw[4 * k + 2], raw[4 * k + 3]]);
    let (first_frame, frames, robots, events) = (word(0), word(1), word(2), word(3));
    let robots_only = ChunkLayout::new(frames as usize, robots as usize, events as usize, 0).ok_or("sizes in its head overflow")?;
    // What follows the robots' sections is the people's: 8 bytes per person and frame.
    let extra = raw.len().checked_sub(robots_only.total).filter(|&b| frames == 0 || b % (8 * frames as usize) == 0);
    let Some(extra) = extra else {
        return Err(format!("holds {} bytes; its head ({frames} frames of {robots} robots, {events} events) needs {}", raw.len(), robots_only.total));
    };
    let people = if frames == 0 { 0 } else { extra / (8 * frames as usize) };
    let lay = ChunkLayout::new(frames as usize, robots as usize, events as usize, people).ok_or("sizes in its head overflow")?;
    if raw.len() != lay.total {
        return Err(format!("holds {} bytes; its head ({frames} frames of {robots} robots, {events} events) needs {}", raw.len(), lay.total));
    }
    let sec = |(off, len): (usize, usize)| &raw[off..off + len];
    let u32s = |s: &[u8]| s.chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect::<Vec<_>>();
    let f32s = |s: &[u8]| s.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect::<Vec<_>>();
    Ok(Chunk {
        first_frame,
        frames,
        robots,
        counters: u32s(sec(lay.counters)),
        x: f32s(sec(lay.x)),
        y: f32s(sec(lay.y)),
        events: u32s(sec(lay.events)),
        energy: sec(lay.energy).chunks_exact(2).map(|b| u16::from_le_bytes([b[0], b[1]])).collect(),
        heading: sec(lay.heading).to_vec(),
        state: sec(lay.state).to_vec(),
        #[allow(clippy::cast_possible_truncation)]
        people: people as u32,
        people_x: f32s(sec(lay.people_x)),
        people_y: f32s(sec(lay.people_y)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::scenario::Scenario;
    use crate::rules::{Run, Simulation};

    #[test]
    fn frames_round_trip_through_the_codec() {
        let mut sim = Simulation::new(&Scenario::paper(3, &[11, 8, 39])).unwrap();
        let mut f = Frames::with_capacity(3, 4);
        let mut frame = Frame::default();
        sim.emit(&mut frame, false);
        f.push(&frame, 0, false);
        for k in 1..=300 {
            sim.step().unwrap();
            if k % 100 == 0 {
                sim.emit(&mut frame, true);
                f.push(&frame, k, true);
            }
        }
        let mut raw = Vec::new();
        f.encode(7, &mut raw);
        let c = decode(&raw).unwrap();
        assert_eq!((c.first_frame, c.frames, c.robots), (7, 4, 3));
        assert_eq!(c.x[9..], sim.robots().x.iter().map(|&v| v as f32).collect::<Vec<_>>()[..]);
        assert_eq!(&c.counters[9..], &[sim.s() as u32, sim.c() as u32, sim.delivered() as u32]);
        assert_eq!(decode(&raw[..raw.len() - 1]).unwrap_err().split(';').next().unwrap(), format!("holds {} bytes", raw.len() - 1));
    }

    #[test]
    fn inflate_refuses_a_bomb() {
        use flate2::write::ZlibEncoder;
        use std::io::Write;
        let mut z = ZlibEncoder::new(Vec::new(), flate2::Compression::best());
        z.write_all(&vec![0u8; 10 << 20]).unwrap();
        let small = z.finish().unwrap();
        assert!(small.len() < 20_000);
        assert!(inflate(&small, 1 << 20).unwrap_err().contains("more than"));
        assert_eq!(inflate(&small, 10 << 20).unwrap().len(), 10 << 20);
        assert!(inflate(b"not zlib", 100).unwrap_err().starts_with("corrupt"));
    }
}
