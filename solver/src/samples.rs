//! Shared sample problems (published reference cases) reused by tests, benchmarks and examples.
