//! Replay recording, in the format of `docs/replay-format.md`.
//!
//! Frames are gathered by chunk, column by column, and each chunk is one zlib stream, so a
//! reader can fetch any stretch of a long run on its own. The file is written under a
//! temporary name and renamed when the run ends: a replay on disk is always whole.

use crate::error::{Error, Result};
use crate::fleet::robot::State;
use crate::output::codec::{Frames, BYTES_PER_ROBOT_STEP, MAGIC, VERSION};
use crate::record::events::EventKind;
use crate::record::frame::{Frame, FrameSink};
use crate::record::resources::{Bottleneck, QueueLog, ResourceUse};
use crate::rules::run::Run;
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

/// What a viewer needs before the first frame: the format, the run's own description
/// ([`Run::describe`]), the caller's `extra` fields (a scenario's text) and the code names.
/// The replay header, and the live viewer's meta.
#[must_use]
pub fn header(run: &dyn Run, extra: Value) -> Value {
    let mut h = json!({"format": "multibots-replay", "version": VERSION});
    for part in [run.describe(), extra, names()] {
        if let (Value::Object(h), Value::Object(part)) = (&mut h, part) {
            h.extend(part);
        }
    }
    h
}

/// Writes a replay while a run goes, under any rules: [`ReplayWriter::create`] before the
/// first step, then the run's frames ([`Run::advance`] with the writer as its sink), then
/// [`ReplayWriter::finish`]. Dropped unfinished, it leaves nothing behind.
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
    /// The last frame, which a step in which nothing happened repeats.
    last: Frame,
    /// The queues frame by frame, where the run reports resources (its footer's `queues`).
    queues: Option<QueueLog>,
}

impl ReplayWriter {
    /// Opens a replay of `run` at `path`, with `extra` header fields, and records frame 0
    /// (the run's state now).
    pub fn create(path: &Path, run: &dyn Run, extra: Value) -> Result<ReplayWriter> {
        let mut frame = Frame::default();
        run.emit(&mut frame, true);
        let mut rw = ReplayWriter::open(path, header(run, extra), frame.robots())?;
        rw.queues = run.queue_log();
        rw.frame(&frame)?;
        Ok(rw)
    }

    /// Opens a replay of `robots` robots with the header `h` (to which `chunk_steps` is
    /// added), and records no frame yet.
    fn open(path: &Path, mut h: Value, robots: usize) -> Result<ReplayWriter> {
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
            last: Frame::default(),
            queues: None,
        };
        // On an error the writer is dropped here, and its temporary file with it.
        written.map(|()| rw)
    }

    fn push(&mut self, with_events: bool) -> Result<()> {
        self.buf.push(&self.last, self.frames, with_events);
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

    /// Writes the last chunk and the footer (the run's [`Run::summary`]; where it reports
    /// resources, their use, the bottleneck and each one's queue frame by frame), and moves
    /// the file into place.
    pub fn finish(self, run: &dyn Run) -> Result<()> {
        let s = run.summary();
        let mut fields = json!({
            "T": s.t,
            "S": s.s,
            "C": s.c,
            "outcome": s.outcome,
            "delivered": s.delivered,
            "window": s.window,
            "windows": s.windows,
        });
        if let Some(log) = &self.queues {
            fields["resources"] = s.resources.iter().map(ResourceUse::to_json).collect();
            fields["bottleneck"] = s.bottleneck.as_ref().map_or(Value::Null, Bottleneck::to_json);
            fields["queues"] = log.to_json(&s.resources);
        }
        self.finish_with(fields)
    }

    /// Writes the last chunk and a footer of `fields` (an object: the indicators) with the
    /// frame count and the chunk table, and moves the file into place.
    fn finish_with(mut self, fields: Value) -> Result<()> {
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
            crate::input::files::replaceable(&self.path).map_err(|message| Error::Io { path: crate::error::shown(&display), message })?;
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

impl FrameSink for ReplayWriter {
    fn frame(&mut self, f: &Frame) -> Result<()> {
        if let (Some(log), Some(q)) = (&mut self.queues, &f.queues) {
            log.record(self.frames, q);
        }
        self.last.clone_from(f);
        self.push(true)
    }

    fn repeat(&mut self) -> Result<()> {
        self.push(false)
    }
}

/// Runs `run` to its end while recording it to `path` (with `extra` header fields).
pub fn run_recorded(run: &mut dyn Run, path: &Path, extra: Value) -> Result<()> {
    let mut w = ReplayWriter::create(path, run, extra)?;
    while !run.done() {
        run.advance(u64::MAX, Some(&mut w))?;
    }
    w.finish(run)
}
