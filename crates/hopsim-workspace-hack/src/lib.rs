//! Depends on the shared dependencies of the workspace with the union of the features
//! its crates enable, so that building any selection of crates (`cargo build`, `cargo
//! install`, `cargo test -p`) compiles each dependency once (docs/performance.md). Generated
//! by `cargo hakari generate`; checked in CI (`.ci/hakari`).
