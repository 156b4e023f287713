//! ncsheet: a spreadsheet formula engine for CNC programming.
//!
//! Layers, each using only those before it: [`formula`] (grammar, syntax tree) →
//! [`eval`] (values, evaluator, functions) → [`workbook`] (cells, dependency graph,
//! recalculation) → [`io`] (csv, xlsx) and [`nc`] (NC programs) → `cli` (in the binary);
//! [`vba`] (macros) runs on a workbook and fills an [`nc`] program. [`geometry`] is pure and
//! stands apart; the evaluator registers it as sheet functions. See ARCHITECTURE.md.

pub mod document;
pub mod eval;
pub mod formula;
pub mod geometry;
pub mod io;
pub mod nc;
pub mod vba;
pub mod workbook;
