//! Shared by the integration tests.

#![allow(dead_code)]

pub use multibots_core::scenario::PAPER_TASKS;
