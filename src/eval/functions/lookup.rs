//! lookup functions.

use super::FnSpec;

pub const FUNCTIONS: &[FnSpec] = &[];
