//! What a run records as it goes, below the rules that write it and the outputs that read
//! it: its events (`events`), its tallies and indicators T, S, C with the figures beyond
//! them (`metrics`, `docs/metrics.md`), how busy each resource was and the bottleneck
//! (`resources`), the League of Robot Runners' action record (`grid`; the 2026 rules' ticks,
//! delays and messages in `grid26`), and the frame a run
//! emits of its state after a step (`frame`), which replays and viewers read.

pub(crate) mod events;
pub mod frame;
pub mod grid;
pub mod grid26;
pub mod metrics;
pub mod resources;
