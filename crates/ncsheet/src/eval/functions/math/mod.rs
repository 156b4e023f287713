//! Math and trigonometry (`basic.rs`), counting, number theory and matrices
//! (`combinatorics.rs`), random numbers (`random.rs`).

pub(crate) mod basic;
pub(crate) mod combinatorics;
pub(crate) mod random;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[basic::FUNCTIONS, combinatorics::FUNCTIONS, random::FUNCTIONS];
