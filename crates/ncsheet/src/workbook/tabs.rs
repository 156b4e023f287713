//! The sheets' tab order. A sheet's id is fixed for its life: formula trees, name scopes and
//! VBA objects hold it. Where a sheet shows among the tabs (`Sheets(2)`, `ws.Index`, SHEET(),
//! the order a saved file lists its sheets) is its place in this order, which a macro's
//! `Sheets.Add Before:=`, `ws.Copy`/`ws.Move` change without touching any id.

use crate::eval::functions;
use crate::formula::ast::{Expr, ExprKind, SheetId, SheetRef};

use super::{Workbook, WorkbookError, NO_FORMULA};

/// The tab order.
#[derive(Default)]
pub(super) struct Tabs {
    /// The sheets' ids in tab order.
    pub(super) order: Vec<SheetId>,
}

impl Workbook {
    /// The sheets' ids in tab order: the order Excel shows them and a saved file lists them.
    pub fn tab_order(&self) -> &[SheetId] {
        &self.tabs.order
    }

    /// The sheets' names in tab order.
    pub fn tab_names(&self) -> Vec<String> {
        let names = self.sheet_names();
        self.tabs.order.iter().map(|&s| names[s as usize].clone()).collect()
    }

    /// Where `sheet` shows among the tabs, from 0; `None` for a sheet the workbook has not.
    pub fn tab_position(&self, sheet: SheetId) -> Option<usize> {
        // Sheets that were never moved sit at their own number: no search.
        if self.tabs.order.get(sheet as usize) == Some(&sheet) {
            return Some(sheet as usize);
        }
        self.tabs.order.iter().position(|&s| s == sheet)
    }

    /// The sheet showing at tab `position` (from 0).
    pub fn sheet_at_tab(&self, position: usize) -> Option<SheetId> {
        self.tabs.order.get(position).copied()
    }

    /// The sheets a 3-D reference from `first` to `last` (`Sheet1:Sheet3!A1`) takes: those
    /// whose tabs lie between the two, ends included, in tab order, whichever end comes
    /// first; none when either is not a sheet of the workbook.
    pub fn sheets_spanned(&self, first: SheetId, last: SheetId) -> &[SheetId] {
        let (Some(a), Some(b)) = (self.tab_position(first), self.tab_position(last)) else { return &[] };
        &self.tabs.order[a.min(b)..=a.max(b)]
    }

    /// Moves `sheet`'s tab so that it shows at `position` (from 0, among all the tabs; past
    /// the last means last). Formulas keep pointing at the same sheets; those whose value is
    /// a sheet's place (SHEET) are recomputed.
    pub fn move_sheet(&mut self, sheet: SheetId, position: usize) -> Result<(), WorkbookError> {
        let Some(from) = self.tab_position(sheet) else {
            return Err(WorkbookError::NoSuchSheet(format!("number {}", sheet as usize + 1)));
        };
        let to = position.min(self.tabs.order.len() - 1);
        if from != to {
            let mut order = self.tabs.order.clone();
            order.remove(from);
            order.insert(to, sheet);
            self.tabs.order = order;
            self.tabs_moved();
        }
        Ok(())
    }

    /// Adds empty sheets named `names`, their tabs side by side from `position` (from 0; past
    /// the last means last), and returns their ids in that order.
    pub fn insert_sheets(&mut self, names: &[String], position: usize) -> Result<Vec<SheetId>, WorkbookError> {
        // All or nothing: every name and the place are checked before the first sheet is added.
        if self.sheets.len() + names.len() > super::MAX_SHEETS {
            return Err(WorkbookError::TooManySheets);
        }
        let mut seen = std::collections::HashSet::with_capacity(names.len());
        for name in names {
            if self.sheet_id(name).is_some() || !seen.insert(name.to_ascii_lowercase()) {
                return Err(WorkbookError::DuplicateSheet(name.clone()));
            }
        }
        let at = position.min(self.tabs.order.len());
        let new_ids = (self.sheets.len()..self.sheets.len() + names.len()).map(|id| id as SheetId);
        let mut order = self.tabs.order.clone();
        order.splice(at..at, new_ids);
        let mut ids = Vec::with_capacity(names.len());
        for name in names {
            ids.push(self.add_sheet(name)?);
        }
        let moved = at < self.tabs.order.len() - ids.len();
        self.tabs.order = order;
        if moved {
            self.tabs_moved();
        }
        Ok(ids)
    }

    /// Takes the tab of `sheet` (being deleted) out of the order.
    pub(super) fn remove_tab(&mut self, sheet: SheetId) -> Result<(), WorkbookError> {
        let here = self.tabs.order.iter().position(|&t| t == sheet);
        let here = here.ok_or_else(|| WorkbookError::NoSuchSheet(format!("number {}", sheet as usize + 1)))?;
        self.tabs.order.remove(here);
        Ok(())
    }

    /// After tabs moved: a file saved back has to list its sheets anew, SHEET reads the new
    /// places, and a 3-D reference takes the sheets now between its ends (its graph edges
    /// made anew: an edge is removed as it was added, by the tab order of the time).
    fn tabs_moved(&mut self) {
        if let Some(log) = &mut self.changes {
            log.sheets = true;
        }
        let readers = self.cells_reading_tab_order();
        if !readers.is_empty() {
            let spans_in = |e: &Expr| holds_sheet_span(e);
            if self.formulas.formulas.iter().any(|f| spans_in(&f.expr)) || self.names.iter().any(|n| spans_in(&n.expr))
            {
                self.rebuild_graph();
            }
            self.recalculate_from(readers);
        }
    }

    /// The formula cells whose value may depend on the tab order: those calling SHEET or
    /// holding a 3-D reference, and those using a defined name or calling a function by name (a LAMBDA's name), whose
    /// formula may call SHEET in turn. Tabs rarely move: recomputing every cell that uses a
    /// name costs less than following names through each other.
    fn cells_reading_tab_order(&self) -> Vec<u32> {
        let may_call_sheet = |formula: &super::SharedFormula| {
            let mut found = false;
            formula.expr.visit(&mut |e| {
                found |= match &e.kind {
                    ExprKind::Call(id, _) => functions::spec(*id).name == "SHEET",
                    ExprKind::Name(_) | ExprKind::SheetName(..) | ExprKind::UnknownCall(..) => true,
                    ExprKind::Ref(r) => matches!(r.sheet, SheetRef::Span(..)),
                    _ => false,
                };
            });
            found
        };
        // The shared formulas are far fewer than the cells running them: most workbooks call
        // SHEET nowhere and need no look at their cells.
        let readers: Vec<bool> = self.formulas.formulas.iter().map(may_call_sheet).collect();
        if !readers.contains(&true) {
            return Vec::new();
        }
        (0..self.cells.len() as u32)
            .filter(|&id| {
                let fid = self.cells[id as usize].formula;
                fid != NO_FORMULA && readers[fid as usize]
            })
            .collect()
    }
}

/// Whether `e` holds a 3-D reference (`Sheet1:Sheet3!A1`).
fn holds_sheet_span(e: &Expr) -> bool {
    let mut found = false;
    e.visit_refs(&mut |r| found |= matches!(r.sheet, SheetRef::Span(..)));
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Value;
    use crate::formula::address::Pos;

    fn book(names: &[&str]) -> Workbook {
        let mut wb = Workbook::new();
        for name in names {
            wb.add_sheet(name).unwrap();
        }
        wb
    }

    // Excel recomputes SHEET() wherever it is called from: through a name, or a LAMBDA named.
    #[test]
    fn sheet_through_a_name_counts_tabs_after_a_move() {
        let mut wb = book(&["A", "B", "C"]);
        wb.define_name("pos", "=SHEET()", None).unwrap();
        wb.define_name("place", "=LAMBDA(x,SHEET()*x)", None).unwrap();
        wb.set_input(2, Pos::new(0, 0), "=pos").unwrap();
        wb.set_input(2, Pos::new(0, 1), "=place(10)").unwrap();
        assert_eq!(wb.value(2, Pos::new(0, 0)), Value::Number(3.0));
        assert_eq!(wb.value(2, Pos::new(0, 1)), Value::Number(30.0));
        wb.move_sheet(2, 0).unwrap();
        assert_eq!(wb.value(2, Pos::new(0, 0)), Value::Number(1.0));
        assert_eq!(wb.value(2, Pos::new(0, 1)), Value::Number(10.0));
    }

    // Excel's SHEET: "the sheet number of the referenced sheet", the number of its tab.
    #[test]
    fn sheet_counts_tabs_after_a_move() {
        let mut wb = book(&["A", "B", "C"]);
        wb.set_input(2, Pos::new(0, 0), "=SHEET()").unwrap();
        wb.set_input(0, Pos::new(0, 0), "=SHEET(\"C\")*10+SHEET(B!A1)").unwrap();
        assert_eq!(wb.value(2, Pos::new(0, 0)), Value::Number(3.0));
        assert_eq!(wb.value(0, Pos::new(0, 0)), Value::Number(32.0));
        wb.move_sheet(2, 0).unwrap();
        assert_eq!(wb.tab_names(), ["C", "A", "B"]);
        assert_eq!((wb.tab_position(2), wb.sheet_at_tab(2)), (Some(0), Some(1)));
        assert_eq!(wb.value(2, Pos::new(0, 0)), Value::Number(1.0));
        assert_eq!(wb.value(0, Pos::new(0, 0)), Value::Number(13.0));
    }

    #[test]
    fn sheets_inserted_side_by_side_or_not_at_all() {
        let mut wb = book(&["A", "B"]);
        let ids = wb.insert_sheets(&["X".into(), "Y".into()], 1).unwrap();
        assert_eq!(ids, [2, 3]);
        assert_eq!(wb.tab_names(), ["A", "X", "Y", "B"]);
        // A name taken, in any case, or twice in the list: nothing is added.
        assert!(matches!(wb.insert_sheets(&["Z".into(), "b".into()], 0), Err(WorkbookError::DuplicateSheet(_))));
        assert!(matches!(wb.insert_sheets(&["Z".into(), "z".into()], 0), Err(WorkbookError::DuplicateSheet(_))));
        assert_eq!(wb.sheet_len(), 4);
        // Past the last tab means last.
        wb.insert_sheets(&["Z".into()], 99).unwrap();
        assert_eq!(wb.tab_names(), ["A", "X", "Y", "B", "Z"]);
    }

    #[test]
    fn a_move_is_a_change_of_the_sheets() {
        let mut wb = book(&["A", "B"]);
        wb.track_changes();
        wb.move_sheet(0, 0).unwrap();
        assert!(!wb.changes().unwrap().sheets, "a sheet moved onto its own place has not moved");
        wb.move_sheet(0, 5).unwrap();
        assert!(wb.changes().unwrap().sheets);
        assert_eq!(wb.tab_names(), ["B", "A"]);
        assert!(matches!(wb.move_sheet(7, 0), Err(WorkbookError::NoSuchSheet(_))));
    }

    // A 3-D reference takes the sheets whose tabs lie between its ends, as they lie when it
    // is read ("Create a 3-D reference to the same cell range on multiple worksheets": a sheet
    // inserted or moved between the ends is added to it, one moved out is removed).
    #[test]
    fn a_3d_reference_takes_the_tabs_between_its_ends() {
        let mut wb = book(&["Jan", "Feb", "Mar", "Apr", "Sum"]);
        for (sheet, v) in [(0, "1"), (1, "2"), (2, "4"), (3, "8")] {
            wb.set_input(sheet, Pos::new(0, 0), v).unwrap();
        }
        wb.set_input(4, Pos::new(0, 0), "=SUM(Jan:Mar!A1)").unwrap();
        let sum = |wb: &Workbook| wb.value(4, Pos::new(0, 0));
        assert_eq!(sum(&wb), Value::Number(7.0));
        wb.move_sheet(3, 1).unwrap();
        assert_eq!(sum(&wb), Value::Number(15.0), "Apr moved between the ends: 1+8+2+4");
        let new = wb.insert_sheets(&["New".into()], 2).unwrap()[0];
        wb.set_input(new, Pos::new(0, 0), "100").unwrap();
        assert_eq!(sum(&wb), Value::Number(115.0), "a sheet inserted between the ends is read, and followed");
        wb.move_sheet(1, 9).unwrap();
        assert_eq!(wb.tab_names(), ["Jan", "Apr", "New", "Mar", "Sum", "Feb"]);
        assert_eq!(sum(&wb), Value::Number(113.0), "Feb moved past the end leaves: 1+8+100+4");
        wb.set_input(1, Pos::new(0, 0), "1000").unwrap();
        assert_eq!(sum(&wb), Value::Number(113.0));
        // Excel quotes the two ends as one when either needs quotes; a cell's name before the
        // colon is a range to another sheet's cell, no span; alone, a span is no one value.
        wb.rename_sheet(2, "Mar 24").unwrap();
        assert_eq!(wb.formula(4, Pos::new(0, 0)).as_deref(), Some("=SUM('Jan:Mar 24'!A1)"));
        for typed in ["=A1:Jan!B1", "=SUM('Jan:Mar 24'!A1:B2)*2"] {
            wb.set_input(4, Pos::new(1, 0), typed).unwrap();
            assert_eq!(wb.formula(4, Pos::new(1, 0)).as_deref(), Some(typed));
        }
        assert_eq!(wb.value(4, Pos::new(1, 0)), Value::Number(226.0));
        wb.set_input(4, Pos::new(1, 0), "=Jan:Apr!A1").unwrap();
        assert_eq!(wb.value(4, Pos::new(1, 0)), Value::Error(crate::eval::XlError::Value));
    }
}
