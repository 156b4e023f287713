//! File formats. Only this layer (and the CLI) touches files.

pub mod xlsx;
