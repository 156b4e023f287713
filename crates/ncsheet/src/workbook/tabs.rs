//! The sheets' tab order. A sheet's id is fixed for its life: formula trees, name scopes and
//! VBA objects hold it. Where a sheet shows among the tabs (`Sheets(2)`, `ws.Index`, SHEET(),
//! the order a saved file lists its sheets) is its place in this order, which a macro's
//! `Sheets.Add Before:=`, `ws.Copy`/`ws.Move` change without touching any id.

use crate::eval::functions;
use crate::formula::ast::{ExprKind, SheetId};

use super::{Workbook, WorkbookError, NO_FORMULA};

/// The tab order, and what holds it in place.
#[derive(Default)]
pub(super) struct Tabs {
    /// The sheets' ids in tab order.
    pub(super) order: Vec<SheetId>,
    /// The sheet spans (first, last) of the file's 3-D references (`Sheet1:Sheet3!A1`). Such
    /// a reference means the sheets whose tabs lie between its ends, and was read as the list
    /// of the sheets between them then: a tab moved or added in or out of a span would make
    /// Excel's reference take other sheets, so it is refused. A set: a file may hold many
    /// 3-D references over few spans; ordered, so the first span refused is always the same.
    spans: std::collections::BTreeSet<(SheetId, SheetId)>,
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

    /// Notes that a formula of the file was read from a 3-D reference spanning the tabs from
    /// `first` to `last` (its list of sheets): no tab may then move or be added in or out of
    /// the span.
    pub fn note_sheet_span(&mut self, first: SheetId, last: SheetId) {
        if first != last {
            self.tabs.spans.insert((first, last));
        }
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
            self.check_spans(&order)?;
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
        self.check_spans(&order)?;
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

    /// Takes the tab of `sheet` (being deleted) out of the order. Refused when a 3-D
    /// reference of the file takes that sheet: the file's `Sheet1:Sheet3!A1` was read as the
    /// list of its sheets, and Excel, deleting a sheet of the span, drops it from the span
    /// (the end moving inward when it is an end), where a list holding it would become
    /// `#REF!`; a list typed so cannot be told from one read from a span.
    pub(super) fn remove_tab(&mut self, sheet: SheetId) -> Result<(), WorkbookError> {
        let at = |s: SheetId| self.tabs.order.iter().position(|&t| t == s);
        let here = at(sheet).ok_or_else(|| WorkbookError::NoSuchSheet(format!("number {}", sheet as usize + 1)))?;
        for &(first, last) in &self.tabs.spans {
            let (Some(a), Some(b)) = (at(first), at(last)) else { continue };
            if (a.min(b)..=a.max(b)).contains(&here) {
                let names = self.sheet_names();
                return Err(WorkbookError::SheetSpan(format!(
                    "sheet '{}' is one of the sheets of a 3-D reference of the file ({}:{}), which ncsheet holds \
                     as the list of those sheets: Excel would take the sheet out of the reference, ncsheet \
                     cannot, so the sheet is not deleted",
                    names[sheet as usize], names[first as usize], names[last as usize],
                )));
            }
        }
        self.tabs.order.remove(here);
        Ok(())
    }

    /// Refuses a tab order in which a 3-D reference of the file would span other sheets than
    /// it was read with.
    fn check_spans(&self, order: &[SheetId]) -> Result<(), WorkbookError> {
        let members = |order: &[SheetId], (a, b): (SheetId, SheetId)| {
            let at = |s| order.iter().position(|&t| t == s).unwrap_or(0);
            let (i, j) = (at(a).min(at(b)), at(a).max(at(b)));
            let mut sheets = order[i..=j].to_vec();
            sheets.sort_unstable();
            sheets
        };
        for &span in &self.tabs.spans {
            let (was, would) = (members(&self.tabs.order, span), members(order, span));
            if was != would {
                let names = self.sheet_names();
                let name = |s: &SheetId| names.get(*s as usize).map_or("a new sheet", String::as_str);
                let listed = |ids: &[SheetId]| ids.iter().map(name).collect::<Vec<_>>().join(", ");
                return Err(WorkbookError::SheetSpan(format!(
                    "a 3-D reference of the file ({}:{}) takes the sheets between its ends, read as {}; with \
                     this order it would take {}, and Excel's result would change: move or add the sheet \
                     outside the span",
                    names[span.0 as usize],
                    names[span.1 as usize],
                    listed(&was),
                    listed(&would),
                )));
            }
        }
        Ok(())
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

    /// The formula cells whose value may depend on the tab order: those calling SHEET, and
    /// those using a defined name or calling a function by name (a LAMBDA's name), whose
    /// formula may call SHEET in turn. Tabs rarely move: recomputing every cell that uses a
    /// name costs less than following names through each other.
    fn cells_reading_tab_order(&self) -> Vec<u32> {
        let may_call_sheet = |formula: &super::SharedFormula| {
            let mut found = false;
            formula.expr.visit(&mut |e| {
                found |= match &e.kind {
                    ExprKind::Call(id, _) => functions::spec(*id).name == "SHEET",
                    ExprKind::Name(_) | ExprKind::SheetName(..) | ExprKind::UnknownCall(..) => true,
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

    // A 3-D reference takes the sheets whose tabs lie between its ends.
    #[test]
    fn a_tab_cannot_cross_the_ends_of_a_3d_span() {
        let mut wb = book(&["A", "B", "C", "D", "E"]);
        wb.note_sheet_span(0, 3);
        assert!(matches!(wb.move_sheet(4, 1), Err(WorkbookError::SheetSpan(_))));
        assert!(matches!(wb.move_sheet(1, 4), Err(WorkbookError::SheetSpan(_))));
        assert!(matches!(wb.insert_sheets(&["N".into()], 2), Err(WorkbookError::SheetSpan(_))));
        assert_eq!((wb.sheet_len(), wb.tab_names()), (5, ["A", "B", "C", "D", "E"].map(String::from).to_vec()));
        // Within the span, or at its edges, the same sheets stay between its ends.
        wb.move_sheet(1, 2).unwrap();
        wb.insert_sheets(&["N".into()], 0).unwrap();
        wb.move_sheet(4, 6).unwrap();
        assert_eq!(wb.tab_names(), ["N", "A", "C", "B", "D", "E"]);
    }
}
