//! Replay recording, in the format of `docs/replay-format.md`.
//!
//! Frames are gathered by chunk, column by column, and each chunk is one zlib stream, so a
//! reader can fetch any stretch of a long run on its own. The file is written under a
//! temporary name and renamed when the run ends: a replay on disk is always whole.

use crate::error::{Error, Result};
use crate::metrics::RunResult;
use crate::sim::Simulation;
use flate2::write::ZlibEncoder;
use flate2::Compression;
use serde_json::json;
use std::f64::consts::TAU;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// File magic.
pub const MAGIC: &[u8; 8] = b"MBREPLAY";
/// Format version.
pub const VERSION: u32 = 1;
/// Bytes per robot per frame before compression.
pub const BYTES_PER_ROBOT_STEP: usize = 12;

/// Heading angle (radians) as one byte: round(α / 2π × 256) mod 256.
#[must_use]
pub fn heading_byte(a: f64) -> u8 {
    ((a / TAU * 256.0).round() as i64).rem_euclid(256) as u8
}

/// Energy as a fraction of full, in 16 bits.
#[must_use]
pub fn energy_word(e: f64, full: f64) -> u16 {
    ((e / full).clamp(0.0, 1.0) * 65535.0).round() as u16
}

struct ChunkInfo {
    offset: u64,
    length: u64,
    first_frame: u64,
    frames: u64,
}

/// Writes a replay while a simulation runs: [`ReplayWriter::create`] before the first step,
/// [`ReplayWriter::frame`] after each step, [`ReplayWriter::finish`] at the end.
pub struct ReplayWriter {
    out: Option<BufWriter<File>>,
    tmp: PathBuf,
    path: PathBuf,
    n: usize,
    chunk_frames: usize,
    energy_full: f64,
    offset: u64,
    first_frame: u64,
    frames: u64,
    chunks: Vec<ChunkInfo>,
    counters: Vec<u32>,
    x: Vec<f32>,
    y: Vec<f32>,
    events: Vec<u32>,
    energy: Vec<u16>,
    heading: Vec<u8>,
    state: Vec<u8>,
    raw: Vec<u8>,
}

impl ReplayWriter {
    /// Opens the replay and records frame 0 (the state before step 1).
    pub fn create(path: &Path, sim: &Simulation, scenario_toml: &str) -> Result<ReplayWriter> {
        let display = path.display().to_string();
        let name = path.file_name().ok_or_else(|| Error::Io { path: display.clone(), message: "not a file name".into() })?;
        let tmp = path.with_file_name(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
        let file = File::create(&tmp).map_err(|e| Error::io(&display, &e))?;
        let n = sim.robots().len();
        let chunk_frames = ((1usize << 20) / (BYTES_PER_ROBOT_STEP * n.max(1))).clamp(16, 1024);
        let (energy_full, threshold) = sim.energy_levels();
        let r = sim.robots();
        let header = json!({
            "format": "multibots-replay",
            "version": VERSION,
            "robots": n,
            "radius": r.radius,
            "home": r.home.iter().map(|h| h.0).collect::<Vec<_>>(),
            "energy_full": energy_full,
            "threshold": threshold,
            "chunk_steps": chunk_frames,
            "cells_full": sim.cells_full().iter().map(|&f| u8::from(f)).collect::<Vec<_>>(),
            "goods_total": sim.goods_total(),
            "layout": sim.world().layout.to_json(),
            "scenario": scenario_toml,
        });
        let header = serde_json::to_vec(&header).expect("JSON serialises");
        let mut out = BufWriter::with_capacity(1 << 16, file);
        let mut w = |b: &[u8]| out.write_all(b).map_err(|e| Error::io(&display, &e));
        w(MAGIC)?;
        w(&VERSION.to_le_bytes())?;
        w(&(header.len() as u32).to_le_bytes())?;
        w(&header)?;
        let mut rw = ReplayWriter {
            out: Some(out),
            tmp,
            path: path.to_path_buf(),
            n,
            chunk_frames,
            energy_full,
            offset: 16 + header.len() as u64,
            first_frame: 0,
            frames: 0,
            chunks: Vec::new(),
            counters: Vec::with_capacity(3 * chunk_frames),
            x: Vec::with_capacity(n * chunk_frames),
            y: Vec::with_capacity(n * chunk_frames),
            events: Vec::new(),
            energy: Vec::with_capacity(n * chunk_frames),
            heading: Vec::with_capacity(n * chunk_frames),
            state: Vec::with_capacity(n * chunk_frames),
            raw: Vec::new(),
        };
        rw.frame(sim)?;
        Ok(rw)
    }

    /// Records the state after the step just run, with its events.
    pub fn frame(&mut self, sim: &Simulation) -> Result<()> {
        let r = sim.robots();
        self.counters.extend_from_slice(&[sim.s() as u32, sim.c() as u32, sim.delivered() as u32]);
        self.x.extend(r.x.iter().map(|&v| v as f32));
        self.y.extend(r.y.iter().map(|&v| v as f32));
        self.energy.extend(r.energy.iter().map(|&e| energy_word(e, self.energy_full)));
        self.heading.extend(r.heading.iter().map(|&a| heading_byte(a)));
        self.state.extend(r.state.iter().zip(&r.marked).map(|(&s, &m)| s as u8 | if m { 0x80 } else { 0 }));
        if self.frames > 0 {
            for e in sim.events() {
                self.events.extend_from_slice(&[self.frames as u32, e.kind as u32, e.robot, e.cell]);
            }
        }
        self.frames += 1;
        if (self.frames - self.first_frame) as usize == self.chunk_frames {
            self.flush_chunk()?;
        }
        Ok(())
    }

    fn flush_chunk(&mut self) -> Result<()> {
        let k = self.frames - self.first_frame;
        if k == 0 {
            return Ok(());
        }
        let raw = &mut self.raw;
        raw.clear();
        let words = |raw: &mut Vec<u8>, v: &[u32]| v.iter().for_each(|w| raw.extend_from_slice(&w.to_le_bytes()));
        words(raw, &[self.first_frame as u32, k as u32, self.n as u32, (self.events.len() / 4) as u32]);
        words(raw, &self.counters);
        self.x.iter().for_each(|v| raw.extend_from_slice(&v.to_le_bytes()));
        self.y.iter().for_each(|v| raw.extend_from_slice(&v.to_le_bytes()));
        words(raw, &self.events);
        self.energy.iter().for_each(|v| raw.extend_from_slice(&v.to_le_bytes()));
        raw.extend_from_slice(&self.heading);
        raw.extend_from_slice(&self.state);
        let mut z = ZlibEncoder::new(Vec::with_capacity(raw.len() / 4), Compression::fast());
        z.write_all(raw).expect("writing to memory");
        let compressed = z.finish().expect("writing to memory");
        let display = self.path.display().to_string();
        let out = self.out.as_mut().expect("open until finished");
        out.write_all(&compressed).map_err(|e| Error::io(&display, &e))?;
        self.chunks.push(ChunkInfo { offset: self.offset, length: compressed.len() as u64, first_frame: self.first_frame, frames: k });
        self.offset += compressed.len() as u64;
        self.first_frame = self.frames;
        self.counters.clear();
        self.x.clear();
        self.y.clear();
        self.events.clear();
        self.energy.clear();
        self.heading.clear();
        self.state.clear();
        Ok(())
    }

    /// Writes the last chunk and the footer, and moves the file into place.
    pub fn finish(mut self, result: &RunResult) -> Result<()> {
        self.flush_chunk()?;
        let footer = json!({
            "frames": self.frames,
            "T": result.t,
            "S": result.s,
            "C": result.c,
            "outcome": result.outcome.map_or("running", |o| o.as_str()),
            "delivered": result.delivered,
            "chunks": self.chunks.iter().map(|c| json!({"offset": c.offset, "length": c.length, "first_frame": c.first_frame, "frames": c.frames})).collect::<Vec<_>>(),
        });
        let footer = serde_json::to_vec(&footer).expect("JSON serialises");
        let display = self.path.display().to_string();
        let mut out = self.out.take().expect("open until finished");
        let io = |e: std::io::Error| Error::io(&display, &e);
        let written = (|| {
            out.write_all(&footer).map_err(io)?;
            out.write_all(&self.offset.to_le_bytes()).map_err(io)?;
            out.write_all(&(footer.len() as u64).to_le_bytes()).map_err(io)?;
            let file = out.into_inner().map_err(|e| Error::io(&display, e.error()))?;
            file.sync_all().map_err(io)?;
            drop(file);
            std::fs::rename(&self.tmp, &self.path).map_err(io)
        })();
        if written.is_err() {
            // Nothing half-written stays behind, here as on drop.
            let _ = std::fs::remove_file(&self.tmp);
        }
        written
    }
}

impl Drop for ReplayWriter {
    fn drop(&mut self) {
        // Not finished: leave nothing half-written behind.
        if self.out.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Runs a simulation to its end while recording it to `path`.
pub fn run_recorded(sim: &mut Simulation, path: &Path, scenario_toml: &str) -> Result<RunResult> {
    let mut w = ReplayWriter::create(path, sim, scenario_toml)?;
    while !sim.done() {
        sim.step()?;
        w.frame(sim)?;
    }
    let result = sim.result();
    w.finish(&result)?;
    Ok(result)
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
    }
}
