//! Text: the classic functions (`strings.rs`), numbers as text and REGEX (`more.rs`), and
//! text cut at delimiters (`split.rs`).

pub(crate) mod more;
pub(crate) mod split;
pub(crate) mod strings;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[strings::FUNCTIONS, more::FUNCTIONS, split::FUNCTIONS];
