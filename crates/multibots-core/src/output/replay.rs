//! Replay recording, in the format of `docs/replay-format.md`.
//!
//! Frames are gathered by chunk, column by column, and each chunk is one zlib stream, so a
//! reader can fetch any stretch of a long run on its own. The file is written under a
//! temporary name and renamed when the run ends: a replay on disk is always whole.

use crate::error::{Error, Result};
use crate::fleet::robot::State;
use crate::output::codec::{Frames, BYTES_PER_ROBOT_STEP, MAGIC, VERSION};
use crate::output::events::EventKind;
use crate::output::metrics::RunResult;
use crate::output::resources::{Bottleneck, QueueLog, ResourceUse};
use crate::rules::Simulation;
use flate2::write::ZlibEncoder;
use flate2::Compression;
use serde_json::{json, Value};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

struct ChunkInfo {
    offset: u64,
    length: u64,
    /// Bytes once inflated: readers refuse to inflate a chunk past it.
    raw_length: u64,
    first_frame: u64,
    frames: u64,
}

/// The names of the state codes and event codes, for readers in other languages.
#[must_use]
pub fn names() -> Value {
    json!({
        "state_names": State::ALL.iter().map(|s| s.name()).collect::<Vec<_>>(),
        "event_names": EventKind::ALL.iter().map(|k| (k.code().to_string(), Value::from(k.name()))).collect::<serde_json::Map<_, _>>(),
    })
}

/// What a viewer needs before the first frame: the fleet, the energy scale, the stock, the
/// layout, the scenario and the code names. The replay header, and the live viewer's meta.
#[must_use]
pub fn header(sim: &Simulation, scenario_toml: &str) -> Value {
    let (energy_full, threshold) = sim.energy_levels();
    let r = sim.robots();
    let mut h = json!({
        "format": "multibots-replay",
        "version": VERSION,
        "robots": r.len(),
        "radius": r.radius,
        "home": r.home.iter().map(|h| h.0).collect::<Vec<_>>(),
        "energy_full": energy_full,
        "threshold": threshold,
        "cells_full": sim.cells_full().iter().map(|&f| u8::from(f)).collect::<Vec<_>>(),
        "goods_total": sim.goods_total(),
        "layout": sim.world().layout.to_json(),
        "scenario": scenario_toml,
    });
    if let Some(p) = sim.people() {
        // The people section of each chunk (crate::output::codec), and what the viewer draws.
        h["humans"] = json!({"count": p.len(), "radius": p.radius, "zones": p.zone_radii()});
    }
    if let (Value::Object(h), Value::Object(names)) = (&mut h, names()) {
        h.extend(names);
    }
    h
}

/// Writes a replay while a simulation runs: [`ReplayWriter::create`] before the first step,
/// [`ReplayWriter::frame`] after each step, [`ReplayWriter::finish`] at the end.
pub struct ReplayWriter {
    out: Option<BufWriter<File>>,
    tmp: PathBuf,
    path: PathBuf,
    chunk_frames: usize,
    offset: u64,
    first_frame: u64,
    frames: u64,
    chunks: Vec<ChunkInfo>,
    buf: Frames,
    raw: Vec<u8>,
    /// The queues frame by frame, for a run of [`Simulation`] (its footer's `queues`).
    queues: Option<QueueLog>,
}

impl ReplayWriter {
    /// Opens the replay and records frame 0 (the state before step 1).
    pub fn create(path: &Path, sim: &Simulation, scenario_toml: &str) -> Result<ReplayWriter> {
        let mut rw = ReplayWriter::open(path, header(sim, scenario_toml), sim.robots().len())?;
        rw.queues = Some(QueueLog::new(&sim.world().layout));
        rw.frame(sim)?;
        Ok(rw)
    }

    /// Opens a replay of `robots` robots with the header `h` (to which `chunk_steps` is
    /// added), and records no frame yet: for runs under other rules than [`Simulation`]'s,
    /// which add their frames with [`ReplayWriter::push_with`].
    pub fn open(path: &Path, mut h: Value, robots: usize) -> Result<ReplayWriter> {
        let display = path.display().to_string();
        let tmp = crate::input::files::output_temp(path).map_err(|message| Error::Io { path: display.clone(), message })?;
        let file = File::create(&tmp).map_err(|e| Error::io(&display, &e))?;
        let chunk_frames = ((1usize << 20) / (BYTES_PER_ROBOT_STEP * robots.max(1))).clamp(16, 1024);
        h["chunk_steps"] = json!(chunk_frames);
        let header = serde_json::to_vec(&h).expect("JSON serialises");
        let mut out = BufWriter::with_capacity(1 << 16, file);
        let mut w = |b: &[u8]| out.write_all(b).map_err(|e| Error::io(&display, &e));
        let written = (|| {
            w(MAGIC)?;
            w(&VERSION.to_le_bytes())?;
            w(&(header.len() as u32).to_le_bytes())?;
            w(&header)
        })();
        let rw = ReplayWriter {
            out: Some(out),
            tmp,
            path: path.to_path_buf(),
            chunk_frames,
            offset: 16 + header.len() as u64,
            first_frame: 0,
            frames: 0,
            chunks: Vec::new(),
            buf: Frames::with_capacity(robots, chunk_frames),
            raw: Vec::new(),
            queues: None,
        };
        // On an error the writer is dropped here, and its temporary file with it.
        written.map(|()| rw)
    }

    /// Records the state after the step just run, with its events.
    pub fn frame(&mut self, sim: &Simulation) -> Result<()> {
        if let Some(log) = &mut self.queues {
            log.record(self.frames, &sim.queues());
        }
        self.buf.push(sim, self.frames, self.frames > 0);
        self.frames += 1;
        if self.buf.len() == self.chunk_frames {
            self.flush_chunk()?;
        }
        Ok(())
    }

    /// Records the next frame from columns filled by the caller ([`Frames::push_with`]).
    pub fn push_with(&mut self, counters: [u32; 3], fill: impl FnOnce(crate::output::codec::Columns<'_>)) -> Result<()> {
        self.buf.push_with(counters, fill);
        self.frames += 1;
        if self.buf.len() == self.chunk_frames {
            self.flush_chunk()?;
        }
        Ok(())
    }

    /// Frames recorded so far; the next frame's number.
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    fn flush_chunk(&mut self) -> Result<()> {
        let k = self.buf.len() as u64;
        if k == 0 {
            return Ok(());
        }
        self.raw.clear();
        self.buf.encode(self.first_frame, &mut self.raw);
        let mut z = ZlibEncoder::new(Vec::with_capacity(self.raw.len() / 4), Compression::fast());
        z.write_all(&self.raw).expect("writing to memory");
        let compressed = z.finish().expect("writing to memory");
        let display = self.path.display().to_string();
        let out = self.out.as_mut().expect("open until finished");
        out.write_all(&compressed).map_err(|e| Error::io(&display, &e))?;
        self.chunks.push(ChunkInfo {
            offset: self.offset,
            length: compressed.len() as u64,
            raw_length: self.raw.len() as u64,
            first_frame: self.first_frame,
            frames: k,
        });
        self.offset += compressed.len() as u64;
        self.first_frame = self.frames;
        self.buf.clear();
        Ok(())
    }

    /// Writes the last chunk and the footer, and moves the file into place.
    pub fn finish(self, result: &RunResult) -> Result<()> {
        let queues = self.queues.as_ref().map_or(Value::Null, |log| log.to_json(&result.resources));
        let fields = json!({
            "T": result.t,
            "S": result.s,
            "C": result.c,
            "outcome": result.outcome.map_or("running", |o| o.as_str()),
            "delivered": result.delivered,
            "window": result.window,
            "windows": result.windows,
            "resources": result.resources.iter().map(ResourceUse::to_json).collect::<Vec<_>>(),
            "bottleneck": result.bottleneck.as_ref().map_or(Value::Null, Bottleneck::to_json),
            "queues": queues,
        });
        self.finish_with(fields)
    }

    /// Writes the last chunk and a footer of `fields` (an object: the indicators) with the
    /// frame count and the chunk table, and moves the file into place.
    pub fn finish_with(mut self, fields: Value) -> Result<()> {
        self.flush_chunk()?;
        let mut footer = fields;
        footer["frames"] = json!(self.frames);
        footer["chunks"] = self
            .chunks
            .iter()
            .map(|c| json!({"offset": c.offset, "length": c.length, "raw_length": c.raw_length, "first_frame": c.first_frame, "frames": c.frames}))
            .collect();
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
            crate::input::files::replaceable(&self.path).map_err(|message| Error::Io { path: crate::input::limits::shown(&display), message })?;
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

/// Runs up to `max_steps` steps (fewer if the run ends), recording each frame when a writer
/// is given; returns the steps run. Callers that must stay responsive (Ctrl-C) call it in
/// slices.
pub fn step_recorded(sim: &mut Simulation, mut writer: Option<&mut ReplayWriter>, max_steps: u64) -> Result<u64> {
    if writer.is_none() {
        return sim.steps(max_steps);
    }
    let mut k = 0;
    while k < max_steps && !sim.done() {
        sim.step()?;
        if let Some(w) = writer.as_deref_mut() {
            w.frame(sim)?;
        }
        k += 1;
    }
    Ok(k)
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
