//! Ranges of several areas, as Excel's Range object holds them ("Range.Areas property": "a
//! collection that contains one object for each selected area"): `Range("C5:D9,G9:H16")`,
//! `Union` of separate ranges, `Intersect` of such ranges, and what a macro does with them.
//! `Count`, `Address`, `Areas`, `For Each` (cells area by area) take every area;
//! `ClearContents`, `Clear`, `ClearFormats`, `Value =`, `Formula =`, `Offset`, `EntireRow`,
//! `EntireColumn` act on each; `Value`, `Formula`, `Text`, `Row`, `Column`, `Rows`,
//! `Columns` and `Cells(i, j)` read the first area, as Excel does. `Copy` is Excel's
//! run-time error 1004; every other member is refused by name, never applied to one area.

use std::rc::Rc;

use crate::eval::{Ctx, Operand, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{Expr, SheetId};

use super::ast::{Link, Span};
use super::interp::{Interp, Run};
use super::objects::lower;
use super::value::{Obj, Var};

/// The most areas one Range holds (`Union` in a loop over cells adds one each time); a
/// union past it is refused naming the limit (docs/limits.md).
pub const MAX_AREAS: usize = 16_384;

/// The cells two rectangles share, if any.
pub(super) fn overlap(a: Rect, b: Rect) -> Option<Rect> {
    let first = Pos::new(a.first.row.max(b.first.row), a.first.col.max(b.first.col));
    let last = Pos::new(a.last.row.min(b.last.row), a.last.col.min(b.last.col));
    (first.row <= last.row && first.col <= last.col).then(|| Rect::new(first, last))
}

fn cells(r: Rect) -> u64 {
    u64::from(r.rows()) * u64::from(r.cols())
}

/// The union of two rectangles when it is itself one (one holds the other, or they are
/// side by side with the same rows or the same columns): what one area holds.
pub(super) fn joined(a: Rect, b: Rect) -> Option<Rect> {
    let hull = Rect::new(
        Pos::new(a.first.row.min(b.first.row), a.first.col.min(b.first.col)),
        Pos::new(a.last.row.max(b.last.row), a.last.col.max(b.last.col)),
    );
    let shared = overlap(a, b).map_or(0, cells);
    (cells(a) + cells(b) - shared == cells(hull)).then_some(hull)
}

/// Adds `rect` to the areas of a union: nothing when an area holds it, joined with an area
/// it completes into one rectangle (again, as long as that joins more), else a new area.
/// An area it partly overlaps without joining is refused: which cells Excel's Union then
/// splits into which areas is not documented, and a guess would change `Count` and `Address`.
pub(super) fn add_area(areas: &mut Vec<Rect>, rect: Rect) -> Result<(), String> {
    place_area(areas, rect, areas.len())
}

/// [`add_area`], a new area going to position `at` (where the area it joined was).
fn place_area(areas: &mut Vec<Rect>, rect: Rect, at: usize) -> Result<(), String> {
    if areas.iter().any(|a| overlap(*a, rect) == Some(rect)) {
        return Ok(());
    }
    let before = areas[..at.min(areas.len())].iter().filter(|a| overlap(**a, rect) == Some(**a)).count();
    areas.retain(|a| overlap(*a, rect) != Some(*a));
    let at = at.min(areas.len()).saturating_sub(before);
    if let Some(k) = areas.iter().position(|a| joined(*a, rect).is_some()) {
        let whole = joined(areas.remove(k), rect).expect("joined above");
        return place_area(areas, whole, k.min(at));
    }
    if areas.iter().any(|a| overlap(*a, rect).is_some()) {
        return Err("the ranges overlap without making one rectangle; give the union separate ranges".into());
    }
    if areas.len() >= MAX_AREAS {
        return Err(format!("a Range holds at most {MAX_AREAS} areas"));
    }
    areas.insert(at.min(areas.len()), rect);
    Ok(())
}

/// The cells every list of areas shares, area by area ("Application.Intersect method").
pub(super) fn intersection(a: &[Rect], b: &[Rect]) -> Vec<Rect> {
    a.iter().flat_map(|x| b.iter().filter_map(move |y| overlap(*x, *y))).collect()
}

/// The object of `areas` on `sheet`: a plain Range for one area, else a Range of several.
pub(super) fn range_of(sheet: SheetId, areas: Vec<Rect>) -> Obj {
    match areas.as_slice() {
        [one] => Obj::Range(sheet, *one),
        _ => Obj::Areas(sheet, areas.into()),
    }
}

/// A union of references as the formula language gives it (`(A1:B2,D4)`): one Range when
/// the areas share a sheet, `None` for areas of several sheets, which no Range holds.
pub(super) fn areas_object(areas: &[(SheetId, Rect)]) -> Option<Obj> {
    let sheet = areas.first()?.0;
    areas.iter().all(|(s, _)| *s == sheet).then(|| range_of(sheet, areas.iter().map(|(_, r)| *r).collect()))
}

/// The references of a Range of several areas, as a worksheet function reads them.
pub(super) fn areas_operand(sheet: SheetId, areas: &[Rect]) -> Operand {
    Operand::Areas(areas.iter().map(|r| (sheet, *r)).collect())
}

/// The parts of an address list `"C5:D9,G9:H16"` at its commas, a quoted sheet name's
/// commas (`'Q1, Q2'!A1`) kept.
pub(super) fn address_parts(text: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut quoted, mut start) = (false, 0);
    for (i, c) in text.char_indices() {
        match c {
            '\'' => quoted = !quoted,
            ',' if !quoted => {
                parts.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&text[start..]);
    parts
}

impl Interp<'_, '_> {
    /// The members of a Range of several areas (see the module's note).
    pub(super) fn areas_member(&self, ctx: &mut Ctx, sheet: SheetId, areas: &Rc<[Rect]>, link: &Link) -> Run<Obj> {
        let name = lower(link);
        let first = areas[0];
        match name.as_str() {
            "areas" => self.area_list_member(ctx, sheet, areas, link),
            // "Range.Count property": the cells of the range, every area's.
            "count" | "countlarge" => {
                Ok(Obj::Value(Value::Number(areas.iter().map(|a| cells(*a)).sum::<u64>() as f64)))
            }
            "address" => {
                let mut parts = Vec::with_capacity(areas.len());
                for a in areas.iter() {
                    parts.push(self.address(ctx, sheet, *a, link)?);
                }
                Ok(Obj::Value(Value::text(parts.join(","))))
            }
            "cells" if link.args.is_none() => Ok(Obj::Areas(sheet, areas.clone())),
            // "Range.Rows property": "If the range is a multiple-area selection, this property
            // returns rows from only the first area of the range" (Columns the same); the
            // first area is also what Value, Formula, Row and Column read.
            "value" | "value2" | "formula" | "formular1c1" | "formulalocal" | "text" | "row" | "column" | "rows"
            | "columns" | "cells" | "item" | "range" => self.range_member(ctx, sheet, first, link),
            "worksheet" | "parent" => Ok(Obj::Sheet(sheet)),
            "clearcontents" | "clear" | "clearformats" => {
                for a in areas.iter() {
                    self.range_member(ctx, sheet, *a, link)?;
                }
                Ok(Obj::Value(Value::Blank))
            }
            "offset" | "entirerow" | "entirecolumn" => self.each_area_range(ctx, sheet, areas, link),
            "delete" => self.delete_areas(ctx, sheet, areas, link),
            "copy" => {
                self.copy_areas(ctx, sheet, areas, link)?;
                Ok(Obj::Value(Value::Blank))
            }
            // Select works only on the active sheet, of one area or several: the selection is
            // then every area, the active cell the first area's first cell, as a selection
            // made with Ctrl is ("Range.Areas property": "a multiple-area selection").
            "select" | "activate" => {
                let method = if name == "select" { "Select" } else { "Activate" };
                self.refuse_hidden(sheet, method, "Range", link.span)?;
                self.refuse_inactive(sheet, method, link.span)?;
                if name == "select" {
                    self.select_areas(sheet, areas);
                    return Ok(Obj::Value(Value::Blank));
                }
                Err(self.unsupported(
                    link.span,
                    "Activate of a Range of several areas: ncsheet activates one range; select the areas (r.Select) or activate one cell"
                        .to_string(),
                ))
            }
            // "Range.Cut method" on several areas: Excel's "This action won't work on multiple
            // selections", run-time error 1004.
            "cut" => Err(self.error_1004(
                link.span,
                format!(
                    "{} method of Range class failed: this action won't work on multiple selections ({} areas); \
                     copy each area (For Each a In r.Areas)",
                    link.name,
                    areas.len()
                ),
            )),
            _ => Err(self.unsupported(
                link.span,
                format!(
                    "{}: ncsheet does not do this to a Range of several areas ({} areas); work on each area \
                     (For Each a In r.Areas)",
                    link.name,
                    areas.len()
                ),
            )),
        }
    }

    /// `Range("A1:B2,D4:E5").Select`, `Union(a, b).Select`: `Selection` is then all the areas
    /// and `ActiveCell` the first area's first cell.
    fn select_areas(&self, sheet: SheetId, areas: &Rc<[Rect]>) {
        self.active.set(sheet);
        self.cursors.borrow_mut().insert(sheet, (areas[0], areas[0].first));
        self.selected_areas.borrow_mut().insert(sheet, areas.clone());
    }

    /// `r.Areas` (the collection) and `r.Areas(i)` (its i-th area, from 1).
    pub(super) fn area_list_member(&self, ctx: &mut Ctx, sheet: SheetId, areas: &Rc<[Rect]>, link: &Link) -> Run<Obj> {
        match link.args {
            None => Ok(Obj::AreaList(sheet, areas.clone())),
            Some(_) => self.area_item(ctx, sheet, areas, link),
        }
    }

    /// The members of an Areas collection: `Count`, `Item(i)`.
    pub(super) fn area_collection_member(
        &self,
        ctx: &mut Ctx,
        sheet: SheetId,
        areas: &Rc<[Rect]>,
        link: &Link,
    ) -> Run<Obj> {
        match lower(link).as_str() {
            "count" => Ok(Obj::Value(Value::Number(areas.len() as f64))),
            "item" => self.area_item(ctx, sheet, areas, link),
            _ => Err(self.no_member(&Obj::AreaList(sheet, areas.clone()), link)),
        }
    }

    fn area_item(&self, ctx: &mut Ctx, sheet: SheetId, areas: &Rc<[Rect]>, link: &Link) -> Run<Obj> {
        let numbers = self.numbers(ctx, link)?;
        match numbers.as_slice() {
            [i] if *i >= 1.0 && (i.round_ties_even() as usize) <= areas.len() => {
                Ok(Obj::Range(sheet, areas[i.round_ties_even() as usize - 1]))
            }
            _ => {
                let mut fault = self.fault_at(
                    link.span,
                    super::super::eval::functions::vba::errors::message(
                        9,
                        format!("{}(i): the range has {} area(s), counted from 1", link.name, areas.len()),
                    ),
                );
                fault.code = 9;
                Err(fault)
            }
        }
    }

    /// `Offset`, `EntireRow`, `EntireColumn` of every area, as one range again.
    fn each_area_range(&self, ctx: &mut Ctx, sheet: SheetId, areas: &Rc<[Rect]>, link: &Link) -> Run<Obj> {
        let mut out = Vec::with_capacity(areas.len());
        for a in areas.iter() {
            let Obj::Range(_, moved) = self.range_member(ctx, sheet, *a, link)? else {
                unreachable!("Offset and EntireRow give a Range")
            };
            add_area(&mut out, moved).map_err(|why| self.fault_at(link.span, format!("{}: {why}", link.name)))?;
        }
        Ok(range_of(sheet, out))
    }

    /// `u.EntireRow.Delete` after collecting rows with `Union`: whole rows (or whole
    /// columns) are deleted from the last up, so each area is still where it was named. Other
    /// areas would shift into one another, which is refused by name.
    fn delete_areas(&self, ctx: &mut Ctx, sheet: SheetId, areas: &Rc<[Rect]>, link: &Link) -> Run<Obj> {
        let rows = areas.iter().all(|a| a.cols() == MAX_COLS);
        let columns = areas.iter().all(|a| a.rows() == MAX_ROWS);
        if !rows && !columns {
            return Err(self.unsupported(
                link.span,
                "Delete of a Range of several areas: ncsheet deletes whole rows or whole columns of several \
                 areas (r.EntireRow.Delete); delete other areas one at a time",
            ));
        }
        let mut order: Vec<Rect> = areas.to_vec();
        order.sort_by_key(|a| std::cmp::Reverse(if rows { a.first.row } else { a.first.col }));
        for a in order {
            self.insert_or_delete(ctx, sheet, a, false, link)?;
        }
        Ok(Obj::Value(Value::Blank))
    }

    /// `r.Value = v`, `r = v`, `r.Formula = "=…"` on a Range of several areas: each area, as
    /// Excel fills every area of a multiple selection.
    pub(super) fn write_areas(&self, sheet: SheetId, areas: &[Rect], v: &Value) -> Run<()> {
        for a in areas {
            self.write_range(sheet, *a, v)?;
        }
        Ok(())
    }

    /// `Range("C5:D9,G9:H16")`: each part an address or a defined name of `sheet`, all on one
    /// sheet (Excel's Range of several areas is one sheet's).
    pub(super) fn range_list(&self, sheet: SheetId, text: &str, span: Span) -> Run<Obj> {
        let mut on = None;
        let mut areas = Vec::new();
        for part in address_parts(text) {
            let (s, r) = self.resolve(sheet, part.trim(), span)?;
            if *on.get_or_insert(s) != s {
                return Err(
                    self.error_1004(span, format!("Range(\"{text}\"): the areas of one Range are on one sheet"))
                );
            }
            if areas.len() >= MAX_AREAS {
                return Err(self.fault_at(span, format!("Range(\"…\"): a Range holds at most {MAX_AREAS} areas")));
            }
            // The list keeps its areas as written, overlaps and repeats too ("A1:B2,B2" counts
            // B2 twice in Excel's Count).
            areas.push(r);
        }
        Ok(range_of(on.unwrap_or(sheet), areas))
    }

    /// The cells `For Each` takes from a Range of several areas: area by area, each row by
    /// row, whole columns stopping at the last used row as a range's cells do.
    pub(super) fn area_cells(&self, sheet: SheetId, areas: &[Rect]) -> Vec<Var> {
        let mut out = Vec::new();
        for a in areas {
            let used = self.ctx().clip_to_used(sheet, *a);
            for row in used.first.row..=used.last.row {
                for col in used.first.col..=used.last.col {
                    out.push(Var::Obj(Obj::Range(sheet, Rect::cell(Pos::new(row, col)))));
                }
            }
        }
        out
    }

    /// `r.Formula = text` on each area.
    pub(super) fn write_formula_areas(&self, sheet: SheetId, areas: &[Rect], value: &Expr, link: &Link) -> Run<()> {
        let v = self.eval(value)?;
        let text = crate::eval::functions::vba::vba_text(&v)
            .map_err(|e| self.fault_at(self.expr_span(value), format!("the formula is {e}")))?;
        let r1c1 = lower(link).starts_with("formular1c1");
        for a in areas {
            self.write_formula(sheet, *a, &text, r1c1, link.span)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(a: (u32, u32), b: (u32, u32)) -> Rect {
        Rect::new(Pos::new(a.0, a.1), Pos::new(b.0, b.1))
    }

    #[test]
    fn a_union_is_one_rectangle_only_when_the_cells_fill_it() {
        // A1:B2 and A3:B4 stack into A1:B4; A1 and C3 leave B2 out.
        assert_eq!(joined(rect((0, 0), (1, 1)), rect((2, 0), (3, 1))), Some(rect((0, 0), (3, 1))));
        assert_eq!(joined(rect((0, 0), (0, 0)), rect((2, 2), (2, 2))), None);
        assert_eq!(joined(rect((0, 0), (3, 3)), rect((1, 1), (2, 2))), Some(rect((0, 0), (3, 3))));
        // Overlapping side by side: A1:B2 and B1:C2 fill A1:C2.
        assert_eq!(joined(rect((0, 0), (1, 1)), rect((0, 1), (1, 2))), Some(rect((0, 0), (1, 2))));
    }

    #[test]
    fn a_union_joins_what_fills_a_rectangle_and_keeps_separate_areas() {
        let mut areas = Vec::new();
        for r in [rect((0, 0), (0, 0)), rect((2, 2), (2, 2)), rect((1, 0), (1, 0)), rect((2, 2), (2, 2))] {
            add_area(&mut areas, r).unwrap();
        }
        // A1 and A2 join; C3 stays apart, once.
        assert_eq!(areas, [rect((0, 0), (1, 0)), rect((2, 2), (2, 2))]);
        // B1:D2 overlaps A1:B4 without filling a rectangle: refused, not guessed.
        let mut areas = vec![rect((0, 0), (3, 1))];
        assert!(add_area(&mut areas, rect((0, 1), (1, 3))).is_err());
    }
}
