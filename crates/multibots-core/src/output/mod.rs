//! What a run is written to, read from what the run records (`crate::record`) and the
//! frames it emits through the run contract (`crate::rules::Run`): replay files
//! (`replay`, one recorder for every rule set) and the byte layout of their frames
//! (`codec`, `docs/replay-format.md`), and the League of Robot Runners' result file with
//! MultiBots' figures beside it (`lorr`; under the 2026 rules `lorr26`).

pub mod codec;
pub mod lorr;
pub mod lorr26;
pub mod replay;
