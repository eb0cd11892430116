//! The engine's integration tests, one binary (one link, not one per file): each module is
//! what was a test file of its own, and `common` what they share.

mod common;

mod allocators;
mod bottleneck;
mod charging;
mod collision_grid;
mod contacts;
mod grid_replay;
mod layers;
mod layouts;
mod lifelong;
mod limits;
mod lorr26_delays;
mod lorr26_model;
mod lorr26_runs;
mod original_rules;
mod outcomes;
mod paper_model;
mod people;
mod schema;
mod traffic;
