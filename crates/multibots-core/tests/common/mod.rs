//! Shared by the integration tests.

#![allow(dead_code)]

pub use multibots_core::input::scenario::PAPER_TASKS;
