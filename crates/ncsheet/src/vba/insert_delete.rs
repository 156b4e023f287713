//! `Range.Delete` and `Range.Insert` (and so `Rows(5).Delete`, `EntireRow.Insert`,
//! `Columns("B").Delete`): the workbook's shift-cells edit (`workbook/shift.rs`), with every
//! formula's references following the cells, as Excel's do.

use std::collections::HashSet;
use std::rc::Rc;

use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::SheetId;
use crate::workbook::{Axis, SheetEdit};

use super::ast::Link;
use super::interp::{one_line, Interp, Run};
use super::sheet_ops::argument;
use super::value::{Obj, Slot, Var};

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
        self.charge_shift();
        // An edit Excel refuses (cutting an array, pushing cells off the sheet) is its
        // run-time error 1004, "Insert method of Range class failed", which On Error traps.
        self.book_mut()?.shift_cells(sheet, edit).map_err(|e| {
            self.error_1004(link.span, format!("{member} method of Range class failed: {}", one_line(&e)))
        })?;
        self.looks.borrow_mut().follow(sheet, &edit);
        self.follow_range_objects(sheet, &edit);
        self.follow_selection(sheet, &edit);
        Ok(Obj::Value(Value::Blank))
    }

    /// Counts an insert or delete against the statement limit by the cells it goes over:
    /// the workbook's shift reads every cell and rebuilds the graph (`workbook/shift.rs`),
    /// an item of work a cell and a statement a formula, so `Rows(1).Insert` in a loop over
    /// a filled sheet, which ran for minutes counting a statement a turn, stops within the
    /// time the limit stands for.
    fn charge_shift(&self) {
        let (cells, formulas) = {
            let wb = self.wb.borrow();
            (wb.cell_count(), wb.formula_counts().0)
        };
        self.add_work(cells as u64 + formulas as u64 * super::interp::WORK_PER_STATEMENT);
    }

    /// The sheet's `Selection` and `ActiveCell` moved with their cells, as Excel's selection
    /// is: select B1, insert column A, and C1 is selected. Cells the edit deleted leave the
    /// selection where it was (what moved into the place is selected).
    fn follow_selection(&self, sheet: SheetId, edit: &SheetEdit) {
        let (selection, active) = self.cursor(sheet);
        let moved = |rect: Rect| edit.moved_rect(rect).unwrap_or(rect);
        let cursor = (moved(selection), moved(Rect::cell(active)).first);
        self.cursors.borrow_mut().insert(sheet, cursor);
        if let Some(areas) = self.selected_areas.borrow_mut().get_mut(&sheet) {
            *areas = areas.iter().map(|&r| moved(r)).collect();
        }
    }

    /// Every Range object the macro holds on `sheet` (in its variables, Static ones, With
    /// blocks, arrays, Types, Collections, Dictionaries and class objects) moved with its
    /// cells, as Excel's do: `Set r = Range("B5")`, then `Rows(2).Insert`, and `r` is B6; one
    /// whose cells were all deleted is gone (error 424 when used).
    fn follow_range_objects(&self, sheet: SheetId, edit: &SheetEdit) {
        let mut follow = Follow { sheet, edit, seen: HashSet::new(), shared: Vec::new() };
        for slots in self.globals.borrow_mut().iter_mut() {
            slots.iter_mut().for_each(|slot| follow.slot(slot));
        }
        for frame in self.frames.borrow_mut().iter_mut() {
            frame.vars.iter_mut().for_each(|slot| follow.slot(slot));
            frame.with_objects().for_each(|obj| follow.obj(obj));
            if let Some(me) = &frame.me {
                follow.obj(&mut Obj::Instance(me.clone()));
            }
        }
        for slot in self.kept.borrow_mut().values_mut().flatten() {
            follow.slot(slot);
        }
        follow.shared_objects();
    }
}

/// A walk over what the macro holds, moving Range objects through one edit of `sheet`.
struct Follow<'e> {
    sheet: SheetId,
    edit: &'e SheetEdit,
    /// The Collections, Dictionaries and class objects met, by address: each is walked once,
    /// however many variables hold it.
    seen: HashSet<*const ()>,
    /// Those met and not walked yet: walked one after another, not inside the one holding
    /// them, so a long chain of them does not take the native stack.
    shared: Vec<Obj>,
}

impl Follow<'_> {
    fn slot(&mut self, slot: &mut Slot) {
        let may_hold_objects = match slot.var() {
            Var::Value(_) => false,
            Var::Array(a) => a.objects.is_some() || a.records.is_some() || a.arrays.is_some(),
            Var::Obj(_) | Var::Record(..) => true,
        };
        if may_hold_objects {
            self.var_tree(slot.var_mut());
        }
    }

    /// `var` and what it holds: arrays' items, Types' fields (an explicit stack: no recursion).
    fn var_tree(&mut self, var: &mut Var) {
        let mut pending = vec![var];
        while let Some(var) = pending.pop() {
            match var {
                Var::Value(_) => {}
                Var::Obj(obj) => self.obj(obj),
                Var::Record(_, fields) => pending.extend(fields.iter_mut()),
                Var::Array(a) => {
                    if let Some(objects) = &mut a.objects {
                        Rc::make_mut(objects).values_mut().for_each(|obj| self.obj(obj));
                    }
                    if let Some(records) = &mut a.records {
                        pending.extend(Rc::make_mut(records).iter_mut());
                    }
                    if let Some(arrays) = &mut a.arrays {
                        for inner in Rc::make_mut(arrays).values_mut() {
                            if let Some(objects) = &mut inner.objects {
                                Rc::make_mut(objects).values_mut().for_each(|obj| self.obj(obj));
                            }
                            if let Some(records) = &mut inner.records {
                                pending.extend(Rc::make_mut(records).iter_mut());
                            }
                        }
                    }
                }
            }
        }
    }

    fn obj(&mut self, obj: &mut Obj) {
        match obj {
            Obj::Range(s, rect) | Obj::Lines(s, rect, _) | Obj::Look(s, rect, _) if *s == self.sheet => {
                match self.edit.moved_rect(*rect) {
                    Some(moved) => *rect = moved,
                    None => *obj = Obj::DeletedRange(self.sheet),
                }
            }
            Obj::Areas(s, areas) if *s == self.sheet => {
                // Each area moves with its cells; an area whose cells were deleted is gone.
                let moved: Vec<Rect> = areas.iter().filter_map(|a| self.edit.moved_rect(*a)).collect();
                *obj = match moved.is_empty() {
                    true => Obj::DeletedRange(self.sheet),
                    false => super::areas::range_of(self.sheet, moved),
                };
            }
            Obj::Store(h) if self.seen.insert(Rc::as_ptr(&h.0) as *const ()) => self.shared.push(obj.clone()),
            Obj::Instance(o) if self.seen.insert(Rc::as_ptr(&o.0) as *const ()) => self.shared.push(obj.clone()),
            _ => {}
        }
    }

    /// The Collections, Dictionaries and class objects met, and those they hold in turn.
    fn shared_objects(&mut self) {
        while let Some(obj) = self.shared.pop() {
            match obj {
                Obj::Store(h) => h.0.borrow_mut().items_mut().for_each(|item| self.var_tree(item)),
                Obj::Instance(o) => o.0.fields.borrow_mut().iter_mut().for_each(|slot| self.slot(slot)),
                _ => {}
            }
        }
    }
}
