//! Graph upkeep: the edges a formula cell's references make (cell by cell for a small range,
//! through a range node for a large one), added and removed as formulas come and go, rebuilt
//! when a name changes meaning, and moved when INDIRECT or OFFSET reach somewhere new.

use super::shared::Part;
use super::*;
use crate::formula::ast::{Reference, SheetRef};

/// A range of at most this many cells is linked cell by cell rather than through a range
/// node: cheaper to build, to walk and to store (`MAX(B3:G3)` is six edges).
const SMALL_RANGE: u64 = 16;

impl Workbook {
    /// Calls `f` with each cell or range a formula cell reads (names expanded).
    pub(super) fn for_each_precedent(&self, id: u32, f: &mut dyn FnMut(SheetId, Rect)) {
        let cell = &self.cells[id as usize];
        let formula = self.formulas.get(cell.formula);
        for &(ref r, part) in formula.refs.iter() {
            let mut f = |sheet, rect| f(sheet, part_of(rect, part));
            if let Some((sheet, rect)) = resolve_static(r, cell.sheet, cell.pos) {
                f(sheet, rect);
            } else if let SheetRef::Span(first, last) = r.sheet {
                self.span_precedents(r, (first, last), cell.pos, Reference::resolve, &mut f);
            }
        }
        for r in formula.tables.iter() {
            if let Ok((sheet, rect)) = self.table_part(r, cell.sheet, cell.pos) {
                f(sheet, rect);
            }
        }
        let mut seen = Vec::new();
        for (name, seen_from) in formula.names.iter() {
            self.name_precedents(name, seen_from.unwrap_or(cell.sheet), cell.pos, (0, &mut seen), f);
        }
    }

    /// The cells name `name` reads when cell `at` uses it (its relative references move
    /// with the cell, as the evaluator reads them). Each name is expanded once (`seen`): a
    /// LAMBDA calling itself twice (`FIB(n-1)+FIB(n-2)`) must not branch without end; and at
    /// most 33 names deep (`depth`).
    fn name_precedents(
        &self,
        name: &str,
        sheet: SheetId,
        at: Pos,
        (depth, seen): (u32, &mut Vec<(String, SheetId)>),
        f: &mut dyn FnMut(SheetId, Rect),
    ) {
        let Some((expr, name_sheet)) = Env::defined_name(self, name, sheet) else { return };
        if depth > 32 || seen.iter().any(|(n, s)| *s == sheet && n.eq_ignore_ascii_case(name)) {
            return;
        }
        seen.push((name.to_string(), sheet));
        expr.visit(&mut |e| match &e.kind {
            crate::formula::ast::ExprKind::Ref(r) => {
                // A name's relative references wrap at the sheet's edges, as the evaluator reads them.
                if let Some((s, rect)) = r.resolve_wrapping(name_sheet, at) {
                    f(s, rect);
                } else if let SheetRef::Span(first, last) = r.sheet {
                    self.span_precedents(r, (first, last), at, Reference::resolve_wrapping, f);
                }
            }
            crate::formula::ast::ExprKind::Table(r) => {
                if let Ok((s, rect)) = self.table_part(r, name_sheet, at) {
                    f(s, rect);
                }
            }
            crate::formula::ast::ExprKind::Name(inner) | crate::formula::ast::ExprKind::UnknownCall(inner, _) => {
                self.name_precedents(inner, name_sheet, at, (depth + 1, seen), f)
            }
            crate::formula::ast::ExprKind::SheetName(crate::formula::ast::SheetRef::Id(seen_from), inner) => {
                self.name_precedents(inner, *seen_from, at, (depth + 1, seen), f)
            }
            _ => {}
        });
    }

    /// The cells 3-D reference `r` from sheet `first` to `last` reads from cell `at`: its
    /// cells on each sheet whose tab lies between them now (the tabs moving, the graph is
    /// rebuilt: `tabs.rs`).
    fn span_precedents(
        &self,
        r: &Reference,
        (first, last): (SheetId, SheetId),
        at: Pos,
        resolve: fn(&Reference, SheetId, Pos) -> Option<(SheetId, Rect)>,
        f: &mut dyn FnMut(SheetId, Rect),
    ) {
        for &sheet in self.sheets_spanned(first, last) {
            if let Some((s, rect)) = resolve(&Reference { sheet: SheetRef::Id(sheet), shape: r.shape }, sheet, at) {
                f(s, rect);
            }
        }
    }

    /// Adds the graph edges of a formula cell.
    pub(super) fn link(&mut self, id: u32) {
        self.for_each_edge(id, Workbook::add_edge);
    }

    /// Removes the graph edges of a formula cell.
    pub(super) fn unlink(&mut self, id: u32) {
        self.for_each_edge(id, Workbook::remove_edge);
        if let Some(dynamic) = self.dynamic_refs.remove(&id) {
            for (sheet, rect) in dynamic {
                self.remove_edge(id, sheet, rect);
            }
        }
    }

    /// Calls `edge` (add or remove) for each cell or range formula cell `id` reads, through
    /// a buffer kept between calls: linking a whole sheet allocates once.
    fn for_each_edge(&mut self, id: u32, edge: fn(&mut Workbook, u32, SheetId, Rect)) {
        let mut precedents = std::mem::take(&mut self.precedents_buf);
        precedents.clear();
        self.for_each_precedent(id, &mut |s, r| precedents.push((s, r)));
        for &(sheet, rect) in &precedents {
            edge(self, id, sheet, rect);
        }
        self.precedents_buf = precedents;
    }

    /// Makes formula cell `id` a dependent of `rect`: of each cell of a small one, of a range
    /// node for a large one, or for a small one whose blank cells would take the workbook
    /// past half the cells it may hold ([`MAX_CELLS`]): the blank cells a link makes only
    /// save time, and must not use up the room the user's own cells need (600,000 formulas
    /// each summing 16 cells of their row made 9.6 million).
    fn add_edge(&mut self, id: u32, sheet: SheetId, rect: Rect) {
        if is_small(rect) && self.blank_cells_fit(sheet, rect) {
            for_each_pos(rect, |pos| {
                let p = self.cell_at(sheet, pos);
                self.cells[p as usize].dependents.push(id);
            });
        } else {
            let r = self.ranges.intern(sheet, rect);
            self.ranges.nodes[r as usize].dependents.push(id);
        }
    }

    /// Whether the cells small `rect` lacks can be made within half of [`MAX_CELLS`].
    fn blank_cells_fit(&self, sheet: SheetId, rect: Rect) -> bool {
        let mut missing = 0;
        for_each_pos(rect, |pos| missing += self.sheets[sheet as usize].get(pos).is_none() as usize);
        missing == 0 || self.cell_count() + missing <= MAX_CELLS / 2
    }

    /// Undoes [`Workbook::add_edge`]; a small range may have been linked either way.
    fn remove_edge(&mut self, id: u32, sheet: SheetId, rect: Rect) {
        if is_small(rect) {
            for_each_pos(rect, |pos| {
                if let Some(p) = self.sheets[sheet as usize].get(pos) {
                    let cell = &mut self.cells[p as usize];
                    cell.dependents.remove(id);
                    if cell.formula == NO_FORMULA && cell.value.is_blank() && cell.dependents.as_slice().is_empty() {
                        self.unlinked_blanks.push(p);
                    }
                }
            });
        }
        if let Some(r) = self.ranges.find(sheet, rect) {
            self.ranges.nodes[r as usize].dependents.remove(id);
        }
    }

    /// Gives formula cell `id` edges from the references it made at run time (INDIRECT,
    /// OFFSET), in place of those of its last evaluation. `true` when it reached somewhere
    /// new: what it read there may not have been computed yet in this pass.
    pub(super) fn relink_dynamic(&mut self, id: u32, refs: Vec<(SheetId, Rect)>) -> bool {
        if self.dynamic_refs.get(&id).map_or(refs.is_empty(), |old| *old == refs) {
            return false;
        }
        if let Some(old) = self.dynamic_refs.remove(&id) {
            for (sheet, rect) in old {
                self.remove_edge(id, sheet, rect);
            }
        }
        if refs.is_empty() {
            return false;
        }
        for &(sheet, rect) in &refs {
            self.add_edge(id, sheet, rect);
        }
        self.dynamic_refs.insert(id, refs);
        true
    }

    /// Gives back the blank cells formulas stopped linking ([`Workbook::remove_edge`]) that
    /// nothing links now and that hold nothing kept by cell: 600,000 `=SUM(B1:Q1)` made 9.6
    /// million blank cells, and deleting or moving the formulas kept them, near the cell
    /// limit for good. Called as a recalculation starts, when no edit is half done (an
    /// insertion reuses emptied cells by id). A cell someone edited stays: the change log
    /// names its place for a save.
    pub(super) fn reclaim_unlinked_blanks(&mut self) {
        if self.unlinked_blanks.is_empty() {
            return;
        }
        let mut candidates = std::mem::take(&mut self.unlinked_blanks);
        candidates.sort_unstable();
        candidates.dedup();
        candidates.retain(|&id| self.holds_nothing(id));
        for &id in &candidates {
            let c = &self.cells[id as usize];
            self.sheets[c.sheet as usize].unset(c.pos);
        }
        self.free(&candidates);
    }

    /// Whether cell `id` is on its sheet's grid, blank, linked by no formula and kept for
    /// nothing else (an edit the change log notes, a note, unparsed text, a place in a spill).
    fn holds_nothing(&self, id: u32) -> bool {
        let c = &self.cells[id as usize];
        let edited = self.changes.as_ref().is_some_and(|log| log.inputs.contains(id) || log.values.contains(id));
        c.formula == NO_FORMULA
            && c.value.is_blank()
            && c.dependents.as_slice().is_empty()
            && self.sheets[c.sheet as usize].get(c.pos) == Some(id)
            && !edited
            && !self.notes.contains_key(&id)
            && !self.bad_inputs.contains_key(&id)
            && self.spill.owner(id).is_none()
            && self.spill.tail_at(c.sheet, c.pos).is_none()
    }

    /// Rebuilds every edge (after a name changes meaning).
    pub(super) fn rebuild_graph(&mut self) {
        self.ranges.clear();
        // The recalculation that follows links run-time references again.
        self.dynamic_refs.clear();
        for (id, c) in self.cells.iter_mut().enumerate() {
            // A blank cell linked before may be linked by nothing after (`reclaim_unlinked_blanks`).
            if !c.dependents.as_slice().is_empty() && c.formula == NO_FORMULA && c.value.is_blank() {
                self.unlinked_blanks.push(id as u32);
            }
            c.dependents = Deps::None;
        }
        for id in 0..self.cells.len() as u32 {
            if self.cells[id as usize].formula != NO_FORMULA {
                self.link(id);
            }
        }
    }
}

/// The cells of `rect` a formula reads whatever it computes (see [`Part`]).
fn part_of(rect: Rect, part: Part) -> Rect {
    match part {
        Part::Whole => rect,
        Part::FirstColumn => Rect { first: rect.first, last: Pos::new(rect.last.row, rect.first.col) },
        Part::FirstRow => Rect { first: rect.first, last: Pos::new(rect.first.row, rect.last.col) },
    }
}

fn is_small(rect: Rect) -> bool {
    rect.rows() as u64 * rect.cols() as u64 <= SMALL_RANGE
}

pub(super) fn for_each_pos(rect: Rect, mut f: impl FnMut(Pos)) {
    for row in rect.first.row..=rect.last.row {
        for col in rect.first.col..=rect.last.col {
            f(Pos::new(row, col));
        }
    }
}
