//! The formula language: grammar binding, syntax tree, printing. Knows nothing of values,
//! workbooks or files.

pub mod address;
pub mod ast;
pub mod error;
pub mod limits;
pub(crate) mod locale_syntax;
pub mod parse;
pub mod print;
pub mod table_ref;

pub use address::{Pos, Rect};
pub use ast::{Expr, ExprKind};
pub use error::XlError;
pub use parse::{parse_formula, FunctionTable, ParseContext, ParseError};
