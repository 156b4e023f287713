//! Pure geometry over nalgebra types: no workbook, no values, no files. The sheet functions
//! that expose it are registered in `eval/functions/geometry/`, and nowhere else.
//!
//! Units at every interface: millimetres and degrees; radians only inside.

use std::fmt;

pub mod ballpath;
pub mod cam;
pub mod chamfer;
pub(crate) mod dropcutter;
pub mod head;

/// Input that has no geometry. The message names the argument and says what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometryError {
    /// A number outside its domain (maps to `#NUM!`).
    OutOfRange(String),
    /// A word that is not one of the allowed ones (maps to `#VALUE!`).
    UnknownWord(String),
}

impl fmt::Display for GeometryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GeometryError::OutOfRange(m) | GeometryError::UnknownWord(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for GeometryError {}

/// Checks `ok`, else an out-of-range error with `message`.
pub(crate) fn ensure(ok: bool, message: impl FnOnce() -> String) -> Result<(), GeometryError> {
    if ok {
        Ok(())
    } else {
        Err(GeometryError::OutOfRange(message()))
    }
}
