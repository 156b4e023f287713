//! The objects a macro reaches through member paths, as a VBA user knows them: `Range`,
//! `Cells`, `Worksheets`, `Application`, `Evaluate`, `MsgBox`; the `Nc` object is in `nc.rs`.

use std::rc::Rc;

use crate::eval::coerce::{parse_plain_number, to_bool, to_number, to_text};
use crate::eval::dates::DateSystem;
use crate::eval::functions::vba::{errors, vba_text};
use crate::eval::functions::Registry;
use crate::eval::{Ctx, Operand, Value};
use crate::formula::address::{column_index, Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{Expr, ExprKind, SheetId};
use crate::formula::parse::{parse_formula, parse_formula_r1c1, ParseContext};
use crate::formula::print::{print_spelled, R1C1};

use super::ast::{Link, Node, Path, Span, Ty};
use super::interp::{Interp, Run, XL_A1, XL_R1C1};
use super::object_model::RangeSet;
use super::sheet_ops::{visibility_value, Direction};
use super::typing::Declared;
use super::value::{print_text, Obj, Var};

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

pub(super) fn lower(link: &Link) -> String {
    link.name.trim_end_matches('$').to_ascii_lowercase()
}

/// Every cell of a sheet: `Cells`, and what `Rows` and `Columns` count.
fn whole_sheet() -> Rect {
    Rect::new(Pos::new(0, 0), Pos::new(MAX_ROWS - 1, MAX_COLS - 1))
}

impl Interp<'_, '_> {
    /// Follows a member path to the object it names.
    pub fn path(&self, ctx: &mut Ctx, path: &Path) -> Run<Obj> {
        self.path_until(ctx, path, path.links.len())
    }

    /// Follows the first `links` links of a path (at least its root): `d.Item(k)` to `d`.
    pub(super) fn path_until(&self, ctx: &mut Ctx, path: &Path, links: usize) -> Run<Obj> {
        let links = &path.links[..links.min(path.links.len())];
        let (mut obj, rest) = if path.with {
            (self.with_object(path.span)?, links)
        } else {
            (self.root(ctx, &path.links[0])?, links.get(1..).unwrap_or_default())
        };
        for link in rest {
            obj = self.member(ctx, obj, link)?;
        }
        Ok(obj)
    }

    /// `A(1)(2).Count`: the members of what the indexed item `base` gives ([`Node::Members`]).
    pub(super) fn members_of(&self, ctx: &mut Ctx, base: &Expr, path: &Path) -> Run<Obj> {
        self.members_until(ctx, base, path, path.links.len())
    }

    /// The first `links` members of [`Interp::members_of`].
    fn members_until(&self, ctx: &mut Ctx, base: &Expr, path: &Path, links: usize) -> Run<Obj> {
        let mut obj = super::collections::var_obj(self.var_of(base, true)?);
        for link in &path.links[..links] {
            obj = self.member(ctx, obj, link)?;
        }
        Ok(obj)
    }

    pub(super) fn no_member(&self, obj: &Obj, link: &Link) -> crate::vba::interp::Fault {
        self.fault_at(link.span, format!("{} has no member {}", obj.describe(), link.name))
    }

    /// The arguments of a link as values (an empty one is blank).
    pub(super) fn values(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<Value>> {
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

    pub(super) fn numbers(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<f64>> {
        let values = self.values(ctx, link)?;
        let what = format!("an argument of {}", link.name);
        values.iter().map(|v| self.number_of(v, &what).map_err(|m| self.fault_at(link.span, m))).collect()
    }

    fn indexes(&self, ctx: &mut Ctx, link: &Link) -> Run<Vec<i64>> {
        Ok(self.numbers(ctx, link)?.into_iter().map(|n| n.round_ties_even() as i64).collect())
    }

    fn root(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        if let Some(var) = self.lookup(&link.name) {
            if let (Var::Obj(Obj::Store(h)), Some(args)) = (&var, &link.args) {
                // `c(1).Value`, `d("k").Count`: the item, the default member.
                let index: Vec<Expr> = args.iter().map(|a| a.value.clone()).collect();
                let key = self.store_key(ctx, &index, link.span)?;
                return self.store_item(h, &key, link.span).map(super::collections::var_obj);
            }
            if let (Var::Array(_), Some(args)) = (&var, &link.args) {
                // `a(1).Field`: the item, an object or a value.
                let index: Vec<Expr> = args.iter().map(|a| a.value.clone()).collect();
                // `pts(i).x`: the field of an item of an array of a Type, the item itself.
                if let Some(k) = self.record_item(&link.name, &index, link.span)? {
                    return Ok(Obj::Record(link.name.clone(), vec![k]));
                }
                return Ok(super::collections::var_obj(self.array_item(&link.name, &index, link.span)?));
            }
            if let (Var::Obj(Obj::Regex(r)), Some(args)) = (&var, &link.args) {
                // `matches(0)`, `m.SubMatches(1)`: the default member, Item.
                let index = self.regex_index(args, link.span)?;
                return self.regex_item(r, &index, link.span).map(super::collections::var_obj);
            }
            if let (Var::Obj(Obj::Instance(object)), Some(args)) = (&var, &link.args) {
                // `bag(2).Name`, `WScript.Arguments(0)`: the object's default member.
                return self.default_member(ctx, object, args, link.span);
            }
            if let (Var::Obj(Obj::Range(sheet, rect)), Some(_)) = (&var, &link.args) {
                // `r(1).Value = x`: a Range's default member is Item, a cell counted from its top-left.
                return self.cells(ctx, *sheet, *rect, link);
            }
            if let (Var::Obj(Obj::Sheets), Some(_)) = (&var, &link.args) {
                // `Container(1).Name` with Container given Worksheets: the collection's Item.
                return self.sheet_or_group(ctx, link);
            }
            if let (Var::Obj(Obj::Areas(sheet, areas)), Some(_)) = (&var, &link.args) {
                // Of several areas, Item counts from the first area's top-left.
                return self.cells(ctx, *sheet, areas[0], link);
            }
            if let (Some(args), true) = (&link.args, self.holds_collection(&link.name)) {
                // `rw(2).Address` with rw set to `r.Rows`: the collection's Item.
                return self.collection_member_item(ctx, var, args, link.span);
            }
            if link.args.is_some() {
                return Err(self.fault_at(link.span, format!("{} is a variable, not an array of objects", link.name)));
            }
            return Ok(match var {
                // A Worksheet (or Range) variable set before its sheet was deleted.
                Var::Obj(o) => self.alive(o, link.span)?,
                Var::Value(v) => Obj::Value(v),
                Var::Array(a) => Obj::Value(Value::Array(a.data)),
                Var::Record(..) => Obj::Record(link.name.clone(), Vec::new()),
            });
        }
        let active = self.active.get();
        let here = self.unqualified_sheet();
        let name = lower(link);
        if let Some((_, sheet)) = self.code_sheets.iter().find(|(code, _)| *code == name) {
            return self.alive(Obj::Sheet(*sheet), link.span);
        }
        match name.as_str() {
            "application" => Ok(Obj::App),
            "worksheetfunction" if link.args.is_none() => Ok(Obj::SheetFunctions),
            "thisworkbook" | "activeworkbook" => Ok(Obj::Workbook),
            "me" => Ok(match self.me() {
                Some(object) => Obj::Instance(object),
                None => self.home.map_or(Obj::Workbook, Obj::Sheet),
            }),
            "activesheet" => Ok(Obj::Sheet(active)),
            "activecell" | "selection" => self.active_range(ctx, active, name == "selection", link),
            "worksheets" | "sheets" => match link.args {
                None => Ok(Obj::Sheets),
                Some(_) => self.sheet_or_group(ctx, link),
            },
            "range" => self.range(ctx, here, None, link),
            "cells" => self.cells(ctx, here, Rect::cell(Pos::new(0, 0)), link),
            "rows" | "columns" => self.range_member(ctx, here, whole_sheet(), link),
            "nc" => Ok(Obj::Nc),
            "err" => Ok(Obj::Err),
            "erl" => Ok(Obj::Value(Value::Number(f64::from(self.err.borrow().line)))),
            "debug" => Ok(Obj::Debug),
            "msgbox" => self.msgbox(ctx, link),
            "evaluate" => self.evaluate(ctx, here, link),
            "callbyname" => self.call_by_name(ctx, link),
            "intersect" => self.range_set(link, RangeSet::Intersect),
            "union" => self.range_set(link, RangeSet::Union),
            // Resolved so only when the run has files (`files.rs`).
            "freefile" | "eof" | "lof" | "loc" | "seek" | "createobject" | "kill" | "dir" | "filelen"
            | "filedatetime" | "filecopy" | "mkdir" | "rmdir" => self.file_root(ctx, link),
            // Answered by `run --input` (`dialogs.rs`).
            "inputbox" => self.input_box(ctx, link),
            // `ActiveWindow.Zoom = 80`: Excel's window, harmless to set (`unmodelled.rs`).
            other => super::unmodelled::window_root(other)
                .ok_or_else(|| self.fault_at(link.span, format!("{} is not an object", link.name))),
        }
    }

    /// `ActiveCell` or `Selection`, and, given an index, its default member Item ("Range.Item
    /// property": "Returns a Range object that represents a range at an offset to the
    /// specified range"): `ActiveCell(j, 1)` is the cell j - 1 rows below the active cell,
    /// where the index was dropped and the active cell itself read or written.
    #[inline(never)]
    fn active_range(&self, ctx: &mut Ctx, active: SheetId, selection: bool, link: &Link) -> Run<Obj> {
        let (selected, cell) = self.cursor(active);
        let origin = if selection { selected } else { Rect::cell(cell) };
        match &link.args {
            Some(args) if !args.is_empty() => self.cells(ctx, active, origin, link),
            _ if selection => Ok(self.selection_of(active)),
            _ => Ok(Obj::Range(active, origin)),
        }
    }

    /// `ThisWorkbook.Save`: "Saves changes to the specified workbook" ("Workbook.Save
    /// method"). ncsheet never writes its input file: the run notes the call, and the command
    /// saves the workbook where `--save` says, or says it was not written.
    #[inline(never)]
    fn workbook_save(&self, link: &Link) -> Run<Obj> {
        self.out.borrow_mut().saves.push(link.span.line);
        Ok(Obj::Value(Value::Blank))
    }

    /// The refusal of `Application.FileDialog`, whose dialog object ncsheet does not model.
    /// No `On Error` traps it: a macro going on without the file it asked for computes
    /// something else than it would in Excel.
    fn no_dialog(&self, link: &Link) -> crate::vba::interp::Fault {
        self.unsupported(
            link.span,
            format!(
                "Application.{}: a macro runs without a user, and ncsheet has no FileDialog object; \
                 Application.GetOpenFilename and GetSaveAsFilename take their answers from `ncsheet run \
                 --input NAME`, or give the file's name as a parameter of the Sub (--arg NAME=FILE)",
                link.name
            ),
        )
    }

    /// A worksheet function called through an object the parser could not tell is
    /// WorksheetFunction (a variable also set to something else, an argument): refused by
    /// name, as ncsheet resolves a worksheet function where it is written.
    #[inline(never)]
    fn sheet_function_through_object(&self, link: &Link) -> crate::vba::interp::Fault {
        let why = format!(
            "WorksheetFunction.{}: a worksheet function is called as WorksheetFunction.{0}(…), or through a variable \
             the project only ever Sets to WorksheetFunction",
            link.name
        );
        self.unsupported(link.span, why)
    }

    pub(super) fn member(&self, ctx: &mut Ctx, obj: Obj, link: &Link) -> Run<Obj> {
        let obj = self.alive(obj, link.span)?;
        if let Some(family) = self.family_member(&obj, link) {
            return Ok(family);
        }
        let name = lower(link);
        match obj {
            Obj::App => match name.as_str() {
                "worksheets" | "sheets" | "range" | "cells" | "activesheet" | "activeworkbook" | "thisworkbook"
                | "activecell" | "selection" | "evaluate" | "msgbox" => self.root(ctx, link),
                // Excel's own InputBox: typed answers, and False for Cancel (`dialogs.rs`).
                "inputbox" => self.application_input_box(ctx, link),
                // "Application.CutCopyMode property": False, or xlCopy (1) while a Copy waits.
                "cutcopymode" => Ok(Obj::Value(match self.clipboard.borrow().is_some() {
                    true => Value::Number(1.0),
                    false => Value::Bool(false),
                })),
                // Read when the workbook's functions are installed (`udf.rs`): a call marks
                // nothing at run time.
                "calculate" | "volatile" => Ok(Obj::Value(Value::Blank)),
                "name" => Ok(Obj::Value(Value::text("ncsheet"))),
                "caller" => match self.caller {
                    Some((sheet, pos)) => Ok(Obj::Range(sheet, Rect::cell(pos))),
                    None => Err(self.fault_at(link.span, "Application.Caller: the macro was not called from a cell")),
                },
                "referencestyle" => Ok(Obj::Value(Value::Number(f64::from(self.reference_style.get())))),
                // Windows Excel's: a macro joins its paths with it (`files.rs` reads both).
                "pathseparator" => Ok(Obj::Value(Value::text("\\"))),
                "run" => self.application_run(link),
                "intersect" => self.range_set(link, RangeSet::Intersect),
                "union" => self.range_set(link, RangeSet::Union),
                // File dialogs: answered by `run --input` (`dialogs.rs`); FileDialog's object is
                // not modelled.
                "getsaveasfilename" | "getopenfilename" => self.file_name_dialog(ctx, link),
                "filedialog" => Err(self.no_dialog(link)),
                "worksheetfunction" if link.args.is_none() => Ok(Obj::SheetFunctions),
                _ => self.unmodelled(&Obj::App, link),
            },
            Obj::Workbook => match name.as_str() {
                "worksheets" | "sheets" | "activesheet" => self.root(ctx, link),
                "path" => self.workbook_path(link),
                "name" => self.workbook_name(link),
                "save" if link.args.is_none() => self.workbook_save(link),
                _ => self.unmodelled(&Obj::Workbook, link),
            },
            Obj::Sheets => match name.as_str() {
                "count" => Ok(Obj::Value(Value::Number(self.wb.borrow().sheet_count() as f64))),
                "add" => self.add_sheet(link),
                "item" => self.sheet_or_group(ctx, link),
                _ => self.unmodelled(&Obj::Sheets, link),
            },
            Obj::Sheet(id) => self.sheet_member(ctx, id, link),
            Obj::SheetGroup(ids) => self.sheet_group_member(ctx, &ids, link),
            Obj::Range(sheet, rect) => self.range_member(ctx, sheet, rect, link),
            Obj::Areas(sheet, areas) => self.areas_member(ctx, sheet, &areas, link),
            Obj::AreaList(sheet, areas) => self.area_collection_member(ctx, sheet, &areas, link),
            Obj::DeletedRange(_) => unreachable!("alive refuses a Range whose cells were deleted"),
            Obj::Lines(sheet, rect, rows) => match name.as_str() {
                "count" => Ok(Obj::Value(Value::Number(if rows { rect.rows() } else { rect.cols() } as f64))),
                "item" => self.line(ctx, sheet, rect, rows, link),
                "autofit" => self.autofit(ctx, sheet, rect, rows).map(|_| Obj::Value(Value::Blank)),
                // The collection is a Range of the same cells: its Value is theirs.
                "value" | "value2" => self.range_member(ctx, sheet, rect, link),
                // `Columns("A").NumberFormat`: the columns are the range's cells.
                _ => match self.look_member(ctx, sheet, rect, link) {
                    Some(look) => look,
                    None => self.unmodelled(&obj, link),
                },
            },
            Obj::Look(sheet, rect, part) => self.look_part_member(ctx, sheet, rect, part, link),
            Obj::Hyperlinks(sheet, within) => self.hyperlinks_member(ctx, sheet, within, link),
            Obj::Hyperlink(sheet, id) => self.hyperlink_member(ctx, sheet, id, link),
            Obj::Table(t) => self.table_member(ctx, &t, link),
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
            Obj::SheetFunctions => Err(self.sheet_function_through_object(link)),
            Obj::Store(h) => self.store_member(ctx, h, link),
            Obj::Files(f) => self.file_member(ctx, f, link),
            Obj::Instance(object) => self.instance_member(ctx, &object, link),
            Obj::SheetSort(sheet) => self.sheet_sort_member(ctx, sheet, link),
            Obj::SortFields(sheet) => self.sort_fields_member(ctx, sheet, link),
            Obj::Regex(r) => self.regex_member(r, link),
            // `ActiveWindow.Panes(1)`: a harmless object's members are harmless too.
            Obj::Unkept(what) => Ok(Obj::Unkept(what)),
            Obj::Record(var, path) => {
                let i = self.field_index(&var, &path, link)?;
                let mut path = path.clone();
                path.push(i);
                if let Some(args) = &link.args {
                    // `p.x(3)`: an item of a field that is an array.
                    path.push(self.field_item(&var, &path, args, link)?);
                }
                match self.record_field(&var, &path) {
                    Some(Var::Value(v)) => Ok(Obj::Value(v)),
                    Some(Var::Array(a)) => Ok(Obj::Value(Value::Array(a.data))),
                    Some(Var::Record(..)) => Ok(Obj::Record(var, path)),
                    // `this.Items.Add x` with `Items As Collection` a field: the object it holds.
                    Some(Var::Obj(object)) => Ok(object),
                    _ => Err(self.no_member(&Obj::Record(var, path), link)),
                }
            }
            // A variable never set, or set to Nothing.
            Obj::Value(Value::Blank) => Err(self.not_set(link)),
            // "Object required (Error 424)": a member of a value; a macro probing what it was
            // given for a method traps the number.
            Obj::Value(v) => {
                let shown = print_text(&v);
                let description = crate::eval::functions::vba::errors::description(424);
                let what =
                    format!("{}: {shown} is a value, not an object: {description} (run-time error 424)", link.name);
                let mut fault = self.fault_at(link.span, what);
                fault.code = 424;
                Err(fault)
            }
        }
    }

    /// `Err.Number = n` and `Err = n` ("Number property": a Long, the number rounded as a
    /// Long takes it, so `Err = 0.3` clears it): sets the number without raising it.
    fn set_err_number(&self, v: &Value, span: Span) -> Run<()> {
        let n = self.number_of(v, "Err.Number").map_err(|m| self.fault_at(span, m))?.round_ties_even();
        if !LONG.contains(&n) {
            return Err(self.fault_at(span, "Err.Number takes a Long (-2147483648 to 2147483647)"));
        }
        self.err.borrow_mut().number = long_bits(n);
        Ok(())
    }

    /// `Err.Number`, `Err.Description`, `Err.Source`, `Err.Clear`, `Err.Raise n [, source [, description]]`.
    fn err_member(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let err = self.err.borrow().clone();
        match lower(link).as_str() {
            "number" => Ok(Obj::Value(Value::Number(f64::from(err.number as i32)))),
            "description" => Ok(Obj::Value(Value::text(err.description))),
            "source" => Ok(Obj::Value(Value::text(err.source))),
            "clear" => {
                *self.err.borrow_mut() = Default::default();
                Ok(Obj::Value(Value::Blank))
            }
            "raise" => {
                let values = self.raise_args(ctx, link)?;
                let number =
                    self.number_of(&values[0], "Err.Raise's number").map_err(|m| self.fault_at(link.span, m))?;
                if number == 0.0 || !LONG.contains(&number) {
                    return Err(self.fault_at(link.span, "Err.Raise takes an error number, a Long other than 0"));
                }
                let message = match values.get(2) {
                    Some(v) if !v.is_blank() => print_text(v),
                    // The description Err then gives, and the number, in the message of an
                    // error nothing traps (`err_state` keeps what is before the marker).
                    // "Raise method": with no description, "the string associated with the error"
                    // when VBA defines the number, else "Application-defined or object-defined error".
                    _ => errors::message(number as u32, "raised by Err.Raise"),
                };
                let mut fault = self.fault_at(link.span, message);
                fault.code = long_bits(number);
                fault.source = values.get(1).filter(|v| !v.is_blank()).map(print_text);
                Err(fault)
            }
            _ => Err(self.no_member(&Obj::Err, link)),
        }
    }

    /// Err.Raise's Number, Source and Description, each given by place or by name ("Raise
    /// method": `object.Raise number, source, description, helpfile, helpcontext`, named
    /// arguments allowed), blank when left out.
    fn raise_args(&self, ctx: &mut Ctx, link: &Link) -> Run<[Value; 3]> {
        const NAMES: [&str; 5] = ["number", "source", "description", "helpfile", "helpcontext"];
        let mut out = [Value::Blank, Value::Blank, Value::Blank];
        for (i, a) in link.args.as_deref().unwrap_or(&[]).iter().enumerate() {
            let at = match &a.name {
                Some(n) => NAMES.iter().position(|k| n.eq_ignore_ascii_case(k)).ok_or_else(|| {
                    self.fault_at(link.span, format!("Err.Raise has no argument named {n} (run-time error 448)"))
                })?,
                None => i,
            };
            let v = ctx.eval(&a.value).unwrap_single();
            self.take_pending()?;
            if let Some(slot) = out.get_mut(at) {
                *slot = v;
            }
        }
        Ok(out)
    }

    /// The index of a field `link` names in the Type of the record at `path`.
    fn field_index(&self, var: &str, path: &[usize], link: &Link) -> Run<usize> {
        let ty = match self.record_field(var, path) {
            Some(Var::Record(t, _)) => &self.module.types[t],
            _ => return Err(self.fault_at(link.span, format!("{var} no longer holds a Type value"))),
        };
        let i = ty
            .field(&link.name)
            .ok_or_else(|| self.fault_at(link.span, format!("Type {} has no field {}", ty.name, link.name)))?;
        // A Variant field may hold an array (`Arr As Variant` given `Array(1, 2)`): `t.Arr(0)`
        // indexes what it holds, as a Variant variable's `v(0)` does ([MS-VBAL] 5.6.13.1).
        let may_hold_array = ty.bounds[i].is_some() || ty.fields[i].1 == Ty::Variant;
        if link.args.is_some() && !may_hold_array {
            return Err(self.fault_at(link.span, format!("{}.{} is a field, not an array", ty.name, link.name)));
        }
        Ok(i)
    }

    /// The row-major position of `p.x(args)` in the array field at `path` of `var`.
    fn field_item(&self, var: &str, path: &[usize], args: &[super::ast::Arg], link: &Link) -> Run<usize> {
        let Some(Var::Array(a)) = self.record_field(var, path) else {
            return Err(self.fault_at(link.span, format!("{var}.{} is not an array", link.name)));
        };
        let at = args.iter().map(|arg| self.index(&arg.value, "the index")).collect::<Run<Vec<i64>>>()?;
        self.element_at(&a, &at).map_err(|m| {
            let mut f = self.fault_at(link.span, errors::message(9, format!("{}: {m}", link.name)));
            f.code = 9;
            f
        })
    }

    /// `Sheets(name or number)`, or `Sheets(Array(…))`: Excel's group of the sheets named
    /// ("Sheets object": "Use Sheets(array) to specify more than one sheet").
    fn sheet_or_group(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        match values.as_slice() {
            [Value::Array(a)] if a.data.len() > 1 => {
                let ids: Run<Vec<SheetId>> =
                    a.data.iter().map(|v| self.sheet_by(std::slice::from_ref(v), link)).collect();
                Ok(Obj::SheetGroup(ids?.into()))
            }
            [Value::Array(a)] if a.data.len() == 1 => self.sheet_by(&a.data[..1], link).map(Obj::Sheet),
            _ => self.sheet_by(&values, link).map(Obj::Sheet),
        }
    }

    fn sheet_by(&self, values: &[Value], link: &Link) -> Run<SheetId> {
        let wb = self.wb.borrow();
        // Excel's run-time error 9 for a sheet the workbook has not.
        let missing = |what: String| {
            let mut fault = self.fault_at(link.span, errors::message(9, what));
            fault.code = 9;
            fault
        };
        match values {
            // A number counts tabs, as they show now (a moved sheet keeps its id).
            [Value::Number(n)] if *n >= 1.0 && (*n as usize) <= wb.sheet_count() => {
                Ok(wb.sheet_at_tab(*n as usize - 1).expect("a tab of the workbook"))
            }
            [Value::Number(n)] => {
                Err(missing(format!("the workbook has {} sheet(s), not a sheet {n}", wb.sheet_count())))
            }
            [Value::Text(name)] => {
                wb.sheet_id(name).ok_or_else(|| missing(format!("the workbook has no sheet named {name}")))
            }
            _ => Err(self.fault_at(link.span, format!("{}(name or number) picks a sheet", link.name))),
        }
    }

    fn sheet_member(&self, ctx: &mut Ctx, id: SheetId, link: &Link) -> Run<Obj> {
        // `ws.[A1]`: "Using square brackets … is identical to calling the Evaluate method"
        // ("Worksheet.Evaluate method"), on that sheet.
        if let Some(text) = link.name.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
            if link.args.is_some() {
                return Err(self.fault_at(link.span, format!("{}: a bracketed member takes no arguments", link.name)));
            }
            return self.evaluate_text(id, text, link);
        }
        match lower(link).as_str() {
            "range" => self.range(ctx, id, None, link),
            "cells" => self.cells(ctx, id, Rect::cell(Pos::new(0, 0)), link),
            "rows" | "columns" => self.range_member(ctx, id, whole_sheet(), link),
            "hyperlinks" => self.hyperlinks(ctx, id, whole_sheet(), link),
            "listobjects" => self.list_objects(ctx, id, link),
            // Pages are what a printer driver lays out from the paper, margins, scaling, breaks
            // and the fonts' metrics: ncsheet lays out none, so it refuses to guess a count.
            "pagesetup" => Err(self.unsupported(
                link.span,
                "PageSetup: ncsheet prints nothing and lays out no pages (paper, margins, scaling, page \
                 breaks, fonts), so it has no page count or print settings to give",
            )),
            "name" => Ok(Obj::Value(Value::text(self.wb.borrow().sheet_names()[id as usize].clone()))),
            "index" => {
                let tab = self.wb.borrow().tab_position(id).expect("a sheet of the workbook");
                Ok(Obj::Value(Value::Number(tab as f64 + 1.0)))
            }
            "activate" | "select" => {
                self.select_sheet(id, link.span)?;
                Ok(Obj::Value(Value::Blank))
            }
            "visible" => Ok(Obj::Value(visibility_value(self.wb.borrow().sheet_visibility(id)))),
            "usedrange" => Ok(Obj::Range(id, self.used_range(id))),
            "evaluate" => self.evaluate(ctx, id, link),
            "copy" => self.copy_sheet(id, link),
            "paste" => self.paste_on_sheet(ctx, id, link).map(|_| Obj::Value(Value::Blank)),
            "delete" => self.delete_sheet(id, link.span),
            "move" => self.move_sheet(id, link),
            "sort" => Ok(Obj::SheetSort(id)),
            "protect" => self.protect_sheet(id, link),
            "unprotect" => self.unprotect_sheet(id, link),
            "protectcontents" => Ok(Obj::Value(Value::Bool(self.protects_contents(id)))),
            "checkboxes" | "optionbuttons" | "dropdowns" | "listboxes" | "buttons" | "shapes" | "oleobjects"
            | "chartobjects" => Err(self.unsupported(
                link.span,
                format!(
                    "{}: a sheet's form controls and shapes are not in ncsheet's workbook (a macro runs \
                     without a window); keep the choice in a cell and read it with Range",
                    link.name
                ),
            )),
            _ => self.unmodelled(&Obj::Sheet(id), link),
        }
    }

    /// `Range("B3")`, `Range("A1:C4")`, `Range("Sheet2!B3")`, `Range("XA")` (a defined name),
    /// `Range(Cells(1, 1), Cells(3, 2))`. Of a range (`r.Range("A3")`), `origin` is its
    /// top-left cell and an address given as text reads from there ("Range.Range property":
    /// "When applied to a Range object, the property is relative to the Range object"); a
    /// Range given as a corner is where it is, as the page's `.Range(.Cells(1, 1), .Cells(5, 3))`.
    fn range(&self, ctx: &mut Ctx, sheet: SheetId, origin: Option<Pos>, link: &Link) -> Run<Obj> {
        let operands = self.operands(ctx, link)?;
        match operands.as_slice() {
            // "Range property": `Range("A1:B2,D4")`, a list of areas, is one Range of them all.
            [Operand::Value(Value::Text(t))] if t.contains(',') => {
                let list = self.range_list(sheet, t, link.span)?;
                return match origin {
                    Some(at) => self.areas_from(list, sheet, at, link),
                    None => Ok(list),
                };
            }
            [Operand::Areas(areas)] => {
                return super::areas::areas_object(areas)
                    .ok_or_else(|| self.error_1004(link.span, "Range: the areas of one Range are on one sheet".into()))
            }
            _ => {}
        }
        let mut corners = Vec::new();
        for op in operands {
            corners.push(match op {
                Operand::Ref(s, r) => (s, r),
                Operand::Value(Value::Text(t)) if t.contains(',') => {
                    let why = format!("Range(\"{t}\", …): a corner is one cell or one area, not a list of areas");
                    return Err(self.fault_at(link.span, why));
                }
                Operand::Value(Value::Text(t)) => {
                    let (s, r) = self.resolve(sheet, &t, link.span)?;
                    match origin {
                        Some(at) => (sheet, self.relative_to(s == sheet, r, at, link)?),
                        None => (s, r),
                    }
                }
                Operand::Value(v) => {
                    let shown = print_text(&v);
                    return Err(self.fault_at(link.span, format!("Range needs an address or a name, not {shown}")));
                }
                Operand::Areas(_) => {
                    return Err(self.fault_at(link.span, "Range(cell1, cell2): a corner is one area, not several"));
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

    /// `r` (an address read from A1) read from `at` instead, for [`Interp::range`] of a range:
    /// `Range("B2:D6").Range("A3")` is B4. An address on another sheet, or one the move takes
    /// off the sheet, is run-time error 1004 as Excel's failing Range is.
    fn relative_to(&self, same_sheet: bool, r: Rect, at: Pos, link: &Link) -> Run<Rect> {
        if !same_sheet {
            let why = format!("{}: an address read from a range is on the range's own sheet", link.name);
            return Err(self.error_1004(link.span, why));
        }
        let moved = |p: Pos| item(Rect::cell(at), &[i64::from(p.row) + 1, i64::from(p.col) + 1]);
        match (moved(r.first), moved(r.last)) {
            (Ok(first), Ok(last)) => Ok(Rect::new(first, last)),
            _ => Err(self.error_1004(link.span, format!("{}: the range would be off the sheet", link.name))),
        }
    }

    /// Every area of `list` (from `Range("A1,C3")`) read from `at`, as [`Interp::relative_to`].
    fn areas_from(&self, list: Obj, sheet: SheetId, at: Pos, link: &Link) -> Run<Obj> {
        let areas: Vec<Rect> = match &list {
            Obj::Range(_, r) => vec![*r],
            Obj::Areas(_, areas) => areas.to_vec(),
            _ => return Ok(list),
        };
        let on_sheet = matches!(list, Obj::Range(s, _) | Obj::Areas(s, _) if s == sheet);
        let moved = areas.into_iter().map(|r| self.relative_to(on_sheet, r, at, link)).collect::<Run<Vec<_>>>()?;
        Ok(super::areas::range_of(sheet, moved))
    }

    /// Address text or a defined name, read as a formula on `sheet` would read it.
    pub(super) fn resolve(&self, sheet: SheetId, text: &str, span: Span) -> Run<(SheetId, Rect)> {
        let parsed = self.wb.borrow().parse_at(text, sheet, Pos::new(0, 0));
        let bad = || self.fault_at(span, format!("Range(\"{text}\"): not a cell address or a defined name of cells"));
        let expr = parsed.map_err(|_| bad())?;
        match Ctx::new(self, sheet, Pos::new(0, 0)).operand(&expr) {
            Operand::Ref(s, r) => Ok((s, r)),
            Operand::Value(_) | Operand::Areas(_) => Err(bad()),
        }
    }

    /// `Cells(row, column)` from the top-left of `origin`; the column may be letters. A row
    /// left out (`r.Cells(, 3)`, `r(, j)`) is the range's first row: "Range.Item property"
    /// gives no rule for it, and the modules that write it read a row's j-th cell
    /// (`For Each r In t.Rows: q = r.Cells(, 1)`) or a column's letter (`Cells(, c).Address`).
    fn cells(&self, ctx: &mut Ctx, sheet: SheetId, origin: Rect, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        if values.is_empty() {
            return Ok(Obj::Range(sheet, if origin.is_cell() { whole_sheet() } else { origin }));
        }
        let row_left_out = matches!(link.args.as_deref(), Some([row, _]) if row.value.kind == ExprKind::Missing);
        let mut index = Vec::new();
        for (i, v) in values.iter().enumerate() {
            if i == 0 && row_left_out {
                index.push(1);
                continue;
            }
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
        let values = self.values(ctx, link)?;
        let (i, j) = match values.as_slice() {
            // `Columns("A:C")`, `Rows("2:5")`, `Columns("B")`: letters or numbers, from 1.
            [Value::Text(t)] => lines_named(t, rows).ok_or_else(|| {
                let example = if rows { "\"2\" or \"2:5\"" } else { "\"B\" or \"A:C\"" };
                self.fault_at(link.span, format!("{}(\"{t}\"): name them as {example}", link.name))
            })?,
            [v] => match self.number_of(v, &format!("an argument of {}", link.name)) {
                Ok(n) if n.round_ties_even() >= 1.0 => {
                    let i = n.round_ties_even().min(f64::from(u32::MAX)) as u32 - 1;
                    (i, i)
                }
                Ok(_) => return Err(self.fault_at(link.span, format!("{}(i) takes one index from 1", link.name))),
                Err(m) => return Err(self.fault_at(link.span, m)),
            },
            _ => return Err(self.fault_at(link.span, format!("{}(i) takes one index from 1", link.name))),
        };
        let off = |base: u32, k: u32| base.saturating_add(k);
        let r = if rows {
            Rect::new(Pos::new(off(rect.first.row, i), rect.first.col), Pos::new(off(rect.first.row, j), rect.last.col))
        } else {
            Rect::new(Pos::new(rect.first.row, off(rect.first.col, i)), Pos::new(rect.last.row, off(rect.first.col, j)))
        };
        if r.last.row >= MAX_ROWS || r.last.col >= MAX_COLS {
            return Err(self.fault_at(link.span, "the row or column would be off the sheet"));
        }
        Ok(Obj::Range(sheet, r))
    }

    pub(super) fn range_member(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Run<Obj> {
        let value = |v: Value| Ok(Obj::Value(v));
        let name = lower(link);
        match name.as_str() {
            // A whole column is all its 1,048,576 rows, not the used part (`whole_array`).
            "value" | "value2" => {
                let v = super::value::whole_array(ctx.rect_value(sheet, rect)).unwrap_single();
                let typed = matches!(v, Value::Number(_)) && name == "value" && rect.first == rect.last;
                self.gave.set(if typed { self.cell_value_type(sheet, rect.first) } else { Declared::Variant });
                value(v)
            }
            "formula" => value(self.formulas(sheet, rect, false)),
            "formulaarray" => value(self.formula_array(sheet, rect)),
            "hasformula" => value(self.has_formula(sheet, rect)),
            "formulalocal" => value(self.formulas_local(sheet, rect)),
            "formular1c1" | "formular1c1local" => value(self.formulas(sheet, rect, true)),
            "text" => value(Value::text(self.shown_text(ctx, sheet, rect.first))),
            "row" => value(Value::Number(rect.first.row as f64 + 1.0)),
            "column" => value(Value::Number(rect.first.col as f64 + 1.0)),
            "count" => value(Value::Number(rect.rows() as f64 * rect.cols() as f64)),
            "address" => value(Value::text(self.address(ctx, sheet, rect, link)?)),
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
            "range" => self.range(ctx, sheet, Some(rect.first), link),
            "end" => {
                let direction = match self.indexes(ctx, link)?.as_slice() {
                    [d] => Direction::of(*d),
                    _ => None,
                };
                let Some(direction) = direction else {
                    return Err(self.fault_at(link.span, "End takes one of xlUp, xlDown, xlToLeft, xlToRight"));
                };
                Ok(Obj::Range(sheet, Rect::cell(self.end(sheet, rect.first, direction))))
            }
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
                if name == "clear" {
                    self.clear_looks(sheet, used)?;
                }
                value(Value::Blank)
            }
            // "Range.ClearFormats method": the cells keep their values, lose their looks.
            "clearformats" => {
                self.clear_looks(sheet, ctx.clip_to_used(sheet, rect))?;
                value(Value::Blank)
            }
            "copy" => {
                self.copy(ctx, sheet, rect, link)?;
                value(Value::Blank)
            }
            "sort" => {
                self.sort_range(ctx, sheet, rect, link)?;
                value(Value::Blank)
            }
            "replace" => self.replace_in_range(ctx, sheet, rect, link),
            "removeduplicates" => self.remove_duplicates(ctx, sheet, rect, link),
            "texttocolumns" => self.text_to_columns(ctx, sheet, rect, link),
            "find" => self.find_in_range(ctx, sheet, rect, link),
            "findnext" | "findprevious" => self.find_next_in_range(ctx, sheet, rect, link, name == "findprevious"),
            "currentregion" => Ok(Obj::Range(sheet, self.current_region(sheet, rect))),
            "specialcells" => self.special_cells(sheet, link),
            "pastespecial" => {
                self.paste_special(ctx, sheet, rect, link)?;
                value(Value::Blank)
            }
            "worksheet" | "parent" => Ok(Obj::Sheet(sheet)),
            "select" | "activate" => {
                let method = if name == "select" { "Select" } else { "Activate" };
                self.refuse_hidden(sheet, method, "Range", link.span)?;
                self.refuse_inactive(sheet, method, link.span)?;
                self.select_range(sheet, rect, name == "activate");
                value(Value::Blank)
            }
            "delete" | "insert" => self.insert_or_delete(ctx, sheet, rect, name == "insert", link),
            "entirerow" => Ok(Obj::Range(sheet, super::insert_delete::entire_rows(rect))),
            "entirecolumn" => Ok(Obj::Range(sheet, super::insert_delete::entire_columns(rect))),
            "hyperlinks" => self.hyperlinks(ctx, sheet, rect, link),
            // "Range.Areas property": for a single area, a collection of the range itself.
            "areas" => self.area_list_member(ctx, sheet, &Rc::from([rect]), link),
            // "Range.ClearHyperlinks method": the links go, the cells keep their values.
            "clearhyperlinks" => Ok(self.delete_hyperlinks(sheet, rect)),
            _ => match self.look_member(ctx, sheet, rect, link) {
                Some(look) => look,
                None => self.unmodelled(&Obj::Range(sheet, rect), link),
            },
        }
    }

    /// `Selection` on `sheet`: every area of the selection the file saved until the macro
    /// selects there ("Range.Areas property"), else the range the cursor holds.
    pub(super) fn selection_of(&self, sheet: SheetId) -> Obj {
        match self.selected_areas.borrow().get(&sheet) {
            Some(areas) => Obj::Areas(sheet, areas.clone()),
            None => Obj::Range(sheet, self.cursor(sheet).0),
        }
    }

    /// `r.Select` (and `r.Activate` outside the selection): the range's sheet becomes the
    /// active one, the range its selection and its first cell the active cell. Activating a
    /// cell inside the selection moves only the active cell, as in Excel.
    fn select_range(&self, sheet: SheetId, rect: Rect, activate: bool) {
        self.active.set(sheet);
        let (selection, _) = self.cursor(sheet);
        let inside = activate && selection.contains(rect.first) && rect.is_cell();
        let selection = if inside { selection } else { rect };
        // Activating a cell inside the selection keeps all its areas, as in Excel.
        if !inside {
            self.selected_areas.borrow_mut().remove(&sheet);
        }
        self.cursors.borrow_mut().insert(sheet, (selection, rect.first));
    }

    /// `.Formula`: what was typed into each cell (its formula, or its constant);
    /// `.FormulaR1C1` (`r1c1`) with the formulas' references in R1C1 style.
    pub(super) fn formulas(&self, sheet: SheetId, rect: Rect, r1c1: bool) -> Value {
        let wb = self.wb.borrow();
        let names = |id: SheetId| Env::sheet_name(&**wb, id).unwrap_or_default();
        let text = |p: Pos| {
            let tree = wb.formula_tree(sheet, p).filter(|_| r1c1);
            let text = match tree {
                Some(t) => format!("={}", print_spelled(&t, p, &Registry, &names, &R1C1)),
                // A text cell's `'` (`'2022`) is how it is typed, not its formula: Excel's
                // Range.Formula gives "2022", the mark being the cell's PrefixCharacter.
                None => wb.input(sheet, p).map(without_text_mark).unwrap_or_default(),
            };
            Value::text(text)
        };
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

    /// `.HasFormula` ("Range.HasFormula property"): True when every cell of the range holds a
    /// formula, False when none does, Null when some do.
    fn has_formula(&self, sheet: SheetId, rect: Rect) -> Value {
        let formulas = self.wb.borrow().formula_cells_in(sheet, rect);
        match formulas {
            0 => Value::Bool(false),
            n if n == u64::from(rect.rows()) * u64::from(rect.cols()) => Value::Bool(true),
            _ => Value::Null,
        }
    }

    /// `.FormulaLocal`: the formulas as the workbook's locale spells them (`;` between
    /// arguments, decimal commas), constants with its decimal mark; no localized function
    /// names (the locale data has none).
    fn formulas_local(&self, sheet: SheetId, rect: Rect) -> Value {
        let locale = self.wb.borrow().settings().locale;
        let local = |v: &Value| match v {
            Value::Text(t) if t.starts_with('=') => Value::text(locale.local_formula(t)),
            Value::Text(t) if parse_plain_number(t).is_some() => Value::text(locale.localize_shown(t)),
            v => v.clone(),
        };
        match self.formulas(sheet, rect, false) {
            Value::Array(a) => {
                let items = a.data.iter().map(local).collect();
                Value::from(crate::eval::Array::new(a.rows, a.cols, items))
            }
            v => local(&v),
        }
    }

    /// `.FormulaLocal =`: what a user of the workbook's locale types (`=RUNDEN` aside:
    /// `=ROUND(B5*0,5;3)`, `0,8`, `28.11.2026`), stored canonically; a number of another
    /// locale is refused with the spelling meant.
    fn write_formula_local(&self, sheet: SheetId, rect: Rect, text: &str, span: Span) -> Run<()> {
        let canonical = self.wb.borrow().typed_input(text).map(|c| c.into_owned());
        let canonical = canonical.map_err(|why| self.fault_at(span, why))?;
        if canonical.starts_with('=') {
            return self.write_formula(sheet, rect, &canonical, false, span);
        }
        let value = match crate::workbook::Input::parse(&canonical, self.wb.borrow().date_system()) {
            crate::workbook::Input::Value(v) => v,
            _ => Value::text(canonical.as_str()),
        };
        self.write_range(sheet, rect, &value)
    }

    fn msgbox(&self, ctx: &mut Ctx, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        let first = link.args.as_deref().and_then(|a| a.first()).map(|a| &a.value);
        // A Date prompt shows its text ("MsgBox function": the prompt is a string expression).
        let prompt = match first.zip(values.first()).and_then(|(e, v)| self.as_date(e, v)) {
            Some(date) => super::value::date_text(date),
            None => values.first().map(print_text).unwrap_or_default(),
        };
        self.within_output_limit(prompt.len())?;
        self.emit(super::Printed::Message(&prompt));
        let buttons = match values.get(1) {
            None | Some(Value::Blank) => 0.0,
            Some(v) => self.number_of(v, "MsgBox's buttons").map_err(|m| self.fault_at(link.span, m))?,
        };
        Ok(Obj::Value(Value::Number(default_button_answer(buttons))))
    }

    /// `Evaluate("SUM(A1:A3)")`: formula text evaluated as in a cell of `sheet`.
    fn evaluate(&self, ctx: &mut Ctx, sheet: SheetId, link: &Link) -> Run<Obj> {
        let values = self.values(ctx, link)?;
        let text = match values.as_slice() {
            [v] => to_text(v).map_err(|e| self.fault_at(link.span, format!("Evaluate: the text is {e}")))?,
            _ => return Err(self.fault_at(link.span, "Evaluate takes one text")),
        };
        self.evaluate_text(sheet, &text, link)
    }

    /// `ws.Evaluate(text)` with its text: a range, or the value of a formula on `sheet`.
    fn evaluate_text(&self, sheet: SheetId, text: &str, link: &Link) -> Run<Obj> {
        let parsed = self.wb.borrow().parse_at(text, sheet, Pos::new(0, 0));
        let expr = parsed.map_err(|e| {
            self.fault_at(link.span, format!("Evaluate: {text}: column {}: {}", e.column(text), e.message))
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
                    let v = self.sheet_value(value)?;
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
            Node::Members { base, path } => {
                let mut ctx = self.ctx();
                let obj = self.members_until(&mut ctx, base, path, path.links.len() - 1)?;
                let last = path.links.last().expect("a member to set");
                self.set_member(&mut ctx, obj, last, value)
            }
            Node::Evaluate { expr, span } => {
                match Ctx::new(self, self.unqualified_sheet(), Pos::new(0, 0)).operand(expr) {
                    Operand::Ref(sheet, rect) => {
                        let v = self.sheet_value(value)?;
                        self.write_range(sheet, rect, &v)
                    }
                    Operand::Value(_) | Operand::Areas(_) => {
                        Err(self.fault_at(*span, "only a bracket naming cells can be assigned"))
                    }
                }
            }
            _ => unreachable!("assignment targets are paths and brackets"),
        }
    }

    pub(super) fn write_default(&self, obj: Obj, v: &Value, span: Span) -> Run<()> {
        match obj {
            // `r.Rows = v`: Rows and Columns are Ranges of r's cells ("Range.Rows property").
            Obj::Range(sheet, rect) | Obj::Lines(sheet, rect, _) => self.write_range(sheet, rect, v),
            Obj::Areas(sheet, areas) => self.write_areas(sheet, &areas, v),
            // `Err = n`: Err's default member is its Number ("Err object").
            Obj::Err => self.set_err_number(v, span),
            other => Err(self.fault_at(span, format!("cannot assign to {}", other.describe()))),
        }
    }

    pub(super) fn set_member(&self, ctx: &mut Ctx, obj: Obj, link: &Link, value: &Expr) -> Run<()> {
        if let Some(done) = self.set_look(&obj, link, value) {
            return done;
        }
        if let Obj::Areas(sheet, areas) = &obj {
            // `Range("B1,B3").NumberFormat = …`: each area's look, as Excel formats a
            // multiple selection (the value is read once per area).
            let each = areas.iter().map(|a| self.set_look(&Obj::Range(*sheet, *a), link, value));
            if let Some(done) = each.collect::<Option<Run<Vec<()>>>>() {
                return done.map(|_| ());
            }
        }
        let name = lower(link);
        match (&obj, name.as_str()) {
            (Obj::Err, "number") => self.set_err_number(&self.eval(value)?, link.span),
            (Obj::Err, "description") => {
                self.err.borrow_mut().description = print_text(&self.eval(value)?);
                Ok(())
            }
            (Obj::Range(sheet, rect) | Obj::Lines(sheet, rect, _), "value" | "value2") => {
                let v = self.sheet_value(value)?;
                self.write_range(*sheet, *rect, &v)
            }
            (Obj::Areas(sheet, areas), "value" | "value2") => {
                let v = self.sheet_value(value)?;
                self.write_areas(*sheet, areas, &v)
            }
            (Obj::Areas(sheet, areas), "formula" | "formular1c1") => {
                self.write_formula_areas(*sheet, areas, value, link)
            }
            (Obj::Range(sheet, rect), "formulaarray") => {
                let v = self.eval(value)?;
                let text =
                    vba_text(&v).map_err(|e| self.fault_at(self.expr_span(value), format!("the formula is {e}")))?;
                self.write_formula_array(*sheet, *rect, &text, link.span)
            }
            (Obj::Range(sheet, rect), "formula" | "formulalocal" | "formular1c1" | "formular1c1local") => {
                let v = self.eval(value)?;
                let text =
                    vba_text(&v).map_err(|e| self.fault_at(self.expr_span(value), format!("the formula is {e}")))?;
                if name == "formulalocal" {
                    return self.write_formula_local(*sheet, *rect, &text, link.span);
                }
                self.write_formula(*sheet, *rect, &text, name.starts_with("formular1c1"), link.span)
            }
            (Obj::Nc, _) => self.set_nc(&name, value, link.span),
            (Obj::Store(h), _) => self.set_store_member(h, link, value),
            (Obj::Instance(object), _) => self.set_instance_member(ctx, object, link, value),
            (Obj::Regex(r), _) => self.set_regex_member(r, link, value),
            (Obj::SheetSort(sheet), _) => self.set_sheet_sort(ctx, *sheet, link, value),
            (Obj::Sheet(sheet), "visible") => {
                let v = self.eval(value)?;
                self.set_visible(*sheet, &v, link.span)
            }
            (Obj::Sheet(sheet), "name") => {
                let v = self.eval(value)?;
                self.rename_sheet(*sheet, &v, link.span)
            }
            (Obj::Hyperlink(sheet, id), _) => self.set_hyperlink_member(*sheet, *id, link, value),
            // A ListObject's Name and TableStyle; a ListRow's `lr.Range(1) = v` writes the cell.
            (
                Obj::Table(table @ super::list_objects::TableObj::Table(_)),
                "name" | "displayname" | "tablestyle" | "showtotals",
            )
            | (Obj::Table(table @ super::list_objects::TableObj::Column(..)), "name") => {
                self.set_table_member(table, link, value)
            }
            (Obj::Record(var, path), _) => {
                let mut path = path.clone();
                path.push(self.field_index(var, &path, link)?);
                if let Some(args) = &link.args {
                    path.push(self.field_item(var, &path, args, link)?);
                }
                let v = self.var_of(value, false)?;
                self.refuse_long_long_past_double(value, &v, "a Type's field")?;
                self.set_record_field(var, &path, v, link.span)
            }
            (Obj::App, "cutcopymode") => {
                // False (or any value) ends the copy: the clipboard's range is forgotten.
                self.eval(value)?;
                *self.clipboard.borrow_mut() = None;
                Ok(())
            }
            (Obj::App, "referencestyle") => {
                let style = to_number(&self.eval(value)?, DateSystem::From1900)
                    .ok()
                    .filter(|s| [XL_A1, XL_R1C1].contains(&(*s as i32)));
                let why = "ReferenceStyle is xlA1 or xlR1C1";
                let style = style.ok_or_else(|| self.fault_at(link.span, why))?;
                self.reference_style.set(style as i32);
                Ok(())
            }
            // `Application.ScreenUpdating = False`, `ActiveWindow.Zoom = 80`: nothing to keep.
            // The value is still computed, for its errors.
            _ if super::unmodelled::harmless_setting(&obj, link) => self.set_harmless(&obj, link, value),
            // `ws.Range("A1") = v`, `r.Offset(1, 0) = v`: the member is a range; write its values.
            _ => match self.member(ctx, obj.clone(), link)? {
                target @ (Obj::Range(..) | Obj::Areas(..) | Obj::Lines(..)) => {
                    let v = self.sheet_value(value)?;
                    self.write_default(target, &v, link.span)
                }
                _ => Err(self.fault_at(link.span, format!("cannot assign to {} of {}", link.name, obj.describe()))),
            },
        }
    }

    /// `.Formula = "=A1*2"` (A1 style, read at the range's first cell) or `.FormulaR1C1 =
    /// "=R[-1]C*2"` into every cell of `rect`: the one tree in each, its relative references
    /// moving along as a fill moves them (VBA does the same). Text not starting with `=` is
    /// typed as a constant.
    pub(super) fn write_formula(&self, sheet: SheetId, rect: Rect, text: &str, r1c1: bool, span: Span) -> Run<()> {
        if !text.starts_with('=') {
            return self.write_range(sheet, rect, &Value::text(text));
        }
        let cells = rect.rows() as u64 * rect.cols() as u64;
        if cells > MAX_FORMULA_WRITE {
            return Err(
                self.beyond_limit(Some(span), format!("writing {cells} formulas at once is more than a macro may"))
            );
        }
        self.refuse_protected(sheet)?;
        let mut wb = self.book_mut()?;
        wb.room_for_rect(sheet, rect).map_err(|e| self.workbook_fault(Some(span), &e))?;
        let parsed = {
            let sheets = |name: &str| wb.sheet_id(name);
            let ctx = ParseContext { at: rect.first, functions: &Registry, sheet: &sheets };
            if r1c1 {
                parse_formula_r1c1(text, &ctx)
            } else {
                parse_formula(text, &ctx)
            }
        };
        let style = if r1c1 { "R1C1" } else { "A1" };
        // `[@Qty]` names the table holding the range's first cell.
        let parsed = parsed.and_then(|mut tree| wb.name_own_table(&mut tree, sheet, rect.first).map(|()| tree));
        let tree = parsed
            .map_err(|e| self.fault_at(span, format!("{text} ({style}): column {}: {}", e.column(text), e.message)))?;
        wb.fill_formula_tree_deferred(sheet, rect, tree);
        wb.recalculate_rect(sheet, rect);
        Ok(())
    }
}

/// The most cells one `.Formula =` fills.
const MAX_FORMULA_WRITE: u64 = 10_000_000;

/// Whether an A1-style reading of a formula took an R1C1 reference for a name (`R1C1`, `R2C3`,
/// `RC`, `R`, `C`): no defined name may be spelled so ("Names in formulas": a name cannot be
/// the same as a cell reference, such as Z$100 or R1C1; R and C are reserved), so the text
/// was written in R1C1 style.
fn names_an_r1c1_cell(tree: &Expr) -> bool {
    let r1c1 = |name: &str| {
        let upper = name.to_ascii_uppercase();
        let Some(rest) = upper.strip_prefix('R') else { return upper == "C" };
        let rest = rest.trim_start_matches(|c: char| c.is_ascii_digit());
        rest.is_empty() && upper == "R" || rest.strip_prefix('C').is_some_and(|c| c.bytes().all(|b| b.is_ascii_digit()))
    };
    let mut found = false;
    tree.visit(&mut |e| {
        if let ExprKind::Name(n) | ExprKind::SheetName(_, n) = &e.kind {
            found |= r1c1(n);
        }
    });
    found
}

impl Interp<'_, '_> {
    /// `.FormulaArray = "=MINVERSE(A1:C3)"` ("Range.FormulaArray property"): one legacy
    /// (Ctrl+Shift+Enter) array formula over the whole range, anchored at its top-left cell,
    /// its result filling exactly the range as Excel fits it (a scalar repeated, `=3` over
    /// A1:C5; missing items #N/A). The text is read in A1 style, as the current page's
    /// example `=Sum(A1:C3)` is, and else in R1C1 style, as the older pages' `=Sum(R1C1:R3C3)`
    /// ("the formula must use the R1C1 reference style"). Text not starting with `=` is a
    /// constant in every cell, as `.Formula` types it.
    pub(super) fn write_formula_array(&self, sheet: SheetId, rect: Rect, text: &str, span: Span) -> Run<()> {
        if !text.starts_with('=') {
            return self.write_range(sheet, rect, &Value::text(text));
        }
        let cells = rect.rows() as u64 * rect.cols() as u64;
        if cells > MAX_FORMULA_WRITE {
            return Err(
                self.beyond_limit(Some(span), format!("an array formula over {cells} cells is more than a macro may"))
            );
        }
        self.refuse_protected(sheet)?;
        let mut wb = self.book_mut()?;
        wb.room_for_rect(sheet, rect).map_err(|e| self.workbook_fault(Some(span), &e))?;
        let parsed = {
            let sheets = |name: &str| wb.sheet_id(name);
            let ctx = ParseContext { at: rect.first, functions: &Registry, sheet: &sheets };
            match parse_formula(text, &ctx) {
                Ok(tree) if !names_an_r1c1_cell(&tree) => Ok(tree),
                Ok(_) => parse_formula_r1c1(text, &ctx),
                Err(a1) => parse_formula_r1c1(text, &ctx).map_err(|_| a1),
            }
        };
        let tree =
            parsed.map_err(|e| self.fault_at(span, format!("{text}: column {}: {}", e.column(text), e.message)))?;
        // The area's other cells hold nothing of their own: the array's items fill them.
        for row in rect.first.row..=rect.last.row {
            for col in rect.first.col..=rect.last.col {
                let pos = Pos::new(row, col);
                if pos != rect.first {
                    wb.set_value_deferred(sheet, pos, Value::Blank);
                }
            }
        }
        wb.fill_formula_tree_deferred(sheet, Rect::cell(rect.first), tree);
        wb.set_array_area_deferred(sheet, rect);
        wb.recalculate_rect(sheet, rect);
        Ok(())
    }

    /// `.FormulaArray` read: the formula of the array formula the range is (or lies in from
    /// its anchor), or of a single cell; Null for several cells that are no one array formula
    /// ("If the specified range doesn't contain an array formula, this property returns
    /// null").
    fn formula_array(&self, sheet: SheetId, rect: Rect) -> Value {
        let area = self.wb.borrow().array_area(sheet, rect.first);
        match area {
            Some(area) if area.contains(rect.last) => self.formulas(sheet, Rect::cell(rect.first), false),
            _ if rect.is_cell() => self.formulas(sheet, rect, false),
            _ => Value::Null,
        }
    }
}

use crate::eval::Env;

/// `"A:C"` (columns) or `"2:5"` (rows), one or two ends in either order, as 0-based indexes
/// (first, last).
fn lines_named(text: &str, rows: bool) -> Option<(u32, u32)> {
    let one = |t: &str| -> Option<u32> {
        let t = t.trim().trim_start_matches('$');
        if rows {
            t.parse::<u32>().ok().filter(|&n| n >= 1).map(|n| n - 1)
        } else {
            column_index(&t.to_ascii_uppercase())
        }
    };
    let (a, b) = match text.split_once(':') {
        Some((a, b)) => (one(a)?, one(b)?),
        None => (one(text)?, one(text)?),
    };
    Some((a.min(b), a.max(b)))
}

/// The values of a Long, the type of `Err.Number` ("Number property"; an object's own errors
/// are numbered from vbObjectError, -2147221504, so they are negative).
const LONG: std::ops::RangeInclusive<f64> = -2147483648.0..=2147483647.0;

/// A Long error number as the runtime carries it: its 32 bits, read back as a Long by
/// `Err.Number` (VBA's own errors, 1 to 65535, are the same either way).
fn long_bits(n: f64) -> u32 {
    n as i32 as u32
}

/// A cell's typed text without the `'` that marks a text typed as text (`'2022`, `'=x`).
fn without_text_mark(input: String) -> String {
    match input.strip_prefix('\'') {
        Some(text) => text.to_string(),
        None => input,
    }
}

/// What MsgBox returns when nobody is there to press a button: its default button's value, as
/// pressing Enter would ("MsgBox function": buttons 0 vbOKOnly, 1 vbOKCancel, 2
/// vbAbortRetryIgnore, 3 vbYesNoCancel, 4 vbYesNo, 5 vbRetryCancel; vbDefaultButton1 to 4 are
/// 0, 256, 512 and 768; the return values vbOK 1, vbCancel 2, vbAbort 3, vbRetry 4, vbIgnore 5,
/// vbYes 6, vbNo 7). A default past the set's last button is its first, as Windows does.
fn default_button_answer(buttons: f64) -> f64 {
    let code = buttons as i64;
    let set: &[f64] = match code & 7 {
        1 => &[1.0, 2.0],
        2 => &[3.0, 4.0, 5.0],
        3 => &[6.0, 7.0, 2.0],
        4 => &[6.0, 7.0],
        5 => &[4.0, 2.0],
        _ => &[1.0],
    };
    let default = ((code >> 8) & 3) as usize;
    set.get(default).copied().unwrap_or(set[0])
}
