//! One workbook as every front end sees it: the command line, a server, a test. A [`Document`]
//! is opened from bytes (the format detected from them, a file name only a hint), holds the
//! workbook with its VBA project's functions installed and what the import left out, takes
//! edits, recalculates, reports problems as data, and saves to bytes with the list of what the
//! saved file loses. It touches no file: paths and atomic writes are the caller's
//! ([`crate::io::Encoded::write`]).
//!
//! ```
//! use ncsheet::document::{Document, OpenOptions, SaveFormat};
//! let csv = b"1,2\n=A1+B1,\n".to_vec();
//! let mut doc = Document::open(csv, &OpenOptions::named("parts.csv")).unwrap();
//! let (sheet, b1) = doc.cell("B1").unwrap();
//! doc.set(sheet, b1, "40").unwrap();
//! let (_, a2) = doc.cell("A2").unwrap();
//! assert_eq!(doc.workbook().value(sheet, a2).to_string(), "41");
//! let saved = doc.save_as(SaveFormat::Csv).unwrap();
//! assert_eq!(saved.bytes(), b"1,40\n=A1+B1,\n");
//! ```

use std::path::{Path, PathBuf};

use crate::eval::Settings;
use crate::formula::address::{Pos, Rect};
use crate::formula::ast::SheetId;
use crate::io::{self, xlsx, Encoded, Format, Opened, Origin};
use crate::vba::{self, ModuleKind, RunOptions, VbaProject};
use crate::workbook::{Problem, ProblemKind, SheetEdit, SheetLook, Workbook, WorkbookError};

/// How to read a document's bytes.
#[derive(Clone, Debug, Default)]
pub struct OpenOptions {
    /// The file's name: said in every message about it, and a hint to the format when the
    /// bytes do not tell (a csv has no signature).
    pub name: PathBuf,
    /// The format, when the caller knows it better than the bytes and the name.
    pub format: Option<Format>,
    /// A csv's separator (`None`: detected from the text).
    pub csv_delimiter: Option<u8>,
    /// How far an xlsx part may inflate and how long a csv field or line may be.
    pub read_limits: io::limits::ReadLimits,
    /// The limits the workbook's own VBA functions run under when cells call them.
    pub functions: RunOptions,
    /// The clock and random sequence the workbook's formulas read (`None`: the system clock
    /// and a sequence seeded from it).
    pub settings: Option<Settings>,
}

impl OpenOptions {
    /// Options for bytes that came from (or stand for) the file `name`.
    pub fn named(name: impl Into<PathBuf>) -> OpenOptions {
        OpenOptions { name: name.into(), ..OpenOptions::default() }
    }
}

/// The formats a document saves to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SaveFormat {
    Xlsx,
    /// An xlsx package with its VBA project (only for a document read from an .xlsm).
    Xlsm,
    /// The first sheet, as comma-separated values (a csv read from a file keeps its own
    /// separator and every untouched field as typed).
    Csv,
}

impl SaveFormat {
    fn extension(self) -> &'static str {
        match self {
            SaveFormat::Xlsx => "xlsx",
            SaveFormat::Xlsm => "xlsm",
            SaveFormat::Csv => "csv",
        }
    }
}

/// A workbook opened from bytes, with what the file held besides its cells.
pub struct Document {
    opened: Opened,
    name: PathBuf,
    csv_delimiter: Option<u8>,
    /// The workbook's VBA project as read once from its `vbaProject.bin` when the file was
    /// opened (`None`: it holds none), for its functions and for every macro run on it.
    project: Option<Result<VbaProject, vba::ProjectError>>,
}

/// A document could not be opened or saved: the error names the file and the part of it.
pub type Error = io::Error;

impl Document {
    /// Reads `bytes` into a recalculated workbook with the VBA project's public Functions
    /// callable from its cells. Cells that hold bad input are not an error: they are error
    /// values, listed by [`Document::problems`]; what the import left out is in
    /// [`Document::notes`].
    pub fn open(bytes: Vec<u8>, options: &OpenOptions) -> Result<Document, Error> {
        let format = match options.format {
            Some(format) => format,
            None => Format::detect(&bytes, &options.name)?,
        };
        let mut opened =
            io::open_bytes_limited(bytes, &options.name, format, options.csv_delimiter, options.read_limits)?;
        let project = opened.layout.as_ref().and_then(|l| l.vba_project.as_deref()).map(vba::read_project);
        install_functions(&mut opened, project.as_ref(), options.functions.clone());
        let mut doc = Document { opened, name: options.name.clone(), csv_delimiter: options.csv_delimiter, project };
        if let Some(settings) = &options.settings {
            let locale = settings.locale_in_force(doc.opened.workbook.date_system());
            read_csv_fields_in_locale(&mut doc.opened, locale);
            doc.set_settings(settings.clone());
        }
        Ok(doc)
    }

    /// Reads the file at `path` (see [`Document::open`]); its format comes from its bytes.
    pub fn open_file(path: &Path, options: &OpenOptions) -> Result<Document, Error> {
        let bytes = io::read_file(path)?;
        Document::open(bytes, &OpenOptions { name: path.to_path_buf(), ..options.clone() })
    }

    /// The name the document was opened under.
    pub fn name(&self) -> &Path {
        &self.name
    }

    pub fn workbook(&self) -> &Workbook {
        &self.opened.workbook
    }

    pub fn workbook_mut(&mut self) -> &mut Workbook {
        &mut self.opened.workbook
    }

    /// What the import left out, one sentence each, for the user to hear.
    pub fn notes(&self) -> &[String] {
        &self.opened.notes
    }

    /// The cells' problems (formulas that do not parse, unknown names, cycles …) as data.
    pub fn problems(&self) -> Vec<Problem> {
        self.opened.workbook.problems()
    }

    /// The values the file stored for its formula cells (empty for a csv).
    pub fn cached(&self) -> &[xlsx::CachedValue] {
        &self.opened.cached
    }

    /// The file's number formats, widths, calculation settings and VBA project (xlsx only).
    pub fn layout(&self) -> Option<&xlsx::Layout> {
        self.opened.layout.as_ref()
    }

    /// The program that last saved the file, whose results [`Document::cached`] holds.
    pub fn written_by(&self) -> Option<&str> {
        self.opened.written_by.as_deref()
    }

    /// The file as read, which a save starts from.
    pub fn origin(&self) -> &Origin {
        &self.opened.origin
    }

    /// The workbook's VBA project, as read when the file was opened (`None`: the file holds
    /// none).
    pub fn vba_project(&self) -> Option<Result<&VbaProject, &vba::ProjectError>> {
        self.project.as_ref().map(Result::as_ref)
    }

    /// A cell by its name as a user types it (`B8`, `Outer!B8`, a defined name), on the first
    /// sheet unless the name says otherwise.
    pub fn cell(&self, name: &str) -> Option<(SheetId, Pos)> {
        let wb = &self.opened.workbook;
        let (sheet, local) = match name.rsplit_once('!') {
            Some((sheet, local)) => (wb.sheet_id(sheet.trim_matches('\''))?, local),
            None => (0, name),
        };
        if let Some(pos) = crate::formula::address::parse_cell(local) {
            return Some((sheet, pos));
        }
        let (sheet, rect) = wb.name_reference(local, sheet)?;
        rect.is_cell().then_some((sheet, rect.first))
    }

    /// Types `input` into a cell, as a user types it in the document's locale (`30`, `0,8`,
    /// `=B5*2`, `=ROUND(B5*0,5;3)`, `'text`), and recalculates what depends on it. Returns the
    /// problems the edit brought; a formula that does not parse, or a value that is a number
    /// only in another locale, is refused and the cell left as it was.
    pub fn set(&mut self, sheet: SheetId, pos: Pos, input: &str) -> Result<Vec<Problem>, Problem> {
        let wb = &mut self.opened.workbook;
        let canonical = wb.typed_input(input).map_err(|why| Problem {
            sheet,
            pos,
            kind: ProblemKind::Parse(why),
            text: input.to_string(),
            span: None,
        })?;
        let canonical = canonical.into_owned();
        let format = typed_date_format(wb, input);
        let problems = wb.set_input(sheet, pos, &canonical)?;
        if let Some(code) = format {
            self.show_as(sheet, pos, code);
        }
        Ok(problems)
    }

    /// After `typed` was typed into a cell (by a front end that types through
    /// `Workbook::typed_input`): a date or time in the locale gives the cell the format Excel
    /// gives it, as [`Document::set`] does. The format given, if any.
    pub fn typed_into(&mut self, sheet: SheetId, pos: Pos, typed: &str) -> Option<&'static str> {
        let format = typed_date_format(&self.opened.workbook, typed);
        if let Some(code) = format {
            self.show_as(sheet, pos, code);
        }
        format
    }

    /// A cell a date or time was typed into shows it in `code` (Excel's built-in date, 14,
    /// `m/d/yyyy` in the file, which every locale shows as its short date; its date and time,
    /// 22; or a time), unless it has a format already.
    fn show_as(&mut self, sheet: SheetId, pos: Pos, code: &str) {
        let Some(name) = self.opened.workbook.sheet_names().into_iter().nth(sheet as usize) else { return };
        let layout = self.opened.layout.get_or_insert_with(Default::default);
        let sheet = layout.sheets.entry(name).or_default();
        if sheet.look.number_formats.contains_key(&pos) {
            return;
        }
        // The file's look is kept, as a macro's change keeps it, so a save over the file's
        // own package writes the new format.
        sheet.file_look.get_or_insert_with(|| sheet.look.clone());
        sheet.look.number_formats.insert(pos, code.to_string());
    }

    /// Inserts or deletes rows, columns or a rectangle's cells (a front end's "insert row"),
    /// as [`Workbook::shift_cells`] does: every reference follows its cells, and so do the
    /// cells' number formats and styles, the columns' widths, the rows' heights and the
    /// file's array formulas. Refused,
    /// with nothing changed, where Excel refuses (an array cut through).
    pub fn shift_cells(&mut self, sheet: SheetId, edit: SheetEdit) -> Result<(), WorkbookError> {
        self.opened.workbook.shift_cells(sheet, edit)?;
        let name = self.opened.workbook.sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
        let Some(layout) = self.opened.layout.as_mut().and_then(|l| l.sheets.get_mut(&name)) else { return Ok(()) };
        layout.look.follow(&edit);
        layout.array_formulas = std::mem::take(&mut layout.array_formulas)
            .into_values()
            .filter_map(|a| {
                let (anchor, first, last) =
                    (edit.moved(a.anchor)?, edit.moved(a.area.first)?, edit.moved(a.area.last)?);
                Some((anchor, xlsx::ArrayFormula { anchor, area: Rect::new(first, last), ..a }))
            })
            .collect();
        Ok(())
    }

    /// Runs a macro (`vba::run`) on the workbook as the file's sheets stand: their code names,
    /// active cells and look (number formats, styles, widths, heights) are the run's. The
    /// cells it writes stay, as in Excel, and so does the look it leaves: the document keeps
    /// it (in [`Document::layout`], not in the output's `looks`) for a save to write. A macro
    /// that stops with an error keeps what it did before it stopped.
    pub fn run_macro(
        &mut self,
        source: &str,
        file: &str,
        options: RunOptions,
    ) -> Result<vba::RunOutput, vba::MacroError> {
        let sheets = self.opened.layout.iter().flat_map(|l| &l.sheets);
        // Text files in the code page of the machine that wrote the workbook's project.
        let own_code_page = self.vba_project().and_then(Result::ok).map(|p| p.code_page);
        let options = RunOptions {
            code_page: options.code_page.or(own_code_page),
            code_names: sheets.clone().filter_map(|(name, s)| Some((s.code_name.clone()?, name.clone()))).collect(),
            active_cells: sheets.clone().filter_map(|(name, s)| Some((name.clone(), s.active_cell?))).collect(),
            selections: sheets.clone().filter_map(|(name, s)| Some((name.clone(), s.selection.clone()?))).collect(),
            looks: sheets.map(|(name, s)| (name.clone(), s.look.clone())).collect(),
            ..options
        };
        let live: Vec<SheetId> = self.opened.workbook.tab_order().to_vec();
        let mut result = vba::run(&mut self.opened.workbook, source, file, &options);
        for sheet in live {
            self.forget_if_deleted(sheet);
        }
        let output = match &mut result {
            Ok(out) => out,
            Err(e) => &mut *e.output,
        };
        self.keep_looks(std::mem::take(&mut output.looks));
        result
    }

    /// Deletes `sheet` as [`Workbook::delete_sheet`] does (references to it become `#REF!`),
    /// with what the file kept of it (look, code name, array formulas), which a sheet given
    /// its name later must not take over.
    pub fn delete_sheet(&mut self, sheet: SheetId) -> Result<(), WorkbookError> {
        self.opened.workbook.delete_sheet(sheet)?;
        self.forget_if_deleted(sheet);
        Ok(())
    }

    /// Drops the layout of `sheet` (by its name) when the sheet was deleted.
    fn forget_if_deleted(&mut self, sheet: SheetId) {
        let wb = &self.opened.workbook;
        if !wb.sheet_deleted(sheet) {
            return;
        }
        let name = &wb.sheet_names()[sheet as usize];
        if let Some(layout) = self.opened.layout.as_mut() {
            layout.sheets.remove(name);
        }
    }

    /// The look a macro left each sheet with, as the document's; the file's own is kept
    /// beside it for a save over the file (`SheetLayout::file_look`).
    fn keep_looks(&mut self, looks: Vec<(String, SheetLook)>) {
        if looks.is_empty() {
            return;
        }
        let layout = self.opened.layout.get_or_insert_with(Default::default);
        for (name, look) in looks {
            let look = look.in_order();
            let sheet = layout.sheets.entry(name).or_default();
            if sheet.look.clone().in_order() == look {
                continue;
            }
            let was = std::mem::replace(&mut sheet.look, look);
            sheet.file_look.get_or_insert(was);
        }
    }

    /// The clock and random sequence the formulas read.
    pub fn settings(&self) -> &Settings {
        self.opened.workbook.settings()
    }

    /// Changes the clock or the random sequence, and recomputes the cells that read them.
    pub fn set_settings(&mut self, settings: Settings) {
        *self.opened.workbook.settings_mut() = settings;
        self.opened.workbook.recalculate();
    }

    /// A cell's value as the cell's number format shows it (General without one), in the
    /// workbook's own date system.
    pub fn shown(&self, sheet: SheetId, pos: Pos) -> String {
        let wb = &self.opened.workbook;
        let value = wb.value(sheet, pos);
        let crate::eval::Value::Number(n) = value else { return value.to_string() };
        let sheet_name = wb.sheet_names().into_iter().nth(sheet as usize).unwrap_or_default();
        let layout = self.layout().and_then(|l| l.sheets.get(&sheet_name));
        let code = layout.and_then(|l| l.look.number_formats.get(&pos)).map(String::as_str);
        crate::eval::format::number_format::shown(n, code, wb.date_system())
    }

    /// Recomputes every cell that an edit made stale.
    pub fn recalculate(&mut self) {
        self.opened.workbook.recalculate();
    }

    /// The document as a file named `target` would hold it (the format by its extension),
    /// computed and not written: its bytes and what it loses of the original.
    pub fn encode(&self, target: &Path) -> Result<Encoded, Error> {
        let layout = self.opened.layout.as_ref();
        io::encode_save_with(&self.opened.workbook, layout, &self.opened.origin, target, self.csv_delimiter)
    }

    /// The document saved in `format`, under its own name with that format's extension.
    pub fn save_as(&self, format: SaveFormat) -> Result<Encoded, Error> {
        let name = match self.name.file_stem() {
            Some(stem) => self.name.with_file_name(stem).with_extension(format.extension()),
            None => PathBuf::from("workbook").with_extension(format.extension()),
        };
        self.encode(&name)
    }

    /// The parts as [`io::open_bytes`] read them, for a caller that takes the workbook away.
    pub fn into_opened(self) -> Opened {
        self.opened
    }
}

/// Makes the public Functions of the workbook's VBA project callable from its cells; a
/// project that cannot be read, or a module that does not parse whose functions a cell
/// calls, becomes a note (those cells stay `#NAME?`).
fn install_functions(
    opened: &mut Opened,
    project: Option<&Result<VbaProject, vba::ProjectError>>,
    options: RunOptions,
) {
    let Some(layout) = opened.layout.as_ref() else { return };
    let project = match project {
        None => return,
        Some(Ok(p)) => p,
        Some(Err(e)) => return opened.notes.push(format!("xl/vbaProject.bin: {e}: its functions are not callable")),
    };
    let code_names = layout.sheets.iter().filter_map(|(name, s)| Some((s.code_name.clone()?, name.clone()))).collect();
    // The file's number formats, for a function reading `Range.Text` as Excel shows the cell.
    let looks = layout.sheets.iter().map(|(name, s)| (name.clone(), s.look.clone())).collect();
    let errors = vba::install_functions(&mut opened.workbook, project, RunOptions { code_names, looks, ..options });
    if errors.is_empty() {
        return;
    }
    let called = unknown_functions(&opened.workbook);
    for e in errors {
        let Some(module) = project.modules.iter().find(|m| m.name == e.file && m.kind == ModuleKind::Standard) else {
            continue;
        };
        let is_called = |f: &String| called.iter().any(|c| names_function(c, f));
        if let Some(f) = module.function_names().into_iter().find(is_called) {
            let place = e.span.map_or(String::new(), |s| format!("{}:{}: ", s.line, s.col));
            opened.notes.push(format!(
                "module {}: {place}{}: its functions ({f} …) are #NAME? in the cells that call them",
                e.file, e.message
            ));
        }
    }
}

/// The number format a cell gets when `typed` is a date or time in the workbook's locale,
/// as Excel gives it in every locale: a date alone (`28.11.2026` in de-DE, `11/28/2026` in
/// en-US) the built-in date (14), a date with a time (`12.03.2025 14:30`) the built-in date
/// and time (22), and a time alone its time format ([`typed_time_format`]). Only the format
/// changes: the value is the same serial (en-US showed a typed `14:30` as 0.604166666666667).
fn typed_date_format(wb: &crate::workbook::Workbook, typed: &str) -> Option<&'static str> {
    typed_date_format_in(wb.settings().locale_in_force(wb.date_system()), wb.date_system(), typed)
}

/// [`typed_date_format`] in `locale`, for dates of `system`.
fn typed_date_format_in(
    locale: crate::eval::Locale,
    system: crate::eval::dates::DateSystem,
    typed: &str,
) -> Option<&'static str> {
    let text = typed.trim();
    if text.starts_with(['=', '\'']) || locale.read_plain_number(text).is_some() {
        return None;
    }
    date_text_format(locale, system, text)
}

/// The format of `text`, no plain number, typed as a date or time in `locale`
/// ([`typed_date_format_in`]).
fn date_text_format(
    locale: crate::eval::Locale,
    system: crate::eval::dates::DateSystem,
    text: &str,
) -> Option<&'static str> {
    let read = locale.read_date_text(text, system)?;
    match (read.date, read.time) {
        (Some(_), None) => Some(crate::eval::locale::BUILTIN_DATE),
        (Some(_), Some(_)) => Some(crate::eval::locale::BUILTIN_DATE_TIME),
        (None, Some(time)) => Some(typed_time_format(&locale.canonical_date_time_text(text)?, time)),
        (None, None) => None,
    }
}

/// The built-in time format Excel gives a time typed alone, `text` read as `time` (a fraction
/// of a day): `h:mm` (20), `h:mm:ss` (21) with seconds, `h:mm AM/PM` (18) or `h:mm:ss AM/PM`
/// (19) when typed with AM or PM, `mm:ss.0` (47) for minutes and seconds with a fraction
/// (`1:30.5`), and `[h]:mm:ss` (46) for a day or more (`25:30`), which `h` would show
/// without its days. `text` spells morning and afternoon in en-US's words (de-DE's
/// `2:30 nachm.` as `2:30 PM`), so that a `.` in a locale's word is no fraction.
fn typed_time_format(text: &str, time: f64) -> &'static str {
    let upper = text.trim_end().to_ascii_uppercase();
    let clock = upper.strip_suffix("AM").or_else(|| upper.strip_suffix("PM"));
    let meridiem = clock.is_some();
    let clock = clock.unwrap_or(&upper);
    let seconds = clock.matches(':').count() > 1;
    match (meridiem, seconds) {
        _ if time >= 1.0 => "[h]:mm:ss",
        (false, false) if clock.contains(['.', ',']) => "mm:ss.0",
        (true, true) => "h:mm:ss AM/PM",
        (true, false) => "h:mm AM/PM",
        (false, true) => "h:mm:ss",
        (false, false) => "h:mm",
    }
}

/// The number format a percent or a scientific number read from a csv in a decimal-comma
/// `locale` gets (`12,5%`, `1,5E+03`), as LibreOffice set to the locale gives it, so that it is
/// written back as LibreOffice writes it: the locale's percent with two decimals (de-DE
/// `12,50 %`, et-EE `12,50%`) and `0.00E+00` (`1,50E+03`); `text` is a plain number there.
fn csv_number_format(locale: crate::eval::Locale, text: &str) -> Option<&'static str> {
    let text = text.trim();
    if locale.is_canonical() {
        return None;
    }
    if text.ends_with('%') {
        return Some(locale.percent_code);
    }
    text.contains(['E', 'e']).then_some("0.00E+00")
}

/// A csv opened in a decimal-comma locale: each field is read as that locale's Excel opens
/// the file, from the file's own text: numbers and dates in its spelling (`1.234,5` in de-DE,
/// `1 234,5` in fr-FR, `12.03.2025`, and `3,750%`, which the file syntax would take for 37.5)
/// and its words for TRUE and FALSE (`WAHR`); a field forced to text with `'` stays text, and
/// so does one that is a number only in the file syntax. A date or time gets the format a
/// date or time typed there gets ([`typed_date_format`]), so that it shows, and is written
/// back, as the file spelled it (`12.03.2025`, not its serial 45728).
fn read_csv_fields_in_locale(opened: &mut Opened, locale: crate::eval::Locale) {
    use crate::eval::Value;
    let Origin::Csv(original) = &opened.origin else { return };
    if locale.is_canonical() {
        return;
    }
    let wb = &mut opened.workbook;
    let mut inputs = Vec::new();
    let mut formats = Vec::new();
    for (pos, value) in wb.values(0) {
        let raw = original.raw_field(pos.row as usize, pos.col as usize).unwrap_or_default();
        let text = unquoted(raw);
        if wb.is_formula(0, pos) || text.starts_with('\'') {
            continue;
        }
        if let Some(b) = locale.read_boolean(&text) {
            if value != Value::Bool(b) {
                inputs.push((pos, if b { "TRUE" } else { "FALSE" }.to_string()));
            }
        } else if let Some((n, code)) = csv_number(locale, wb.date_system(), &text) {
            formats.extend(code.map(|code| (pos, code)));
            if value != Value::Number(n) {
                // The shortest spelling that reads back as the same number, in the file syntax.
                inputs.push((pos, format!("{n}")));
            }
        } else if matches!(value, Value::Number(_)) && original.delimiter() != b',' {
            // In a `;` file, a number only in the file syntax (`0.8`, `12/03/2025` in de-DE)
            // is text, as LibreOffice set to the locale opens it: never the en-US reading. A
            // `,` file is read with decimal points, as the command line notes.
            inputs.push((pos, format!("'{text}")));
        }
    }
    for (pos, input) in inputs {
        let _ = wb.set_input_deferred(0, pos, &input);
    }
    // The locale's reading is the file's own, not an edit: a save writes those fields back
    // byte for byte (`1.234,5`, not `1234,5`).
    wb.track_changes();
    let Some(sheet) = wb.sheet_names().into_iter().next() else { return };
    if formats.is_empty() {
        return;
    }
    let layout = opened.layout.get_or_insert_with(Default::default);
    let shown = &mut layout.sheets.entry(sheet).or_default().look.number_formats;
    // The file's own formats stay; the rest go in at once (one by one, each would move the
    // cells after it).
    let absent: Vec<_> = formats.into_iter().filter(|(pos, _)| !shown.contains_key(pos)).collect();
    shown.extend(absent.into_iter().map(|(pos, code)| (pos, code.to_string())));
}

/// A csv field read as a number in a decimal-comma `locale`, its plain number read once, with
/// the format it gets: a percent's or a scientific number's ([`csv_number_format`]), or a
/// date's or a time's ([`typed_date_format_in`]).
fn csv_number(
    locale: crate::eval::Locale,
    system: crate::eval::dates::DateSystem,
    text: &str,
) -> Option<(f64, Option<&'static str>)> {
    if let Some(n) = locale.read_plain_number(text) {
        return Some((n, csv_number_format(locale, text)));
    }
    let n = locale.read_number_beyond_plain(text, system)?;
    let text = text.trim();
    let code = if text.starts_with(['=', '\'']) { None } else { date_text_format(locale, system, text) };
    Some((n, code))
}

/// A csv field's text: without the quotes around it, `""` inside it one `"`.
fn unquoted(raw: &str) -> String {
    match raw.strip_prefix('"').and_then(|r| r.strip_suffix('"')) {
        Some(inner) => inner.replace("\"\"", "\""),
        None => raw.to_string(),
    }
}

/// The names cells call that are no function the workbook knows.
fn unknown_functions(wb: &Workbook) -> Vec<String> {
    let unknown = |p: Problem| match p.kind {
        ProblemKind::UnknownFunction(name) => Some(name),
        _ => None,
    };
    wb.problems().into_iter().filter_map(unknown).collect()
}

/// Whether a call of `called` (`tip`, `Module1.Tip`) names the function `f`, as VBA matches
/// names: case aside, bare or qualified by its module.
fn names_function(called: &str, f: &str) -> bool {
    let bare = called.rsplit('.').next().unwrap_or(called);
    bare.eq_ignore_ascii_case(f)
}
