//! Deleting a sheet, as Excel's `Worksheet.Delete` does: the sheet leaves the tabs (and
//! `Worksheets`, `SHEETS()`, a saved file), its cells go, every reference to it elsewhere
//! becomes `#REF!` (a cell's formula, a defined name's), a 3-D reference ending at it ends
//! one tab inward, and what depends on them recomputes; the names scoped to it go with it.
//!
//! The sheet's id is not given back: formula trees, name scopes, a macro's Worksheet and
//! Range objects and the front ends hold ids, and an id reused for a later sheet would show
//! them that sheet's cells. The slot in `Workbook::sheets` stays, marked deleted, its grid
//! empty ([`Workbook::sheet_deleted`]); only the tab order and the name index forget it.
//! A workbook numbers at most [`MAX_SHEETS`] sheets over its life, deleted ones counted.

use super::*;
use crate::formula::ast::{ExprKind, SheetRef};

impl Workbook {
    /// Whether `sheet` was deleted ([`Workbook::delete_sheet`]): its id names no sheet any more.
    pub fn sheet_deleted(&self, sheet: SheetId) -> bool {
        self.sheets.get(sheet as usize).is_some_and(|s| s.deleted)
    }

    /// How many sheets the workbook has (their tabs), hidden ones counted, deleted ones not:
    /// Excel's `Worksheets.Count` and `SHEETS()`. Ids run to [`Workbook::sheet_len`].
    pub fn sheet_count(&self) -> usize {
        self.tabs.order.len()
    }

    /// Deletes `sheet` and recalculates. Refused, with nothing changed, for the last visible
    /// sheet (Excel: "A workbook must contain at least one visible worksheet"). The active sheet, if it was this one,
    /// becomes the visible sheet to its right, or to its left when it was the last.
    pub fn delete_sheet(&mut self, sheet: SheetId) -> Result<(), WorkbookError> {
        let Some(place) = self.tab_position(sheet).filter(|_| !self.sheet_deleted(sheet)) else {
            return Err(WorkbookError::NoSuchSheet(format!("number {}", sheet as usize + 1)));
        };
        let visible = |wb: &Workbook, s: SheetId| s != sheet && wb.sheet_visibility(s) == Visibility::Visible;
        if !self.tabs.order.iter().any(|&s| visible(self, s)) {
            return Err(WorkbookError::LastVisibleSheet(self.sheets[sheet as usize].name.clone()));
        }
        let successor = self.tabs.order[place + 1..]
            .iter()
            .chain(self.tabs.order[..place].iter().rev())
            .copied()
            .find(|&s| visible(self, s));
        let record = self.journal.is_some().then(|| self.deleted_record(sheet, place));
        let order = self.tabs.order.clone();
        self.remove_tab(sheet)?;
        if let (Some(record), Some(journal)) = (record, &mut self.journal) {
            journal.deleted.push(record);
        }
        let cells = self.empty_sheet(sheet);
        self.strike_formulas_reading(sheet, &order);
        let names_changed = self.strike_names_of(sheet, &order);
        let name = std::mem::take(&mut self.sheets[sheet as usize].name);
        self.sheet_index.remove(&name.to_ascii_lowercase());
        self.sheets[sheet as usize] = Sheet::new(&name);
        self.sheets[sheet as usize].deleted = true;
        // Off the grid now, the cells go back for new ones: a loop adding a sheet, filling
        // it and deleting it met the cell limit in its ninth turn, one sheet left.
        self.free(&cells);
        if self.active_sheet == sheet {
            self.active_sheet = successor.expect("a visible sheet is left");
        }
        if let Some(log) = &mut self.changes {
            log.sheets = true;
            log.names |= names_changed;
        }
        // Formula texts parsed while the name was taken read anew (a new sheet may take it).
        self.formulas.forget_keys();
        self.names_unlinked = true;
        self.recalculate();
        Ok(())
    }

    /// What deleting `sheet` (at tab `place`) takes that an undo must give back: the cells
    /// other sheets' formulas lose to `#REF!` are in the journal already (`note_input`).
    fn deleted_record(&self, sheet: SheetId, place: usize) -> DeletedSheet {
        let inputs = (0..self.cells.len() as u32)
            .filter(|&id| self.cells[id as usize].sheet == sheet)
            .filter(|&id| self.sheets[sheet as usize].get(self.cells[id as usize].pos) == Some(id))
            .filter_map(|id| {
                let pos = self.cells[id as usize].pos;
                self.input(sheet, pos).map(|input| (pos, input))
            })
            .collect();
        DeletedSheet {
            id: sheet,
            name: self.sheets[sheet as usize].name.clone(),
            tab: place,
            visibility: self.sheets[sheet as usize].visibility,
            inputs,
            names: self.names.clone(),
            active: self.active_sheet,
        }
    }

    /// The sheets deleted since [`Workbook::start_journal`], in the order deleted, each with
    /// what [`Workbook::restore_sheet`] needs; the journal goes on.
    pub fn take_deleted_sheets(&mut self) -> Vec<DeletedSheet> {
        self.journal.as_mut().map_or(Vec::new(), |j| std::mem::take(&mut j.deleted))
    }

    /// Brings a deleted sheet back under its id (what held the id reaches it again), with
    /// its name, tab, cells and the workbook's defined names as they were when it was
    /// deleted, then recalculates. The inputs of other cells its deletion struck to `#REF!`
    /// are the journal's to type back, after this. Refused when the id is not a deleted
    /// sheet's or another sheet took the name since.
    pub fn restore_sheet(&mut self, record: &DeletedSheet) -> Result<(), WorkbookError> {
        if !self.sheet_deleted(record.id) {
            return Err(WorkbookError::NoSuchSheet(format!("number {}, not deleted", record.id as usize + 1)));
        }
        if self.sheet_id(&record.name).is_some() {
            return Err(WorkbookError::DuplicateSheet(record.name.clone()));
        }
        let mut sheet = Sheet::new(&record.name);
        sheet.visibility = record.visibility;
        self.sheets[record.id as usize] = sheet;
        self.sheet_index.insert(record.name.to_ascii_lowercase(), record.id);
        let at = record.tab.min(self.tabs.order.len());
        self.tabs.order.insert(at, record.id);
        self.names = record.names.clone();
        self.forget_name_index();
        self.formulas.forget_keys();
        self.names_unlinked = true;
        if let Some(log) = &mut self.changes {
            log.sheets = true;
            log.names = true;
        }
        for (pos, input) in &record.inputs {
            self.set_input_deferred(record.id, *pos, input)?;
        }
        self.active_sheet = record.active;
        self.recalculate();
        Ok(())
    }

    /// Clears every cell of `sheet`: formulas (and their spills) first, then values; its
    /// cells' ids, for [`Workbook::free`] once the sheet's grid is gone.
    fn empty_sheet(&mut self, sheet: SheetId) -> Vec<u32> {
        let grid = &self.sheets[sheet as usize];
        let on_sheet = |id: &u32| {
            let c = &self.cells[*id as usize];
            c.sheet == sheet && grid.get(c.pos) == Some(*id)
        };
        let ids: Vec<u32> = (0..self.cells.len() as u32).filter(on_sheet).collect();
        for &id in &ids {
            self.clear_formula(id);
        }
        for &id in &ids {
            self.take_spilled_cell(id);
            self.store_value(id, Value::Blank);
        }
        ids
    }

    /// Every stored formula reading `sheet` with that reference struck to `#REF!`; the cells
    /// running one are noted as edited (their formula text changes, as in Excel). The graph
    /// is rebuilt by the recalculation that follows.
    fn strike_formulas_reading(&mut self, sheet: SheetId, order: &[SheetId]) {
        let mut struck = Vec::new();
        for (fid, formula) in self.formulas.formulas.iter().enumerate() {
            // Which sheets a tree reads does not depend on the numbers a copy holds.
            if reads_any(&formula.expr, sheet) {
                let mut tree = formula.own_tree();
                strike(&mut tree, sheet, order);
                struck.push((fid as u32, SharedFormula::new(tree)));
            }
        }
        if struck.is_empty() {
            return;
        }
        let fids: std::collections::HashSet<u32> = struck.iter().map(|&(fid, _)| fid).collect();
        for id in 0..self.cells.len() as u32 {
            if fids.contains(&self.cells[id as usize].formula) {
                self.note_input(id);
            }
        }
        self.formulas.replace(struck);
    }

    /// Removes the names scoped to `sheet` and strikes references to it in the others;
    /// whether any name changed.
    fn strike_names_of(&mut self, sheet: SheetId, order: &[SheetId]) -> bool {
        let before = self.names.len();
        self.names.retain(|n| n.scope != Some(sheet));
        self.forget_name_index();
        let mut changed = self.names.len() != before;
        for name in &mut self.names {
            if let Some(tree) = struck_tree(&name.expr, sheet, order) {
                name.expr = Rc::new(tree);
                changed = true;
            }
        }
        changed
    }
}

/// A sheet [`Workbook::delete_sheet`] took, as an undo brings it back
/// ([`Workbook::restore_sheet`]).
#[derive(Clone, Debug)]
pub struct DeletedSheet {
    id: SheetId,
    name: String,
    /// Its place among the tabs.
    tab: usize,
    visibility: Visibility,
    /// What a user would type to make each of its cells again.
    inputs: Vec<(Pos, String)>,
    /// The workbook's defined names before the delete: those scoped to the sheet went, and
    /// references to it in the others became `#REF!`.
    names: Vec<DefinedName>,
    /// The active sheet before the delete.
    active: SheetId,
}

impl DeletedSheet {
    /// The id the sheet had, and has again once restored.
    pub fn id(&self) -> SheetId {
        self.id
    }
}

/// `tree` with each reference to `sheet` (`Merged!A1`, a name as `Merged` sees it,
/// `Merged!Rate`) replaced by `#REF!`, and each 3-D reference ending at it shrunk; `None`
/// when it has none. `order`: the tabs before the delete.
fn struck_tree(tree: &Expr, sheet: SheetId, order: &[SheetId]) -> Option<Expr> {
    if !reads_any(tree, sheet) {
        return None;
    }
    let mut tree = tree.clone();
    strike(&mut tree, sheet, order);
    Some(tree)
}

/// Whether a node of `tree` reads `sheet` by name: a sheet in the middle of a 3-D reference
/// is not named, and leaves it by leaving the tabs.
fn reads_any(tree: &Expr, sheet: SheetId) -> bool {
    let mut found = false;
    tree.visit(&mut |e| found |= reads_sheet(e, sheet));
    found
}

fn reads_sheet(e: &Expr, sheet: SheetId) -> bool {
    let on = |r: &SheetRef| match *r {
        SheetRef::Id(id) => id == sheet,
        SheetRef::Span(first, last) => first == sheet || last == sheet,
        SheetRef::Current | SheetRef::Missing(_) => false,
    };
    match &e.kind {
        ExprKind::Ref(r) => on(&r.sheet),
        ExprKind::SheetName(r, _) => on(r),
        _ => false,
    }
}

/// Replaces in place each node of `e` that reads `sheet` by `#REF!`, and moves the end of a
/// 3-D reference that is `sheet` one tab inward, as Excel does ("Create a 3-D reference to
/// the same cell range on multiple worksheets": deleting an endpoint, the calculation
/// adjusts to the sheets left between the ends).
fn strike(e: &mut Expr, sheet: SheetId, order: &[SheetId]) {
    e.visit_mut(&mut |node| {
        if !reads_sheet(node, sheet) {
            return;
        }
        match &mut node.kind {
            ExprKind::Ref(r) if matches!(r.sheet, SheetRef::Span(..)) => r.sheet = span_without(&r.sheet, sheet, order),
            _ => node.kind = ExprKind::Error(XlError::Ref),
        }
    });
}

/// 3-D reference `span`, one of whose ends is `sheet` (being deleted), with that end moved one
/// tab toward the other (`order`: the tabs before the delete); one sheet left, that sheet.
fn span_without(span: &SheetRef, sheet: SheetId, order: &[SheetId]) -> SheetRef {
    let SheetRef::Span(first, last) = *span else { return span.clone() };
    let at = |s: SheetId| order.iter().position(|&t| t == s);
    let (Some(here), Some(other_at)) = (at(sheet), at(if first == sheet { last } else { first })) else {
        return SheetRef::Missing("#REF".into());
    };
    let inward = if other_at > here { order[here + 1] } else { order[here - 1] };
    match (first == sheet, inward == order[other_at]) {
        (_, true) => SheetRef::Id(inward),
        (true, false) => SheetRef::Span(inward, last),
        (false, false) => SheetRef::Span(first, inward),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // A spill on the deleted sheet and a legacy array formula reading it go quietly: the
    // spill's cells with the sheet, the reader to `#REF!` (Excel's value for a reference
    // whose sheet is gone); SUM over the other sheet's spill still reads it.
    #[test]
    fn spills_and_arrays_follow_a_deleted_sheet() {
        let mut wb = Workbook::new();
        for name in ["Keep", "Gone"] {
            wb.add_sheet(name).unwrap();
        }
        let at = |r, c| Pos::new(r, c);
        wb.set_input(1, at(0, 1), "=SEQUENCE(3)").unwrap();
        wb.set_input(0, at(0, 0), "=SEQUENCE(2)*10").unwrap();
        wb.set_input(0, at(0, 1), "=SUM(Gone!B1#)").unwrap();
        wb.set_input(0, at(0, 2), "=SUM(A1#)").unwrap();
        assert_eq!(wb.value(0, at(0, 1)), Value::Number(6.0));
        wb.delete_sheet(1).unwrap();
        assert_eq!(wb.value(0, at(0, 1)), Value::Error(XlError::Ref));
        assert_eq!(wb.value(0, at(0, 2)), Value::Number(30.0));
        assert_eq!(wb.value(1, at(1, 1)), Value::Blank);
        assert!(wb.sheet_deleted(1) && wb.sheet_count() == 1 && wb.sheet_len() == 2);
        // A second delete of the same id, and a delete of the last sheet, are refused.
        assert!(matches!(wb.delete_sheet(1), Err(WorkbookError::NoSuchSheet(_))));
        assert!(matches!(wb.delete_sheet(0), Err(WorkbookError::LastVisibleSheet(_))));
    }
}
