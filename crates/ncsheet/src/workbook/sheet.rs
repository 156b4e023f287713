//! One sheet's grid: which cell id sits at each position. Columns are dense vectors,
//! which suits spreadsheets (data runs down columns) and makes range scans cheap.

use std::collections::BTreeMap;

use crate::eval::RowHidden;
use crate::formula::address::{Pos, Rect};

/// Marks an empty slot.
pub const NO_CELL: u32 = u32::MAX;

pub struct Sheet {
    pub name: String,
    columns: Vec<Vec<u32>>,
    /// The last row and column that ever held a value (grows only; blank cells that exist
    /// because a formula points at them do not count).
    extent: Option<Pos>,
    /// The first row and column that ever held a value, as `extent` the last: Excel's
    /// UsedRange starts there, not at A1.
    origin: Option<Pos>,
    /// Hidden rows (0-based), as the file hid them.
    hidden_rows: BTreeMap<u32, RowHidden>,
    /// Column widths in characters as Excel shows them: spans (first, last column, width),
    /// later spans over earlier ones, and the width of the other columns.
    widths: Vec<(u32, u32, f64)>,
    default_width: Option<f64>,
    /// Whether the sheet's tab shows (`<sheet state=…>`; a macro's `Visible`).
    pub visibility: Visibility,
    /// The sheet was deleted (`delete_sheet.rs`): its id stays taken, its grid empty.
    pub deleted: bool,
}

/// Excel's `XlSheetVisibility`: a sheet shown, hidden, or hidden so that only a macro can
/// show it again.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Visibility {
    #[default]
    Visible,
    Hidden,
    VeryHidden,
}

impl Sheet {
    pub fn new(name: &str) -> Sheet {
        Sheet {
            name: name.to_string(),
            columns: Vec::new(),
            extent: None,
            origin: None,
            hidden_rows: BTreeMap::new(),
            widths: Vec::new(),
            default_width: None,
            visibility: Visibility::Visible,
            deleted: false,
        }
    }

    /// The width of column `col` in characters, `None` when the sheet says nothing of it.
    pub fn column_width(&self, col: u32) -> Option<f64> {
        let own = self.widths.iter().rev().find(|(first, last, _)| (*first..=*last).contains(&col));
        own.map(|&(_, _, w)| w).or(self.default_width)
    }

    /// Sets the width of columns `first..=last` (`None`: of every other column).
    pub fn set_column_width(&mut self, span: Option<(u32, u32)>, width: f64) {
        match span {
            Some((first, last)) => self.widths.push((first, last, width)),
            None => self.default_width = Some(width),
        }
    }

    /// Moves or drops the spans of set widths as columns are inserted or deleted: `f` gives
    /// a span's new first and last column, `None` when its columns are all deleted.
    pub fn map_width_spans(&mut self, f: impl Fn(u32, u32) -> Option<(u32, u32)>) {
        self.widths = self.widths.iter().filter_map(|&(a, b, w)| f(a, b).map(|(a, b)| (a, b, w))).collect();
    }

    /// Whether row `row` is hidden, and how.
    pub fn row_hidden(&self, row: u32) -> Option<RowHidden> {
        self.hidden_rows.get(&row).copied()
    }

    /// The hidden rows, in order, and how each is hidden.
    pub fn hidden_rows(&self) -> impl Iterator<Item = (u32, RowHidden)> + '_ {
        self.hidden_rows.iter().map(|(&row, &how)| (row, how))
    }

    /// Hides row `row` (`None` shows it again).
    pub fn set_row_hidden(&mut self, row: u32, hidden: Option<RowHidden>) {
        match hidden {
            Some(h) => self.hidden_rows.insert(row, h),
            None => self.hidden_rows.remove(&row),
        };
    }

    pub fn grow_extent(&mut self, p: Pos) {
        let e = self.extent.get_or_insert(p);
        e.row = e.row.max(p.row);
        e.col = e.col.max(p.col);
        let o = self.origin.get_or_insert(p);
        o.row = o.row.min(p.row);
        o.col = o.col.min(p.col);
    }

    /// The extent after whole rows (`rows`) or columns were inserted or deleted: its last line
    /// goes where `to` sends it, as the cells do; so a sheet's used range shrinks when its
    /// last column is deleted (Excel's UsedRange), where the extent only grew.
    /// The origin's first line goes where `first_to` sends it.
    pub fn move_extent(&mut self, rows: bool, to: impl Fn(u32) -> u32, first_to: impl Fn(u32) -> u32) {
        fn line(p: &mut Pos, rows: bool) -> &mut u32 {
            if rows {
                &mut p.row
            } else {
                &mut p.col
            }
        }
        if let Some(e) = self.extent.as_mut() {
            let last = line(e, rows);
            *last = to(*last);
        }
        if let Some(o) = self.origin.as_mut() {
            let first = line(o, rows);
            *first = first_to(*first);
        }
    }

    /// The rectangle from the first to the last row and column that ever held a value
    /// (Excel's UsedRange of the cells), or `None` when nothing was ever stored.
    pub fn used_area(&self) -> Option<Rect> {
        let last = self.extent?;
        let first = self.origin.unwrap_or(last);
        // Deleting every used line leaves the origin past the extent: the area is its last cell.
        Some(Rect::new(Pos::new(first.row.min(last.row), first.col.min(last.col)), last))
    }

    /// A1 to the extent, or `None` when nothing was ever stored.
    pub fn extent(&self) -> Option<Rect> {
        self.extent.map(|e| Rect::new(Pos::new(0, 0), e))
    }

    #[inline]
    pub fn get(&self, pos: Pos) -> Option<u32> {
        let id = *self.columns.get(pos.col as usize)?.get(pos.row as usize)?;
        (id != NO_CELL).then_some(id)
    }

    pub fn set(&mut self, pos: Pos, id: u32) {
        let (row, col) = (pos.row as usize, pos.col as usize);
        if self.columns.len() <= col {
            self.columns.resize_with(col + 1, Vec::new);
        }
        let column = &mut self.columns[col];
        if column.len() <= row {
            column.resize(row + 1, NO_CELL);
        }
        column[row] = id;
    }

    /// Forgets the cell at `pos` (an insertion or deletion reusing it elsewhere); a column
    /// left empty gives its memory back, so inserting columns before a full one in a loop
    /// does not keep a million empty slots for each column it passed.
    pub fn unset(&mut self, pos: Pos) {
        let Some(column) = self.columns.get_mut(pos.col as usize) else { return };
        let Some(slot) = column.get_mut(pos.row as usize) else { return };
        *slot = NO_CELL;
        while column.last() == Some(&NO_CELL) {
            column.pop();
        }
        if column.is_empty() {
            *column = Vec::new();
        }
    }

    /// Cell ids in `rect`, row by row.
    pub fn for_each_in(&self, rect: Rect, f: &mut dyn FnMut(Pos, u32)) {
        let last_col = (rect.last.col as usize).min(self.columns.len().saturating_sub(1));
        if self.columns.is_empty() || rect.first.col as usize > last_col {
            return;
        }
        let cols = &self.columns[rect.first.col as usize..=last_col];
        let last_row = cols.iter().map(Vec::len).max().unwrap_or(0).min(rect.last.row as usize + 1);
        if rect.is_cell() || cols.len() == 1 {
            let col = rect.first.col;
            for (row, &id) in cols[0].iter().enumerate().take(last_row).skip(rect.first.row as usize) {
                if id != NO_CELL {
                    f(Pos::new(row as u32, col), id);
                }
            }
            return;
        }
        let area = (last_row.saturating_sub(rect.first.row as usize)) as u64 * cols.len() as u64;
        let stored: u64 = cols.iter().map(|c| c.len() as u64).sum();
        if area > 4 * stored.max(1024) {
            // Few cells far apart (one in XFD1048576): walk the cells there are, not the
            // rows times the columns between them.
            let mut found: Vec<(u32, u32, u32)> = Vec::new();
            for (i, column) in cols.iter().enumerate() {
                let rows = column.iter().enumerate().take(last_row).skip(rect.first.row as usize);
                found.extend(rows.filter(|(_, &id)| id != NO_CELL).map(|(row, &id)| (row as u32, i as u32, id)));
            }
            found.sort_unstable();
            for (row, i, id) in found {
                f(Pos::new(row, rect.first.col + i), id);
            }
            return;
        }
        for row in rect.first.row as usize..last_row {
            for (i, column) in cols.iter().enumerate() {
                if let Some(&id) = column.get(row) {
                    if id != NO_CELL {
                        f(Pos::new(row as u32, rect.first.col + i as u32), id);
                    }
                }
            }
        }
    }
}
