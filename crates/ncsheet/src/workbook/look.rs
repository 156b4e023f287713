//! How a sheet looks: its cells' number formats and styles, its columns' widths and its rows'
//! heights. One type for the file's look (the xlsx reader fills it, the writers save it) and
//! the macro's (a run starts from it and leaves its changes in it), kept by the `Document`.
//! Nothing here changes a value.

use std::borrow::Borrow;
use std::collections::{BTreeMap, HashMap};
use std::hash::Hash;

use crate::eval::format::cell_style::CellStyle;
use crate::formula::address::{Pos, Rect};

use super::{Axis, SheetEdit};

/// A sheet's look, as a file keeps it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SheetLook {
    /// Cells with a number format other than General, with its format code.
    pub number_formats: LooksByCell<String>,
    /// Cells with more style than the Normal style (alignment, bold, fill …).
    pub cell_styles: LooksByCell<CellStyle>,
    /// Column → width in characters of the Normal font's digits, as stored in the file and
    /// as `ColumnWidth` gives it.
    pub column_widths: Vec<(u16, f64)>,
    /// Row → height in points.
    pub row_heights: Vec<(u32, f64)>,
    /// Rows hidden (`<row hidden="1">`, `Rows(3).Hidden = True`), by hand or by a filter.
    pub hidden_rows: Vec<u32>,
    /// Columns hidden (`<col hidden="1">`, `Columns("C").Hidden = True`).
    pub hidden_columns: Vec<u16>,
    /// The sheet's hyperlinks in the order they were made (`<hyperlinks>`, `Hyperlinks.Add`).
    pub hyperlinks: Vec<Hyperlink>,
}

/// A hyperlink on cells (Excel's Hyperlink object): where it leads, a file or web address
/// (`Address`) and/or a place in the workbook (`SubAddress`, `'Sheet 2'!A1`), and the text
/// and tip it shows.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Hyperlink {
    /// The cells it is on (`ref`, `Anchor`).
    pub anchor: Rect,
    /// An address outside the workbook (a relationship's target in the file), "" for none.
    pub address: String,
    /// A place in the workbook (`location` in the file), "" for none.
    pub sub_address: String,
    /// `display`, `TextToDisplay`.
    pub text: Option<String>,
    /// `tooltip`, `ScreenTip`.
    pub tip: Option<String>,
}

impl SheetLook {
    /// Rows, columns or cells inserted or deleted: each cell's format and style, each
    /// column's width and each row's height go where their cells went (Excel moves them
    /// with the cells); a deleted one's dropped.
    pub fn follow(&mut self, edit: &SheetEdit) {
        self.number_formats.follow(edit);
        self.cell_styles.follow(edit);
        match edit.axis {
            Axis::Columns => {
                self.column_widths = follow_columns(std::mem::take(&mut self.column_widths), edit);
                self.hidden_columns = follow_hidden_columns(std::mem::take(&mut self.hidden_columns), edit);
            }
            Axis::Rows => {
                self.row_heights = follow_rows(std::mem::take(&mut self.row_heights), edit);
                self.hidden_rows = follow_hidden_rows(std::mem::take(&mut self.hidden_rows), edit);
            }
        }
        self.hyperlinks.retain_mut(|link| follow_hyperlink(link, edit));
    }

    /// The same look with its widths and heights in order, one each (the last given wins),
    /// so that two looks compare by what they show.
    pub fn in_order(mut self) -> SheetLook {
        let widths: BTreeMap<u16, f64> = self.column_widths.into_iter().collect();
        let heights: BTreeMap<u32, f64> = self.row_heights.into_iter().collect();
        self.column_widths = widths.into_iter().collect();
        self.row_heights = heights.into_iter().collect();
        self.hidden_rows.sort_unstable();
        self.hidden_rows.dedup();
        self.hidden_columns.sort_unstable();
        self.hidden_columns.dedup();
        self
    }

    /// Nothing but the Normal look.
    pub fn is_plain(&self) -> bool {
        self.number_formats.is_empty()
            && self.cell_styles.is_empty()
            && self.column_widths.is_empty()
            && self.row_heights.is_empty()
            && self.hidden_rows.is_empty()
            && self.hidden_columns.is_empty()
            && self.hyperlinks.is_empty()
    }
}

/// A look (a format code, a style) by cell, each distinct look kept once and each cell
/// holding its look's index, the cells in order: a sheet styles a million cells with a
/// handful of looks, and a copy of the look in every cell of a hash map cost a hundred MiB.
/// A reader gives all its cells at once (`collect`); an edit's cell goes in between others,
/// moving those after it.
#[derive(Clone, Debug)]
pub struct LooksByCell<T> {
    /// (cell, index into `distinct`), in the order of the cells.
    cells: Vec<(Pos, u32)>,
    distinct: Vec<T>,
    index_of: HashMap<T, u32>,
}

impl<T> Default for LooksByCell<T> {
    fn default() -> Self {
        LooksByCell { cells: Vec::new(), distinct: Vec::new(), index_of: HashMap::new() }
    }
}

impl<T: Clone + Eq + Hash> LooksByCell<T> {
    /// `pos` gets `look` (in place of the one it had).
    pub fn insert(&mut self, pos: Pos, look: T) {
        let index = self.index_for(&look);
        match self.cells.binary_search_by_key(&pos, |&(p, _)| p) {
            Ok(at) => self.cells[at].1 = index,
            Err(at) => self.cells.insert(at, (pos, index)),
        }
    }

    fn index_for(&mut self, look: &T) -> u32 {
        if let Some(&index) = self.index_of.get(look) {
            return index;
        }
        // A sheet holds fewer cells than 2^32 in memory, so fewer distinct looks.
        let index = u32::try_from(self.distinct.len()).expect("fewer distinct looks than cells");
        self.distinct.push(look.clone());
        self.index_of.insert(look.clone(), index);
        index
    }
}

impl<T> LooksByCell<T> {
    pub fn get(&self, pos: &Pos) -> Option<&T> {
        let at = self.cells.binary_search_by_key(pos, |&(p, _)| p).ok()?;
        Some(&self.distinct[self.cells[at].1 as usize])
    }

    pub fn contains_key(&self, pos: &Pos) -> bool {
        self.get(pos).is_some()
    }

    /// The cells with a look, by row and column.
    pub fn keys(&self) -> impl Iterator<Item = &Pos> {
        self.cells.iter().map(|(pos, _)| pos)
    }

    /// Each cell with its look, by row and column.
    pub fn iter(&self) -> impl Iterator<Item = (&Pos, &T)> {
        self.cells.iter().map(|(pos, index)| (pos, &self.distinct[*index as usize]))
    }

    pub fn len(&self) -> usize {
        self.cells.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// How many different looks the cells share.
    pub fn distinct_len(&self) -> usize {
        self.distinct.len()
    }

    /// Each look moved with its cell by `edit`; a deleted cell's dropped.
    pub fn follow(&mut self, edit: &SheetEdit) {
        let cells = std::mem::take(&mut self.cells).into_iter();
        self.cells = cells.filter_map(|(pos, index)| Some((edit.moved(pos)?, index))).collect();
        // Cells moved down a band of columns pass cells beside them.
        self.cells.sort_unstable_by_key(|&(pos, _)| pos);
    }
}

/// Two tables are equal when every cell has the same look, however their looks are numbered.
impl<T: PartialEq> PartialEq for LooksByCell<T> {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().zip(other.iter()).all(|(a, b)| a == b)
    }
}

impl<T> std::ops::Index<&Pos> for LooksByCell<T> {
    type Output = T;

    fn index(&self, pos: &Pos) -> &T {
        self.get(pos).expect("the cell has a look")
    }
}

/// The cells in any order; a cell given twice keeps its last look, as a map's would.
impl<T: Clone + Eq + Hash> FromIterator<(Pos, T)> for LooksByCell<T> {
    fn from_iter<I: IntoIterator<Item = (Pos, T)>>(given: I) -> Self {
        let mut table = LooksByCell::default();
        table.add_all(given);
        table
    }
}

/// Borrowed looks, each copied once however many cells share it (a reader's million cells
/// and its handful of styles).
impl<'a, T: Clone + Eq + Hash + 'a> FromIterator<(Pos, &'a T)> for LooksByCell<T> {
    fn from_iter<I: IntoIterator<Item = (Pos, &'a T)>>(given: I) -> Self {
        let mut table = LooksByCell::default();
        table.add_all(given);
        table
    }
}

/// Many cells at once (a csv's million fields), put in order once rather than one by one;
/// a cell given again keeps the last look given.
impl<T: Clone + Eq + Hash> Extend<(Pos, T)> for LooksByCell<T> {
    fn extend<I: IntoIterator<Item = (Pos, T)>>(&mut self, given: I) {
        self.add_all(given);
    }
}

impl<T: Clone + Eq + Hash> LooksByCell<T> {
    fn add_all<L: Borrow<T>>(&mut self, given: impl IntoIterator<Item = (Pos, L)>) {
        let mut cells = std::mem::take(&mut self.cells);
        cells.extend(given.into_iter().map(|(pos, look)| (pos, self.index_for(look.borrow()))));
        // Stable (and quick on cells already in order, as a file gives them), so that of a
        // cell given twice the later comes last, and is kept.
        cells.sort_by_key(|&(pos, _)| pos);
        cells.dedup_by(|later, kept| {
            let same = later.0 == kept.0;
            if same {
                kept.1 = later.1;
            }
            same
        });
        cells.shrink_to_fit();
        self.cells = cells;
    }
}

/// What is kept by cell moved with its cell by `edit`; a deleted cell's dropped.
pub fn follow_cells<T>(map: &mut HashMap<Pos, T>, edit: &SheetEdit) {
    *map = std::mem::take(map).into_iter().filter_map(|(p, v)| edit.moved(p).map(|to| (to, v))).collect();
}

/// Columns' widths moved by an edit of columns; a deleted column's dropped.
pub fn follow_columns<C: FromIterator<(u16, f64)>>(
    widths: impl IntoIterator<Item = (u16, f64)>,
    edit: &SheetEdit,
) -> C {
    let moved = |(col, w): (u16, f64)| edit.moved_line(u32::from(col)).map(|c| (c as u16, w));
    widths.into_iter().filter_map(moved).collect()
}

/// Rows' heights moved by an edit of rows; a deleted row's dropped.
pub fn follow_rows<C: FromIterator<(u32, f64)>>(heights: impl IntoIterator<Item = (u32, f64)>, edit: &SheetEdit) -> C {
    heights.into_iter().filter_map(|(row, h)| Some((edit.moved_line(row)?, h))).collect()
}

/// Hidden columns moved by an edit of columns; a deleted one's dropped.
pub fn follow_hidden_columns<C: FromIterator<u16>>(columns: impl IntoIterator<Item = u16>, edit: &SheetEdit) -> C {
    columns.into_iter().filter_map(|col| edit.moved_line(u32::from(col)).map(|c| c as u16)).collect()
}

/// Hidden rows moved by an edit of rows; a deleted one's dropped.
pub fn follow_hidden_rows<C: FromIterator<u32>>(rows: impl IntoIterator<Item = u32>, edit: &SheetEdit) -> C {
    rows.into_iter().filter_map(|row| edit.moved_line(row)).collect()
}

/// A hyperlink goes with its cells (Excel moves a hyperlink with its anchor); one whose cells
/// were all deleted is gone (false).
pub fn follow_hyperlink(link: &mut Hyperlink, edit: &SheetEdit) -> bool {
    match edit.moved_rect(link.anchor) {
        Some(anchor) => {
            link.anchor = anchor;
            true
        }
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bold() -> CellStyle {
        CellStyle { bold: true, ..CellStyle::default() }
    }

    #[test]
    fn a_thousand_cells_sharing_one_look_keep_it_once() {
        let mut styles = LooksByCell::default();
        let mut formats = LooksByCell::default();
        for row in 0..1000 {
            styles.insert(Pos::new(row, 2), bold());
            formats.insert(Pos::new(row, 2), "0.000".to_string());
        }
        assert_eq!((styles.len(), styles.distinct_len()), (1000, 1));
        assert_eq!((formats.len(), formats.distinct_len()), (1000, 1));
        assert_eq!(styles.get(&Pos::new(999, 2)), Some(&bold()));
        assert_eq!(formats.get(&Pos::new(0, 2)).map(String::as_str), Some("0.000"));
        assert_eq!(styles.get(&Pos::new(0, 3)), None);
    }

    #[test]
    fn a_cell_given_a_new_look_shows_it_and_the_others_keep_theirs() {
        let mut formats: LooksByCell<String> =
            [(Pos::new(0, 0), "0.0"), (Pos::new(1, 0), "0.0")].into_iter().map(|(p, c)| (p, c.to_string())).collect();
        formats.insert(Pos::new(1, 0), "0%".to_string());
        assert_eq!(formats.get(&Pos::new(0, 0)).map(String::as_str), Some("0.0"));
        assert_eq!(formats[&Pos::new(1, 0)], "0%");
        assert_eq!((formats.len(), formats.distinct_len()), (2, 2));
    }

    #[test]
    fn looks_move_with_their_cells_when_rows_go_in_and_out() {
        let mut styles: LooksByCell<CellStyle> =
            [(Pos::new(0, 0), bold()), (Pos::new(3, 0), bold())].into_iter().collect();
        // Two rows inserted above row 2 (0-based 1): A4 goes to A6, A1 stays.
        styles.follow(&SheetEdit::rows(1, 2, true));
        assert_eq!(
            styles.keys().copied().collect::<std::collections::BTreeSet<_>>(),
            [Pos::new(0, 0), Pos::new(5, 0)].into()
        );
        // Row 1 deleted: its cell's look goes with it, A6 moves up to A5.
        styles.follow(&SheetEdit::rows(0, 1, false));
        assert_eq!(styles.iter().map(|(p, s)| (*p, *s)).collect::<Vec<_>>(), vec![(Pos::new(4, 0), bold())]);
    }

    #[test]
    fn tables_compare_by_each_cells_look_not_by_how_looks_are_numbered() {
        let (a, b) = (Pos::new(0, 0), Pos::new(5, 1));
        let one: LooksByCell<String> = [(a, "0.0".to_string()), (b, "0%".to_string())].into_iter().collect();
        let other: LooksByCell<String> = [(b, "0%".to_string()), (a, "0.0".to_string())].into_iter().collect();
        assert_eq!(one, other);
        let twice: LooksByCell<String> =
            [(b, "0.0".to_string()), (a, "0.0".to_string()), (b, "0%".to_string())].into_iter().collect();
        assert_eq!(twice, one, "the last look given a cell is kept");
        let mut extended: LooksByCell<String> = [(b, "0.0".to_string())].into_iter().collect();
        extended.extend([(a, "0.0".to_string()), (b, "0%".to_string())]);
        assert_eq!(extended, one, "extended as if inserted one by one");
        let third: LooksByCell<String> = [(a, "0%".to_string()), (b, "0.0".to_string())].into_iter().collect();
        assert_ne!(one, third);
    }
}
