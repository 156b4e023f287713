//! Helpers shared by integration tests.

#![allow(dead_code)]

pub mod cli;
pub mod corpus;
pub mod excel_oracle;
pub mod fuzz;
pub mod locale;
pub mod openpyxl;
pub mod rs274;
pub mod sheet;
pub mod vba;
pub mod xlsx;

#[allow(unused_imports)]
pub use xlsx::*;
