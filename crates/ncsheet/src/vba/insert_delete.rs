//! `Range.Delete` and `Range.Insert` (and so `Rows(5).Delete`, `EntireRow.Insert`,
//! `Columns("B").Delete`): the workbook's shift-cells edit (`workbook/shift.rs`), with every
//! formula's references following the cells, as Excel's do.

use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::SheetId;
use crate::workbook::{Axis, SheetEdit};

use super::ast::Link;
use super::interp::{one_line, Interp, Run};
use super::sheet_ops::argument;
use super::value::Obj;

/// `XlDeleteShiftDirection` and `XlInsertShiftDirection`: `xlShiftUp` (-4162) and
/// `xlShiftToLeft` (-4159) for Delete, `xlShiftDown` (-4121) and `xlShiftToRight` (-4161)
/// for Insert.
fn shift_axis(code: i64, insert: bool) -> Option<Axis> {
    match (code, insert) {
        (-4162, false) | (-4121, true) => Some(Axis::Rows),
        (-4159, false) | (-4161, true) => Some(Axis::Columns),
        _ => None,
    }
}

/// The whole rows of `rect` (`EntireRow`).
pub(super) fn entire_rows(rect: Rect) -> Rect {
    Rect::new(Pos::new(rect.first.row, 0), Pos::new(rect.last.row, MAX_COLS - 1))
}

/// The whole columns of `rect` (`EntireColumn`).
pub(super) fn entire_columns(rect: Rect) -> Rect {
    Rect::new(Pos::new(0, rect.first.col), Pos::new(MAX_ROWS - 1, rect.last.col))
}

impl Interp<'_, '_> {
    /// `r.Delete [Shift]` (`insert` false) or `r.Insert [Shift] [CopyOrigin]`. Whole rows or
    /// columns go or come whole; a rectangle's cells shift the way `Shift` says or, without
    /// it, "Excel decides based on the shape of the range" (Microsoft's Range.Delete and
    /// Range.Insert pages): up (down) unless the range is taller than wide.
    pub(super) fn insert_or_delete(
        &self,
        ctx: &mut Ctx,
        sheet: SheetId,
        rect: Rect,
        insert: bool,
        link: &Link,
    ) -> Run<Obj> {
        let member = if insert { "Insert" } else { "Delete" };
        let whole_rows = rect.cols() == MAX_COLS;
        let whole_columns = rect.rows() == MAX_ROWS;
        let axis = match argument(link, 0, "shift") {
            _ if whole_rows => Axis::Rows,
            _ if whole_columns => Axis::Columns,
            Some(expr) => {
                let v = ctx.eval(expr).unwrap_single();
                self.take_pending()?;
                let what = format!("{member}'s Shift");
                let code = self.number_of(&v, &what).map_err(|m| self.fault_at(link.span, m))?;
                shift_axis(code as i64, insert).ok_or_else(|| {
                    let names = if insert { "xlShiftDown or xlShiftToRight" } else { "xlShiftUp or xlShiftToLeft" };
                    self.fault_at(link.span, format!("{what} is {code}: it takes {names}"))
                })?
            }
            None if rect.rows() > rect.cols() => Axis::Columns,
            None => Axis::Rows,
        };
        let edit = SheetEdit::cells(rect, axis, insert);
        // An edit Excel refuses (cutting an array, pushing cells off the sheet) is its
        // run-time error 1004, "Insert method of Range class failed", which On Error traps.
        self.book_mut()?.shift_cells(sheet, edit).map_err(|e| {
            self.error_1004(link.span, format!("{member} method of Range class failed: {}", one_line(&e)))
        })?;
        self.looks.borrow_mut().follow(sheet, &edit);
        Ok(Obj::Value(Value::Blank))
    }
}
