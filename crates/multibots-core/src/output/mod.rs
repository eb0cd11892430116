//! What a run gives back: its events (`events`), its indicators T, S, C and the figures
//! beyond them (`metrics`, `docs/metrics.md`), how busy each resource was and the bottleneck
//! (`resources`), and recorded runs: the replay file
//! (`replay`; `grid_replay` for the League of Robot Runners' runs) and the byte layout of its
//! frames (`codec`, `docs/replay-format.md`).

pub mod codec;
pub(crate) mod events;
pub mod grid_replay;
pub mod lorr;
pub mod metrics;
pub mod replay;
pub mod resources;
