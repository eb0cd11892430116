//! The engine's criterion benchmarks live in `benches/step.rs`; this crate exists so that
//! `make test` never compiles criterion (a dev-dependency of every test target of the crate
//! that declares it).
