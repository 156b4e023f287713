//! The objects a macro reaches through member paths, as a VBA user knows them: `Range`,
//! `Cells`, `Worksheets`, `Application`, `Evaluate`, `MsgBox`, and `Nc`, ncsheet's NC program
//! under construction.
//!
//! `Nc` (an ncsheet object, not VBA's): `Nc.Rapid x, z`, `Nc.Line x, z [, f]`,
//! `Nc.ArcCW x, z, cx, cz [, f]` / `Nc.ArcCCW` (centre absolute, written like a point),
//! `Nc.Dwell seconds`, `Nc.Comment text`, `Nc.Block "G1", "X", x, …`; on a mill the points are
//! `x, y, z` (arcs `x, y, cx, cy`). Any coordinate may be named (`Z:=-2`) or left out
//! (`Nc.Line , -10` keeps X). Properties: `Nc.Feed` (modal, written when it changes),
//! `Nc.Machine` ("lathe" or "mill"), `Nc.Name`, `Nc.Number`, `Nc.Dialect` (read only),
//! `Nc.Count` (blocks so far). On a lathe X is a diameter, as everywhere in ncsheet.
//!
//! The machine's state: `Nc.FeedPerRev [f]` / `Nc.FeedPerMin [f]` (what F means from here on;
//! a lathe program must say it before its first cut), `Nc.Spindle 800` (M3), `Nc.Spindle 800,
//! "ccw"` (M4), `Nc.Spindle 0` (stop), `Nc.Spindle Vc:=180, Limit:=2500` (constant surface
//! speed on a lathe: m/min, and the spindle limit in 1/min), `Nc.Tool 3`, `Nc.Coolant True`.

use crate::eval::coerce::{to_bool, to_text};
use crate::eval::functions::vba::vba_text;
use crate::eval::functions::Registry;
use crate::eval::{Ctx, Operand, Value};
use crate::formula::address::{column_index, column_name, Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{Expr, ExprKind, SheetId};
use crate::formula::print::print_formula;
use crate::nc::{ArcDirection, Block, FeedMode, Machine, Spindle, SpindleDirection, Target, Word};

use super::ast::{Link, Node, Path, Span};
use super::interp::{input_text, one_line, print_text, Interp, Obj, Run};

/// The modal state of the program being emitted.
#[derive(Debug, Default)]
pub struct NcState {
    /// The feed the next cut uses (`Nc.Feed = 0.1` or `F:=` on a cut).
    feed: Option<f64>,
    /// The feed last written into a block: a cut writes F only when it changes.
    written: Option<f64>,
}

/// The cell `index` picks in `rect` (1-based): `(i)` counts row by row, `(i, j)` is row and
/// column; both may run past the range, as in VBA, but not off the sheet.
pub fn item(rect: Rect, index: &[i64]) -> Result<Pos, String> {
    let (row, col) = match index {
        [i] => {
            let cols = rect.cols() as i64;
            (rect.first.row as i64 + (i - 1).div_euclid(cols), rect.first.col as i64 + (i - 1).rem_euclid(cols))
        }
        [i, j] => (rect.first.row as i64 + i - 1, rect.first.col as i64 + j - 1),
        _ => return Err("a cell is picked by (index) or (row, column)".into()),
    };
    if !(0..MAX_ROWS as i64).contains(&row) || !(0..MAX_COLS as i64).contains(&col) {
        return Err("the cell would be off the sheet".into());
    }
    Ok(Pos::new(row as u32, col as u32))
}

fn lower(link: &Link) -> String {
    link.name.trim_end_matches('$').to_ascii_lowercase()
}

/// `$B$3` or `$A$1:$C$4`, as VBA's Address.
fn address(rect: Rect) -> String {
    let cell = |p: Pos| format!("${}${}", column_name(p.col), p.row + 1);
    if rect.is_cell() {
        cell(rect.first)
    } else {
        format!("{}:{}", cell(rect.first), cell(rect.last))
    }
}

impl Interp<'_, '_> {
    /// Follows a member path to the object it names.
    pub fn path(&self, ctx: &mut Ctx, path: &Path) -> Run<Obj> {
        let (mut obj, rest) = if path.with {
            (self.with_object(path.span)?, &path.links[..])
        } else {
            (self.root(ctx, &path.links[0])?, &path.links[1..])
        };
        for link in rest {
            obj = self.member(ctx, obj, link)?;
        }
        Ok(obj)
    }

    fn no_member(&self, obj: &Obj, link: &Link) -> crate::vba::interp::Fault {
        self.fault_at(link.span, format!("{} has no member {}", obj.describe(), link.name))
    }

    /// The arguments of a link as values (an empty one is blank).
    fn values(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<Value>> {
        let mut out = Vec::new();
        for a in link.args.as_deref().unwrap_or(&[]) {
            out.push(ctx.eval(&a.value).unwrap_single());
            self.take_pending()?;
        }
        Ok(out)
    }

    fn operands(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<Operand>> {
        let mut out = Vec::new();
        for a in link.args.as_deref().unwrap_or(&[]) {
            out.push(ctx.operand(&a.value));
            self.take_pending()?;
        }
        Ok(out)
    }

    fn numbers(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<f64>> {
        let values = self.values(ctx, link)?;
        let what = format!("an argument of {}", link.name);
        values.iter().map(|v| self.number_of(v, &what).map_err(|m| self.fault_at(link.span, m))).collect()
    }

    fn indexes(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<i64>> {
        Ok(self.numbers(ctx, link)?.into_iter().map(|n| n.round_ties_even() as i64).collect())
    }

    fn root(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        if let Some(var) = self.lookup(&link.name) {
            if link.args.is_some() {
                return Err(self.fault_at(link.span, format!("{} is a variable, not an array of objects", link.name)));
            }
            return Ok(match var {
                super::interp::Var::Obj(o) => o,
                super::interp::Var::Value(v) => Obj::Value(v),
                super::interp::Var::Array(a) => Obj::Value(Value::Array(a.data)),
                super::interp::Var::Record(..) => Obj::Record(link.name.clone(), Vec::new()),
            });
        }
        let active = self.active.get();
        match lower(link).as_str() {
            "application" => Ok(Obj::App),
            "thisworkbook" | "activeworkbook" => Ok(Obj::Workbook),
            "activesheet" => Ok(Obj::Sheet(active)),
            "worksheets" | "sheets" => match link.args {
                None => Ok(Obj::Sheets),
                Some(_) => self.sheet_by(ctx, link).map(Obj::Sheet),
            },
            "range" => self.range(ctx, active, link),
            "cells" => self.cells(ctx, active, Rect::cell(Pos::new(0, 0)), link),
            "nc" => Ok(Obj::Nc),
            "err" => Ok(Obj::Err),
            "debug" => Ok(Obj::Debug),
            "msgbox" => self.msgbox(ctx, link),
            "evaluate" => self.evaluate(ctx, active, link),
            "inputbox" => Err(self.fault_at(
                link.span,
                "InputBox: a macro runs without a user; pass values with --arg NAME=VALUE or read them from cells",
            )),
            _ => Err(self.fault_at(link.span, format!("{} is not an object", link.name))),
        }
    }

    fn member(&self, ctx: &mut Ctx, obj: Obj, link: &Link) -> Run<Obj> {
        let name = lower(link);
        match obj {
            Obj::App => match name.as_str() {
                "worksheets" | "sheets" | "range" | "cells" | "activesheet" | "activeworkbook" | "thisworkbook"
                | "evaluate" | "inputbox" | "msgbox" => self.root(ctx, link),
                "screenupdating" | "displayalerts" | "enableevents" => Ok(Obj::Value(Value::Bool(true))),
                "calculate" => Ok(Obj::Value(Value::Blank)),
                "name" => Ok(Obj::Value(Value::text("ncsheet"))),
                _ => Err(self.no_member(&Obj::App, link)),
            },
            Obj::Workbook => match name.as_str() {
                "worksheets" | "sheets" | "activesheet" => self.root(ctx, link),
                _ => Err(self.no_member(&Obj::Workbook, link)),
            },
            Obj::Sheets => match name.as_str() {
                "count" => Ok(Obj::Value(Value::Number(self.wb.borrow().sheet_len() as f64))),
                "item" => self.sheet_by(ctx, link).map(Obj::Sheet),
                _ => Err(self.no_member(&Obj::Sheets, link)),
            },
            Obj::Sheet(id) => self.sheet_member(ctx, id, link),
            Obj::Range(sheet, rect) => self.range_member(ctx, sheet, rect, link),
            Obj::Lines(sheet, rect, rows) => match name.as_str() {
                "count" => Ok(Obj::Value(Value::Number(if rows { rect.rows() } else { rect.cols() } as f64))),
                "item" => self.line(ctx, sheet, rect, rows, link),
                _ => Err(self.no_member(&obj, link)),
            },
            Obj::Nc => self.nc_member(ctx, link),
            Obj::Debug => match name.as_str() {
                "assert" => {
                    let holds = self.values(ctx, link)?.first().map(to_bool);
                    match holds {
                        Some(Ok(true)) => Ok(Obj::Value(Value::Blank)),
                        _ => Err(self.fault_at(link.span, "Debug.Assert failed")),
                    }
                }
                _ => Err(self.no_member(&Obj::Debug, link)),
            },
            Obj::Err => self.err_member(ctx, link),
            Obj::Record(var, path) => {
                let i = self.field_index(&var, &path, link)?;
                let mut path = path.clone();
                path.push(i);
                match self.record_field(&var, &path) {
                    Some(super::interp::Var::Value(v)) => Ok(Obj::Value(v)),
                    Some(super::interp::Var::Record(..)) => Ok(Obj::Record(var, path)),
                    _ => Err(self.no_member(&Obj::Record(var, path), link)),
                }
            }
            Obj::Value(v) => {
                let shown = print_text(&v);
                Err(self.fault_at(link.span, format!("{}: {shown} is a value, not an object", link.name)))
            }
        }
    }

    /// `Err.Number`, `Err.Description`, `Err.Source`, `Err.Clear`, `Err.Raise n [, source [, description]]`.
    fn err_member(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let err = self.err.borrow().clone();
        match lower(link).as_str() {
            "number" => Ok(Obj::Value(Value::Number(err.number as f64))),
            "description" => Ok(Obj::Value(Value::text(err.description))),
            "source" => Ok(Obj::Value(Value::text("ncsheet"))),
            "clear" => {
                *self.err.borrow_mut() = Default::default();
                Ok(Obj::Value(Value::Blank))
            }
            "raise" => {
                let values = self.values(ctx, link)?;
                let number = values.first().map(|v| self.number_of(v, "Err.Raise's number")).transpose();
                let number = number.map_err(|m| self.fault_at(link.span, m))?.unwrap_or(0.0);
                if !(1.0..=65535.0).contains(&number) {
                    return Err(self.fault_at(link.span, "Err.Raise takes an error number from 1 to 65535"));
                }
                let description = match values.get(2) {
                    Some(v) if !v.is_blank() => print_text(v),
                    _ => format!("error {number}"),
                };
                let mut fault = self.fault_at(link.span, description);
                fault.code = number as u32;
                Err(fault)
            }
            _ => Err(self.no_member(&Obj::Err, link)),
        }
    }

    /// The index of a field `link` names in the Type of the record at `path`.
    fn field_index(&self, var: &str, path: &[usize], link: &Link) -> Run<usize> {
        let ty = match self.record_field(var, path) {
            Some(super::interp::Var::Record(t, _)) => &self.module.types[t],
            _ => return Err(self.fault_at(link.span, format!("{var} no longer holds a Type value"))),
        };
        if link.args.is_some() {
            return Err(self.fault_at(link.span, format!("{}.{} is a field, not an array", ty.name, link.name)));
        }
        ty.field(&link.name)
            .ok_or_else(|| self.fault_at(link.span, format!("Type {} has no field {}", ty.name, link.name)))
    }

    fn sheet_by(&self, ctx: &mut Ctx, link: &Link) -> Run<SheetId> {
        let values = self.values(ctx, link)?;
        let wb = self.wb.borrow();
        match values.as_slice() {
            [Value::Number(n)] if *n >= 1.0 && (*n as usize) <= wb.sheet_len() => Ok(*n as SheetId - 1),
            [Value::Text(name)] => wb
                .sheet_id(name)
                .ok_or_else(|| self.fault_at(link.span, format!("the workbook has no sheet named {name}"))),
            _ => Err(self.fault_at(link.span, format!("{}(name or number) picks a sheet", link.name))),
        }
    }

    fn sheet_member(&self, ctx: &mut Ctx, id: SheetId, link: &Link) -> Run<Obj> {
        match lower(link).as_str() {
            "range" => self.range(ctx, id, link),
            "cells" => self.cells(ctx, id, Rect::cell(Pos::new(0, 0)), link),
            "name" => Ok(Obj::Value(Value::text(self.wb.borrow().sheet_names()[id as usize].clone()))),
            "index" => Ok(Obj::Value(Value::Number(id as f64 + 1.0))),
            "activate" | "select" => {
                self.active.set(id);
                Ok(Obj::Value(Value::Blank))
            }
            "usedrange" => {
                let used = self.wb.borrow().used_rect(id).unwrap_or(Rect::cell(Pos::new(0, 0)));
                Ok(Obj::Range(id, used))
            }
            "evaluate" => self.evaluate(ctx, id, link),
            _ => Err(self.no_member(&Obj::Sheet(id), link)),
        }
    }

    /// `Range("B3")`, `Range("A1:C4")`, `Range("Sheet2!B3")`, `Range("XA")` (a defined name),
    /// `Range(Cells(1, 1), Cells(3, 2))`.
    fn range(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        let operands = self.operands(ctx, link)?;
        let mut corners = Vec::new();
        for op in operands {
            corners.push(match op {
                Operand::Ref(s, r) => (s, r),
                Operand::Value(Value::Text(t)) => self.resolve(sheet, &t, link.span)?,
                Operand::Value(v) => {
                    let shown = print_text(&v);
                    return Err(self.fault_at(link.span, format!("Range needs an address or a name, not {shown}")));
                }
                Operand::Areas(_) => {
                    return Err(self.fault_at(link.span, "Range of several areas is not supported"));
                }
            });
        }
        match corners.as_slice() {
            [(s, r)] => Ok(Obj::Range(*s, *r)),
            [(s1, a), (s2, b)] if s1 == s2 => {
                let first = Pos::new(a.first.row.min(b.first.row), a.first.col.min(b.first.col));
                let last = Pos::new(a.last.row.max(b.last.row), a.last.col.max(b.last.col));
                Ok(Obj::Range(*s1, Rect { first, last }))
            }
            _ => Err(self.fault_at(link.span, "Range takes an address, or two corners on one sheet")),
        }
    }

    /// Address text or a defined name, read as a formula on `sheet` would read it.
    fn resolve(&self, sheet: SheetId, text: &str, span: Span) -> Run<(SheetId, Rect)> {
        let parsed = self.wb.borrow().parse_at(text, sheet, Pos::new(0, 0));
        let bad = || self.fault_at(span, format!("Range(\"{text}\"): not a cell address or a defined name of cells"));
        let expr = parsed.map_err(|_| bad())?;
        match Ctx::new(self, sheet, Pos::new(0, 0)).operand(&expr) {
            Operand::Ref(s, r) => Ok((s, r)),
            Operand::Value(_) | Operand::Areas(_) => Err(bad()),
        }
    }

    /// `Cells(row, column)` from the top-left of `origin`; the column may be letters.
    fn cells(&self, ctx: &mut Ctx, sheet: SheetId, origin: Rect, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        if values.is_empty() {
            let whole = Rect::new(Pos::new(0, 0), Pos::new(MAX_ROWS - 1, MAX_COLS - 1));
            return Ok(Obj::Range(sheet, if origin.is_cell() { whole } else { origin }));
        }
        let mut index = Vec::new();
        for (i, v) in values.iter().enumerate() {
            let letters = match v {
                Value::Text(t) if i == 1 => column_index(&t.to_ascii_uppercase()).map(|c| c as i64 + 1),
                _ => None,
            };
            let n = match letters {
                Some(c) => c,
                None => self.number_of(v, "a Cells index").map_err(|m| self.fault_at(link.span, m))?.round_ties_even()
                    as i64,
            };
            index.push(n);
        }
        let pos = item(origin, &index).map_err(|m| self.fault_at(link.span, format!("{}: {m}", link.name)))?;
        Ok(Obj::Range(sheet, Rect::cell(pos)))
    }

    fn line(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, rows: bool, link: &Link) -> Run<Obj> {
        let i = match self.indexes(ctx, link)?.as_slice() {
            [i] if *i >= 1 => *i as u32 - 1,
            _ => return Err(self.fault_at(link.span, format!("{}(i) takes one index from 1", link.name))),
        };
        let r = if rows {
            Rect::new(Pos::new(rect.first.row + i, rect.first.col), Pos::new(rect.first.row + i, rect.last.col))
        } else {
            Rect::new(Pos::new(rect.first.row, rect.first.col + i), Pos::new(rect.last.row, rect.first.col + i))
        };
        if r.last.row >= MAX_ROWS || r.last.col >= MAX_COLS {
            return Err(self.fault_at(link.span, "the row or column would be off the sheet"));
        }
        Ok(Obj::Range(sheet, r))
    }

    fn range_member(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        let value = |v: Value| Ok(Obj::Value(v));
        match lower(link).as_str() {
            "value" | "value2" => value(ctx.rect_value(sheet, rect).unwrap_single()),
            "formula" | "formulalocal" => value(self.formulas(sheet, rect)),
            "text" => value(Value::text(print_text(&ctx.rect_value(sheet, Rect::cell(rect.first))))),
            "row" => value(Value::Number(rect.first.row as f64 + 1.0)),
            "column" => value(Value::Number(rect.first.col as f64 + 1.0)),
            "count" => value(Value::Number(rect.rows() as f64 * rect.cols() as f64)),
            "address" => value(Value::text(address(rect))),
            "offset" => {
                let (dr, dc) = match self.indexes(ctx, link)?.as_slice() {
                    [r] => (*r, 0),
                    [r, c] => (*r, *c),
                    _ => return Err(self.fault_at(link.span, "Offset(rows, columns)")),
                };
                let first = item(Rect::cell(rect.first), &[dr + 1, dc + 1]);
                let last = item(Rect::cell(rect.last), &[dr + 1, dc + 1]);
                match (first, last) {
                    (Ok(a), Ok(b)) => Ok(Obj::Range(sheet, Rect::new(a, b))),
                    _ => Err(self.fault_at(link.span, "Offset: the range would be off the sheet")),
                }
            }
            "resize" => {
                let (rows, cols) = match self.indexes(ctx, link)?.as_slice() {
                    [r] => (*r, rect.cols() as i64),
                    [r, c] => (*r, *c),
                    _ => return Err(self.fault_at(link.span, "Resize(rows, columns)")),
                };
                match (rows >= 1 && cols >= 1).then(|| item(Rect::cell(rect.first), &[rows, cols])) {
                    Some(Ok(last)) => Ok(Obj::Range(sheet, Rect::new(rect.first, last))),
                    _ => Err(self.fault_at(link.span, "Resize: not a size on the sheet")),
                }
            }
            "cells" | "item" => self.cells(ctx, sheet, rect, link),
            "rows" | "columns" => {
                let rows = lower(link) == "rows";
                match link.args {
                    Some(_) => self.line(ctx, sheet, rect, rows, link),
                    None => Ok(Obj::Lines(sheet, rect, rows)),
                }
            }
            "clearcontents" | "clear" => {
                let used = ctx.clip_to_used(sheet, rect);
                self.write_range(sheet, used, &Value::Blank)?;
                value(Value::Blank)
            }
            "worksheet" | "parent" => Ok(Obj::Sheet(sheet)),
            "select" | "activate" => {
                self.active.set(sheet);
                value(Value::Blank)
            }
            _ => Err(self.no_member(&Obj::Range(sheet, rect), link)),
        }
    }

    /// `.Formula`: what was typed into each cell (its formula, or its constant).
    fn formulas(&self, sheet: SheetId, rect: Rect) -> Value {
        let wb = self.wb.borrow();
        let text = |p: Pos| Value::text(wb.input(sheet, p).unwrap_or_default());
        if rect.is_cell() {
            return text(rect.first);
        }
        let mut items = Vec::new();
        for row in rect.first.row..=rect.last.row {
            for col in rect.first.col..=rect.last.col {
                items.push(text(Pos::new(row, col)));
            }
        }
        Value::from(crate::eval::Array::new(rect.rows() as usize, rect.cols() as usize, items))
    }

    fn msgbox(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        let prompt = values.first().map(print_text).unwrap_or_default();
        self.within_output_limit(prompt.len())?;
        self.emit(super::Printed::Message(&prompt));
        // vbOK: nobody is there to press another button.
        Ok(Obj::Value(Value::Number(1.0)))
    }

    /// `Evaluate("SUM(A1:A3)")`: formula text evaluated as in a cell of `sheet`.
    fn evaluate(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        let text = match values.as_slice() {
            [v] => to_text(v).map_err(|e| self.fault_at(link.span, format!("Evaluate: the text is {e}")))?,
            _ => return Err(self.fault_at(link.span, "Evaluate takes one text")),
        };
        let parsed = self.wb.borrow().parse_at(&text, sheet, Pos::new(0, 0));
        let expr = parsed.map_err(|e| {
            self.fault_at(link.span, format!("Evaluate: {text}: column {}: {}", e.column(&text), e.message))
        })?;
        Ok(match Ctx::new(self, sheet, Pos::new(0, 0)).operand(&expr) {
            Operand::Ref(s, r) => Obj::Range(s, r),
            Operand::Value(v) => Obj::Value(v),
            Operand::Areas(_) => Obj::Value(Value::Error(crate::eval::XlError::Value)),
        })
    }

    // ---- assignment ------------------------------------------------------------------

    /// `Range("B3").Value = v`, `Cells(1, 2) = v`, `Nc.Feed = 0.1`, `[B3] = v`.
    pub fn assign_node(&self, id: u32, value: &Expr) -> Run<()> {
        match &self.module.nodes[id as usize] {
            Node::Path(path) => {
                let mut ctx = self.ctx();
                if !path.with && path.links.len() == 1 {
                    let obj = self.root(&mut ctx, &path.links[0])?;
                    let v = self.eval(value)?;
                    return self.write_default(obj, &v, path.span);
                }
                let (mut obj, members) = if path.with {
                    (self.with_object(path.span)?, &path.links[..])
                } else {
                    (self.root(&mut ctx, &path.links[0])?, &path.links[1..])
                };
                let (last, between) = members.split_last().expect("a member to set");
                for link in between {
                    obj = self.member(&mut ctx, obj, link)?;
                }
                self.set_member(&mut ctx, obj, last, value)
            }
            Node::Evaluate { expr, span } => match Ctx::new(self, self.active.get(), Pos::new(0, 0)).operand(expr) {
                Operand::Ref(sheet, rect) => {
                    let v = self.eval(value)?;
                    self.write_range(sheet, rect, &v)
                }
                Operand::Value(_) | Operand::Areas(_) => {
                    Err(self.fault_at(*span, "only a bracket naming cells can be assigned"))
                }
            },
            _ => unreachable!("assignment targets are paths and brackets"),
        }
    }

    fn write_default(&self, obj: Obj, v: &Value, span: Span) -> Run<()> {
        match obj {
            Obj::Range(sheet, rect) => self.write_range(sheet, rect, v),
            other => Err(self.fault_at(span, format!("cannot assign to {}", other.describe()))),
        }
    }

    fn set_member(&self, ctx: &mut Ctx, obj: Obj, link: &Link, value: &Expr) -> Run<()> {
        let name = lower(link);
        match (&obj, name.as_str()) {
            (Obj::Range(sheet, rect), "value" | "value2") => {
                let v = self.eval(value)?;
                self.write_range(*sheet, *rect, &v)
            }
            (Obj::Range(sheet, rect), "formula" | "formulalocal") => {
                let v = self.eval(value)?;
                let text =
                    vba_text(&v).map_err(|e| self.fault_at(self.expr_span(value), format!("the formula is {e}")))?;
                self.write_formula(*sheet, *rect, &text, link.span)
            }
            (Obj::Nc, _) => self.set_nc(&name, value, link.span),
            (Obj::Record(var, path), _) => {
                let mut path = path.clone();
                path.push(self.field_index(var, &path, link)?);
                let v = self.var_of(value, false)?;
                self.set_record_field(var, &path, v, link.span)
            }
            (Obj::App, "screenupdating" | "displayalerts" | "enableevents" | "calculation" | "statusbar") => {
                // Settings of Excel's window: nothing to do without one.
                self.eval(value).map(|_| ())
            }
            // `ws.Range("A1") = v`, `r.Offset(1, 0) = v`: the member is a range; write its values.
            _ => match self.member(ctx, obj.clone(), link)? {
                target @ Obj::Range(..) => {
                    let v = self.eval(value)?;
                    self.write_default(target, &v, link.span)
                }
                _ => Err(self.fault_at(link.span, format!("cannot assign to {} of {}", link.name, obj.describe()))),
            },
        }
    }

    /// `.Formula = "=A1*2"` into every cell of `rect`, relative references moving along as a
    /// fill moves them (VBA does the same).
    fn write_formula(&self, sheet: SheetId, rect: Rect, text: &str, span: Span) -> Run<()> {
        if rect.is_cell() || !text.starts_with('=') {
            return self.write_range(sheet, rect, &Value::text(text));
        }
        let texts = {
            let wb = self.wb.borrow();
            let expr = wb
                .parse_at(text, sheet, rect.first)
                .map_err(|e| self.fault_at(span, format!("{text}: column {}: {}", e.column(text), e.message)))?;
            let names = |id: SheetId| Env::sheet_name(&**wb, id).unwrap_or_default();
            let mut texts = Vec::new();
            for row in rect.first.row..=rect.last.row {
                for col in rect.first.col..=rect.last.col {
                    let pos = Pos::new(row, col);
                    texts.push((pos, format!("={}", print_formula(&expr, pos, &Registry, &names))));
                }
            }
            texts
        };
        let mut wb = self.wb.borrow_mut();
        for (pos, t) in texts {
            wb.set_input_deferred(sheet, pos, &t).map_err(|e| self.fault_at(span, one_line(&e)))?;
        }
        wb.recalculate();
        Ok(())
    }

    // ---- Nc --------------------------------------------------------------------------

    fn machine(&self) -> Machine {
        self.out.borrow().program.machine
    }

    fn nc_member(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let name = lower(link);
        // `Nc.Feed 0.1`, a statement as a VBA user writes it, sets the feed as `Nc.Feed = 0.1`.
        if let (Some([arg]), "feed") = (link.args.as_deref(), name.as_str()) {
            self.set_nc("feed", &arg.value, link.span)?;
            return Ok(Obj::Value(Value::Blank));
        }
        let out = self.out.borrow();
        let property = match name.as_str() {
            "name" => Some(Value::text(out.program.name.clone())),
            "number" => Some(Value::Number(out.program.number.unwrap_or(0) as f64)),
            "machine" => Some(Value::text(if out.program.machine == Machine::Lathe { "lathe" } else { "mill" })),
            "feed" => Some(self.nc.borrow().feed.map_or(Value::Blank, Value::Number)),
            "dialect" => Some(Value::text(self.options.dialect.clone().unwrap_or_default())),
            "count" => Some(Value::Number(out.program.blocks.len() as f64)),
            _ => None,
        };
        drop(out);
        if let Some(v) = property {
            return Ok(Obj::Value(v));
        }
        let block = match name.as_str() {
            "rapid" => {
                let a = self.nc_args(ctx, link, &self.axes(&[]))?;
                Block::Rapid(self.target(&a, link)?)
            }
            "line" => {
                let a = self.nc_args(ctx, link, &self.axes(&["f"]))?;
                let to = self.target(&a, link)?;
                Block::Line { to, feed: self.feed(get(&a, "f"), link)? }
            }
            "arccw" | "arcccw" => self.arc(ctx, link, name == "arccw")?,
            "dwell" => match self.numbers(ctx, link)?.as_slice() {
                [s] if *s >= 0.0 => Block::Dwell(*s),
                _ => return Err(self.fault_at(link.span, "Nc.Dwell takes the seconds to wait")),
            },
            "comment" => {
                let values = self.values(ctx, link)?;
                Block::Comment(values.iter().map(print_text).collect::<Vec<_>>().join(" "))
            }
            "block" => Block::Words(self.words(ctx, link)?),
            "feedperrev" | "feedpermin" => {
                let mode = if name == "feedperrev" { FeedMode::PerRevolution } else { FeedMode::PerMinute };
                match self.numbers(ctx, link)?.as_slice() {
                    [] => {}
                    [f] if *f > 0.0 && f.is_finite() => self.nc.borrow_mut().feed = Some(*f),
                    _ => return Err(self.fault_at(link.span, format!("Nc.{} takes the feed, above 0", link.name))),
                }
                // F means something else now: the next cut writes it again.
                self.nc.borrow_mut().written = None;
                Block::FeedMode(mode)
            }
            "spindle" => Block::Spindle(self.spindle(ctx, link)?),
            "tool" => match self.numbers(ctx, link)?.as_slice() {
                [n] if (1.0..=99.0).contains(n) && n.fract() == 0.0 => Block::Tool(*n as u32),
                _ => return Err(self.fault_at(link.span, "Nc.Tool takes a tool number from 1 to 99")),
            },
            "coolant" => match self.values(ctx, link)?.as_slice() {
                [v] => {
                    Block::Coolant(to_bool(v).map_err(|_| self.fault_at(link.span, "Nc.Coolant takes True or False"))?)
                }
                _ => return Err(self.fault_at(link.span, "Nc.Coolant takes True or False")),
            },
            _ => return Err(self.no_member(&Obj::Nc, link)),
        };
        self.out.borrow_mut().program.push(block);
        Ok(Obj::Value(Value::Blank))
    }

    /// `Nc.Spindle S [, Dir]`, `Nc.Spindle Vc:=…, Limit:=… [, Dir:=…]`; S 0 stops it.
    fn spindle(&self, ctx: &mut Ctx, link: &Link) -> Run<Spindle> {
        const NAMES: [&str; 4] = ["s", "dir", "vc", "limit"];
        let usage = "Nc.Spindle takes S (1/min) and Dir (\"cw\" or \"ccw\"), or Vc:= (m/min) and Limit:= (1/min)";
        let mut got: Vec<(&str, Value)> = Vec::new();
        for (i, a) in link.args.as_deref().unwrap_or(&[]).iter().enumerate() {
            let key = match &a.name {
                Some(n) => NAMES.iter().find(|k| k.eq_ignore_ascii_case(n)).copied(),
                None => NAMES.get(i).copied().filter(|_| i < 2),
            };
            let Some(key) = key else { return Err(self.fault_at(link.span, usage)) };
            if a.value.kind == ExprKind::Missing {
                continue;
            }
            let v = ctx.eval(&a.value).unwrap_single();
            self.take_pending()?;
            got.push((key, v));
        }
        let find = |k: &str| got.iter().find(|(n, _)| *n == k).map(|(_, v)| v);
        let number = |k: &str| -> Run<Option<f64>> {
            find(k)
                .map(|v| self.number_of(v, &format!("Nc.Spindle: {}", k.to_uppercase())))
                .transpose()
                .map_err(|m| self.fault_at(link.span, m))
        };
        let direction = match find("dir").map(print_text).map(|t| t.to_ascii_lowercase()) {
            None => SpindleDirection::Clockwise,
            Some(t) if t == "cw" || t == "m3" => SpindleDirection::Clockwise,
            Some(t) if t == "ccw" || t == "m4" => SpindleDirection::CounterClockwise,
            Some(t) => {
                return Err(self.fault_at(link.span, format!("Nc.Spindle: Dir is \"cw\" or \"ccw\", not \"{t}\"")))
            }
        };
        match (number("s")?, number("vc")?, number("limit")?) {
            (Some(0.0), None, None) => Ok(Spindle::Stop),
            (Some(rpm), None, None) if rpm > 0.0 => Ok(Spindle::Rpm { rpm, direction }),
            (None, Some(v), Some(max)) if v > 0.0 && max > 0.0 => {
                Ok(Spindle::SurfaceSpeed { metres_per_min: v, max_rpm: max, direction })
            }
            _ => Err(self.fault_at(link.span, usage)),
        }
    }

    /// The point parameters of the machine: X Z on a lathe, X Y Z on a mill.
    fn axes(&self, extra: &[&'static str]) -> Vec<&'static str> {
        let mut names = match self.machine() {
            Machine::Lathe => vec!["x", "z"],
            Machine::Mill => vec!["x", "y", "z"],
        };
        names.extend_from_slice(extra);
        names
    }

    /// Numeric arguments by parameter name: positional in `names` order, or named (`Z:=`);
    /// the rotary axes A B C may only be named. Empty ones are left out.
    fn nc_args(&self, ctx: &mut Ctx, link: &Link, names: &[&'static str]) -> Run<Vec<(String, f64)>> {
        let mut out: Vec<(String, f64)> = Vec::new();
        let all: Vec<&str> = names.iter().copied().chain(["x", "y", "z", "a", "b", "c"]).collect();
        for (i, a) in link.args.as_deref().unwrap_or(&[]).iter().enumerate() {
            let key = match &a.name {
                Some(n) if all.contains(&n.to_ascii_lowercase().as_str()) => n.to_ascii_lowercase(),
                Some(n) => {
                    let list = names.join(", ").to_uppercase();
                    return Err(
                        self.fault_at(link.span, format!("Nc.{} has no argument {n} (it takes {list})", link.name))
                    );
                }
                None if i < names.len() => names[i].to_string(),
                None => {
                    let list = names.join(", ").to_uppercase();
                    return Err(self.fault_at(link.span, format!("Nc.{} takes {list}", link.name)));
                }
            };
            if a.value.kind == ExprKind::Missing {
                continue;
            }
            let v = ctx.eval(&a.value).unwrap_single();
            self.take_pending()?;
            let what = format!("Nc.{}: {}", link.name, key.to_uppercase());
            let n = self.number_of(&v, &what).map_err(|m| self.fault_at(self.expr_span(&a.value), m))?;
            if out.iter().any(|(k, _)| *k == key) {
                return Err(
                    self.fault_at(link.span, format!("Nc.{}: {} is given twice", link.name, key.to_uppercase()))
                );
            }
            out.push((key, n));
        }
        Ok(out)
    }

    fn target(&self, a: &[(String, f64)], link: &Link) -> Run<Target> {
        let t =
            Target { x: get(a, "x"), y: get(a, "y"), z: get(a, "z"), a: get(a, "a"), b: get(a, "b"), c: get(a, "c") };
        if t.axes().next().is_none() {
            return Err(self.fault_at(link.span, format!("Nc.{} needs a point to move to", link.name)));
        }
        Ok(t)
    }

    /// The feed of a cut: given, else the modal one; written only when it changes.
    fn feed(&self, given: Option<f64>, link: &Link) -> Run<Option<f64>> {
        let mut nc = self.nc.borrow_mut();
        if let Some(f) = given {
            if f <= 0.0 {
                return Err(self.fault_at(link.span, format!("Nc.{}: the feed must be above 0", link.name)));
            }
            nc.feed = Some(f);
        }
        let Some(feed) = nc.feed else {
            return Err(
                self.fault_at(link.span, format!("Nc.{} needs a feed: pass F:= or set Nc.Feed first", link.name))
            );
        };
        if nc.written == Some(feed) {
            return Ok(None);
        }
        nc.written = Some(feed);
        Ok(Some(feed))
    }

    fn arc(&self, ctx: &mut Ctx, link: &Link, clockwise: bool) -> Run<Block> {
        let names: &[&'static str] = match self.machine() {
            Machine::Lathe => &["x", "z", "cx", "cz", "f"],
            Machine::Mill => &["x", "y", "cx", "cy", "f", "z", "cz"],
        };
        let a = self.nc_args(ctx, link, names)?;
        let to = self.target(&a, link)?;
        let centre = Target { x: get(&a, "cx"), y: get(&a, "cy"), z: get(&a, "cz"), ..Target::default() };
        let in_plane = match self.machine() {
            Machine::Lathe => centre.x.is_some() && centre.z.is_some(),
            Machine::Mill => centre.x.is_some() && centre.y.is_some(),
        };
        if !in_plane {
            return Err(self
                .fault_at(link.span, format!("Nc.{} needs the centre (CX and C{})", link.name, self.plane_second())));
        }
        let direction = if clockwise { ArcDirection::Clockwise } else { ArcDirection::CounterClockwise };
        Ok(Block::Arc { direction, to, centre, feed: self.feed(get(&a, "f"), link)? })
    }

    fn plane_second(&self) -> char {
        if self.machine() == Machine::Lathe {
            'Z'
        } else {
            'Y'
        }
    }

    /// `Nc.Block "G1", "X", x, "Z", z` or `Nc.Block "G1 X10 Z-2"`: words of letters and numbers.
    fn words(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<Word>> {
        let values = self.values(ctx, link)?;
        let bad = |m: String| self.fault_at(link.span, format!("Nc.Block: {m}"));
        let mut words = Vec::new();
        let mut letter: Option<char> = None;
        for v in &values {
            if let Value::Text(t) = v {
                for token in t.split_whitespace() {
                    // `Nc.Block "T", "0101"`: the number of a letter given before, as typed.
                    if let Some(l) = letter.take() {
                        let n = typed_number(token).ok_or_else(|| bad(format!("{l} needs a number after it")))?;
                        words.push(Word::typed(l, n, token));
                        continue;
                    }
                    let mut chars = token.chars();
                    let first = chars.next().expect("a token").to_ascii_uppercase();
                    if !first.is_ascii_alphabetic() {
                        return Err(bad(format!("\"{token}\" does not start with an address letter")));
                    }
                    let rest = chars.as_str();
                    if rest.is_empty() {
                        letter = Some(first);
                        continue;
                    }
                    let n =
                        typed_number(rest).ok_or_else(|| bad(format!("\"{token}\" is not a letter and a number")))?;
                    words.push(Word::typed(first, n, rest));
                }
                continue;
            }
            let Some(l) = letter.take() else {
                return Err(bad(format!("{} has no address letter before it", print_text(v))));
            };
            let n = self.number_of(v, &format!("Nc.Block: {l}")).map_err(|m| self.fault_at(link.span, m))?;
            words.push(Word::new(l, n));
        }
        if let Some(l) = letter {
            return Err(bad(format!("{l} needs a number after it")));
        }
        if words.is_empty() {
            return Err(bad("no words".into()));
        }
        Ok(words)
    }

    fn set_nc(&self, name: &str, value: &Expr, span: Span) -> Run<()> {
        let v = self.eval(value)?;
        let text = || input_text(&v);
        match name {
            "feed" => {
                let f = self.number_of(&v, "Nc.Feed").map_err(|m| self.fault_at(span, m))?;
                if f <= 0.0 {
                    return Err(self.fault_at(span, "Nc.Feed must be above 0"));
                }
                self.nc.borrow_mut().feed = Some(f);
            }
            "name" => self.out.borrow_mut().program.name = text(),
            "number" => {
                let n = self.number_of(&v, "Nc.Number").map_err(|m| self.fault_at(span, m))?;
                if !(0.0..=99_999_999.0).contains(&n) || n.fract() != 0.0 {
                    return Err(self.fault_at(span, "Nc.Number is a whole number from 0"));
                }
                self.out.borrow_mut().program.number = Some(n as u32);
            }
            "machine" => {
                let machine = match text().to_ascii_lowercase().as_str() {
                    "lathe" => Machine::Lathe,
                    "mill" => Machine::Mill,
                    other => {
                        return Err(self.fault_at(span, format!("Nc.Machine is \"lathe\" or \"mill\", not \"{other}\"")))
                    }
                };
                self.out.borrow_mut().program.machine = machine;
            }
            _ => return Err(self.fault_at(span, format!("Nc.{name} cannot be assigned"))),
        }
        Ok(())
    }
}

/// The number of a word's text (`0101`, `-2.5`), finite.
fn typed_number(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().filter(|n| n.is_finite())
}

fn get(args: &[(String, f64)], key: &str) -> Option<f64> {
    args.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
}

use crate::eval::Env;
