//! What a function body needs of the evaluator, in one place: the evaluation context and its
//! operands, the value types, the argument helpers (`args.rs`, `scalar.rs`) and the row types
//! of the table. The families import this, never `evaluator.rs`: the evaluator may change
//! inside without touching the library, and the only circle left is the registry's own (the
//! evaluator calls a body through its `FnSpec`, the body evaluates its arguments through `Ctx`).

pub use super::args::*;
pub use super::scalar::*;
pub use super::{find, ArgSet, FnSpec, Outside, Registry, Searched, MANY};
pub use crate::eval::evaluator::{
    bind_own_name, broadcast2, broadcast_whole, comparison_holds, number_result, power, Ctx, Env, Operand, RowHidden,
};
