//! Statistics: aggregates and the conditional ones (`aggregates.rs`), spread (`dispersion.rs`),
//! order statistics (`order.rs`), distributions (`distributions.rs`, over the numerics of
//! `special.rs`), samples and tests (`sample_stats.rs`), regression (`regression.rs`).

pub(crate) mod aggregates;
pub(crate) mod dispersion;
pub(crate) mod distributions;
pub(crate) mod order;
pub(crate) mod regression;
pub(crate) mod sample_stats;
pub(crate) mod special;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[
    aggregates::FUNCTIONS,
    dispersion::FUNCTIONS,
    distributions::FUNCTIONS,
    sample_stats::FUNCTIONS,
    regression::FUNCTIONS,
    order::FUNCTIONS,
];
