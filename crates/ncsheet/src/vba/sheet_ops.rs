//! What a recorded macro does with the keyboard and the clipboard: `Range.End` (Ctrl+arrow),
//! `Range.Copy` and `PasteSpecial`, a sheet's `Visible`, and adding, copying, moving and
//! renaming sheets (`Sheets.Add`, `ws.Copy`, `ws.Move`, `ws.Name =`), and protecting them
//! (`ws.Protect`, `ws.Unprotect`).

use std::rc::Rc;

use crate::eval::{Ctx, Operand, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::SheetId;
use crate::workbook::{Visibility, WorkbookError, MAX_SHEETS};

use super::ast::{Link, Span};
use super::interp::{Fault, Interp, Run};
use super::value::{print_text, Obj, Var};

/// Excel's `XlDirection`: where `Range.End` moves.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Direction {
    Up,
    Down,
    Left,
    Right,
}

impl Direction {
    /// `xlUp` (-4162), `xlDown` (-4121), `xlToLeft` (-4159), `xlToRight` (-4161).
    pub fn of(code: i64) -> Option<Direction> {
        match code {
            -4162 => Some(Direction::Up),
            -4121 => Some(Direction::Down),
            -4159 => Some(Direction::Left),
            -4161 => Some(Direction::Right),
            _ => None,
        }
    }

    /// The next cell from `p` this way, `None` at the sheet's edge.
    fn step(self, p: Pos) -> Option<Pos> {
        match self {
            Direction::Up => p.row.checked_sub(1).map(|r| Pos::new(r, p.col)),
            Direction::Down => (p.row + 1 < MAX_ROWS).then(|| Pos::new(p.row + 1, p.col)),
            Direction::Left => p.col.checked_sub(1).map(|c| Pos::new(p.row, c)),
            Direction::Right => (p.col + 1 < MAX_COLS).then(|| Pos::new(p.row, p.col + 1)),
        }
    }

    /// The last cell of the sheet this way from `p`.
    fn edge(self, p: Pos) -> Pos {
        match self {
            Direction::Up => Pos::new(0, p.col),
            Direction::Down => Pos::new(MAX_ROWS - 1, p.col),
            Direction::Left => Pos::new(p.row, 0),
            Direction::Right => Pos::new(p.row, MAX_COLS - 1),
        }
    }

    /// From `p`, outside the used area `used`, the first cell that may be filled this way
    /// (on the used area's border), or `None` when every cell left this way is empty.
    fn into_used(self, p: Pos, used: Rect) -> Option<Pos> {
        let (rows, cols) = (used.first.row..=used.last.row, used.first.col..=used.last.col);
        match self {
            Direction::Up | Direction::Down if !cols.contains(&p.col) => None,
            Direction::Left | Direction::Right if !rows.contains(&p.row) => None,
            Direction::Up if p.row > used.last.row => Some(Pos::new(used.last.row, p.col)),
            Direction::Down if p.row < used.first.row => Some(Pos::new(used.first.row, p.col)),
            Direction::Left if p.col > used.last.col => Some(Pos::new(p.row, used.last.col)),
            Direction::Right if p.col < used.first.col => Some(Pos::new(p.row, used.first.col)),
            _ if used.contains(p) => Some(p),
            _ => None,
        }
    }
}

impl Interp<'_, '_> {
    /// `Range.End(direction)` from `from`, as Ctrl+arrow moves: from a filled cell whose
    /// neighbour is filled, to the last filled cell of that run; otherwise to the next
    /// filled cell, or the sheet's edge when there is none. A formula showing "" is filled.
    /// Each cell it reads counts as an item of work against the statement limit: a run of
    /// 100,000 filled cells is 100,000 reads, and `End(xlDown)` in a loop over it ran for
    /// minutes counting a statement a turn.
    pub(super) fn end(&self, sheet: SheetId, from: Pos, direction: Direction) -> Pos {
        let read = std::cell::Cell::new(0u64);
        let found = self.end_reading(sheet, from, direction, &read);
        self.add_work(read.get());
        found
    }

    /// [`Interp::end`], counting the cells read in `read`.
    fn end_reading(&self, sheet: SheetId, from: Pos, direction: Direction, read: &std::cell::Cell<u64>) -> Pos {
        let Some(next) = direction.step(from) else { return from };
        let wb = self.wb.borrow();
        let Some(used) = wb.used_rect(sheet) else { return direction.edge(from) };
        let filled = |p: Pos| {
            read.set(read.get() + 1);
            used.contains(p)
                && (wb.formula_id(sheet, p).is_some() || !matches!(wb.value(sheet, p), crate::eval::Value::Blank))
        };
        if filled(from) && filled(next) {
            let mut last = next;
            while let Some(p) = direction.step(last).filter(|&p| filled(p)) {
                last = p;
            }
            return last;
        }
        let mut p = next;
        loop {
            match direction.into_used(p, used) {
                None => return direction.edge(from),
                Some(q) if filled(q) => return q,
                Some(q) => match direction.step(q) {
                    Some(n) => p = n,
                    None => return q,
                },
            }
        }
    }
}

/// `ws.Visible` as VBA reads it: `xlSheetVisible` (-1, which is True), `xlSheetHidden` (0,
/// False) or `xlSheetVeryHidden` (2).
pub fn visibility_value(v: Visibility) -> Value {
    Value::Number(match v {
        Visibility::Visible => -1.0,
        Visibility::Hidden => 0.0,
        Visibility::VeryHidden => 2.0,
    })
}

fn visibility_of(v: &Value) -> Option<Visibility> {
    match v {
        Value::Bool(true) => Some(Visibility::Visible),
        Value::Bool(false) => Some(Visibility::Hidden),
        Value::Number(n) if *n == -1.0 => Some(Visibility::Visible),
        Value::Number(n) if *n == 0.0 => Some(Visibility::Hidden),
        Value::Number(n) if *n == 2.0 => Some(Visibility::VeryHidden),
        _ => None,
    }
}

impl Interp<'_, '_> {
    /// `ws.Visible = v`. As in Excel, the last visible sheet cannot be hidden.
    pub(super) fn set_visible(&self, sheet: SheetId, v: &Value, span: Span) -> Run<()> {
        let Some(visibility) = visibility_of(v) else {
            return Err(
                self.fault_at(span, "Visible takes True, False, xlSheetVisible, xlSheetHidden or xlSheetVeryHidden")
            );
        };
        let mut wb = self.book_mut()?;
        let others_shown = wb.tab_order().iter().any(|&s| s != sheet && wb.sheet_visibility(s) == Visibility::Visible);
        if visibility != Visibility::Visible && !others_shown {
            return Err(self.fault_at(span, "Visible: a workbook keeps at least one sheet visible"));
        }
        wb.set_sheet_visibility(sheet, visibility);
        Ok(())
    }

    /// Excel's run-time error 1004 for selecting on a hidden sheet: "`Select` method of
    /// `Range` class failed".
    pub(super) fn refuse_hidden(&self, sheet: SheetId, method: &str, class: &str, span: Span) -> Run<()> {
        if self.wb.borrow().sheet_visibility(sheet) == Visibility::Visible {
            return Ok(());
        }
        let name = self.wb.borrow().sheet_names()[sheet as usize].clone();
        let mut fault = self.fault_at(
            span,
            format!(
                "{method} method of {class} class failed (run-time error 1004): {name} is hidden; set its Visible \
                 to True first"
            ),
        );
        fault.code = 1004;
        Err(fault)
    }

    /// `r.Select` or `r.Activate` of a range on a sheet other than the active one: "Select
    /// works only on the active worksheet. If you run your Sub procedure from the module, the
    /// Select method will fail unless your procedure activates the worksheet before using the
    /// Select method on a range of cells" ("Selecting and Activating Cells"), run-time error
    /// 1004, where the other sheet was made active.
    pub(super) fn refuse_inactive(&self, sheet: SheetId, method: &str, span: Span) -> Run<()> {
        if sheet == self.active.get() {
            return Ok(());
        }
        let name = self.wb.borrow().sheet_names()[sheet as usize].clone();
        let why = format!("{method} method of Range class failed: {name} is not the active sheet; activate it first");
        Err(self.error_1004(span, why))
    }

    /// `ws.Delete` ("Worksheet.Delete method"): the sheet goes, references to it become
    /// `#REF!` (`workbook/delete_sheet.rs`). No dialog asks (a run has no user, as with
    /// `DisplayAlerts = False`), so it returns True, the page's value for "the user chose
    /// Delete". The last visible sheet is run-time error 1004, as in Excel. When the sheet
    /// was the active one, the visible sheet to its right (else left) becomes active.
    pub(super) fn delete_sheet(&self, sheet: SheetId, span: Span) -> Run<Obj> {
        let mut wb = self.book_mut()?;
        // The run's active sheet, not the file's, is the one Excel would move away from.
        let file_active = wb.active_sheet();
        wb.set_active_sheet(self.active.get());
        let deleted = wb.delete_sheet(sheet);
        self.active.set(wb.active_sheet());
        if file_active != sheet {
            wb.set_active_sheet(file_active);
        }
        drop(wb);
        deleted.map_err(|e| self.error_1004(span, format!("Delete method of Worksheet class failed: {e}")))?;
        Ok(Obj::Value(Value::Bool(true)))
    }

    /// `obj` itself, unless it is a sheet, or cells of a sheet, that was deleted: Excel's
    /// object is gone then, and using it is an error (ids are never reused, so it could
    /// not reach another sheet's cells; this says why nothing is there).
    pub(super) fn alive(&self, obj: Obj, span: Span) -> Run<Obj> {
        let sheet = match &obj {
            Obj::Sheet(s)
            | Obj::Range(s, _)
            | Obj::Areas(s, _)
            | Obj::AreaList(s, _)
            | Obj::Lines(s, ..)
            | Obj::Look(s, ..)
            | Obj::DeletedRange(s) => *s,
            _ => return Ok(obj),
        };
        let wb = self.wb.borrow();
        let cells_deleted = matches!(obj, Obj::DeletedRange(_));
        if !cells_deleted && !wb.sheet_deleted(sheet) {
            return Ok(obj);
        }
        let why = match cells_deleted {
            // Insert/Delete moved every other Range the macro holds (`insert_delete.rs`).
            true => format!("{} on sheet '{}' (Delete took them)", obj.describe(), wb.sheet_names()[sheet as usize]),
            false => format!("{} of sheet '{}', which was deleted", obj.describe(), wb.sheet_names()[sheet as usize]),
        };
        let mut fault = self.fault_at(span, crate::eval::functions::vba::errors::message(424, why));
        fault.code = 424;
        Err(fault)
    }

    /// `ws.Select`: Excel refuses to select a hidden sheet (run-time error 1004).
    pub(super) fn select_sheet(&self, sheet: SheetId, span: Span) -> Run<()> {
        self.refuse_hidden(sheet, "Select", "Worksheet", span)?;
        self.active.set(sheet);
        Ok(())
    }
}

/// What `PasteSpecial` pastes: everything a cell holds (its formula or constant), or only
/// the values the cells show.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Paste {
    Inputs,
    Values,
}

/// The most cells one Copy or PasteSpecial writes.
const MAX_PASTE: u64 = 10_000_000;

/// Where a copy of `source`'s size lands at `dest`: a one-cell destination (or one whose
/// size is not a multiple of the source's) takes the source's size from its top-left cell,
/// as Excel pastes; a multiple repeats the source over it.
fn paste_area(source: Rect, dest: Rect) -> Option<Rect> {
    let tiles = dest.rows().is_multiple_of(source.rows()) && dest.cols().is_multiple_of(source.cols());
    if tiles && !dest.is_cell() {
        return Some(dest);
    }
    let last = Pos::new(dest.first.row + source.rows() - 1, dest.first.col + source.cols() - 1);
    (last.row < MAX_ROWS && last.col < MAX_COLS).then(|| Rect::new(dest.first, last))
}

/// The argument named `name` (`Paste:=…`), or else the one at `position`.
pub(super) fn argument<'l>(link: &'l Link, position: usize, name: &str) -> Option<&'l crate::formula::ast::Expr> {
    let args = link.args.as_deref()?;
    let named = args.iter().find(|a| a.name.as_deref().is_some_and(|n| n.eq_ignore_ascii_case(name)));
    let arg = named.or_else(|| args.get(position).filter(|a| a.name.is_none()))?;
    (!matches!(arg.value.kind, crate::formula::ast::ExprKind::Missing)).then_some(&arg.value)
}

impl Interp<'_, '_> {
    /// `r.Copy` (onto the clipboard, for a later `PasteSpecial`) or `r.Copy Destination`
    /// (pasted at once, formulas and constants).
    pub(super) fn copy(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<()> {
        let Some(expr) = argument(link, 0, "destination") else {
            *self.clipboard.borrow_mut() = Some((sheet, rect));
            return Ok(());
        };
        let dest = ctx.operand(expr);
        self.take_pending()?;
        match dest {
            Operand::Ref(to, area) => self.paste((sheet, rect), (to, area), Paste::Inputs, true, link.span),
            _ => Err(self.fault_at(link.span, "Copy: the destination is not a range")),
        }
    }

    /// `u.Copy Destination:=r` of a Range of several areas ("Range.Copy method"): Excel copies
    /// areas that share their columns (whole rows collected with Union) or their rows as one
    /// block, one under another (or side by side) in the sheet's order, and pastes the block
    /// at the destination; areas sharing neither are its "This action won't work on multiple
    /// selections", run-time error 1004. Onto the clipboard (no Destination), or onto a block
    /// overlapping the areas, it is refused by name: ncsheet's clipboard holds one range.
    #[inline(never)]
    pub(super) fn copy_areas(&self, ctx: &mut Ctx, sheet: SheetId, areas: &[Rect], link: &Link) -> Run<()> {
        let first = areas[0];
        let stacked = areas.iter().all(|a| (a.first.col, a.last.col) == (first.first.col, first.last.col));
        let side_by_side = areas.iter().all(|a| (a.first.row, a.last.row) == (first.first.row, first.last.row));
        if !stacked && !side_by_side {
            let why = format!(
                "Copy method of Range class failed: this action won't work on multiple selections ({} areas in \
                 neither the same columns nor the same rows); copy each area (For Each a In r.Areas)",
                areas.len()
            );
            return Err(self.error_1004(link.span, why));
        }
        let Some(expr) = argument(link, 0, "destination") else {
            let why = "Copy of a Range of several areas onto the clipboard: ncsheet's clipboard holds one range; \
                       give the place (u.Copy Destination:=r)";
            return Err(self.unsupported(link.span, why));
        };
        let Operand::Ref(to, dest) = ctx.operand(expr) else {
            return Err(self.fault_at(link.span, "Copy: the destination is not a range"));
        };
        self.take_pending()?;
        let mut order = areas.to_vec();
        order.sort_by_key(|a| if stacked { (a.first.row, a.first.col) } else { (a.first.col, a.first.row) });
        let (rows, cols) = match stacked {
            true => (order.iter().map(|a| a.rows()).sum::<u32>(), first.cols()),
            false => (first.rows(), order.iter().map(|a| a.cols()).sum::<u32>()),
        };
        let block = Rect::new(
            dest.first,
            Pos::new(dest.first.row.saturating_add(rows - 1), dest.first.col.saturating_add(cols - 1)),
        );
        let meets = |a: &Rect| {
            a.first.row <= block.last.row
                && block.first.row <= a.last.row
                && a.first.col <= block.last.col
                && block.first.col <= a.last.col
        };
        if to == sheet && order.iter().any(meets) {
            let why = "Copy of a Range of several areas onto cells among them: ncsheet pastes such areas one by one; \
                       copy to a place apart from them";
            return Err(self.unsupported(link.span, why));
        }
        let mut at = dest.first;
        for a in order {
            self.paste((sheet, a), (to, Rect::cell(at)), Paste::Inputs, true, link.span)?;
            match stacked {
                true => at.row = at.row.saturating_add(a.rows()),
                false => at.col = at.col.saturating_add(a.cols()),
            }
        }
        Ok(())
    }

    /// `r.PasteSpecial Paste:=xlPasteValues` (or `xlPasteAll`, `xlPasteFormulas`): what the
    /// last `Copy` put on the clipboard, pasted at `r`.
    pub(super) fn paste_special(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<()> {
        let Some(source) = *self.clipboard.borrow() else {
            return Err(self.fault_at(link.span, "PasteSpecial: nothing was copied (Copy a range first)"));
        };
        let code = match argument(link, 0, "paste") {
            None => -4104.0,
            Some(expr) => {
                let v = ctx.eval(expr).unwrap_single();
                self.take_pending()?;
                self.number_of(&v, "PasteSpecial's Paste").map_err(|m| self.fault_at(link.span, m))?
            }
        };
        let how = match code as i64 {
            -4163 => Paste::Values,
            -4104 | -4123 => Paste::Inputs,
            _ => {
                return Err(self.unsupported(
                    link.span,
                    "PasteSpecial: only xlPasteValues, xlPasteFormulas and xlPasteAll (a workbook here holds no \
                     comments or validation)",
                ))
            }
        };
        self.refuse_paste_special_options(ctx, link)?;
        // xlPasteAll brings the cells' formats too; xlPasteFormulas and xlPasteValues do not.
        self.paste(source, (sheet, rect), how, code as i64 == -4104, link.span)
    }

    /// PasteSpecial's Operation, SkipBlanks and Transpose as the macro recorder writes them
    /// (`Operation:=xlNone, SkipBlanks:=False, Transpose:=False`) paste as given; an operation
    /// on the destination's values, skipping blanks or transposing ("Range.PasteSpecial
    /// method") are refused: pasting without them would be another result than Excel's.
    fn refuse_paste_special_options(&self, ctx: &mut Ctx, link: &Link) -> Run<()> {
        if let Some(expr) = argument(link, 1, "operation") {
            let v = ctx.eval(expr).unwrap_single();
            self.take_pending()?;
            let operation = self.number_of(&v, "PasteSpecial's Operation").map_err(|m| self.fault_at(link.span, m))?;
            // xlPasteSpecialOperationNone, which is xlNone (-4142).
            if operation != -4142.0 {
                let why = format!(
                    "PasteSpecial Operation:={operation}: ncsheet pastes no sum, difference, product or quotient with \
                     the destination's values"
                );
                return Err(self.unsupported(link.span, why));
            }
        }
        for (position, name) in [(2, "skipblanks"), (3, "transpose")] {
            let Some(expr) = argument(link, position, name) else { continue };
            let v = ctx.eval(expr).unwrap_single();
            self.take_pending()?;
            if crate::eval::coerce::to_bool(&v).map_err(|e| self.fault_at(link.span, e.to_string()))? {
                let what = if position == 2 { "SkipBlanks" } else { "Transpose" };
                return Err(
                    self.unsupported(link.span, format!("PasteSpecial {what}:=True: ncsheet pastes without it"))
                );
            }
        }
        Ok(())
    }

    /// `ws.Paste` or `ws.Paste Destination:=r` ("Worksheet.Paste method"): what the last
    /// `Copy` put on the clipboard, pasted as Excel pastes it (formulas, constants and formats)
    /// at Destination, or else at the sheet's selection ("If this argument is omitted, the
    /// current selection is used"). `Link:=True`, a paste of links to the copied cells, is refused.
    pub(super) fn paste_on_sheet(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<()> {
        let Some(source) = *self.clipboard.borrow() else {
            return Err(self.fault_at(link.span, "Paste: nothing was copied (Copy a range first)"));
        };
        if let Some(expr) = argument(link, 1, "link") {
            let wants_links = ctx.eval(expr).unwrap_single();
            self.take_pending()?;
            if crate::eval::coerce::to_bool(&wants_links).map_err(|e| self.fault_at(link.span, e.to_string()))? {
                return Err(self.unsupported(link.span, "Paste Link:=True: ncsheet pastes no links to copied cells"));
            }
        }
        let dest = match argument(link, 0, "destination") {
            None => (sheet, self.cursor(sheet).0),
            Some(expr) => match ctx.operand(expr) {
                Operand::Ref(to, area) if to == sheet => (to, area),
                Operand::Ref(..) => {
                    let why = "Paste method of Worksheet class failed: the destination is on another sheet";
                    return Err(self.error_1004(link.span, why.into()));
                }
                _ => return Err(self.fault_at(link.span, "Paste: the destination is not a range")),
            },
        };
        self.take_pending()?;
        self.paste(source, dest, Paste::Inputs, true, link.span)
    }

    /// The part of a paste that changes anything: where the source has cells, or the
    /// destination has cells to blank. Whole columns or rows (`Columns("A:C").Copy`) hold a
    /// million cells each, nearly all empty on both sides. A source pasted several times over
    /// is kept whole.
    fn within_used(&self, (from, source): (SheetId, Rect), (to, area): (SheetId, Rect)) -> Option<(Rect, Rect)> {
        if (area.rows(), area.cols()) != (source.rows(), source.cols()) {
            return Some((source, area));
        }
        let wb = self.wb.borrow();
        let (dr, dc) =
            (area.first.row as i64 - source.first.row as i64, area.first.col as i64 - source.first.col as i64);
        let shift = |r: Rect| {
            let at = |p: Pos| Pos::new((p.row as i64 + dr) as u32, (p.col as i64 + dc) as u32);
            Rect::new(at(r.first), at(r.last))
        };
        let copied = wb.used_rect(from).and_then(|u| intersect(u, source)).map(shift);
        let blanked = wb.used_rect(to).and_then(|u| intersect(u, area));
        let work = match (copied, blanked) {
            (Some(a), Some(b)) => bounding(a, b),
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => return None,
        };
        let back = |p: Pos| Pos::new((p.row as i64 - dr) as u32, (p.col as i64 - dc) as u32);
        Some((Rect::new(back(work.first), back(work.last)), work))
    }

    fn paste(
        &self,
        (from, source): (SheetId, Rect),
        (to, dest): (SheetId, Rect),
        how: Paste,
        looks: bool,
        span: Span,
    ) -> Run<()> {
        let Some(area) = paste_area(source, dest) else {
            return Err(self.fault_at(span, "the pasted range would be off the sheet"));
        };
        let Some((source, area)) = self.within_used((from, source), (to, area)) else {
            return Ok(());
        };
        let cells = area.rows() as u64 * area.cols() as u64;
        if cells > MAX_PASTE {
            return Err(
                self.beyond_limit(Some(span), format!("pasting {cells} cells at once is more than a macro may"))
            );
        }
        let room = self.room_to_paste((from, source), (to, area), how);
        room.map_err(|e| self.workbook_fault(Some(span), &e))?;
        // Everything is read before anything is written: the areas may overlap.
        let mut items = Vec::with_capacity(cells as usize);
        let mut look_pairs = Vec::with_capacity(if looks { cells as usize } else { 0 });
        {
            let wb = self.wb.borrow();
            for row in 0..area.rows() {
                for col in 0..area.cols() {
                    let p = Pos::new(source.first.row + row % source.rows(), source.first.col + col % source.cols());
                    if looks {
                        look_pairs.push((p, Pos::new(area.first.row + row, area.first.col + col)));
                    }
                    let tree = (how == Paste::Inputs).then(|| wb.formula_tree(from, p)).flatten();
                    items.push(match tree {
                        Some(t) => Err(t.into_owned()),
                        None => Ok(wb.value(from, p)),
                    });
                }
            }
        }
        let mut wb = self.book_mut()?;
        let width = area.cols() as usize;
        for (i, item) in items.into_iter().enumerate() {
            let p = Pos::new(area.first.row + (i / width) as u32, area.first.col + (i % width) as u32);
            match item {
                Err(tree) => wb.fill_formula_tree_deferred(to, Rect::cell(p), tree),
                Ok(Value::Blank) => {
                    wb.set_input_deferred(to, p, "").map_err(|e| self.workbook_fault(Some(span), &e))?
                }
                Ok(v) => wb.set_value_deferred(to, p, v),
            }
        }
        wb.recalculate_rect(to, area);
        drop(wb);
        self.copy_looks(from, to, &look_pairs);
        Ok(())
    }
}

impl Interp<'_, '_> {
    /// Refuses a paste past the workbook's cell limit before anything is read or written:
    /// each cell of `area` whose source holds a value (or, pasting inputs, a formula) makes a
    /// cell where there is none.
    fn room_to_paste(
        &self,
        (from, source): (SheetId, Rect),
        (to, area): (SheetId, Rect),
        how: Paste,
    ) -> Result<(), WorkbookError> {
        let wb = self.wb.borrow();
        let source_of = |q: Pos| {
            let (row, col) = (q.row - area.first.row, q.col - area.first.col);
            Pos::new(source.first.row + row % source.rows(), source.first.col + col % source.cols())
        };
        let filled = |q: Pos| {
            let p = source_of(q);
            (how == Paste::Inputs && wb.is_formula(from, p)) || !wb.value(from, p).is_blank()
        };
        wb.room_for_filled(to, area, filled)
    }
}

pub(super) fn intersect(a: Rect, b: Rect) -> Option<Rect> {
    let first = Pos::new(a.first.row.max(b.first.row), a.first.col.max(b.first.col));
    let last = Pos::new(a.last.row.min(b.last.row), a.last.col.min(b.last.col));
    (first.row <= last.row && first.col <= last.col).then(|| Rect::new(first, last))
}

fn bounding(a: Rect, b: Rect) -> Rect {
    Rect::new(
        Pos::new(a.first.row.min(b.first.row), a.first.col.min(b.first.col)),
        Pos::new(a.last.row.max(b.last.row), a.last.col.max(b.last.col)),
    )
}

/// `Range.Address(RowAbsolute, ColumnAbsolute, ReferenceStyle, External, RelativeTo)`, as
/// Excel's reference ("Range.Address property") describes it: `$B$2` by default, `B2` with
/// both absolutes False, `R2C2` or `R[1]C[-1]` (relative to `RelativeTo`, else the active
/// cell) in xlR1C1 style, and `[Book.xlsx]Sheet1!$B$2` when External is True. Whole
/// columns and rows are written as such (`$A:$A`, `$1:$3`, `C1`, `R1:R3`).
const ADDRESS_PARAMETERS: [&str; 5] = ["rowabsolute", "columnabsolute", "referencestyle", "external", "relativeto"];

impl Interp<'_, '_> {
    pub(super) fn address(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<String> {
        let args = link.args.as_deref().unwrap_or(&[]);
        if args.len() > ADDRESS_PARAMETERS.len() {
            let why = format!("Address takes at most 5 arguments, not {} (wrong number of arguments)", args.len());
            return Err(self.fault_at(link.span, why));
        }
        if let Some(unknown) = args
            .iter()
            .filter_map(|a| a.name.as_deref())
            .find(|n| !ADDRESS_PARAMETERS.iter().any(|p| p.eq_ignore_ascii_case(n)))
        {
            return Err(self.fault_at(link.span, format!("Address has no argument named {unknown}")));
        }
        let mut flag = |position: usize, default: bool| -> Run<bool> {
            let Some(e) = argument(link, position, ADDRESS_PARAMETERS[position]) else { return Ok(default) };
            let v = ctx.eval(e).unwrap_single();
            self.take_pending()?;
            crate::eval::coerce::to_bool(&v).map_err(|_| {
                self.fault_at(link.span, format!("Address: {} is True or False", ADDRESS_PARAMETERS[position]))
            })
        };
        let row_absolute = flag(0, true)?;
        let column_absolute = flag(1, true)?;
        let external = flag(3, false)?;
        let style = match argument(link, 2, "referencestyle") {
            None => super::interp::XL_A1,
            Some(e) => self.number(e, "Address's ReferenceStyle")? as i32,
        };
        let text = match style {
            super::interp::XL_A1 => a1_address(rect, row_absolute, column_absolute),
            super::interp::XL_R1C1 => {
                let origin = match argument(link, 4, "relativeto") {
                    Some(e) => match self.var_of(e, true)? {
                        super::value::Var::Obj(super::value::Obj::Range(_, r)) => r.first,
                        _ => return Err(self.fault_at(link.span, "Address: RelativeTo is a Range")),
                    },
                    None => self.cursor(sheet).1,
                };
                r1c1_address(rect, row_absolute, column_absolute, origin)
            }
            other => {
                return Err(self.fault_at(
                    link.span,
                    format!("Address: ReferenceStyle is xlA1 (1) or xlR1C1 (-4150), not {other}"),
                ))
            }
        };
        if !external {
            return Ok(text);
        }
        let book = self.options.workbook_name.as_deref().ok_or_else(|| {
            self.unsupported(
                link.span,
                "Address(External:=True) needs the workbook's file name, which this run does not know",
            )
        })?;
        let name = self.wb.borrow().sheet_names()[sheet as usize].clone();
        let plain = name.chars().all(|c| c.is_alphanumeric() || c == '_')
            && book.chars().all(|c| c.is_alphanumeric() || c == '_' || c == '.');
        Ok(if plain {
            format!("[{book}]{name}!{text}")
        } else {
            format!("'[{book}]{}'!{text}", name.replace('\'', "''"))
        })
    }
}

fn whole_columns(rect: Rect) -> bool {
    rect.first.row == 0 && rect.last.row == MAX_ROWS - 1
}

fn whole_rows(rect: Rect) -> bool {
    rect.first.col == 0 && rect.last.col == MAX_COLS - 1
}

fn a1_address(rect: Rect, row_absolute: bool, column_absolute: bool) -> String {
    let dollar = |on: bool| if on { "$" } else { "" };
    let col = |c: u32| format!("{}{}", dollar(column_absolute), crate::formula::address::column_name(c));
    let row = |r: u32| format!("{}{}", dollar(row_absolute), r + 1);
    if whole_columns(rect) && !whole_rows(rect) {
        return format!("{}:{}", col(rect.first.col), col(rect.last.col));
    }
    if whole_rows(rect) && !whole_columns(rect) {
        return format!("{}:{}", row(rect.first.row), row(rect.last.row));
    }
    let cell = |p: Pos| format!("{}{}", col(p.col), row(p.row));
    if rect.is_cell() {
        cell(rect.first)
    } else {
        format!("{}:{}", cell(rect.first), cell(rect.last))
    }
}

fn r1c1_address(rect: Rect, row_absolute: bool, column_absolute: bool, origin: Pos) -> String {
    let part = |letter: char, n: u32, absolute: bool, from: u32| -> String {
        if absolute {
            return format!("{letter}{}", n + 1);
        }
        match n as i64 - from as i64 {
            0 => letter.to_string(),
            d => format!("{letter}[{d}]"),
        }
    };
    let row = |r: u32| part('R', r, row_absolute, origin.row);
    let col = |c: u32| part('C', c, column_absolute, origin.col);
    let span = |a: String, b: String| if a == b { a } else { format!("{a}:{b}") };
    if whole_columns(rect) && !whole_rows(rect) {
        return span(col(rect.first.col), col(rect.last.col));
    }
    if whole_rows(rect) && !whole_columns(rect) {
        return span(row(rect.first.row), row(rect.last.row));
    }
    let cell = |p: Pos| format!("{}{}", row(p.row), col(p.col));
    span(cell(rect.first), cell(rect.last))
}

/// Excel's `xlWorksheet` (`Sheets.Add`'s Type): the one kind of sheet ncsheet's workbook holds.
const XL_WORKSHEET: f64 = -4167.0;

/// Why Excel refuses `name` for a sheet ("Rename a worksheet": at most 31 characters, not
/// blank, none of `: \ / ? * [ ]`, no apostrophe first or last, not "History").
fn sheet_name_fault(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        Some("a sheet's name cannot be blank")
    } else if name.chars().count() > 31 {
        Some("a sheet's name has at most 31 characters")
    } else if name.contains([':', '\\', '/', '?', '*', '[', ']']) {
        Some("a sheet's name cannot hold : \\ / ? * [ or ]")
    } else if name.starts_with('\'') || name.ends_with('\'') {
        Some("a sheet's name cannot begin or end with an apostrophe")
    } else if name.eq_ignore_ascii_case("history") {
        Some("History is a name Excel keeps for itself")
    } else {
        None
    }
}

impl Interp<'_, '_> {
    /// Excel's run-time error 1004 with its reason.
    pub(super) fn error_1004(&self, span: Span, why: String) -> Fault {
        let mut fault = self.fault_at(span, format!("{why} (run-time error 1004)"));
        fault.code = 1004;
        fault
    }

    /// `Sheets.Add [Before], [After], [Count], [Type]` ("Sheets.Add method"): `Count` new,
    /// empty worksheets (one by default), each named as Excel names one (`Sheet` and the next
    /// free number), side by side before `Before`, after `After`, or with neither before the
    /// active sheet. The last one added becomes the active sheet and is returned (as
    /// LibreOffice's VBA does with a Count; Microsoft's page names one new sheet).
    pub(super) fn add_sheet(&self, link: &Link) -> Run<Obj> {
        let place = self.placement(link, "Sheets.Add")?;
        let count = match argument(link, 2, "Count") {
            Some(e) => {
                let count =
                    self.number_of(&self.eval(e)?, "Sheets.Add's Count").map_err(|m| self.fault_at(link.span, m))?;
                let count = count.round_ties_even();
                if !(1.0..=MAX_SHEETS as f64).contains(&count) {
                    return Err(self.error_1004(link.span, format!("Sheets.Add's Count is {count}, not 1 or more")));
                }
                count as usize
            }
            None => 1,
        };
        if let Some(e) = argument(link, 3, "Type") {
            if self.number_of(&self.eval(e)?, "Sheets.Add's Type").ok() != Some(XL_WORKSHEET) {
                let why = "Sheets.Add: ncsheet's workbooks hold worksheets only (Type:=xlWorksheet)";
                return Err(self.unsupported(link.span, why));
            }
        }
        let at = match place {
            Some(place) => self.tab_at(place),
            None => self.wb.borrow().tab_position(self.active.get()).unwrap_or(0),
        };
        // Each name looked up in the workbook's index: listing every name to check against
        // made `Worksheets.Add` in a loop quadratic (70,000 adds ran for minutes). The
        // numbers only grow, so the fresh names differ from one another.
        let fresh: Vec<String> = {
            let wb = self.wb.borrow();
            (wb.sheet_len() + 1..)
                .map(|n| format!("Sheet{n}"))
                .filter(|name| wb.sheet_id(name).is_none())
                .take(count)
                .collect()
        };
        let ids = self.book_mut()?.insert_sheets(&fresh, at).map_err(|e| self.error_1004(link.span, e.to_string()))?;
        let last = *ids.last().expect("at least one sheet added");
        self.active.set(last);
        Ok(Obj::Sheet(last))
    }

    /// `ws.Copy Before|After` ("Worksheet.Copy method"): a new sheet holding the sheet's
    /// cells, formulas as they are (a reference to another sheet, the original included,
    /// still points there), named as Excel names a copy (`Data (2)`), placed before `Before`
    /// or after `After`; it becomes the active sheet. Without Before or After Excel makes a
    /// new workbook, which a run has not: refused.
    pub(super) fn copy_sheet(&self, sheet: SheetId, link: &Link) -> Run<Obj> {
        let place = self.copy_place(link)?;
        self.copy_sheet_to(sheet, place, link)
    }

    fn copy_place(&self, link: &Link) -> Run<(SheetId, bool)> {
        self.placement(link, "Worksheet.Copy")?.ok_or_else(|| {
            let why = "Worksheet.Copy without Before or After copies the sheet into a new workbook, which a \
                       run has not: write ws.Copy After:=Sheets(Sheets.Count)";
            self.fault_at(link.span, why)
        })
    }

    /// A copy of `sheet` before (after, `place.1`) the sheet `place.0`.
    fn copy_sheet_to(&self, sheet: SheetId, place: (SheetId, bool), link: &Link) -> Run<Obj> {
        let at = self.tab_at(place);
        let names = self.wb.borrow().sheet_names();
        let original = &names[sheet as usize];
        let taken = |n: &str| names.iter().any(|s| s.eq_ignore_ascii_case(n));
        let name = (2..).map(|k| format!("{original} ({k})")).find(|n| !taken(n)).expect("a free name");
        let copy =
            self.book_mut()?.insert_sheets(&[name], at).map_err(|e| self.error_1004(link.span, e.to_string()))?[0];
        let used = self.wb.borrow().used_rect(sheet);
        if let Some(used) = used {
            self.paste((sheet, used), (copy, used), Paste::Inputs, false, link.span)?;
        }
        // The copy looks as the original does (number formats, styles, widths).
        self.looks.borrow_mut().copy_sheet(sheet, copy);
        self.active.set(copy);
        Ok(Obj::Value(Value::Blank))
    }

    /// `ws.Move Before|After` ("Worksheet.Move method"): the sheet's tab moves before
    /// `Before` or after `After`; its cells, and every formula pointing at it, stay as they
    /// are. Without Before or After Excel moves the sheet into a new workbook, which a run has
    /// not: refused.
    pub(super) fn move_sheet(&self, sheet: SheetId, link: &Link) -> Run<Obj> {
        let place = self.move_place(link)?;
        self.move_sheet_to(sheet, place, link)
    }

    fn move_place(&self, link: &Link) -> Run<(SheetId, bool)> {
        self.placement(link, "Worksheet.Move")?.ok_or_else(|| {
            let why = "Worksheet.Move without Before or After moves the sheet into a new workbook, which a \
                       run has not: write ws.Move Before:=… or After:=…";
            self.fault_at(link.span, why)
        })
    }

    /// `sheet`'s tab moved before (after, `place.1`) the sheet `place.0`.
    fn move_sheet_to(&self, sheet: SheetId, place: (SheetId, bool), link: &Link) -> Run<Obj> {
        let at = self.tab_at(place);
        // `at` counts the tabs with the sheet still in its place; without it, one less past it.
        let from = self.wb.borrow().tab_position(sheet).expect("a sheet of the workbook");
        let to = if at > from { at - 1 } else { at };
        self.book_mut()?.move_sheet(sheet, to).map_err(|e| self.error_1004(link.span, e.to_string()))?;
        Ok(Obj::Value(Value::Blank))
    }

    /// The members of `Sheets(Array(…))`: `Count`, `Item(i)`, `Select` (the first sheet
    /// becomes the active one), `Delete` (each), and `Copy`/`Move Before|After`, which keep the
    /// group's order: before a sheet each goes in turn, after one the last goes first.
    pub(super) fn sheet_group_member(&self, ctx: &mut Ctx, ids: &Rc<[SheetId]>, link: &Link) -> Run<Obj> {
        let done = Ok(Obj::Value(Value::Blank));
        match link.name.to_ascii_lowercase().as_str() {
            "count" => Ok(Obj::Value(Value::Number(ids.len() as f64))),
            "item" => match self.numbers(ctx, link)?.as_slice() {
                [i] if *i >= 1.0 && (*i as usize) <= ids.len() => Ok(Obj::Sheet(ids[*i as usize - 1])),
                _ => Err(self.fault_at(link.span, format!("the group has {} sheets: Item(1 to that)", ids.len()))),
            },
            "select" | "activate" => {
                self.select_sheet(ids[0], link.span)?;
                done
            }
            "delete" => {
                for &id in ids.iter() {
                    self.delete_sheet(id, link.span)?;
                }
                done
            }
            "copy" | "move" => {
                let copy = link.name.eq_ignore_ascii_case("copy");
                // The place is read once: `Before:=Sheets(1)` is the sheet first before the copies.
                let place = if copy { self.copy_place(link)? } else { self.move_place(link)? };
                let order: Vec<SheetId> = if place.1 { ids.iter().rev().copied().collect() } else { ids.to_vec() };
                let mut first_copy = None;
                for id in order {
                    if copy {
                        self.copy_sheet_to(id, place, link)?;
                        first_copy = first_copy.or(Some(self.active.get()));
                    } else {
                        self.move_sheet_to(id, place, link)?;
                    }
                }
                // The copies stand in the group's order, and the first of them is active.
                if let (Some(first), false) = (first_copy, place.1) {
                    self.active.set(first);
                }
                done
            }
            _ => self.unmodelled(&Obj::SheetGroup(ids.clone()), link),
        }
    }

    /// The sheet `Before:=` or `After:=` names, and whether it is After; `None` when neither
    /// is given.
    fn placement(&self, link: &Link, what: &str) -> Run<Option<(SheetId, bool)>> {
        let before = argument(link, 0, "Before").map(|e| self.sheet_argument(e, "Before")).transpose()?;
        let after = argument(link, 1, "After").map(|e| self.sheet_argument(e, "After")).transpose()?;
        match (before, after) {
            (Some(_), Some(_)) => Err(self.error_1004(link.span, format!("{what} takes Before or After, not both"))),
            (Some(b), None) => Ok(Some((b, false))),
            (None, Some(a)) => Ok(Some((a, true))),
            (None, None) => Ok(None),
        }
    }

    /// The tab position (from 0, among the tabs as they are) a sheet put before (after) the
    /// sheet of `place` takes.
    fn tab_at(&self, (sheet, after): (SheetId, bool)) -> usize {
        let tab = self.wb.borrow().tab_position(sheet).expect("a sheet of the workbook");
        tab + usize::from(after)
    }

    /// `ThisWorkbook.Name` ("Workbook.Name property"): the workbook's file name with its
    /// extension (`Book1.xlsm`), as the run was given it.
    pub(super) fn workbook_name(&self, link: &Link) -> Run<Obj> {
        match self.options.workbook_name.as_deref() {
            Some(name) => Ok(Obj::Value(Value::text(name))),
            None => {
                Err(self.unsupported(link.span, "ThisWorkbook.Name: this run was not given the workbook's file name"))
            }
        }
    }

    /// The sheet a `Before:=` or `After:=` argument names.
    fn sheet_argument(&self, e: &crate::formula::ast::Expr, what: &str) -> Run<SheetId> {
        match self.var_of(e, true)? {
            Var::Obj(Obj::Sheet(id)) => Ok(id),
            _ => Err(self.fault_at(self.expr_span(e), format!("{what}:= takes a sheet (Sheets(\"Name\"), Sheets(n))"))),
        }
    }

    /// `ws.Name = v` ("Worksheet.Name property"): renames the sheet; formulas that refer to it
    /// show the new name. A name Excel refuses, or one another sheet has, is run-time error 1004.
    pub(super) fn rename_sheet(&self, sheet: SheetId, v: &Value, span: Span) -> Run<()> {
        let name = print_text(v);
        if let Some(why) = sheet_name_fault(&name) {
            return Err(self.error_1004(span, format!("{why}, not \"{name}\"")));
        }
        let taken = self.wb.borrow().sheet_id(&name).is_some_and(|other| other != sheet);
        if taken {
            let why = format!("That name is already taken: a sheet is named {name}");
            return Err(self.error_1004(span, why));
        }
        self.book_mut()?.rename_sheet(sheet, &name).map_err(|e| self.fault_at(span, e.to_string()))
    }
}

/// What `ws.Protect` set on a sheet in this run ("Worksheet.Protect method"): its password
/// (empty for none), and whether a macro may still change its cells (`UserInterfaceOnly:=True`
/// protects only the user interface; `Contents:=False` leaves the cells unprotected).
#[derive(Clone, Debug)]
pub(super) struct SheetProtection {
    password: String,
    macros_may_write: bool,
}

impl Interp<'_, '_> {
    /// `ws.Protect [Password], [DrawingObjects], [Contents], [Scenarios], [UserInterfaceOnly], …`
    /// ("Worksheet.Protect method"). The Allow… arguments are about the user's window, which a
    /// run has not.
    pub(super) fn protect_sheet(&self, sheet: SheetId, link: &Link) -> Run<Obj> {
        let password = self.text_argument(link, 0, "Password")?.unwrap_or_default();
        let contents = self.flag_argument(link, 2, "Contents")?.unwrap_or(true);
        let interface_only = self.flag_argument(link, 4, "UserInterfaceOnly")?.unwrap_or(false);
        let protection = SheetProtection { password, macros_may_write: interface_only || !contents };
        self.protections.borrow_mut().insert(sheet, protection);
        Ok(Obj::Value(Value::Blank))
    }

    /// `ws.Unprotect [Password]` ("Worksheet.Unprotect method"): a sheet that is not protected
    /// stays as it is, whatever the password; a password-protected one needs its password,
    /// case and all, else run-time error 1004. Without one Excel would ask the user, whom a run
    /// has not.
    pub(super) fn unprotect_sheet(&self, sheet: SheetId, link: &Link) -> Run<Obj> {
        let given = self.text_argument(link, 0, "Password")?;
        let mut protections = self.protections.borrow_mut();
        let Some(protection) = protections.get(&sheet) else { return Ok(Obj::Value(Value::Blank)) };
        match given {
            _ if protection.password.is_empty() => {}
            Some(password) if password == protection.password => {}
            Some(_) => return Err(self.error_1004(link.span, "The password you supplied is not correct".into())),
            None => {
                let why = "the sheet is protected with a password and Unprotect gave none (Excel would ask the \
                           user, whom a run has not): ws.Unprotect \"password\"";
                return Err(self.error_1004(link.span, why.into()));
            }
        }
        protections.remove(&sheet);
        Ok(Obj::Value(Value::Blank))
    }

    /// `ws.ProtectContents` ("Worksheet.ProtectContents property"): True while `Protect` guards
    /// the sheet's cells.
    pub(super) fn protects_contents(&self, sheet: SheetId) -> bool {
        self.protections.borrow().contains_key(&sheet)
    }

    /// A macro's write into the cells of a sheet it protected (without UserInterfaceOnly) is
    /// run-time error 1004 in Excel, as every cell is locked until unlocked.
    pub(super) fn refuse_protected(&self, sheet: SheetId) -> Run<()> {
        let protections = self.protections.borrow();
        if protections.get(&sheet).is_none_or(|p| p.macros_may_write) {
            return Ok(());
        }
        let name = self.wb.borrow().sheet_names()[sheet as usize].clone();
        let why = format!(
            "the cell you are trying to change is on the protected sheet {name} (ws.Protect without \
             UserInterfaceOnly:=True); ws.Unprotect it first (run-time error 1004)"
        );
        let mut fault = self.fault(why);
        fault.code = 1004;
        Err(fault)
    }

    pub(super) fn text_argument(&self, link: &Link, position: usize, name: &str) -> Run<Option<String>> {
        argument(link, position, name).map(|e| self.eval(e).map(|v| print_text(&v))).transpose()
    }

    pub(super) fn flag_argument(&self, link: &Link, position: usize, name: &str) -> Run<Option<bool>> {
        argument(link, position, name).map(|e| self.truth(e, name)).transpose()
    }
}

impl Interp<'_, '_> {
    /// `rng.CurrentRegion` ("Range.CurrentRegion property", Ctrl+*): the range grown until a
    /// blank row and a blank column (or the sheet's edge) bound it on every side, corners
    /// included; an empty cell with empty neighbours is its own region.
    pub(super) fn current_region(&self, sheet: SheetId, rect: Rect) -> Rect {
        let wb = self.wb.borrow();
        let Some(used) = wb.used_rect(sheet) else { return rect };
        let filled = |p: Pos| {
            used.contains(p)
                && (wb.formula_id(sheet, p).is_some() || !matches!(wb.value(sheet, p), crate::eval::Value::Blank))
        };
        // A line of cells just outside `r`, reaching one further at both ends for the corners.
        let any_filled = |rows: (u32, u32), cols: (u32, u32)| {
            (rows.0..=rows.1).any(|row| (cols.0..=cols.1).any(|col| filled(Pos::new(row, col))))
        };
        let mut r = rect;
        loop {
            let (top, bottom) = (r.first.row.saturating_sub(1), (r.last.row + 1).min(MAX_ROWS - 1));
            let (left, right) = (r.first.col.saturating_sub(1), (r.last.col + 1).min(MAX_COLS - 1));
            let mut grown = r;
            if r.first.row > 0 && any_filled((top, top), (left, right)) {
                grown.first.row = top;
            }
            if r.last.row < MAX_ROWS - 1 && any_filled((bottom, bottom), (left, right)) {
                grown.last.row = bottom;
            }
            if r.first.col > 0 && any_filled((top, bottom), (left, left)) {
                grown.first.col = left;
            }
            if r.last.col < MAX_COLS - 1 && any_filled((top, bottom), (right, right)) {
                grown.last.col = right;
            }
            if grown == r {
                return r;
            }
            r = grown;
        }
    }

    /// `rng.SpecialCells(xlCellTypeLastCell)` ("Range.SpecialCells method", Ctrl+End): the
    /// last cell of the sheet's used range. The other types give ranges of several areas,
    /// which ncsheet's Range is not: refused by name.
    pub(super) fn special_cells(&self, sheet: SheetId, link: &Link) -> Run<Obj> {
        const XL_CELL_TYPE_LAST_CELL: f64 = 11.0;
        let kind = argument(link, 0, "Type").map(|e| self.eval(e)).transpose()?;
        match kind {
            Some(Value::Number(n)) if n == XL_CELL_TYPE_LAST_CELL => {
                Ok(Obj::Range(sheet, Rect::cell(self.used_range(sheet).last)))
            }
            _ => Err(self.unsupported(
                link.span,
                "SpecialCells: ncsheet gives xlCellTypeLastCell only; the other types are ranges of several \
                 areas, which its Range is not (loop over the cells and test each)",
            )),
        }
    }
}
