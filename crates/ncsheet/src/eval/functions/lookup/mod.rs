//! Lookup and reference: lookups and INDEX (`search.rs`), facts about the workbook and
//! SUBTOTAL (`reference.rs`), references made at run time (`dynamic_ref.rs`), the indexes a
//! lookup of many keys builds once (`key_index.rs`).

pub(crate) mod dynamic_ref;
pub(crate) mod key_index;
pub(crate) mod reference;
pub(crate) mod search;

use crate::eval::functions::api::FnSpec;

/// The family's rows, file by file.
pub(crate) const TABLES: &[&[FnSpec]] = &[search::FUNCTIONS, reference::FUNCTIONS, dynamic_ref::FUNCTIONS];
