//! How a sheet looks: its cells' number formats and styles, its columns' widths and its rows'
//! heights. One type for the file's look (the xlsx reader fills it, the writers save it) and
//! the macro's (a run starts from it and leaves its changes in it), kept by the `Document`.
//! Nothing here changes a value.

use std::collections::{BTreeMap, HashMap};

use crate::eval::format::cell_style::CellStyle;
use crate::formula::address::Pos;

use super::{Axis, SheetEdit};

/// A sheet's look, as a file keeps it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SheetLook {
    /// Cells with a number format other than General, with its format code.
    pub number_formats: HashMap<Pos, String>,
    /// Cells with more style than the Normal style (alignment, bold, fill …).
    pub cell_styles: HashMap<Pos, CellStyle>,
    /// Column → width in characters of the Normal font's digits, as stored in the file and
    /// as `ColumnWidth` gives it.
    pub column_widths: Vec<(u16, f64)>,
    /// Row → height in points.
    pub row_heights: Vec<(u32, f64)>,
}

impl SheetLook {
    /// Rows, columns or cells inserted or deleted: each cell's format and style, each
    /// column's width and each row's height go where their cells went (Excel moves them
    /// with the cells); a deleted one's dropped.
    pub fn follow(&mut self, edit: &SheetEdit) {
        follow_cells(&mut self.number_formats, edit);
        follow_cells(&mut self.cell_styles, edit);
        match edit.axis {
            Axis::Columns => self.column_widths = follow_columns(std::mem::take(&mut self.column_widths), edit),
            Axis::Rows => self.row_heights = follow_rows(std::mem::take(&mut self.row_heights), edit),
        }
    }

    /// The same look with its widths and heights in order, one each (the last given wins),
    /// so that two looks compare by what they show.
    pub fn in_order(mut self) -> SheetLook {
        let widths: BTreeMap<u16, f64> = self.column_widths.into_iter().collect();
        let heights: BTreeMap<u32, f64> = self.row_heights.into_iter().collect();
        self.column_widths = widths.into_iter().collect();
        self.row_heights = heights.into_iter().collect();
        self
    }

    /// Nothing but the Normal look.
    pub fn is_plain(&self) -> bool {
        self.number_formats.is_empty()
            && self.cell_styles.is_empty()
            && self.column_widths.is_empty()
            && self.row_heights.is_empty()
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
