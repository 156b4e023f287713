//! Evaluation: values, coercions, the evaluator and the function table. Reads cells only
//! through the [`Env`] trait; knows nothing of workbooks, files or the command line.

pub(crate) mod coerce;
pub mod dates;
pub(crate) mod diff;
pub mod evaluator;
pub mod format;
pub mod functions;
pub mod locale;
pub mod regex_limits;
pub mod settings;
pub mod surface;
#[cfg(any(test, feature = "testing"))]
pub mod testing;
pub mod value;

pub use evaluator::{CallFrame, Ctx, Env, Note, Operand, RowHidden, UserCall, WorkDone};
pub use locale::Locale;
pub use settings::{FunctionLimits, Settings};
pub use value::{too_many_items, too_many_items_note, Array, Value, XlError, XlResult, MAX_ARRAY_ITEMS};
