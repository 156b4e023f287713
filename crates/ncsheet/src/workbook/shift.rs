//! Inserting and deleting rows, columns and cells, as Excel does: the cells after the edit
//! move, and every reference of the workbook follows what it pointed at. A reference after
//! the edit moves (`$` too: it matters only to copying); one to a deleted cell becomes
//! `#REF!`; a range the edit cuts through grows or shrinks. Shifting a rectangle's cells
//! (`Range("B2:B3").Delete xlShiftUp`) moves only the cells in its columns (rows), and only
//! the references lying wholly inside those columns follow, as in Excel and LibreOffice.
//! References built at run time (INDIRECT, OFFSET's text) do not follow, as in Excel.
//!
//! The edit rewrites the formulas it changes, moves the cells it moves and rebuilds the
//! graph once: its cost is linear in the cells of the workbook.

use super::*;
use crate::formula::address::{MAX_COLS, MAX_ROWS};
use crate::formula::ast::{CellCoord, Coord, ExprKind, RefShape, SheetRef};

/// Which way the cells move: `Rows` inserts or deletes rows (cells move down or up),
/// `Columns` columns (cells move right or left).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    Rows,
    Columns,
}

/// One insertion or deletion on a sheet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SheetEdit {
    pub axis: Axis,
    /// The first row (column) inserted or deleted, 0-based, and how many.
    pub at: u32,
    pub count: u32,
    /// The columns (for `Rows`; rows for `Columns`) whose cells move; `None` for whole rows
    /// (columns).
    pub band: Option<(u32, u32)>,
    pub insert: bool,
}

impl SheetEdit {
    /// Whole rows `at..at+count` inserted (`insert`) or deleted.
    pub fn rows(at: u32, count: u32, insert: bool) -> SheetEdit {
        SheetEdit { axis: Axis::Rows, at, count, band: None, insert }
    }

    /// Whole columns `at..at+count` inserted (`insert`) or deleted.
    pub fn columns(at: u32, count: u32, insert: bool) -> SheetEdit {
        SheetEdit { axis: Axis::Columns, at, count, band: None, insert }
    }

    /// The cells of `rect` deleted (`insert` false), those below (`Axis::Rows`) or right of
    /// it moving into their place; or cells inserted over `rect`, its cells and those below
    /// (right) moving away. A rectangle as wide (tall) as the sheet is whole rows (columns).
    pub fn cells(rect: Rect, axis: Axis, insert: bool) -> SheetEdit {
        let (at, count, across, limit) = match axis {
            Axis::Rows => (rect.first.row, rect.rows(), (rect.first.col, rect.last.col), MAX_COLS),
            Axis::Columns => (rect.first.col, rect.cols(), (rect.first.row, rect.last.row), MAX_ROWS),
        };
        let band = (across != (0, limit - 1)).then_some(across);
        SheetEdit { axis, at, count, band, insert }
    }

    /// The last index along the axis.
    fn limit(&self) -> u32 {
        match self.axis {
            Axis::Rows => MAX_ROWS,
            Axis::Columns => MAX_COLS,
        }
    }

    /// The count of lines across the axis (columns when rows move).
    fn across_limit(&self) -> u32 {
        match self.axis {
            Axis::Rows => MAX_COLS,
            Axis::Columns => MAX_ROWS,
        }
    }

    /// (along the axis, across it) of `p`.
    fn split(&self, p: Pos) -> (u32, u32) {
        match self.axis {
            Axis::Rows => (p.row, p.col),
            Axis::Columns => (p.col, p.row),
        }
    }

    fn join(&self, along: u32, across: u32) -> Pos {
        match self.axis {
            Axis::Rows => Pos::new(along, across),
            Axis::Columns => Pos::new(across, along),
        }
    }

    /// Whether what spans `across` (inclusive) lies wholly in the moving band.
    pub(super) fn covers(&self, across: (u32, u32)) -> bool {
        self.band.is_none_or(|(b1, b2)| b1 <= across.0 && across.1 <= b2)
    }

    /// Whether `across` meets the moving band.
    pub(super) fn meets(&self, across: (u32, u32)) -> bool {
        self.band.is_none_or(|(b1, b2)| across.0 <= b2 && b1 <= across.1)
    }

    /// Where the index `along` of a moving cell goes; `None` when it is deleted (or pushed
    /// off the sheet).
    fn index(&self, along: u32) -> Option<u32> {
        if along < self.at {
            return Some(along);
        }
        if self.insert {
            let to = along as u64 + self.count as u64;
            return (to < self.limit() as u64).then_some(to as u32);
        }
        (along >= self.at + self.count).then(|| along - self.count)
    }

    /// Where the span `along` (inclusive) of a reference goes: deleted wholly, `None`
    /// (`#REF!`); cut through, shrunk to what is left; an insertion inside it, grown.
    fn span(&self, (s1, s2): (u32, u32)) -> Option<(u32, u32)> {
        let last = self.limit() - 1;
        if self.insert {
            if s1 >= self.at {
                let first = self.index(s1)?;
                return Some((first, (s2 + self.count).min(last)));
            }
            return Some(if s2 >= self.at { (s1, (s2 + self.count).min(last)) } else { (s1, s2) });
        }
        let (d1, d2) = (self.at, self.at + self.count - 1);
        match (s1 < d1, s2 > d2) {
            _ if s2 < d1 => Some((s1, s2)),
            _ if s1 > d2 => Some((s1 - self.count, s2 - self.count)),
            (false, false) => None,
            (first_kept, last_kept) => {
                let first = if first_kept { s1 } else { d1 };
                let last = if last_kept { s2 - self.count } else { d1 - 1 };
                Some((first, last))
            }
        }
    }

    /// Where the cell at `p` goes (what is kept by position, a cell's format, follows it):
    /// `None` when it is deleted.
    pub fn moved(&self, p: Pos) -> Option<Pos> {
        let (along, across) = self.split(p);
        if !self.covers((across, across)) {
            return Some(p);
        }
        self.index(along).map(|a| self.join(a, across))
    }

    /// Where the cells of `rect` go, as a macro's Range object follows them: `None` when they
    /// are all deleted; cut through, shrunk to what is left; an insertion inside, grown.
    /// Whole columns stay whole when rows come or go (and whole rows when columns do).
    pub fn moved_rect(&self, rect: Rect) -> Option<Rect> {
        let whole_across = match self.axis {
            Axis::Rows => rect.rows() == MAX_ROWS,
            Axis::Columns => rect.cols() == MAX_COLS,
        };
        let (a1, c1) = self.split(rect.first);
        let (a2, c2) = self.split(rect.last);
        if whole_across || !self.covers((c1, c2)) {
            return Some(rect);
        }
        let (b1, b2) = self.span((a1, a2))?;
        Some(Rect::new(self.join(b1, c1), self.join(b2, c2)))
    }

    /// Where row (for `Axis::Rows`; else column) `index` goes, with what is kept by row
    /// (a height, hiddenness) or column (a width): only whole rows (columns) move them.
    pub fn moved_line(&self, index: u32) -> Option<u32> {
        match self.band {
            Some(_) => Some(index),
            None => self.index(index),
        }
    }

    /// Whether the edit would cut through an array's area `rect` (part of it moved or
    /// deleted and part not), which Excel refuses ("You can't change part of an array").
    fn cuts(&self, rect: Rect) -> bool {
        let (a1, c1) = self.split(rect.first);
        let (a2, c2) = self.split(rect.last);
        if a2 < self.at || !self.meets((c1, c2)) {
            return false;
        }
        if !self.covers((c1, c2)) {
            return true;
        }
        let deleted_whole = !self.insert && a1 >= self.at && a2 < self.at + self.count;
        let moved_whole = if self.insert { a1 >= self.at } else { a1 >= self.at + self.count };
        !(deleted_whole || moved_whole)
    }
}

/// A moving formula: one whose references all point where they did relative to it keeps
/// its stored formula (shared with its copies); one whose references changed is rewritten.
enum Rewrite {
    Kept(u32),
    New { old: u32, tree: Expr },
}

/// A reference after the edit: the same, rewritten, or pointing at deleted cells (`#REF!`).
enum Followed {
    Same,
    To(Reference),
    Deleted,
}

/// A cell the edit changes: its id, where it goes (`None`: deleted) and what it will hold.
type Move = (u32, Option<Pos>, Content);

/// A cell's new content, written once every moving cell has been cleared.
enum Content {
    /// A formula (with a legacy array's rows and columns): its own, or rewritten.
    Formula(Rewrite, Option<(u32, u32)>),
    Value(Value),
    /// Formula text that does not parse, with the value its file cached if it keeps one.
    Unparsed(String, ParseError, Option<Value>),
}

impl Workbook {
    /// Inserts or deletes rows, columns or a rectangle's cells on `sheet` (see [`SheetEdit`])
    /// and recalculates. Refused, with nothing changed, when the edit would cut through an
    /// array formula's or a spill's area, or push filled cells off the sheet.
    pub fn shift_cells(&mut self, sheet: SheetId, edit: SheetEdit) -> Result<(), WorkbookError> {
        if edit.count == 0 {
            return Ok(());
        }
        if edit.at as u64 + edit.count as u64 > edit.limit() as u64 {
            return Err(WorkbookError::CannotShift("the rows or columns are off the sheet".into()));
        }
        self.check_arrays_whole(sheet, &edit)?;
        self.check_tables_whole(sheet, &edit)?;
        let mut moves = self.moves(sheet, &edit)?;
        let idle = self.idle_cells(sheet, &edit);
        let free = self.free_slots(&moves);
        // Unlinked while their edges lie where they were made: the moving cells are cleared
        // and written below, which unlinks and links the formulas among them.
        let readers = self.other_readers(sheet, &edit, &moves);
        for &id in &readers {
            self.unlink(id);
        }
        let mut touched: Vec<u32> = moves.iter().map(|&(id, _, _)| id).chain(readers.iter().copied()).collect();
        for &(id, _, _) in &moves {
            let c = &self.cells[id as usize];
            let (s, p) = (c.sheet, c.pos);
            let first_edit = self.changes.as_ref().is_some_and(|log| !log.inputs.contains(id));
            self.set_constant(s, p, Value::Blank);
            if first_edit {
                // A formula moved or deleted with its row was not replaced by a constant
                // (what `Changes::formulas_replaced` warns of when saving).
                self.changes.as_mut().map(|log| log.had_formula.remove(&id));
            }
        }
        self.store_rewrites(&mut moves, &free);
        self.place_moved_cells(&moves, idle);
        // Before the moved cells are written: each grows the extent to where it went, and
        // moving the extent after that would move its last line twice.
        self.move_extent(sheet, &edit);
        for (id, to, content) in moves {
            let s = self.cells[id as usize].sheet;
            let Some(to) = to else { continue };
            match content {
                Content::Formula(rewrite, area) => {
                    let Rewrite::Kept(fid) = rewrite else { unreachable!("stored by store_rewrites") };
                    let cell = self.cleared_cell(s, to);
                    self.install_formula(cell, fid);
                    if let Some((rows, cols)) = area {
                        let last = Pos::new(to.row + rows - 1, to.col + cols - 1);
                        self.set_array_area_deferred(s, Rect::new(to, last));
                    }
                }
                Content::Value(v) => self.set_value_deferred(s, to, v),
                Content::Unparsed(text, why, Some(v)) => self.keep_formula_value_deferred(s, to, &text, why, v),
                Content::Unparsed(text, _, None) => {
                    let _still_unparsed = self.set_input_deferred(s, to, &text);
                }
            }
            touched.extend(self.sheets[s as usize].get(to));
        }
        let names_moved = self.follow_names(sheet, &edit);
        self.follow_tables(sheet, &edit);
        self.shift_lines(sheet, &edit);
        if let Some(log) = self.changes.as_mut() {
            log.names |= names_moved;
            log.shifted = true;
        }
        for &id in &readers {
            self.link(id);
        }
        self.recalculate_shifted(sheet, touched);
        Ok(())
    }

    /// Recomputes what the edit changed: the cells it cleared, wrote or relinked and what
    /// depends on them, as an edit of those cells would, and the spills blocked on `sheet`
    /// (what blocked one may have moved away). A full recalculation when names were
    /// redefined before without relinking, which only it catches up on.
    fn recalculate_shifted(&mut self, sheet: SheetId, mut touched: Vec<u32>) {
        self.ranges.drop_unused();
        if self.names_unlinked {
            self.recalculate();
            return;
        }
        let blocked = self.spill.blocked_anchors().filter(|&a| self.cells[a as usize].sheet == sheet);
        touched.extend(blocked.collect::<Vec<_>>());
        self.recalculate_from(touched);
    }

    /// The formula cells not among `moves` whose edges reach the part of `sheet` the edit
    /// moves or deletes: those reading it through a defined name, a 3-D reference, or a
    /// reference made at run time (INDIRECT, OFFSET), whose formula the edit leaves as it
    /// is while the cells under it move. Found through the graph, before anything moves:
    /// the dependents of the cells there and of the range nodes meeting it. Every other
    /// formula reading there is among `moves`, its reference following its cells.
    fn other_readers(&self, sheet: SheetId, edit: &SheetEdit, moves: &[Move]) -> Vec<u32> {
        let mut readers = Vec::new();
        for (id, c) in self.cells.iter().enumerate() {
            if c.sheet == sheet
                && !c.dependents.is_empty()
                && edit.moved(c.pos) != Some(c.pos)
                && self.sheets[sheet as usize].get(c.pos) == Some(id as u32)
            {
                readers.extend_from_slice(c.dependents.as_slice());
            }
        }
        let (across_first, across_last) = edit.band.unwrap_or((0, edit.across_limit() - 1));
        let part = Rect::new(edit.join(edit.at, across_first), edit.join(edit.limit() - 1, across_last));
        // Each node looked at once: `RangeIndex::meeting` reads a bucket per column and 16
        // rows, billions for the rest of a sheet.
        for node in self.ranges.nodes.iter().filter(|n| n.sheet == sheet && recalc::meets(n.rect, part)) {
            readers.extend_from_slice(node.dependents.as_slice());
        }
        readers.sort_unstable();
        readers.dedup();
        // `moves` is in cell order.
        readers.retain(|id| moves.binary_search_by_key(id, |&(moved, _, _)| moved).is_err());
        readers
    }

    /// Gives every moved cell a cell where it lands, before any is written (a formula
    /// written links the cells it reads, and would make them where a moved cell is still to
    /// come). Where no cell is, it takes one the edit leaves empty for good: a moving cell,
    /// once cleared, or a blank one in the moving part (`idle`), at a place nothing moves
    /// into and holding nothing kept by cell (a formula, text that did not parse, a note, a
    /// place in a spill). So an edit makes no more cells than it empties: a loop of
    /// `Columns(1).Insert` before a full column made a million cells a turn, and passed the
    /// workbook's cell limit in nine turns.
    fn place_moved_cells(&mut self, moves: &[Move], idle: Vec<u32>) {
        // The cells where something arrives, each at its place on the grid as the cells
        // offered for reuse are (by id: a map of a million places took a seventh of a
        // `Columns(1).Insert` before a full column).
        let mut arriving = CellBits::default();
        for &(id, to, _) in moves {
            if let Some(cell) = to.and_then(|to| self.sheets[self.cells[id as usize].sheet as usize].get(to)) {
                arriving.insert(cell);
            }
        }
        let reusable = |id: &u32| {
            let c = &self.cells[*id as usize];
            c.formula == NO_FORMULA
                && c.value.is_blank()
                && !arriving.contains(*id)
                && !self.bad_inputs.contains_key(id)
                && !self.notes.contains_key(id)
                && self.spill.owner(*id).is_none()
        };
        let mut spare: Vec<u32> = moves.iter().map(|&(id, _, _)| id).chain(idle).filter(reusable).collect();
        for &(id, to, _) in moves {
            let s = self.cells[id as usize].sheet;
            let Some(to) = to else { continue };
            if self.sheets[s as usize].get(to).is_some() {
                continue;
            }
            let Some(cell) = spare.pop() else { return };
            self.reuse_cell(cell, s, to);
        }
    }

    /// The blank cells of `sheet` the edit moves or deletes (a formula's link made them),
    /// read before the moving cells are cleared: nothing is written to their place, so
    /// [`Workbook::place_moved_cells`] may reuse them.
    fn idle_cells(&self, sheet: SheetId, edit: &SheetEdit) -> Vec<u32> {
        let idle = |(id, c): (usize, &Cell)| {
            let id = id as u32;
            (c.sheet == sheet
                && c.formula == NO_FORMULA
                && c.value.is_blank()
                && edit.moved(c.pos) != Some(c.pos)
                && self.sheets[sheet as usize].get(c.pos) == Some(id))
            .then_some(id)
        };
        self.cells.iter().enumerate().filter_map(idle).collect()
    }

    /// Moves emptied cell `id` ([`Workbook::place_moved_cells`]) to `to`, where no cell is:
    /// the place it leaves reads as blank without it (a csv saved after the edit writes the
    /// places of its text that hold nothing now as empty: `io::save`). The formulas that
    /// read it are unlinked already, and link the cells where they read next. The journal
    /// keeps the place it takes as blank before (an undo empties it).
    fn reuse_cell(&mut self, id: u32, sheet: SheetId, to: Pos) {
        let (left_sheet, left) = (self.cells[id as usize].sheet, self.cells[id as usize].pos);
        self.sheets[left_sheet as usize].unset(left);
        if let Some(journal) = self.journal.as_mut() {
            if journal.seen.insert((sheet, to)) {
                journal.before.push((sheet, to, String::new()));
            }
        }
        self.cells[id as usize].dependents = Deps::None;
        self.place_cell(id, sheet, to);
    }

    /// The stored formulas the rewritten ones may take over: a formula every one of whose
    /// cells is rewritten, all to one same tree (a filled-down column whose `$A$1` became
    /// `$A$2`, a `SUM` whose range grew), will serve no cell after the edit, so the new tree
    /// takes its slot. A macro inserting rows in a loop leaves the store as large as it was.
    /// Read before the moving cells are cleared.
    fn free_slots(&self, moves: &[Move]) -> Vec<u32> {
        // Per old formula: the first rewritten tree, how many cells are rewritten, all alike.
        let mut groups: FxMap<u32, (&Expr, usize, bool)> = FxMap::default();
        let mut deleted: FxMap<u32, usize> = FxMap::default();
        for (_, to, content) in moves {
            match content {
                Content::Formula(Rewrite::New { old, tree }, _) => {
                    let group = groups.entry(*old).or_insert((tree, 0, true));
                    group.1 += 1;
                    group.2 &= group.1 == 1 || group.0 == tree;
                }
                Content::Formula(Rewrite::Kept(old), _) if to.is_none() => *deleted.entry(*old).or_default() += 1,
                _ => {}
            }
        }
        if groups.is_empty() {
            return Vec::new();
        }
        let mut users: FxMap<u32, usize> = groups.keys().map(|&old| (old, 0)).collect();
        for c in &self.cells {
            if let Some(n) = users.get_mut(&c.formula) {
                *n += 1;
            }
        }
        let mut free: Vec<u32> = groups
            .into_iter()
            .filter(|(old, (_, count, alike))| *alike && users[old] == count + deleted.get(old).unwrap_or(&0))
            .map(|(old, _)| old)
            .collect();
        free.sort_unstable();
        free
    }

    /// Stores the rewritten trees, once the moving cells are cleared: in the slots `free`
    /// ([`Workbook::free_slots`]) or new ones, rewrites alike of one formula sharing one.
    /// Every `Rewrite::New` of `moves` becomes `Rewrite::Kept` of its stored formula.
    fn store_rewrites(&mut self, moves: &mut [Move], free: &[u32]) {
        let mut in_place = Vec::new();
        // The stored formula the last rewrite of each old one took, to share with the next.
        let mut last: FxMap<u32, u32> = FxMap::default();
        for (_, _, content) in moves.iter_mut() {
            let Content::Formula(rewrite @ Rewrite::New { .. }, _) = content else { continue };
            let Rewrite::New { old, tree } = std::mem::replace(rewrite, Rewrite::Kept(NO_FORMULA)) else {
                unreachable!("matched as New")
            };
            let fid = if free.binary_search(&old).is_ok() {
                if !last.contains_key(&old) {
                    in_place.push((old, SharedFormula::new(tree)));
                }
                old
            } else {
                match last.get(&old) {
                    Some(&fid) if *self.formulas.get(fid).expr == tree => fid,
                    _ => self.formulas.add(None, SharedFormula::new(tree)),
                }
            };
            last.insert(old, fid);
            *rewrite = Rewrite::Kept(fid);
        }
        self.formulas.replace(in_place);
    }

    /// Refuses an edit that would cut through a legacy array formula's area or a spill.
    fn check_arrays_whole(&self, sheet: SheetId, edit: &SheetEdit) -> Result<(), WorkbookError> {
        let fixed = self.fixed_arrays.iter().map(|(&id, &(rows, cols))| {
            let p = self.cells[id as usize].pos;
            (id, Rect::new(p, Pos::new(p.row + rows - 1, p.col + cols - 1)))
        });
        let spills = self.spill.anchors().filter_map(|id| self.spill.rect(id).map(|r| (id, r)));
        for (id, rect) in fixed.chain(spills) {
            if self.cells[id as usize].sheet == sheet && edit.cuts(rect) {
                let anchor = self.cell_name(sheet, self.cells[id as usize].pos);
                return Err(WorkbookError::CannotShift(format!(
                    "the edit would change part of the array of {anchor}, which Excel refuses: move or delete it whole"
                )));
            }
        }
        Ok(())
    }

    /// Every cell the edit moves, deletes (no destination) or whose formula it rewrites.
    fn moves(&self, sheet: SheetId, edit: &SheetEdit) -> Result<Vec<Move>, WorkbookError> {
        let mut moves = Vec::new();
        for (id, c) in self.cells.iter().enumerate() {
            let id = id as u32;
            let on_sheet = c.sheet == sheet;
            if !on_sheet && c.formula == NO_FORMULA {
                continue;
            }
            let to = if on_sheet { edit.moved(c.pos) } else { Some(c.pos) };
            if on_sheet && to.is_none() && edit.insert && c.formula != NO_FORMULA {
                return Err(pushed_off(self.cell_name(sheet, c.pos)));
            }
            if c.formula != NO_FORMULA {
                let Some(dest) = to else {
                    // Deleted: its formula is not written anywhere.
                    moves.push((id, to, Content::Formula(Rewrite::Kept(c.formula), None)));
                    continue;
                };
                let tree = self.formula_tree(c.sheet, c.pos).expect("a formula cell has a tree");
                let rewrite = match follow_tree(&tree, c.sheet, c.pos, dest, sheet, edit) {
                    None if dest == c.pos => continue,
                    None => Rewrite::Kept(c.formula),
                    Some(tree) => Rewrite::New { old: c.formula, tree },
                };
                moves.push((id, to, Content::Formula(rewrite, self.fixed_arrays.get(&id).copied())));
                continue;
            }
            if to == Some(c.pos) {
                continue;
            }
            let content = match self.bad_inputs.get(&id) {
                Some((text, why)) => {
                    let kept = self.kept_values.contains_key(&id).then(|| c.value.clone());
                    Content::Unparsed(text.clone(), why.clone(), kept)
                }
                None if c.value.is_blank() || self.spill.owner(id).is_some() => continue,
                None => Content::Value(c.value.clone()),
            };
            if to.is_none() && edit.insert {
                return Err(pushed_off(self.cell_name(sheet, c.pos)));
            }
            moves.push((id, to, content));
        }
        Ok(moves)
    }

    /// Defined names' absolute references follow the edit too; whether one did. A name's
    /// relative reference is read from the cell that uses it: it moves with that cell, not
    /// with the edit, so it stays as written beside absolute ones that follow.
    fn follow_names(&mut self, sheet: SheetId, edit: &SheetEdit) -> bool {
        let mut moved = false;
        for i in 0..self.names.len() {
            let name = &self.names[i];
            let home = name.scope.unwrap_or(SheetId::MAX);
            let origin = Pos::new(0, 0);
            let absolute = |r: &Reference| !has_relative(r);
            if let Some(tree) = follow_refs(&name.expr, home, origin, origin, sheet, edit, &absolute) {
                self.names[i].expr = Rc::new(tree);
                moved = true;
            }
        }
        moved
    }

    /// The sheet's used extent moves with whole rows and columns.
    fn move_extent(&mut self, sheet: SheetId, edit: &SheetEdit) {
        if edit.band.is_some() {
            return;
        }
        // A deleted last line leaves the line before the deleted ones last: every cell left
        // there lies before them; a deleted first line leaves the line after them first.
        self.sheets[sheet as usize].move_extent(
            edit.axis == Axis::Rows,
            |line| edit.index(line).unwrap_or(edit.at.saturating_sub(1)),
            |line| edit.index(line).unwrap_or(edit.at),
        );
    }

    /// Hidden rows and column widths move with whole rows and columns.
    fn shift_lines(&mut self, sheet: SheetId, edit: &SheetEdit) {
        if edit.band.is_some() {
            return;
        }
        let s = &mut self.sheets[sheet as usize];
        match edit.axis {
            Axis::Rows => {
                let hidden: Vec<(u32, RowHidden)> = s.hidden_rows().collect();
                for &(row, _) in &hidden {
                    s.set_row_hidden(row, None);
                }
                for (row, how) in hidden {
                    if let Some(to) = edit.index(row) {
                        s.set_row_hidden(to, Some(how));
                    }
                }
            }
            Axis::Columns => s.map_width_spans(|first, last| edit.span((first, last))),
        }
    }
}

fn has_relative(r: &Reference) -> bool {
    let coords: &[Coord] = match &r.shape {
        RefShape::Cell(c) => &[c.row, c.col],
        RefShape::Cells(a, b) => &[a.row, a.col, b.row, b.col],
        RefShape::Cols(a, b) | RefShape::Rows(a, b) => &[*a, *b],
    };
    coords.iter().any(|c| !c.absolute)
}

/// The formula `tree`, written in cell `from` of sheet `home` and moving to `to`, with its
/// references following `edit` of sheet `edited`; `None` when nothing in it changes (its
/// references, relative ones counted from `to`, are as written).
fn follow_tree(tree: &Expr, home: SheetId, from: Pos, to: Pos, edited: SheetId, edit: &SheetEdit) -> Option<Expr> {
    follow_refs(tree, home, from, to, edited, edit, &|_| true)
}

/// [`follow_tree`] for the references `moving` picks; the others stay as written.
fn follow_refs(
    tree: &Expr,
    home: SheetId,
    from: Pos,
    to: Pos,
    edited: SheetId,
    edit: &SheetEdit,
    moving: &dyn Fn(&Reference) -> bool,
) -> Option<Expr> {
    let followed = |r: &Reference| if moving(r) { follow(r, home, from, to, edited, edit) } else { Followed::Same };
    let mut changed = false;
    tree.visit_refs(&mut |r| changed |= !matches!(followed(r), Followed::Same));
    if !changed {
        return None;
    }
    let mut tree = tree.clone();
    each_ref_mut(&mut tree, &mut |e| {
        let ExprKind::Ref(r) = &e.kind else { return };
        match followed(r) {
            Followed::Same => {}
            Followed::To(r) => e.kind = ExprKind::Ref(r),
            Followed::Deleted => e.kind = ExprKind::Error(XlError::Ref),
        }
    });
    Some(tree)
}

/// Calls `f` on every reference node of the tree.
fn each_ref_mut(e: &mut Expr, f: &mut dyn FnMut(&mut Expr)) {
    e.visit_mut(&mut |node| {
        if matches!(node.kind, ExprKind::Ref(_)) {
            f(node)
        }
    });
}

/// Reference `r` of a formula in `from` on sheet `home` (moving to `to`) after `edit` of
/// sheet `edited`.
fn follow(r: &Reference, home: SheetId, from: Pos, to: Pos, edited: SheetId, edit: &SheetEdit) -> Followed {
    let target = match &r.sheet {
        SheetRef::Current => home,
        SheetRef::Id(id) => *id,
        // A 3-D reference names the same cells on several sheets: rows or columns inserted
        // on one of them leave it as it is (Excel moves it only when every sheet of the span
        // is edited at once, sheets grouped, which no edit here does).
        SheetRef::Missing(_) | SheetRef::Span(..) => return Followed::Same,
    };
    let Some((_, rect)) = r.resolve(home, from) else { return Followed::Same };
    let rect = if target == edited { follow_rect(rect, &r.shape, edit) } else { Some(rect) };
    let Some(rect) = rect else { return Followed::Deleted };
    let shape = reshape(&r.shape, rect, from, to);
    if shape == r.shape {
        Followed::Same
    } else {
        Followed::To(Reference { sheet: r.sheet.clone(), shape })
    }
}

/// Where the cells of a reference covering `rect` go; `None` when they are all deleted.
fn follow_rect(rect: Rect, shape: &RefShape, edit: &SheetEdit) -> Option<Rect> {
    // Whole columns (rows) stay whole when rows (columns) come or go.
    let spans_axis =
        !matches!((shape, edit.axis), (RefShape::Cols(..), Axis::Rows) | (RefShape::Rows(..), Axis::Columns));
    let (a1, c1) = edit.split(rect.first);
    let (a2, c2) = edit.split(rect.last);
    if !spans_axis || !edit.covers((c1, c2)) {
        return Some(rect);
    }
    let (b1, b2) = edit.span((a1, a2))?;
    Some(Rect::new(edit.join(b1, c1), edit.join(b2, c2)))
}

/// `shape` pointing at `rect`, its relative coordinates counted from `to` (they were
/// counted from `from`). The corners keep the order they were written in (`A3:A1` stays so).
fn reshape(shape: &RefShape, rect: Rect, from: Pos, to: Pos) -> RefShape {
    let coord = |old: Coord, index: u32, base: u32| {
        if old.absolute {
            Coord::absolute(index)
        } else {
            Coord::relative(index as i32 - base as i32)
        }
    };
    let row = |old: Coord, index: u32| coord(old, index, to.row);
    let col = |old: Coord, index: u32| coord(old, index, to.col);
    // The written corners as they were: the first the lower one, or the other way round.
    let pair = |a: Coord, b: Coord, base: u32, lo: u32, hi: u32| {
        let v = |c: Coord| if c.absolute { c.value as i64 } else { base as i64 + c.value as i64 };
        if v(a) <= v(b) {
            (lo, hi)
        } else {
            (hi, lo)
        }
    };
    let rows = |a: Coord, b: Coord| pair(a, b, from.row, rect.first.row, rect.last.row);
    let cols = |a: Coord, b: Coord| pair(a, b, from.col, rect.first.col, rect.last.col);
    match *shape {
        RefShape::Cell(c) => {
            RefShape::Cell(CellCoord { row: row(c.row, rect.first.row), col: col(c.col, rect.first.col) })
        }
        RefShape::Cells(a, b) => {
            let (ar, br) = rows(a.row, b.row);
            let (ac, bc) = cols(a.col, b.col);
            RefShape::Cells(
                CellCoord { row: row(a.row, ar), col: col(a.col, ac) },
                CellCoord { row: row(b.row, br), col: col(b.col, bc) },
            )
        }
        RefShape::Rows(a, b) => {
            let (x, y) = rows(a, b);
            RefShape::Rows(row(a, x), row(b, y))
        }
        RefShape::Cols(a, b) => {
            let (x, y) = cols(a, b);
            RefShape::Cols(col(a, x), col(b, y))
        }
    }
}

/// The refusal of an insert that would push the filled cell `cell` (a value or a formula) off
/// the sheet, as Excel refuses it.
fn pushed_off(cell: String) -> WorkbookError {
    WorkbookError::CannotShift(format!(
        "{cell} would be pushed off the sheet: Excel cannot shift filled cells off the worksheet"
    ))
}
