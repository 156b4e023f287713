//! Excel 365's dynamic arrays that reshape and select (`reshape.rs`).

pub(crate) mod reshape;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[reshape::FUNCTIONS];
