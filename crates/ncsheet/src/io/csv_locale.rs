//! Formulas in a `;`-separated csv, as a spreadsheet whose locale writes decimal commas types
//! them: the separator swap is the formula layer's (`formula::locale_syntax`), shared with
//! what a user types in such a locale (`eval::locale`).

pub use crate::formula::locale_syntax::{from_semicolon_locale, to_semicolon_locale};
