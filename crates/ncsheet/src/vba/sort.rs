//! Sorting a range's rows as Excel does: `Range.Sort Key1:=…, Order1:=…, Header:=…` and the
//! worksheet's `Sort` object the macro recorder writes (`.Sort.SortFields.Clear`,
//! `.SortFields.Add Key:=…, Order:=…`, `.SetRange`, `.Header`, `.Apply`).
//!
//! Excel's order ("Sort data in a range or table", the sort order table): numbers, then text
//! (not case-sensitive unless MatchCase), then logical values (FALSE before TRUE), then
//! errors, in ascending order; descending reverses that; blank cells always go last. Rows
//! that tie keep their order. A moved row's formulas move as a paste moves them: their
//! relative references follow the row.

use std::cmp::Ordering;

use crate::eval::functions::sort_cmp;
use crate::eval::{Ctx, Value};
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::{Expr, SheetId};

use super::ast::Link;
use super::interp::{Interp, Run};
use super::sheet_ops::argument;
use super::value::Obj;

/// XlSortOrder ("XlSortOrder enumeration"): xlAscending 1, xlDescending 2.
const XL_DESCENDING: f64 = 2.0;
/// XlYesNoGuess: xlGuess 0, xlYes 1, xlNo 2.
const XL_GUESS: f64 = 0.0;
const XL_YES: f64 = 1.0;
/// xlTopToBottom (1, the same number as xlSortColumns): rows are reordered. xlLeftToRight
/// (2) reorders columns, which ncsheet does not do.
const XL_LEFT_TO_RIGHT: f64 = 2.0;

/// One sort key: the sheet column it reads and its direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct SortKey {
    col: u32,
    descending: bool,
}

/// A worksheet's `Sort` object: what `SortFields.Add`, `SetRange`, `Header` and `MatchCase`
/// set, until `Apply` sorts (the object keeps them after, as Excel's does).
#[derive(Clone, Debug, Default)]
pub(super) struct SheetSort {
    fields: Vec<SortKey>,
    range: Option<Rect>,
    header: bool,
    match_case: bool,
}

/// The ascending order of two non-blank values of a sort key: SORT's order (numbers, text
/// ignoring case, booleans, errors); with MatchCase, lowercase sorts before uppercase among
/// texts equal but for case.
pub(super) fn ascending(a: &Value, b: &Value, match_case: bool) -> Ordering {
    match (sort_cmp(a, b), a, b) {
        (Ordering::Equal, Value::Text(x), Value::Text(y)) if match_case => y.cmp(x),
        (order, ..) => order,
    }
}

/// The order of two rows' key values: blanks last whatever the direction.
fn by_key(a: &Value, b: &Value, key: SortKey, match_case: bool) -> Ordering {
    match (a.is_blank(), b.is_blank()) {
        (true, true) => Ordering::Equal,
        (true, false) => Ordering::Greater,
        (false, true) => Ordering::Less,
        (false, false) if key.descending => ascending(b, a, match_case),
        (false, false) => ascending(a, b, match_case),
    }
}

/// What a cell holds, to be put in another row: its formula (relative to the cell) or value.
enum Content {
    Formula(Expr),
    Value(Value),
}

impl Interp<'_, '_> {
    /// `r.Sort Key1, Order1, Key2, Type, Order2, Key3, Order3, Header, OrderCustom, MatchCase,
    /// Orientation …` ("Range.Sort method": Header xlNo by default).
    pub(super) fn sort_range(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<()> {
        let mut keys = Vec::new();
        for (key_at, order_at, n) in [(0, 1, 1), (2, 4, 2), (5, 6, 3)] {
            let Some(key) = argument(link, key_at, &format!("key{n}")) else { continue };
            let col = self.key_column(ctx, sheet, rect, key, link)?;
            let descending =
                self.sort_number(ctx, argument(link, order_at, &format!("order{n}")), link)? == Some(XL_DESCENDING);
            keys.push(SortKey { col, descending });
        }
        let header = self.sort_number(ctx, argument(link, 7, "header"), link)?;
        let match_case = match argument(link, 9, "matchcase") {
            Some(e) => self.sort_flag(ctx, e, link)?,
            None => false,
        };
        if self.sort_number(ctx, argument(link, 10, "orientation"), link)? == Some(XL_LEFT_TO_RIGHT) {
            return Err(self.sort_refusal(link, "sorts rows only (Orientation xlTopToBottom)"));
        }
        if keys.is_empty() {
            return Err(self.sort_refusal(link, "needs Key1 (the column to sort by)"));
        }
        let header = match header {
            Some(XL_YES) => true,
            Some(XL_GUESS) => self.guess_header(sheet, rect, keys[0].col),
            _ => false,
        };
        self.sort_rows(sheet, rect, header, &keys, match_case, link)
    }

    /// `ws.Sort`'s members: `SortFields` (its own object), `SetRange r`, `Apply`, and the
    /// settings `Header`, `MatchCase`, `Orientation`, `SortMethod` read back.
    pub(super) fn sheet_sort_member(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        let blank = Ok(Obj::Value(Value::Blank));
        match link.name.to_ascii_lowercase().as_str() {
            "sortfields" => Ok(Obj::SortFields(sheet)),
            "setrange" => {
                let Some(e) = argument(link, 0, "rng") else {
                    return Err(self.sort_refusal(link, "SetRange needs the range to sort"));
                };
                let rect = self.sort_rect(ctx, sheet, e, link)?;
                self.sorts.borrow_mut().entry(sheet).or_default().range = Some(rect);
                blank
            }
            "apply" => {
                let state = self.sorts.borrow().get(&sheet).cloned().unwrap_or_default();
                let Some(rect) = state.range else {
                    return Err(self.sort_refusal(link, "Apply: SetRange names no range to sort"));
                };
                if state.fields.is_empty() {
                    return Err(self.sort_refusal(link, "Apply: SortFields.Add names no key"));
                }
                self.sort_rows(sheet, rect, state.header, &state.fields, state.match_case, link)?;
                blank
            }
            "header" => {
                let yes = self.sorts.borrow().get(&sheet).is_some_and(|s| s.header);
                Ok(Obj::Value(Value::Number(if yes { XL_YES } else { 2.0 })))
            }
            "matchcase" => Ok(Obj::Value(Value::Bool(self.sorts.borrow().get(&sheet).is_some_and(|s| s.match_case)))),
            "orientation" => Ok(Obj::Value(Value::Number(1.0))),
            "sortmethod" => Ok(Obj::Value(Value::Number(1.0))),
            _ => self.unmodelled(&Obj::SheetSort(sheet), link),
        }
    }

    /// `ws.Sort.Header = xlYes`, `.MatchCase = False`, `.Orientation = xlTopToBottom`,
    /// `.SortMethod = xlPinYin` (the order of Chinese text, which ncsheet's sort does not
    /// tell from the stroke order: both sort other text alike).
    pub(super) fn set_sheet_sort(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link, value: &Expr) -> Run<()> {
        let name = link.name.to_ascii_lowercase();
        match name.as_str() {
            "header" => {
                let v = self.sort_number(ctx, Some(value), link)?;
                let header = match v {
                    Some(XL_YES) => true,
                    Some(XL_GUESS) => {
                        let range = self.sorts.borrow().get(&sheet).and_then(|s| s.range);
                        let col = self.sorts.borrow().get(&sheet).and_then(|s| s.fields.first().map(|k| k.col));
                        match (range, col) {
                            (Some(r), Some(c)) => self.guess_header(sheet, r, c),
                            _ => false,
                        }
                    }
                    _ => false,
                };
                self.sorts.borrow_mut().entry(sheet).or_default().header = header;
                Ok(())
            }
            "matchcase" => {
                let yes = self.sort_flag(ctx, value, link)?;
                self.sorts.borrow_mut().entry(sheet).or_default().match_case = yes;
                Ok(())
            }
            "orientation" => match self.sort_number(ctx, Some(value), link)? {
                Some(XL_LEFT_TO_RIGHT) => Err(self.sort_refusal(link, "sorts rows only (Orientation xlTopToBottom)")),
                _ => Ok(()),
            },
            "sortmethod" => self.sort_number(ctx, Some(value), link).map(|_| ()),
            _ => Err(self.fault_at(link.span, format!("cannot assign to {} of a Sort", link.name))),
        }
    }

    /// `ws.Sort.SortFields.Clear` and `.Add Key, SortOn, Order, CustomOrder, DataOption`
    /// ("SortFields.Add method": SortOn xlSortOnValues is the only one without colors).
    pub(super) fn sort_fields_member(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        match link.name.to_ascii_lowercase().as_str() {
            "clear" => {
                self.sorts.borrow_mut().entry(sheet).or_default().fields.clear();
                Ok(Obj::Value(Value::Blank))
            }
            "add" | "add2" => {
                let Some(key) = argument(link, 0, "key") else {
                    return Err(self.sort_refusal(link, "SortFields.Add needs Key (the column to sort by)"));
                };
                let used = self.wb.borrow().used_rect(sheet).unwrap_or(Rect::cell(Pos::new(0, 0)));
                let col = self.key_column(ctx, sheet, used, key, link)?;
                if !matches!(self.sort_number(ctx, argument(link, 1, "sorton"), link)?, None | Some(0.0)) {
                    return Err(self.sort_refusal(link, "sorts on values only (SortOn xlSortOnValues)"));
                }
                let descending = self.sort_number(ctx, argument(link, 2, "order"), link)? == Some(XL_DESCENDING);
                self.sorts.borrow_mut().entry(sheet).or_default().fields.push(SortKey { col, descending });
                Ok(Obj::Value(Value::Blank))
            }
            "count" => {
                let n = self.sorts.borrow().get(&sheet).map_or(0, |s| s.fields.len());
                Ok(Obj::Value(Value::Number(n as f64)))
            }
            _ => self.unmodelled(&Obj::SortFields(sheet), link),
        }
    }

    /// The sheet column a key names: a range's first column (`Key1:=Range("B2")`), or a
    /// column of the range by its header's text (`Key1:="Qty"`).
    fn key_column(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, key: &Expr, link: &Link) -> Run<u32> {
        let operand = ctx.operand(key);
        self.take_pending()?;
        match operand {
            crate::eval::Operand::Ref(_, r) => Ok(r.first.col),
            other => {
                let v = ctx.deref(other).unwrap_single();
                let Value::Text(name) = &v else {
                    return Err(self.sort_refusal(link, "a key is a range or a column's header text"));
                };
                let wb = self.wb.borrow();
                (rect.first.col..=rect.last.col)
                    .find(|&c| matches!(wb.value(sheet, Pos::new(rect.first.row, c)), Value::Text(t) if t.eq_ignore_ascii_case(name)))
                    .ok_or_else(|| self.sort_refusal(link, &format!("no column of the range is headed {name}")))
            }
        }
    }

    fn sort_rect(&self, ctx: &mut Ctx, _sheet: SheetId, e: &Expr, link: &Link) -> Run<Rect> {
        let operand = ctx.operand(e);
        self.take_pending()?;
        match operand {
            crate::eval::Operand::Ref(_, r) => Ok(r),
            _ => Err(self.sort_refusal(link, "SetRange takes a range")),
        }
    }

    /// A number argument (an Xl constant), `None` when left out.
    fn sort_number(&self, ctx: &mut Ctx, e: Option<&Expr>, link: &Link) -> Run<Option<f64>> {
        let Some(e) = e else { return Ok(None) };
        let v = ctx.eval(e).unwrap_single();
        self.take_pending()?;
        if v.is_blank() {
            return Ok(None);
        }
        self.number_of(&v, &link.name).map(Some).map_err(|m| self.fault_at(link.span, m))
    }

    fn sort_flag(&self, ctx: &mut Ctx, e: &Expr, link: &Link) -> Run<bool> {
        Ok(self.sort_number(ctx, Some(e), link)?.is_some_and(|n| n != 0.0))
    }

    /// xlGuess: the first row is a header when its key cell is text and the row below's is
    /// not (a column of texts under a text heading is taken as data, as Excel does not know).
    pub(super) fn guess_header(&self, sheet: SheetId, rect: Rect, col: u32) -> bool {
        if rect.rows() < 2 {
            return false;
        }
        let wb = self.wb.borrow();
        let top = wb.value(sheet, Pos::new(rect.first.row, col));
        let next = wb.value(sheet, Pos::new(rect.first.row + 1, col));
        matches!(top, Value::Text(_)) && !matches!(next, Value::Text(_))
    }

    fn sort_refusal(&self, link: &Link, why: &str) -> super::interp::Fault {
        self.error_1004(link.span, format!("Sort {why}"))
    }

    /// Reorders the rows of `rect` (past its header row) by `keys`: every cell of a row moves
    /// with it, formulas as a paste moves them.
    fn sort_rows(
        &self,
        sheet: SheetId,
        rect: Rect,
        header: bool,
        keys: &[SortKey],
        match_case: bool,
        link: &Link,
    ) -> Run<()> {
        // Rows past the sheet's used range are blank: they stay where they are, last.
        let used = self.wb.borrow().used_rect(sheet);
        let Some(used) = used else { return Ok(()) };
        let first = rect.first.row + u32::from(header);
        let last = rect.last.row.min(used.last.row);
        let (left, right) = (rect.first.col, rect.last.col.min(used.last.col.max(rect.first.col)));
        if first >= last || keys.iter().any(|k| k.col < rect.first.col || k.col > rect.last.col) {
            return match keys.iter().any(|k| k.col < rect.first.col || k.col > rect.last.col) {
                true => Err(self.sort_refusal(link, "key is outside the range it sorts")),
                false => Ok(()),
            };
        }
        let order = {
            let wb = self.wb.borrow();
            let key_values: Vec<Vec<Value>> =
                (first..=last).map(|r| keys.iter().map(|k| wb.value(sheet, Pos::new(r, k.col))).collect()).collect();
            let mut order: Vec<usize> = (0..key_values.len()).collect();
            // A stable sort: rows that tie keep their order.
            order.sort_by(|&a, &b| {
                keys.iter()
                    .enumerate()
                    .map(|(i, k)| by_key(&key_values[a][i], &key_values[b][i], *k, match_case))
                    .find(|o| *o != Ordering::Equal)
                    .unwrap_or(Ordering::Equal)
            });
            order
        };
        let order: Vec<Option<usize>> = order.into_iter().map(Some).collect();
        self.rearrange_rows(sheet, first, (left, right), &order, link)
    }

    /// Rearranges the rows of the block from row `first`, columns `left..=right`: row
    /// `first + to` takes what row `first + order[to]` held, or is emptied where `order[to]`
    /// is `None`. Every cell of a row moves with it, formulas as a paste moves them, looks too.
    pub(super) fn rearrange_rows(
        &self,
        sheet: SheetId,
        first: u32,
        (left, right): (u32, u32),
        order: &[Option<usize>],
        link: &Link,
    ) -> Run<()> {
        if order.iter().enumerate().all(|(i, &o)| o == Some(i)) || order.is_empty() {
            return Ok(());
        }
        let last = first + order.len() as u32 - 1;
        let rows: Vec<Vec<Content>> = {
            let wb = self.wb.borrow();
            (first..=last)
                .map(|r| {
                    (left..=right)
                        .map(|c| {
                            let p = Pos::new(r, c);
                            match wb.formula_tree(sheet, p) {
                                Some(t) => Content::Formula(t.into_owned()),
                                None => Content::Value(wb.value(sheet, p)),
                            }
                        })
                        .collect()
                })
                .collect()
        };
        let mut rows: Vec<Option<Vec<Content>>> = rows.into_iter().map(Some).collect();
        let moved_cells: Vec<(Pos, Pos)> = (order.iter().enumerate())
            .filter_map(|(to, from)| from.filter(|&f| f != to).map(|f| (to, f)))
            .flat_map(|(to, from)| {
                (left..=right).map(move |c| (Pos::new(first + from as u32, c), Pos::new(first + to as u32, c)))
            })
            .collect();
        let width = (right - left + 1) as usize;
        // A row moving where its cells have none makes them: past the workbook's cell
        // limit, the sort is refused before a cell is written.
        let filled = |p: Pos| {
            let to = (p.row - first) as usize;
            let moved = order[to].filter(|&from| from != to).and_then(|from| rows[from].as_ref());
            moved.is_some_and(|row| !matches!(row[(p.col - left) as usize], Content::Value(Value::Blank)))
        };
        let block = Rect::new(Pos::new(first, left), Pos::new(last, right));
        self.wb.borrow().room_for_filled(sheet, block, filled).map_err(|e| self.workbook_fault(Some(link.span), &e))?;
        let mut wb = self.book_mut()?;
        for (to, &from) in order.iter().enumerate() {
            if from == Some(to) {
                continue;
            }
            let row = match from {
                Some(from) => rows[from].take().expect("each row moves once"),
                None => (0..width).map(|_| Content::Value(Value::Blank)).collect(),
            };
            for (i, content) in row.into_iter().enumerate() {
                let p = Pos::new(first + to as u32, left + i as u32);
                match content {
                    Content::Formula(tree) => wb.fill_formula_tree_deferred(sheet, Rect::cell(p), tree),
                    Content::Value(Value::Blank) => {
                        wb.set_input_deferred(sheet, p, "").map_err(|e| self.workbook_fault(Some(link.span), &e))?
                    }
                    Content::Value(v) => wb.set_value_deferred(sheet, p, v),
                }
            }
        }
        wb.recalculate_rect(sheet, Rect::new(Pos::new(first, left), Pos::new(last, right)));
        drop(wb);
        self.copy_looks(sheet, sheet, &moved_cells);
        Ok(())
    }
}
