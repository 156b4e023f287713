//! Financial functions: annuities, cash flows, depreciation and rates (`cash_flows.rs`), and
//! the Analysis ToolPak's securities (`securities.rs`).

pub(crate) mod cash_flows;
pub(crate) mod securities;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[cash_flows::FUNCTIONS, securities::FUNCTIONS];
