//! The benchmark workloads of docs/BENCHMARKS.md, defined once so that the native
//! benchmark and the wasm build under Node do exactly the same work.

pub mod apartment;
pub mod intel;
