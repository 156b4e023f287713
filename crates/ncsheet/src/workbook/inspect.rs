//! Looking inside a workbook for a user (`ncsheet show`, names as cell arguments): what a
//! defined name points at, the cells a formula reads and the cells that read a cell. Read
//! from the dependency graph, so what is shown is what recalculation uses.

use super::*;

impl Workbook {
    /// The sheet and rectangle a defined name refers to, when it is a plain reference
    /// (`=Outer!$G$6`); a sheet's own name wins over a workbook-wide one, as in Excel.
    pub fn name_reference(&self, name: &str, sheet: SheetId) -> Option<(SheetId, Rect)> {
        let (expr, name_sheet) = Env::defined_name(self, name, sheet)?;
        match &expr.kind {
            crate::formula::ast::ExprKind::Ref(r) => resolve_static(r, name_sheet, Pos::new(0, 0)),
            _ => None,
        }
    }

    /// The cells and ranges a formula cell reads, names expanded to what they point at;
    /// empty for a constant. In the order the formula names them, each once.
    pub fn precedents(&self, sheet: SheetId, pos: Pos) -> Vec<(SheetId, Rect)> {
        let mut out: Vec<(SheetId, Rect)> = Vec::new();
        let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) else { return out };
        if self.cells[id as usize].formula == NO_FORMULA {
            return out;
        }
        self.for_each_precedent(id, &mut |s, r| {
            if !out.contains(&(s, r)) {
                out.push((s, r));
            }
        });
        for &(s, r) in self.dynamic_refs.get(&id).into_iter().flatten() {
            if !out.contains(&(s, r)) {
                out.push((s, r));
            }
        }
        out
    }

    /// The formula cells that read this cell, directly or through a range, sorted by place.
    pub fn dependents(&self, sheet: SheetId, pos: Pos) -> Vec<(SheetId, Pos)> {
        let mut ids: Vec<u32> = Vec::new();
        if let Some(id) = self.sheets.get(sheet as usize).and_then(|s| s.get(pos)) {
            ids.extend_from_slice(self.cells[id as usize].dependents.as_slice());
        }
        self.ranges
            .containing(sheet, pos, |r| ids.extend_from_slice(self.ranges.nodes[r as usize].dependents.as_slice()));
        let mut out: Vec<(SheetId, Pos)> =
            ids.into_iter().map(|id| (self.cells[id as usize].sheet, self.cells[id as usize].pos)).collect();
        out.sort_by_key(|&(s, p)| (s, p.row, p.col));
        out.dedup();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn precedents_and_dependents_follow_names_and_ranges() {
        let mut wb = Workbook::with_sheet();
        wb.set_input(0, Pos::new(0, 0), "2").unwrap();
        wb.define_name("alpha", "=Sheet1!$A$1", None).unwrap();
        wb.set_input(0, Pos::new(0, 1), "=alpha*3").unwrap();
        wb.set_input(0, Pos::new(1, 1), "=SUM(A1:A100)+B1").unwrap();
        assert_eq!(wb.name_reference("ALPHA", 0), Some((0, Rect::cell(Pos::new(0, 0)))));
        let a1 = Rect::cell(Pos::new(0, 0));
        assert_eq!(wb.precedents(0, Pos::new(0, 1)), vec![(0, a1)]);
        assert_eq!(wb.dependents(0, Pos::new(0, 0)), vec![(0, Pos::new(0, 1)), (0, Pos::new(1, 1))]);
        assert!(wb.precedents(0, Pos::new(0, 0)).is_empty());
    }
}
