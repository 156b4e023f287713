//! `Range.RemoveDuplicates Columns:=…, Header:=…` ("Range.RemoveDuplicates method"): the
//! rows of the range whose cells in the key columns repeat an earlier row's are removed, the
//! first of each kept; the rows below them, inside the range only, move up, and the range's
//! last rows are left empty. Cells outside the range do not move.
//!
//! Two rows repeat when each key cell shows the same text, ignoring case: Excel compares
//! "what appears in the cell, not the underlying value" (Microsoft's "Filter for unique
//! values or remove duplicate values": the same date shown as 3/8/2006 and Mar 8, 2006 is
//! two values), and its duplicates ignore case (Apple and APPLE are one).

use std::collections::HashSet;

use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;

use super::ast::Link;
use super::interp::{Interp, Run};
use super::sheet_ops::argument;
use super::value::Obj;

/// XlYesNoGuess ("XlYesNoGuess enumeration"): xlGuess 0, xlYes 1, xlNo 2.
const XL_GUESS: f64 = 0.0;
const XL_YES: f64 = 1.0;
const XL_NO: f64 = 2.0;

impl Interp<'_, '_> {
    pub(super) fn remove_duplicates(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        let rect = ctx.clip_to_used(sheet, rect);
        let keys = self.duplicate_key_columns(ctx, rect, link)?;
        let header = match argument(link, 1, "header") {
            None => false,
            Some(e) => {
                let v = ctx.eval(e).unwrap_single();
                self.take_pending()?;
                match self.number_of(&v, "RemoveDuplicates's Header") {
                    Ok(XL_YES) => true,
                    Ok(XL_NO) => false,
                    // The same guess as Range.Sort's (`sort.rs`): a text over a non-text.
                    Ok(XL_GUESS) => self.guess_header(sheet, rect, keys[0]),
                    _ => {
                        return Err(
                            self.error_1004(link.span, "RemoveDuplicates: Header is xlYes, xlNo or xlGuess".into())
                        )
                    }
                }
            }
        };
        let first = rect.first.row + u32::from(header);
        if first > rect.last.row {
            return Ok(Obj::Value(Value::Blank));
        }
        let mut seen = HashSet::new();
        let mut kept = Vec::new();
        for (i, row) in (first..=rect.last.row).enumerate() {
            let key: Vec<String> =
                keys.iter().map(|&c| self.shown_text(ctx, sheet, Pos::new(row, c)).to_uppercase()).collect();
            if seen.insert(key) {
                kept.push(Some(i));
            }
        }
        let rows = (rect.last.row - first + 1) as usize;
        kept.resize(rows, None);
        self.rearrange_rows(sheet, first, (rect.first.col, rect.last.col), &kept, link)?;
        Ok(Obj::Value(Value::Blank))
    }

    /// The sheet columns `Columns:=` names, counted from the range's first column: one
    /// number or an array of them; every column of the range when it is left out (as
    /// Excel 2007's page has it). A column outside the range is Excel's run-time error 1004.
    fn duplicate_key_columns(&self, ctx: &mut Ctx, rect: Rect, link: &Link) -> Run<Vec<u32>> {
        let Some(e) = argument(link, 0, "columns") else {
            return Ok((rect.first.col..=rect.last.col).collect());
        };
        let v = ctx.eval(e);
        self.take_pending()?;
        let given: Vec<Value> = match v {
            Value::Array(a) => a.data.to_vec(),
            v => vec![v],
        };
        let mut columns = Vec::with_capacity(given.len());
        for g in &given {
            let n = self.number_of(g, "a column of RemoveDuplicates").map_err(|m| self.fault_at(link.span, m))?;
            let n = n.round_ties_even();
            if n < 1.0 || n > f64::from(rect.cols()) {
                let why = format!("RemoveDuplicates: column {n} is not one of the range's {} columns", rect.cols());
                return Err(self.error_1004(link.span, why));
            }
            columns.push(rect.first.col + n as u32 - 1);
        }
        if columns.is_empty() {
            return Err(self.error_1004(link.span, "RemoveDuplicates: Columns names no column".into()));
        }
        Ok(columns)
    }
}
