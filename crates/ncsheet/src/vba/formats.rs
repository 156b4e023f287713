//! How cells look, as automation macros set it: `Range.NumberFormat` (which changes what a
//! cell shows: `Range.Text`, and the saved file), `HorizontalAlignment`, `VerticalAlignment`,
//! `WrapText`, `Font.Bold`/`Italic`, `Interior.Color`, `ColumnWidth`, `RowHeight` and
//! `AutoFit`, and rows and columns `Hidden`. None of them changes a value. The run starts from the look the file gave
//! ([`RunOptions::looks`](super::RunOptions::looks)) and hands back the look it leaves
//! ([`RunOutput::looks`](super::RunOutput::looks)) for the caller to save.
//!
//! Formatting a whole column or row (`Columns("A").NumberFormat = "0"`) formats its cells
//! that have a look of their own now and, as a line format, every other cell of it, those
//! written later included: in Excel a cell takes its column's format when it is first
//! filled. The file keeps it per cell (the column's own style, for cells typed later in
//! Excel, is not written).

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::rc::Rc;

use crate::eval::format::cell_style::{self, CellStyle};
use crate::eval::{Ctx, RowHidden, Value};
use crate::formula::address::{Pos, Rect, MAX_COLS, MAX_ROWS};
use crate::formula::ast::{Expr, SheetId};
use crate::workbook::look::{
    follow_cells, follow_columns, follow_hidden_columns, follow_hidden_rows, follow_hyperlink, follow_rows, Hyperlink,
};
use crate::workbook::{Axis, SheetEdit, SheetLook, Workbook};

use super::ast::{Link, Span};
use super::interp::{Interp, Run};
use super::typing::Declared;
use super::value::{print_text, Obj};

/// Excel's standard column width (8.43 digits of Calibri 11) and row height (15 points), the
/// look of a column or row nobody sized.
pub const STANDARD_WIDTH: f64 = 8.43;
pub const STANDARD_HEIGHT: f64 = 15.0;

/// Excel's limits: "ColumnWidth" (0 to 255 characters) and "RowHeight" (0 to 409 points).
const MAX_WIDTH: f64 = 255.0;
const MAX_HEIGHT: f64 = 409.0;

/// The most cells one formatting statement sets one by one (whole rows and columns aside).
const MAX_FORMATTED_CELLS: u64 = 10_000_000;

/// The most rows one `Hidden = True` hides: each is kept, and saved as its own `<row>`
/// (the whole sheet, `Rows.Hidden = True`, would be a million of them).
const MAX_HIDDEN_ROWS: u32 = 100_000;

/// Excel's XlColorIndex: no colour, and the automatic one.
const XL_COLOR_INDEX_NONE: f64 = -4142.0;
const XL_COLOR_INDEX_AUTOMATIC: f64 = -4105.0;

/// Interior.Color of a cell without fill: white, as Excel answers.
const NO_FILL: u32 = 0xFF_FFFF;

/// Font.Size of a cell whose size was not set: the Normal style's Calibri 11.
const STANDARD_FONT_SIZE: f64 = 11.0;

/// The palette index (a ColorIndex answer) nearest an RGB colour.
fn palette_index(color: u32) -> f64 {
    f64::from(cell_style::nearest_palette_index(color))
}

/// One formatting statement's change to a cell.
#[derive(Clone, Debug, PartialEq)]
enum Edit {
    Format(Rc<str>),
    Horizontal(Option<i32>),
    Vertical(Option<i32>),
    Bold(bool),
    Italic(bool),
    Wrap(bool),
    Fill(Option<u32>),
    FontColor(Option<u32>),
    FontSize(Option<u16>),
    Underline(Option<i32>),
}

impl Edit {
    fn apply(&self, style: &mut CellStyle) {
        match self {
            Edit::Format(_) => {}
            Edit::Horizontal(h) => style.horizontal = *h,
            Edit::Vertical(v) => style.vertical = *v,
            Edit::Bold(b) => style.bold = *b,
            Edit::Italic(i) => style.italic = *i,
            Edit::Wrap(w) => style.wrap = *w,
            Edit::Fill(f) => style.fill = *f,
            Edit::FontColor(c) => style.font_color = *c,
            Edit::FontSize(s) => style.font_size = *s,
            Edit::Underline(u) => style.underline = *u,
        }
    }
}

/// One sheet's look during a run.
#[derive(Clone, Debug, Default)]
pub(super) struct SheetState {
    /// Cells' own number formats ("General" included: it hides a line format).
    formats: HashMap<Pos, Rc<str>>,
    /// Cells' own styles.
    styles: HashMap<Pos, CellStyle>,
    /// Whole rows and columns formatted, in order: they reach every cell of theirs without
    /// a format or style of its own.
    lines: Vec<(Rect, Edit)>,
    widths: BTreeMap<u16, f64>,
    heights: BTreeMap<u32, f64>,
    hidden_rows: BTreeSet<u32>,
    hidden_columns: BTreeSet<u16>,
    /// The sheet's hyperlinks in the order made, each with the id its Hyperlink objects
    /// name it by (`hyperlinks.rs`).
    pub(super) hyperlinks: Vec<(u32, Hyperlink)>,
    /// The id the next hyperlink made gets.
    next_link: u32,
}

impl SheetState {
    fn from_look(look: &SheetLook) -> SheetState {
        SheetState {
            formats: look.number_formats.iter().map(|(p, c)| (*p, Rc::from(c.as_str()))).collect(),
            styles: look.cell_styles.iter().map(|(p, s)| (*p, *s)).collect(),
            lines: Vec::new(),
            widths: look.column_widths.iter().copied().collect(),
            heights: look.row_heights.iter().copied().collect(),
            hidden_rows: look.hidden_rows.iter().copied().collect(),
            hidden_columns: look.hidden_columns.iter().copied().collect(),
            hyperlinks: (0..).zip(look.hyperlinks.iter().cloned()).collect(),
            next_link: look.hyperlinks.len() as u32,
        }
    }

    /// A new hyperlink's id.
    pub(super) fn next_link_id(&mut self) -> u32 {
        self.next_link += 1;
        self.next_link - 1
    }

    fn format(&self, pos: Pos) -> Option<Rc<str>> {
        if let Some(own) = self.formats.get(&pos) {
            return Some(own.clone());
        }
        self.lines.iter().rev().find_map(|(r, e)| match e {
            Edit::Format(code) if r.contains(pos) => Some(code.clone()),
            _ => None,
        })
    }

    fn style(&self, pos: Pos) -> CellStyle {
        if let Some(own) = self.styles.get(&pos) {
            return *own;
        }
        let mut style = CellStyle::default();
        for (_, edit) in self.lines.iter().filter(|(r, _)| r.contains(pos)) {
            edit.apply(&mut style);
        }
        style
    }

    fn edit_cell(&mut self, pos: Pos, edit: &Edit) {
        match edit {
            Edit::Format(code) => _ = self.formats.insert(pos, code.clone()),
            _ => {
                let mut style = self.style(pos);
                edit.apply(&mut style);
                self.styles.insert(pos, style);
            }
        }
    }

    /// Gives each cell its look (a format and a style taken from another cell): a look left
    /// plain clears the cell's own entry.
    fn put_cells(&mut self, looks: Vec<(Pos, Option<Rc<str>>, CellStyle)>) {
        for (to, format, style) in looks {
            match format {
                Some(code) => _ = self.formats.insert(to, code),
                None => {
                    self.formats.remove(&to);
                    // A General cell pasted into a formatted column stays General.
                    if self.format(to).is_some() {
                        self.formats.insert(to, Rc::from("General"));
                    }
                }
            }
            if style.is_plain() {
                self.styles.remove(&to);
            } else {
                self.styles.insert(to, style);
            }
        }
    }

    /// A whole row or column: its cells' own entries change, the rest follow the line.
    fn edit_lines(&mut self, rect: Rect, edit: Edit) {
        match &edit {
            Edit::Format(_) => self.formats.retain(|p, _| !rect.contains(*p)),
            _ => {
                for (_, style) in self.styles.iter_mut().filter(|(p, _)| rect.contains(**p)) {
                    edit.apply(style);
                }
            }
        }
        self.lines.push((rect, edit));
    }

    /// The cells, lines, widths and heights moved as [`SheetLook::follow`] moves a file's.
    fn follow(&mut self, edit: &SheetEdit) {
        follow_cells(&mut self.formats, edit);
        follow_cells(&mut self.styles, edit);
        self.lines =
            std::mem::take(&mut self.lines).into_iter().filter_map(|(r, e)| Some((moved_line(r, edit)?, e))).collect();
        match edit.axis {
            Axis::Columns => {
                self.widths = follow_columns(std::mem::take(&mut self.widths), edit);
                self.hidden_columns = follow_hidden_columns(std::mem::take(&mut self.hidden_columns), edit);
            }
            Axis::Rows => {
                self.heights = follow_rows(std::mem::take(&mut self.heights), edit);
                self.hidden_rows = follow_hidden_rows(std::mem::take(&mut self.hidden_rows), edit);
            }
        }
        self.hyperlinks.retain_mut(|(_, link)| follow_hyperlink(link, edit));
    }

    /// The look to save: every written cell a line reaches gets its format and style.
    fn finish(&self, wb: &Workbook, sheet: SheetId) -> SheetLook {
        let mut formats = self.formats.clone();
        let mut styles = self.styles.clone();
        if !self.lines.is_empty() {
            for (pos, _) in wb.values(sheet) {
                if let Some(code) = self.format(pos) {
                    formats.entry(pos).or_insert(code);
                }
                styles.entry(pos).or_insert_with(|| self.style(pos));
            }
        }
        SheetLook {
            number_formats: formats
                .into_iter()
                .filter(|(_, c)| !c.eq_ignore_ascii_case("General"))
                .map(|(p, c)| (p, c.to_string()))
                .collect(),
            cell_styles: styles.into_iter().filter(|(_, s)| !s.is_plain()).collect(),
            column_widths: self.widths.iter().map(|(c, w)| (*c, *w)).collect(),
            row_heights: self.heights.iter().map(|(r, h)| (*r, *h)).collect(),
            hidden_rows: self.hidden_rows.iter().copied().collect(),
            hidden_columns: self.hidden_columns.iter().copied().collect(),
            hyperlinks: self.hyperlinks.iter().map(|(_, link)| link.clone()).collect(),
        }
    }
}

/// The look of every sheet during a run, by sheet.
#[derive(Clone, Debug, Default)]
pub(super) struct Looks {
    sheets: HashMap<SheetId, SheetState>,
}

impl Looks {
    /// The looks of `given` (by sheet name) for the sheets of `wb`.
    pub(super) fn new(wb: &Workbook, given: &[(String, SheetLook)]) -> Looks {
        let sheets =
            given.iter().filter_map(|(name, look)| Some((wb.sheet_id(name)?, SheetState::from_look(look)))).collect();
        Looks { sheets }
    }

    /// The look each sheet is left with, by its name now.
    pub(super) fn finish(&self, wb: &Workbook) -> Vec<(String, SheetLook)> {
        let names = wb.sheet_names();
        let mut out: Vec<_> = self
            .sheets
            .iter()
            // A deleted sheet's look goes with it (a new sheet may have taken its name).
            .filter(|(id, _)| !wb.sheet_deleted(**id))
            .filter_map(|(id, state)| Some((names.get(*id as usize)?.clone(), state.finish(wb, *id))))
            .collect();
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }

    pub(super) fn sheet(&mut self, sheet: SheetId) -> &mut SheetState {
        self.sheets.entry(sheet).or_default()
    }

    /// Rows, columns or cells of `sheet` inserted or deleted: each cell's format and style,
    /// each column's width and each row's height go where their cells went (Excel moves
    /// them with the cells); a deleted one's dropped.
    pub(super) fn follow(&mut self, sheet: SheetId, edit: &SheetEdit) {
        if let Some(state) = self.sheets.get_mut(&sheet) {
            state.follow(edit);
        }
    }

    /// A copy of `from`'s look for the new sheet `to` (`Worksheet.Copy`).
    pub(super) fn copy_sheet(&mut self, from: SheetId, to: SheetId) {
        if let Some(state) = self.sheets.get(&from).cloned() {
            self.sheets.insert(to, state);
        }
    }
}

/// Which of Excel's formatting objects a member path reached (`r.Font`, `r.Interior`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LookPart {
    Font,
    Interior,
}

/// A formatted whole row or column after `edit`: a line along the edit (a column when rows
/// move) stays whole where it is; one across it moves, or is gone with its lines.
fn moved_line(rect: Rect, edit: &SheetEdit) -> Option<Rect> {
    let along_edit = match edit.axis {
        Axis::Rows => rect.first.row == 0 && rect.last.row == MAX_ROWS - 1,
        Axis::Columns => rect.first.col == 0 && rect.last.col == MAX_COLS - 1,
    };
    if along_edit {
        return Some(rect);
    }
    Some(Rect::new(edit.moved(rect.first)?, edit.moved(rect.last)?))
}

/// `rect` grown to take in `p`.
fn reaching(rect: Rect, p: Pos) -> Rect {
    let first = Pos::new(rect.first.row.min(p.row), rect.first.col.min(p.col));
    Rect::new(first, Pos::new(rect.last.row.max(p.row), rect.last.col.max(p.col)))
}

/// A rectangle reaching the sheet's last row (whole columns) or last column (whole rows).
fn is_whole_lines(rect: Rect) -> bool {
    rect.last.row == MAX_ROWS - 1 || rect.last.col == MAX_COLS - 1
}

/// Every cell's answer when they agree, Null when they do not ("Range.NumberFormat": "returns
/// Null if all cells in the specified range don't have the same number format").
fn agreed<T: PartialEq>(mut answers: impl Iterator<Item = T>) -> Option<T> {
    let first = answers.next()?;
    answers.all(|a| a == first).then_some(first)
}

impl Interp<'_, '_> {
    /// The cells a formatting read looks at: a whole row or column by its used part (the
    /// rest of it answers as its line does, which its first cell tells).
    fn look_cells(&self, ctx: &Ctx, sheet: SheetId, rect: Rect) -> Vec<Pos> {
        let mut cells = vec![rect.first];
        let used = if is_whole_lines(rect) { ctx.clip_to_used(sheet, rect) } else { rect };
        if rect.rows() as u64 * rect.cols() as u64 <= MAX_FORMATTED_CELLS || is_whole_lines(rect) {
            for row in used.first.row..=used.last.row {
                cells.extend((used.first.col..=used.last.col).map(|col| Pos::new(row, col)));
            }
        }
        cells
    }

    /// `Worksheet.UsedRange`: from the first to the last cell holding a value or a look of its
    /// own (Excel counts formatted cells as used), A1 on an empty sheet.
    pub(super) fn used_range(&self, sheet: SheetId) -> Rect {
        let values = self.wb.borrow().used_area(sheet);
        let looks = self.looks.borrow();
        let styled = looks.sheets.get(&sheet).map(|s| s.formats.keys().chain(s.styles.keys())).into_iter().flatten();
        styled
            .fold(values, |used, &p| Some(used.map_or(Rect::cell(p), |u| reaching(u, p))))
            .unwrap_or(Rect::cell(Pos::new(0, 0)))
    }

    /// The number format code a cell shows its number in ("General" without one).
    pub(super) fn cell_format(&self, sheet: SheetId, pos: Pos) -> Option<Rc<str>> {
        self.looks.borrow().sheets.get(&sheet).and_then(|s| s.format(pos))
    }

    /// The type `Range.Value` gives a cell's number in ("Range.Value property": unlike Value2,
    /// Value gives the Currency and Date data types): a Date where the cell's number format
    /// shows a date or time, a Currency where it shows a currency symbol (Excel's Currency and
    /// Accounting formats: `"$"#,##0.00`, `[$€-407] #,##0.00`), a Double (Variant) elsewhere.
    pub(super) fn cell_value_type(&self, sheet: SheetId, pos: Pos) -> Declared {
        let Some(code) = self.cell_format(sheet, pos) else { return Declared::Variant };
        if crate::eval::locale::is_date_code(&code) {
            Declared::Date
        } else if code.contains(['$', '€', '£', '¥']) {
            Declared::Currency
        } else {
            Declared::Variant
        }
    }

    /// `Range.Text`: the first cell's value as its number format shows it.
    pub(super) fn shown_text(&self, ctx: &mut Ctx, sheet: SheetId, pos: Pos) -> String {
        match ctx.rect_value(sheet, Rect::cell(pos)) {
            Value::Number(n) => {
                let code = self.cell_format(sheet, pos);
                let dates = self.wb.borrow().date_system();
                crate::eval::format::number_format::shown(n, code.as_deref(), dates)
            }
            v => print_text(&v),
        }
    }

    /// Every cell's style answer `f` when they agree, else Null.
    fn style_answer(&self, ctx: &Ctx, sheet: SheetId, rect: Rect, f: fn(&CellStyle) -> Value) -> Obj {
        let cells = self.look_cells(ctx, sheet, rect);
        let looks = self.looks.borrow();
        let state = looks.sheets.get(&sheet);
        let answers = cells.into_iter().map(|p| f(&state.map(|s| s.style(p)).unwrap_or_default()));
        Obj::Value(agreed(answers).unwrap_or(Value::Null))
    }

    /// Reads of the formatting members of a range; `None` when `name` is none of them.
    pub(super) fn look_member(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, link: &Link) -> Option<Run<Obj>> {
        let name = link.name.to_ascii_lowercase();
        Some(match name.as_str() {
            "numberformat" | "numberformatlocal" => {
                if let Some(refusal) = self.refuse_local_format(&name, link.span) {
                    return Some(Err(refusal));
                }
                let cells = self.look_cells(ctx, sheet, rect);
                let answers = cells.into_iter().map(|p| self.cell_format(sheet, p));
                let code = agreed(answers).map(|c| Value::text(c.as_deref().unwrap_or("General")));
                Ok(Obj::Value(code.unwrap_or(Value::Null)))
            }
            "horizontalalignment" => Ok(self.style_answer(ctx, sheet, rect, |s| {
                Value::Number(f64::from(s.horizontal.unwrap_or(cell_style::XL_GENERAL)))
            })),
            // A cell's vertical alignment is bottom until set (xlBottom).
            "verticalalignment" => Ok(self.style_answer(ctx, sheet, rect, |s| {
                Value::Number(f64::from(s.vertical.unwrap_or(cell_style::XL_BOTTOM)))
            })),
            "wraptext" => Ok(self.style_answer(ctx, sheet, rect, |s| Value::Bool(s.wrap))),
            "font" => Ok(Obj::Look(sheet, rect, LookPart::Font)),
            "interior" => Ok(Obj::Look(sheet, rect, LookPart::Interior)),
            "columnwidth" => {
                let last = rect.last.col.min(rect.first.col + MAX_COLS);
                let widths = (rect.first.col..=last).map(|c| self.width(sheet, c));
                Ok(Obj::Value(agreed(widths).map_or(Value::Null, Value::Number)))
            }
            "rowheight" => {
                let heights = (rect.first.row..=rect.last.row).map(|r| self.height(sheet, r));
                Ok(Obj::Value(agreed(heights).map_or(Value::Null, Value::Number)))
            }
            "autofit" => self.autofit_range(ctx, sheet, rect, link.span).map(|_| Obj::Value(Value::Blank)),
            "hidden" => self.hidden(sheet, rect, link.span).map(Obj::Value),
            _ => return None,
        })
    }

    /// `r.Font.Bold`, `r.Interior.Color` …
    pub(super) fn look_part_member(
        &self,
        ctx: &Ctx,
        sheet: SheetId,
        rect: Rect,
        part: LookPart,
        link: &Link,
    ) -> Run<Obj> {
        let name = link.name.to_ascii_lowercase();
        match (part, name.as_str()) {
            (LookPart::Font, "bold") => Ok(self.style_answer(ctx, sheet, rect, |s| Value::Bool(s.bold))),
            (LookPart::Font, "italic") => Ok(self.style_answer(ctx, sheet, rect, |s| Value::Bool(s.italic))),
            // An automatic font colour is black ("Font.Color": RGB).
            (LookPart::Font, "color") => {
                Ok(self.style_answer(ctx, sheet, rect, |s| Value::Number(f64::from(s.font_color.unwrap_or(0)))))
            }
            (LookPart::Font, "colorindex") => Ok(self.style_answer(ctx, sheet, rect, |s| {
                Value::Number(s.font_color.map_or(XL_COLOR_INDEX_AUTOMATIC, palette_index))
            })),
            (LookPart::Font, "size") => Ok(self.style_answer(ctx, sheet, rect, |s| {
                Value::Number(s.font_size.map_or(STANDARD_FONT_SIZE, |t| f64::from(t) / 20.0))
            })),
            (LookPart::Font, "underline") => Ok(self.style_answer(ctx, sheet, rect, |s| {
                Value::Number(f64::from(s.underline.unwrap_or(cell_style::XL_UNDERLINE_NONE)))
            })),
            (LookPart::Interior, "color") => {
                Ok(self.style_answer(ctx, sheet, rect, |s| Value::Number(f64::from(s.fill.unwrap_or(NO_FILL)))))
            }
            // A cell without fill answers xlColorIndexNone; a filled one the palette's index nearest its colour.
            (LookPart::Interior, "colorindex") => Ok(self
                .style_answer(ctx, sheet, rect, |s| Value::Number(s.fill.map_or(XL_COLOR_INDEX_NONE, palette_index)))),
            // `Interior.Pattern`: harmless, as the table says; `Font.Name`: refused.
            _ => self.unmodelled(&Obj::Look(sheet, rect, part), link).map_err(|_| self.look_part_refused(part, link)),
        }
    }

    fn look_part_refused(&self, part: LookPart, link: &Link) -> super::interp::Fault {
        let kept = match part {
            LookPart::Font => "Font's Bold, Italic, Color, ColorIndex, Size and Underline",
            LookPart::Interior => "Interior's Color and ColorIndex",
        };
        let what = if part == LookPart::Font { "Font" } else { "Interior" };
        self.unsupported(
            link.span,
            format!(
                "{what}.{} is not modelled by ncsheet: of this, it keeps {kept} only, so the run stops here \
                 (On Error does not skip it)",
                link.name
            ),
        )
    }

    /// `NumberFormatLocal` is the code in the workbook's locale: the same text where the
    /// locale writes numbers as en-US does; elsewhere refused (its separators differ).
    fn refuse_local_format(&self, name: &str, span: Span) -> Option<super::interp::Fault> {
        if name != "numberformatlocal" {
            return None;
        }
        let locale = self.wb.borrow().settings().locale;
        let english = locale.localize_shown("1234.5") == "1234.5";
        (!english).then(|| {
            self.unsupported(
                span,
                "NumberFormatLocal: the workbook's locale spells format codes its own way; use NumberFormat",
            )
        })
    }

    /// Writes of the formatting members; `None` when `name` is none of them.
    pub(super) fn set_look(&self, obj: &Obj, link: &Link, value: &Expr) -> Option<Run<()>> {
        let name = link.name.to_ascii_lowercase();
        let (sheet, rect, part) = match obj {
            Obj::Range(s, r) | Obj::Lines(s, r, _) => (*s, *r, None),
            Obj::Look(s, r, p) => (*s, *r, Some(*p)),
            _ => return None,
        };
        let known = match part {
            None => matches!(
                name.as_str(),
                "numberformat"
                    | "numberformatlocal"
                    | "horizontalalignment"
                    | "verticalalignment"
                    | "wraptext"
                    | "columnwidth"
                    | "rowheight"
                    | "hidden"
                    | "style"
            ),
            Some(_) => true,
        };
        if !known {
            return None;
        }
        Some(self.set_look_value((sheet, rect, part), link, value))
    }

    fn set_look_value(
        &self,
        (sheet, rect, part): (SheetId, Rect, Option<LookPart>),
        link: &Link,
        value: &Expr,
    ) -> Run<()> {
        let name = link.name.to_ascii_lowercase();
        let v = self.eval(value)?;
        let span = link.span;
        let number = |what: &str| self.number_of(&v, what).map_err(|m| self.fault_at(span, m));
        let boolean = || {
            crate::eval::coerce::to_bool(&v)
                .map_err(|_| self.fault_at(span, format!("{} takes True or False", link.name)))
        };
        let edit = match (part, name.as_str()) {
            (None, "numberformat" | "numberformatlocal") => {
                if let Some(refusal) = self.refuse_local_format(&name, span) {
                    return Err(refusal);
                }
                let code =
                    crate::eval::coerce::to_text(&v).map_err(|e| self.fault_at(span, format!("the format is {e}")))?;
                Edit::Format(Rc::from(&*code))
            }
            (None, "style") => {
                let style = crate::eval::coerce::to_text(&v).unwrap_or_default();
                let Some(code) = built_in_style_format(&style) else {
                    let why = format!(
                        "Style = \"{style}\": ncsheet applies Excel's number styles Percent, Comma, Comma [0], \
                         Currency and Currency [0] only"
                    );
                    return Err(self.unsupported(span, why));
                };
                Edit::Format(Rc::from(code))
            }
            (None, "horizontalalignment") => {
                let a = number("HorizontalAlignment")?.round() as i32;
                if !cell_style::is_horizontal(a) {
                    return Err(self.error_1004(
                        span,
                        "HorizontalAlignment takes an XlHAlign value (xlLeft, xlCenter, xlRight …)".into(),
                    ));
                }
                Edit::Horizontal((a != cell_style::XL_GENERAL).then_some(a))
            }
            (None, "verticalalignment") => {
                let a = number("VerticalAlignment")?.round() as i32;
                if !cell_style::is_vertical(a) {
                    return Err(self.error_1004(
                        span,
                        "VerticalAlignment takes an XlVAlign value (xlTop, xlCenter, xlBottom …)".into(),
                    ));
                }
                Edit::Vertical((a != cell_style::XL_BOTTOM).then_some(a))
            }
            (None, "wraptext") => Edit::Wrap(boolean()?),
            (None, "columnwidth") => return self.set_widths(sheet, rect, number("ColumnWidth")?, span),
            (None, "rowheight") => return self.set_heights(sheet, rect, number("RowHeight")?, span),
            (None, "hidden") => return self.set_hidden(sheet, rect, boolean()?, span),
            (Some(LookPart::Font), "bold") => Edit::Bold(boolean()?),
            (Some(LookPart::Font), "italic") => Edit::Italic(boolean()?),
            (Some(LookPart::Font), "color") => {
                Edit::FontColor(Some(self.rgb_of(number("Font.Color")?, "Font", span)?))
            }
            // "Font.ColorIndex property": a palette index, or xlColorIndexAutomatic or
            // xlColorIndexNone, both the automatic colour of a font.
            (Some(LookPart::Font), "colorindex") => {
                Edit::FontColor(self.palette_of(number("Font.ColorIndex")?, "Font", span)?)
            }
            (Some(LookPart::Font), "size") => Edit::FontSize(Some(self.font_size(number("Font.Size")?, span)?)),
            (Some(LookPart::Font), "underline") => Edit::Underline(self.underline_of(&v, span)?),
            (Some(LookPart::Interior), "color") => {
                Edit::Fill(Some(self.rgb_of(number("Interior.Color")?, "Interior", span)?))
            }
            // "Interior.ColorIndex property": xlColorIndexNone (xlNone, -4142) is no fill; so is
            // xlColorIndexAutomatic (-4105) for an interior; else a palette index.
            (Some(LookPart::Interior), "colorindex") => {
                Edit::Fill(self.palette_of(number("Interior.ColorIndex")?, "Interior", span)?)
            }
            // `Interior.Pattern = xlSolid`: a look ncsheet does not keep, harmless to skip.
            (Some(p), _) if super::unmodelled::harmless_setting(&Obj::Look(sheet, rect, p), link) => return Ok(()),
            (Some(p), _) => return Err(self.look_part_refused(p, link)),
            _ => unreachable!("set_look checked the member"),
        };
        self.edit_look(sheet, rect, edit, span)
    }

    /// A `Color` set: an RGB colour, 0 to 16777215 (else error 1004, as Excel's).
    fn rgb_of(&self, n: f64, what: &str, span: Span) -> Run<u32> {
        let c = n.round();
        if !(0.0..=f64::from(NO_FILL)).contains(&c) {
            return Err(
                self.error_1004(span, format!("{what}.Color takes a colour from RGB(…), 0 to 16777215, not {n}"))
            );
        }
        Ok(c as u32)
    }

    /// A `ColorIndex` set: 1 to 56, the default palette's colour; xlColorIndexNone or
    /// xlColorIndexAutomatic, none (`None`); else error 1004.
    fn palette_of(&self, n: f64, what: &str, span: Span) -> Run<Option<u32>> {
        if n == XL_COLOR_INDEX_NONE || n == XL_COLOR_INDEX_AUTOMATIC {
            return Ok(None);
        }
        match cell_style::palette_color(n.round() as u32) {
            Some(c) if n.round() >= 1.0 => Ok(Some(c)),
            _ => Err(self.error_1004(
                span,
                format!(
                    "{what}.ColorIndex takes 1 to 56 (the palette), xlColorIndexNone or xlColorIndexAutomatic, not {n}"
                ),
            )),
        }
    }

    /// `Font.Size`: 1 to 409 points (Excel's font sizes), kept in twentieths of a point.
    fn font_size(&self, points: f64, span: Span) -> Run<u16> {
        if !(1.0..=MAX_HEIGHT).contains(&points) {
            return Err(self.error_1004(span, format!("Font.Size is 1 to 409 points, not {points}")));
        }
        Ok((points * 20.0).round() as u16)
    }

    /// `Font.Underline`: an XlUnderlineStyle value; True is a single underline and False
    /// none, as Excel takes them.
    fn underline_of(&self, v: &Value, span: Span) -> Run<Option<i32>> {
        let style = match v {
            Value::Bool(true) => return Ok(Some(cell_style::XL_UNDERLINE_SINGLE)),
            Value::Bool(false) => return Ok(None),
            v => self.number_of(v, "Font.Underline").map_err(|m| self.fault_at(span, m))?.round() as i32,
        };
        match style {
            cell_style::XL_UNDERLINE_NONE => Ok(None),
            s if cell_style::is_underline(s) => Ok(Some(s)),
            s => Err(self.error_1004(
                span,
                format!("Font.Underline takes an XlUnderlineStyle value (xlUnderlineStyleSingle …), not {s}"),
            )),
        }
    }

    /// Gives each cell of `to` the look (format and style, its own or a line's) of the cell
    /// of `from` it is paired with, all read before any is written: a sort's rows, a paste's
    /// cells. Excel moves the whole cell, its format with its value.
    pub(super) fn copy_looks(&self, from: SheetId, to: SheetId, cells: &[(Pos, Pos)]) {
        let mut looks = self.looks.borrow_mut();
        let source = looks.sheets.get(&from);
        let taken = cells
            .iter()
            .map(|&(f, t)| (t, source.and_then(|s| s.format(f)), source.map(|s| s.style(f)).unwrap_or_default()))
            .collect();
        looks.sheet(to).put_cells(taken);
    }

    /// `rng.Clear` and `rng.ClearFormats` ("Range.Clear method" clears "the entire object",
    /// formats included): the cells go back to General and the plain style, also under a
    /// formatted whole row or column.
    pub(super) fn clear_looks(&self, sheet: SheetId, rect: Rect) -> Run<()> {
        drop(self.book_mut()?);
        let mut looks = self.looks.borrow_mut();
        let state = looks.sheet(sheet);
        let overlaps = |a: &Rect| {
            a.first.row <= rect.last.row
                && rect.first.row <= a.last.row
                && a.first.col <= rect.last.col
                && rect.first.col <= a.last.col
        };
        let under_lines = state.lines.iter().any(|(line, _)| overlaps(line));
        let mut cells: Vec<Pos> =
            state.formats.keys().chain(state.styles.keys()).filter(|p| rect.contains(**p)).copied().collect();
        if under_lines {
            let all = (rect.first.row..=rect.last.row)
                .flat_map(|row| (rect.first.col..=rect.last.col).map(move |col| Pos::new(row, col)));
            cells.extend(all);
        }
        cells.sort_unstable_by_key(|p| (p.row, p.col));
        cells.dedup();
        state.put_cells(cells.into_iter().map(|p| (p, None, CellStyle::default())).collect());
        Ok(())
    }

    fn edit_look(&self, sheet: SheetId, rect: Rect, edit: Edit, span: Span) -> Run<()> {
        // A function called from a cell shares the macro's look but, as in Excel, cannot
        // change it any more than it can change a cell.
        drop(self.book_mut()?);
        let cells = rect.rows() as u64 * rect.cols() as u64;
        let mut looks = self.looks.borrow_mut();
        let state = looks.sheet(sheet);
        if is_whole_lines(rect) {
            state.edit_lines(rect, edit);
            return Ok(());
        }
        if cells > MAX_FORMATTED_CELLS {
            return Err(
                self.beyond_limit(Some(span), format!("formatting {cells} cells one by one is more than a macro may"))
            );
        }
        for row in rect.first.row..=rect.last.row {
            for col in rect.first.col..=rect.last.col {
                state.edit_cell(Pos::new(row, col), &edit);
            }
        }
        Ok(())
    }

    /// A column's width: 0 while it is hidden (Excel's smallest width, "0 (hidden)"), else
    /// as the macro or the file set it, else the standard width. The width set stays kept
    /// for when the column is shown again.
    fn width(&self, sheet: SheetId, col: u32) -> f64 {
        let looks = self.looks.borrow();
        let state = looks.sheets.get(&sheet);
        if state.is_some_and(|s| s.hidden_columns.contains(&(col as u16))) {
            return 0.0;
        }
        let own = state.and_then(|s| s.widths.get(&(col as u16)).copied());
        own.or_else(|| crate::eval::Env::column_width(&**self.wb.borrow(), sheet, col)).unwrap_or(STANDARD_WIDTH)
    }

    /// A row's height: 0 while it is hidden, as a column's width.
    fn height(&self, sheet: SheetId, row: u32) -> f64 {
        let looks = self.looks.borrow();
        let state = looks.sheets.get(&sheet);
        if state.is_some_and(|s| s.hidden_rows.contains(&row)) {
            return 0.0;
        }
        state.and_then(|s| s.heights.get(&row).copied()).unwrap_or(STANDARD_HEIGHT)
    }

    /// `ColumnWidth = w` for every column of `rect`; CELL("width") sees it too.
    fn set_widths(&self, sheet: SheetId, rect: Rect, width: f64, span: Span) -> Run<()> {
        if !(0.0..=MAX_WIDTH).contains(&width) {
            return Err(self.error_1004(span, format!("ColumnWidth is 0 to 255 characters, not {width}")));
        }
        for col in rect.first.col..=rect.last.col {
            self.set_width(sheet, col, width)?;
        }
        Ok(())
    }

    fn set_width(&self, sheet: SheetId, col: u32, width: f64) -> Run<()> {
        self.looks.borrow_mut().sheet(sheet).widths.insert(col as u16, width);
        self.book_mut()?.set_column_width(sheet, Some((col, col)), width);
        Ok(())
    }

    fn set_heights(&self, sheet: SheetId, rect: Rect, height: f64, span: Span) -> Run<()> {
        if !(0.0..=MAX_HEIGHT).contains(&height) {
            return Err(self.error_1004(span, format!("RowHeight is 0 to 409 points, not {height}")));
        }
        if rect.rows() as u64 > MAX_FORMATTED_CELLS {
            return Err(
                self.beyond_limit(Some(span), "RowHeight: set the height of the rows in use, not of the whole sheet")
            );
        }
        let mut looks = self.looks.borrow_mut();
        let state = looks.sheet(sheet);
        for row in rect.first.row..=rect.last.row {
            state.heights.insert(row, height);
        }
        Ok(())
    }

    /// Which lines `Hidden` reaches: Microsoft's "Range.Hidden property" says "the
    /// specified range must span an entire column or row"; whole rows (the whole sheet
    /// included) are rows, whole columns columns, any other range error 1004.
    fn hidden_lines(&self, rect: Rect, span: Span) -> Run<(Axis, u32, u32)> {
        if rect.first.col == 0 && rect.last.col == MAX_COLS - 1 {
            Ok((Axis::Rows, rect.first.row, rect.last.row))
        } else if rect.first.row == 0 && rect.last.row == MAX_ROWS - 1 {
            Ok((Axis::Columns, rect.first.col, rect.last.col))
        } else {
            Err(self.error_1004(
                span,
                "Hidden: the range must span an entire column or row (use r.EntireRow.Hidden or \
                 r.EntireColumn.Hidden)"
                    .into(),
            ))
        }
    }

    /// `r.Hidden`: True when every row (or column) of `r` is hidden, False when none is,
    /// Null when some are (a Variant, as the other looks of a mixed range).
    fn hidden(&self, sheet: SheetId, rect: Rect, span: Span) -> Run<Value> {
        let (axis, first, last) = self.hidden_lines(rect, span)?;
        let looks = self.looks.borrow();
        // The hidden lines in the range, counted from the set (not line by line over the
        // million rows of `Rows.Hidden`).
        let hidden = looks.sheets.get(&sheet).map_or(0, |s| match axis {
            Axis::Rows => s.hidden_rows.range(first..=last).count(),
            Axis::Columns => s.hidden_columns.range(first as u16..=last as u16).count(),
        });
        Ok(match hidden {
            0 => Value::Bool(false),
            n if n as u64 == u64::from(last - first) + 1 => Value::Bool(true),
            _ => Value::Null,
        })
    }

    /// `r.Hidden = True/False`; a row's also hides it from SUBTOTAL(101…) as Excel does.
    fn set_hidden(&self, sheet: SheetId, rect: Rect, hide: bool, span: Span) -> Run<()> {
        let (axis, first, last) = self.hidden_lines(rect, span)?;
        if hide && axis == Axis::Rows && last - first >= MAX_HIDDEN_ROWS {
            let rows = last - first + 1;
            return Err(self.beyond_limit(
                Some(span),
                format!(
                    "Hidden: hiding rows {} to {} ({rows} rows) is more than a macro may (each is kept and \
                     saved on its own; at most {MAX_HIDDEN_ROWS}): hide the rows in use",
                    first + 1,
                    last + 1
                ),
            ));
        }
        {
            let mut looks = self.looks.borrow_mut();
            let state = looks.sheet(sheet);
            let columns = first as u16..=last as u16;
            match (axis, hide) {
                (Axis::Rows, true) => state.hidden_rows.extend(first..=last),
                (Axis::Rows, false) => state.hidden_rows.retain(|row| !(first..=last).contains(row)),
                (Axis::Columns, true) => state.hidden_columns.extend(columns),
                (Axis::Columns, false) => state.hidden_columns.retain(|col| !columns.contains(col)),
            }
        }
        if axis == Axis::Rows {
            let mut book = self.book_mut()?;
            // Showing rows visits only the hidden ones: `Rows.Hidden = False` shows all.
            let rows: Vec<u32> = match hide {
                true => (first..=last).collect(),
                false => book
                    .hidden_rows(sheet)
                    .into_iter()
                    .map(|(row, _)| row)
                    .filter(|row| (first..=last).contains(row))
                    .collect(),
            };
            for row in rows {
                book.set_row_hidden(sheet, row, hide.then_some(RowHidden::Manually));
            }
        }
        Ok(())
    }

    /// `r.AutoFit`: Excel's needs whole rows or whole columns ("Range.AutoFit": "must be a
    /// row or a range of rows, or a column or a range of columns"; else error 1004).
    fn autofit_range(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, span: Span) -> Run<()> {
        if rect.last.row == MAX_ROWS - 1 && rect.first.row == 0 {
            self.autofit(ctx, sheet, rect, false)
        } else if rect.last.col == MAX_COLS - 1 && rect.first.col == 0 {
            self.autofit(ctx, sheet, rect, true)
        } else {
            Err(self.error_1004(span, "AutoFit method of Range class failed: the range must be whole rows or whole columns (use r.Columns.AutoFit)".into()))
        }
    }

    /// `Columns.AutoFit` / `Rows.AutoFit` over the cells of `rect`, as Excel fits only by
    /// the cells of the range. Excel measures the shown text in the font's pixels; ncsheet
    /// has no fonts, so a column becomes as wide as its longest shown text in characters,
    /// each taken as wide as a digit (exact for numbers in Excel's default font, an
    /// approximation for letters), and a row 15 points per line of its tallest wrapped
    /// cell. A column or row with nothing shown keeps its size.
    pub(super) fn autofit(&self, ctx: &mut Ctx, sheet: SheetId, rect: Rect, rows: bool) -> Run<()> {
        let used = ctx.clip_to_used(sheet, rect);
        let mut longest: BTreeMap<u32, usize> = BTreeMap::new();
        for row in used.first.row..=used.last.row {
            for col in used.first.col..=used.last.col {
                let pos = Pos::new(row, col);
                let text = self.shown_text(ctx, sheet, pos);
                if text.is_empty() {
                    continue;
                }
                let size = if rows {
                    let wraps = self.looks.borrow().sheets.get(&sheet).is_some_and(|s| s.style(pos).wrap);
                    if wraps {
                        text.lines().count().max(1)
                    } else {
                        1
                    }
                } else {
                    text.lines().map(|l| l.chars().count()).max().unwrap_or(0)
                };
                let line = if rows { row } else { col };
                let best = longest.entry(line).or_insert(0);
                *best = (*best).max(size);
            }
        }
        for (line, size) in longest {
            if rows {
                self.looks.borrow_mut().sheet(sheet).heights.insert(line, STANDARD_HEIGHT * size as f64);
            } else {
                self.set_width(sheet, line, (size as f64).min(MAX_WIDTH))?;
            }
        }
        Ok(())
    }
}

/// The number format of Excel's built-in number styles, which apply their number format and
/// nothing else (their "Style Includes" is Number alone): ECMA-376 Part 1, 18.8.30's built-in
/// formats 9 (Percent), 43 (Comma), 41 (Comma [0]), 44 (Currency) and 42 (Currency [0]).
fn built_in_style_format(style: &str) -> Option<&'static str> {
    match style.to_ascii_lowercase().as_str() {
        "percent" => Some("0%"),
        "comma" => Some(r#"_(* #,##0.00_);_(* \(#,##0.00\);_(* "-"??_);_(@_)"#),
        "comma [0]" => Some(r#"_(* #,##0_);_(* \(#,##0\);_(* "-"_);_(@_)"#),
        "currency" => Some(r#"_("$"* #,##0.00_);_("$"* \(#,##0.00\);_("$"* "-"??_);_(@_)"#),
        "currency [0]" => Some(r#"_("$"* #,##0_);_("$"* \(#,##0\);_("$"* "-"_);_(@_)"#),
        _ => None,
    }
}
