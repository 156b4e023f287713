//! How values are shown as text: a number as a cell shows it in General (`number_format.rs`:
//! 15 significant digits) and Excel's number-format language as TEXT, FIXED and VBA's Format
//! apply it (`text_format.rs`).

pub mod cell_style;
pub mod number_format;
pub(crate) mod text_format;
