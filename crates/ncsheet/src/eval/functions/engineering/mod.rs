//! Engineering: base conversions, bits, DELTA, GESTEP, ERF (`bases.rs`), CONVERT's unit
//! table (`convert.rs`), Bessel functions (`bessel.rs`), complex numbers (`complex.rs`).

pub(crate) mod bases;
pub(crate) mod bessel;
pub(crate) mod complex;
pub(crate) mod convert;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[bases::FUNCTIONS, convert::FUNCTIONS, bessel::FUNCTIONS, complex::FUNCTIONS];
