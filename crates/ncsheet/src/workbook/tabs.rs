//! The sheets' tab order. A sheet's id is fixed for its life: formula trees, name scopes and
//! VBA objects hold it. Where a sheet shows among the tabs (`Sheets(2)`, `ws.Index`, SHEET(),
//! the order a saved file lists its sheets) is its place in this order, which a macro's
//! `Sheets.Add Before:=`, `ws.Copy`/`ws.Move` change without touching any id.

use crate::eval::functions;
use crate::formula::ast::{ExprKind, SheetId};

use super::{Workbook, WorkbookError, NO_FORMULA};

impl Workbook {
    /// The sheets' ids in tab order: the order Excel shows them and a saved file lists them.
    pub fn tab_order(&self) -> &[SheetId] {
        &self.tabs
    }

    /// The sheets' names in tab order.
    pub fn tab_names(&self) -> Vec<String> {
        let names = self.sheet_names();
        self.tabs.iter().map(|&s| names[s as usize].clone()).collect()
    }

    /// Where `sheet` shows among the tabs, from 0; `None` for a sheet the workbook has not.
    pub fn tab_position(&self, sheet: SheetId) -> Option<usize> {
        // Sheets that were never moved sit at their own number: no search.
        if self.tabs.get(sheet as usize) == Some(&sheet) {
            return Some(sheet as usize);
        }
        self.tabs.iter().position(|&s| s == sheet)
    }

    /// The sheet showing at tab `position` (from 0).
    pub fn sheet_at_tab(&self, position: usize) -> Option<SheetId> {
        self.tabs.get(position).copied()
    }

    /// Moves `sheet`'s tab so that it shows at `position` (from 0, among all the tabs; past
    /// the last means last). Formulas keep pointing at the same sheets; those whose value is
    /// a sheet's place (SHEET) are recomputed.
    pub fn move_sheet(&mut self, sheet: SheetId, position: usize) -> Result<(), WorkbookError> {
        let Some(from) = self.tab_position(sheet) else {
            return Err(WorkbookError::NoSuchSheet(format!("number {}", sheet as usize + 1)));
        };
        let to = position.min(self.tabs.len() - 1);
        if from != to {
            self.tabs.remove(from);
            self.tabs.insert(to, sheet);
            self.tabs_moved();
        }
        Ok(())
    }

    /// Adds empty sheets named `names`, their tabs side by side from `position` (from 0; past
    /// the last means last), and returns their ids in that order.
    pub fn insert_sheets(&mut self, names: &[String], position: usize) -> Result<Vec<SheetId>, WorkbookError> {
        // All or nothing: every name is checked before the first sheet is added.
        if self.sheets.len() + names.len() > super::MAX_SHEETS {
            return Err(WorkbookError::TooManySheets);
        }
        let mut seen = std::collections::HashSet::with_capacity(names.len());
        for name in names {
            if self.sheet_id(name).is_some() || !seen.insert(name.to_ascii_lowercase()) {
                return Err(WorkbookError::DuplicateSheet(name.clone()));
            }
        }
        let mut ids = Vec::with_capacity(names.len());
        for name in names {
            ids.push(self.add_sheet(name)?);
        }
        let at = position.min(self.tabs.len() - ids.len());
        if at + ids.len() < self.tabs.len() {
            self.tabs.truncate(self.tabs.len() - ids.len());
            self.tabs.splice(at..at, ids.iter().copied());
            self.tabs_moved();
        }
        Ok(ids)
    }

    /// After tabs moved: a file saved back has to list its sheets anew, and SHEET reads the
    /// new places.
    fn tabs_moved(&mut self) {
        if let Some(log) = &mut self.changes {
            log.sheets = true;
        }
        let readers = self.cells_reading_tab_order();
        if !readers.is_empty() {
            self.recalculate_from(readers);
        }
    }

    /// The formula cells whose value depends on the tab order: those calling SHEET.
    fn cells_reading_tab_order(&self) -> Vec<u32> {
        let calls_sheet = |formula: &super::SharedFormula| {
            let mut found = false;
            formula.expr.visit(&mut |e| {
                if let ExprKind::Call(id, _) = &e.kind {
                    found |= functions::spec(*id).name == "SHEET";
                }
            });
            found
        };
        // The shared formulas are far fewer than the cells running them: most workbooks call
        // SHEET nowhere and need no look at their cells.
        let readers: Vec<bool> = self.formulas.formulas.iter().map(calls_sheet).collect();
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
}
