//! Excel tables (`xl/tables/tableN.xml`, named from a worksheet's relationships). The
//! structured references that name their parts (`Table1[Qty]`) are read by the formula
//! language (`formula/table_ref.rs`) and looked up in the workbook's tables when evaluated.

use crate::formula::address::{parse_rect, Rect};
use crate::formula::ast::SheetId;
use crate::workbook::ColumnTotal;

use super::xml::{for_each_tag, unescape, TagKind};

/// A table: a named rectangle of a sheet with named columns — the workbook's own type, which
/// the macros' ListObjects read too.
pub use crate::workbook::TableShape as Table;

/// Reads a table part; `None` when it names no valid range.
pub fn parse_table(xml: &[u8], sheet: SheetId) -> Option<Table> {
    let mut table = None;
    let mut columns: Vec<String> = Vec::new();
    let mut style = None;
    let (mut calculated, mut totals) = (Vec::new(), Vec::new());
    for_each_tag(xml, &mut |tag, text| match tag.name {
        b"table" => {
            let number = |key: &str, default: u32| tag.parsed(key).unwrap_or(default);
            let name = tag.attr("displayName").or_else(|| tag.attr("name")).map(unescape).unwrap_or_default();
            let rect = tag.attr("ref").and_then(|r| parse_rect(&unescape(r)));
            if let Some(rect) = rect {
                let (header_rows, totals_rows) = (number("headerRowCount", 1), number("totalsRowCount", 0));
                table = Some(Table {
                    name,
                    sheet,
                    rect,
                    header_rows,
                    totals_rows,
                    columns: Vec::new(),
                    style: None,
                    calculated: Vec::new(),
                    totals: Vec::new(),
                    id: 0,
                });
            }
        }
        b"tableColumn" => {
            let name = tag.attr("name").map(unescape).unwrap_or_default();
            if let Some(label) = tag.attr("totalsRowLabel") {
                totals.push((name.clone(), ColumnTotal::Label(unescape(label))));
            } else if let Some(function) = tag.attr("totalsRowFunction").filter(|f| *f != b"none") {
                totals.push((name.clone(), ColumnTotal::Function(unescape(function))));
            }
            columns.push(name);
        }
        // The column's formula, in the `<tableColumn>` just read.
        b"calculatedColumnFormula" => {
            if let Some(column) = columns.last() {
                calculated.push((column.clone(), unescape(text)));
            }
        }
        // A `custom` total's formula, in the `<tableColumn>` just read.
        b"totalsRowFormula" => {
            if let Some((column, total)) = totals.last_mut() {
                if columns.last() == Some(column) && *total == ColumnTotal::Function("custom".into()) {
                    *total = ColumnTotal::Formula(unescape(text));
                }
            }
        }
        b"tableStyleInfo" => style = tag.attr("name").map(unescape),
        _ => {}
    });
    let mut table = table?;
    table.columns = columns;
    table.style = style;
    (table.calculated, table.totals) = (calculated, totals);
    (!table.name.is_empty()).then_some(table)
}

/// The range of a table part's `<autoFilter>` when it filters on a column: the rows it hides are filtered rows, which every SUBTOTAL skips.
pub fn active_filter(xml: &[u8]) -> Option<Rect> {
    let (mut area, mut filtering) = (None, false);
    for_each_tag(xml, &mut |tag, _| match tag.name {
        b"autoFilter" if tag.kind != TagKind::End => area = tag.attr("ref").and_then(|r| parse_rect(&unescape(r))),
        b"filterColumn" => filtering = true,
        _ => {}
    });
    area.filter(|_| filtering)
}
