//! ncsheet: a spreadsheet formula engine for CNC programming.
//!
//! Layers, each using only those before it: [`formula`] (grammar, syntax tree) →
//! [`eval`] (values, evaluator, functions) → [`workbook`] (cells, dependency graph,
//! recalculation) → [`io`] (csv, xlsx) → `cli` (in the binary). See ARCHITECTURE.md.

pub mod eval;
pub mod formula;
pub mod geometry;
pub mod io;
pub mod workbook;
