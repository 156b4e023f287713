//! Excel itself as the oracle, one formula cell at a time: the harness of the
//! `tests/excel_corpus_*.rs` tests, which differ only in the [`Suite`] they check.
//!
//! The corpus workbooks (see tests/data/excel-corpus/README.md) were saved by Excel, so
//! every formula cell caches the value Excel computed. A sheet's cached values are loaded
//! as constants into a [`MapEnv`]; every formula cell that calls only functions we have and
//! reads only its own sheet is evaluated on them and compared with its own cached value. A
//! cell's inputs are Excel's values, not ours, so each check is independent of every other
//! function.
//!
//! An array result must match the cached values of the cells it spills into; failing that,
//! the formula is read as Excel read it before dynamic arrays (implicit intersection), since
//! many of these workbooks hold such legacy formulas.
//!
//! Run a test with `-- --nocapture` for the per-file and per-function tables, with
//! `NCSHEET_CORPUS_VERBOSE=1` to list every formula left unchecked, and with
//! `NCSHEET_EXCEL_CORPUS` naming another copy of the corpus's `ironcalc` folder.

use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use calamine::{open_workbook, CellErrorType, DataRef, Reader, Xlsx, XlsxFormulaMetadata};
use ncsheet::eval::functions::{spec, Outside, Registry};
use ncsheet::eval::testing::MapEnv;
use ncsheet::eval::{Ctx, Operand, Value, XlError};
use ncsheet::formula::ast::{BinOp, Expr, ExprKind, RefShape, SheetRef, UnaryOp};
use ncsheet::formula::{parse_formula, ParseContext, Pos};

use super::corpus::NOT_FROM_EXCEL;

/// What one corpus test checks; everything else is common.
pub struct Suite {
    /// Folders (the `.xlsx` files directly in them) and single workbooks, relative to the
    /// corpus root.
    pub sources: &'static [&'static str],
    /// Cells where we knowingly differ from Excel. Keep this short: a disagreement in scope
    /// is a bug to fix, not a line to add.
    pub allowed: &'static [Allowed],
    /// Texts Excel reads as numbers where we do not (yet). A formula that differs while
    /// reading a cell holding one of them is excused, not counted: the difference is in the
    /// shared text-to-number coercion, not in the function checked.
    pub excused_texts: &'static [&'static str],
}

/// Cells of one sheet where we knowingly differ from Excel, and why.
pub struct Allowed {
    /// Relative to the corpus root, as in [`Suite::sources`].
    pub file: &'static str,
    pub sheet: &'static str,
    pub cells: &'static [&'static str],
    pub why: &'static str,
}

/// Checks every formula cell of the suite's workbooks against Excel, prints the tallies and
/// fails on any difference not allowed. Without the corpus it returns (failing on CI, see
/// [`super::corpus::root`]).
pub fn check(suite: &Suite) {
    let Some(root) = super::corpus::root() else { return };
    let mut report = Report::default();
    for path in workbooks(&root, suite.sources) {
        check_workbook(&root, &path, suite, &mut report);
    }
    report.print(suite.allowed);
    let checked = report.total().checked;
    assert!(report.failures.is_empty(), "{} formula cells differ from Excel (listed above)", report.failures.len());
    assert!(checked >= 500, "only {checked} cells checked: is the corpus complete?");
}

/// The suite's workbooks in the order of its sources, each folder's sorted by name.
fn workbooks(root: &Path, sources: &[&str]) -> Vec<PathBuf> {
    let files =
        sources.iter().map(|source| root.join(source)).flat_map(|p| if p.is_dir() { xlsx_in(&p) } else { vec![p] });
    files.filter(|p| !NOT_FROM_EXCEL.iter().any(|n| p.ends_with(n))).collect()
}

fn xlsx_in(folder: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(folder)
        .unwrap_or_else(|e| panic!("{}: {e}", folder.display()))
        .map(|e| e.expect("folder entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "xlsx"))
        .collect();
    found.sort();
    found
}

fn check_workbook(root: &Path, path: &Path, suite: &Suite, report: &mut Report) {
    let file = path.strip_prefix(root).unwrap_or(path).display().to_string();
    let mut workbook: Xlsx<BufReader<File>> = open_workbook(path).unwrap_or_else(|e| panic!("{file}: {e}"));
    // Listed even when none of its formulas is in scope, so the table shows what was read.
    report.per_file.entry(file.clone()).or_default();
    let ours = ncsheet::io::xlsx::load(path).ok();
    for name in workbook.sheet_names() {
        let Some(mut sheet) = read_sheet(&mut workbook, &name) else {
            report.skip("sheet we cannot read");
            continue;
        };
        if let Some(imported) = &ours {
            name_newer_errors(imported, &name, &mut sheet.values);
        }
        let env = MapEnv { cells: sheet.values, ..MapEnv::default() };
        let check = SheetCheck { file: &file, sheet: &name, suite, env, formulas: &sheet.formulas };
        check.run(report);
    }
}

/// Excel 365 stores a `#CALC!` or `#SPILL!` as `#VALUE!` for older readers, the real error
/// kept as value metadata, which calamine does not read: such cells get the error ncsheet's
/// reader finds there. (That reading is checked against Excel itself in
/// tests/xlsx_conformance.rs: ERROR.TYPE of such cells, as Excel cached it, is 14 and 9.)
fn name_newer_errors(
    imported: &ncsheet::io::xlsx::Imported,
    sheet_name: &str,
    values: &mut BTreeMap<(u32, u32), Value>,
) {
    let Some(sheet) = imported.workbook.sheet_id(sheet_name) else { return };
    for (&(row, col), value) in values.iter_mut().filter(|(_, v)| **v == Value::Error(XlError::Value)) {
        let pos = Pos::new(row, col);
        let stored = match imported.cached.iter().find(|c| c.sheet == sheet && c.pos == pos) {
            Some(c) => c.value.clone(),
            None if imported.workbook.formula(sheet, pos).is_none() => imported.workbook.value(sheet, pos),
            None => continue,
        };
        if matches!(stored, Value::Error(XlError::Calc | XlError::Spill)) {
            *value = stored;
        }
    }
}

/// One worksheet as Excel saved it.
pub struct Sheet {
    /// Every cached value, formula results included: the constants formulas are evaluated on.
    pub values: BTreeMap<(u32, u32), Value>,
    pub formulas: BTreeMap<(u32, u32), Formula>,
}

/// A formula cell: the formula text and the cell it was written for. A shared formula (one
/// formula filled over a range) is stored once, at its template cell; our trees keep
/// relative references as offsets, so the template's tree evaluated at each cell is that
/// cell's formula (calamine's own expansion starts from the top-left of the shared range,
/// which is not always the template's cell: FLOOR_CEILING.xlsx has such groups).
#[derive(Clone)]
pub struct Formula {
    pub text: String,
    pub anchor: Pos,
}

/// Reads a worksheet in one pass; `None` where calamine cannot, or a shared formula comes
/// before its template.
pub fn read_sheet(workbook: &mut Xlsx<BufReader<File>>, name: &str) -> Option<Sheet> {
    let mut reader = workbook.worksheet_cells_reader(name).ok()?;
    let mut templates: BTreeMap<usize, Formula> = BTreeMap::new();
    let mut sheet = Sheet { values: BTreeMap::new(), formulas: BTreeMap::new() };
    while let Some(cell) = reader.next_cell_with_formula_metadata().ok()? {
        let formula = match cell.formula {
            None => None,
            Some(record) => Some(formula_of(record, Pos::new(cell.pos.0, cell.pos.1), &mut templates)?),
        };
        let value = match (value_of(&cell.value), &formula) {
            // Excel writes an empty-text result as `<v/>`, which calamine reads as empty.
            (None, Some(_)) => Some(Value::text("")),
            (v, _) => v,
        };
        if let Some(v) = value {
            sheet.values.insert(cell.pos, v);
        }
        if let Some(f) = formula.filter(|f| !f.text.is_empty()) {
            sheet.formulas.insert(cell.pos, f);
        }
    }
    Some(sheet)
}

/// A cell's formula record as a [`Formula`]; `None` for a shared formula whose template
/// has not been read.
fn formula_of(record: XlsxFormulaMetadata, at: Pos, templates: &mut BTreeMap<usize, Formula>) -> Option<Formula> {
    match record {
        XlsxFormulaMetadata::Normal { formula } => Some(Formula { text: formula, anchor: at }),
        XlsxFormulaMetadata::Shared { shared_index, formula, .. } => {
            templates.insert(shared_index, Formula { text: formula.clone(), anchor: at });
            Some(Formula { text: formula, anchor: at })
        }
        XlsxFormulaMetadata::SharedDerived { shared_index } => templates.get(&shared_index).cloned(),
        other => panic!("unexpected formula record {other:?}"),
    }
}

/// A cached cell value as ours (`None` for an empty cell).
fn value_of(d: &DataRef) -> Option<Value> {
    Some(match d {
        DataRef::Empty => return None,
        DataRef::Int(i) => Value::Number(*i as f64),
        DataRef::Float(f) => Value::Number(*f),
        DataRef::String(s) => Value::text(s.as_str()),
        DataRef::SharedString(s) => Value::text(*s),
        DataRef::Bool(b) => Value::Bool(*b),
        DataRef::DateTime(d) => Value::Number(d.as_f64()),
        DataRef::DateTimeIso(s) | DataRef::DurationIso(s) => Value::text(s.as_str()),
        DataRef::Error(e) => Value::Error(error_of(e)),
    })
}

fn error_of(e: &CellErrorType) -> XlError {
    match e {
        CellErrorType::Div0 => XlError::Div0,
        CellErrorType::NA => XlError::NA,
        CellErrorType::Name => XlError::Name,
        CellErrorType::Null => XlError::Null,
        CellErrorType::Num => XlError::Num,
        CellErrorType::Ref => XlError::Ref,
        CellErrorType::Value => XlError::Value,
        CellErrorType::GettingData => XlError::GettingData,
    }
}

/// Numbers agree when |a - b| <= 1e-9 * max(1, |b|): relative, but absolute near zero.
/// Not `ncsheet::io::xlsx::values_agree`, which is relative all the way down: Excel's
/// results near zero (COS(PI()/2), MOD of near-equal numbers) are not ours to the last
/// digits, and the corpus holds such cells.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1.0)
}

/// Whether our value agrees with Excel's cached one. Excel caches an error it wrote as
/// text (`t="str"`) too; the corpus protocol counts that as the error.
fn agrees(ours: &Value, excel: &Value) -> bool {
    match (ours, excel) {
        (Value::Number(a), Value::Number(b)) => close(*a, *b),
        (Value::Error(e), Value::Text(t)) => e.as_str() == &**t,
        _ => ours == excel,
    }
}

/// How our result for a formula cell compares with what Excel cached around it.
enum Verdict {
    Agrees,
    /// Agrees once read as a pre-dynamic-array formula (implicit intersection).
    AgreesAsLegacy,
    Differs(String),
    /// Not judged, and why.
    Unjudged(&'static str),
}

/// One sheet: its cached values as an environment and its formulas by position.
struct SheetCheck<'a> {
    file: &'a str,
    sheet: &'a str,
    suite: &'a Suite,
    env: MapEnv,
    formulas: &'a BTreeMap<(u32, u32), Formula>,
}

impl SheetCheck<'_> {
    fn run(&self, report: &mut Report) {
        for (&(row, col), formula) in self.formulas {
            self.check(Pos::new(row, col), formula, report);
        }
    }

    fn check(&self, at: Pos, formula: &Formula, report: &mut Report) {
        let expr = match self.parse(formula) {
            Ok(expr) => expr,
            Err(why) => return self.skip(report, at, formula, &why),
        };
        let verdict = self.judge(at, &expr);
        if let Verdict::Unjudged(why) = verdict {
            return self.skip(report, at, formula, why);
        }
        if matches!(verdict, Verdict::Differs(_)) && self.reads_excused_text(at, &expr) {
            report.excused += 1;
            return;
        }
        report.count(self.file, &functions_in(&expr), &verdict);
        if let Verdict::Differs(how) = &verdict {
            self.differs(report, at, formula, how);
        }
    }

    /// The formula's tree, or why it is out of scope.
    fn parse(&self, formula: &Formula) -> Result<Expr, String> {
        // Other sheets are not loaded: a reference to one parses as a missing sheet.
        let context = ParseContext { at: formula.anchor, functions: &Registry, sheet: &|_| None };
        let expr = parse_formula(&formula.text, &context).map_err(|_| "formula we do not parse".to_string())?;
        match out_of_scope(&expr, &formula.text) {
            Some(why) => Err(why),
            None => Ok(expr),
        }
    }

    fn skip(&self, report: &mut Report, at: Pos, formula: &Formula, why: &str) {
        if std::env::var_os("NCSHEET_CORPUS_VERBOSE").is_some() {
            println!("skip {} [{}] {at} ={}: {why}", self.file, self.sheet, formula.text);
        }
        report.skip(why);
    }

    /// Records a difference: allowed, or a failure.
    fn differs(&self, report: &mut Report, at: Pos, formula: &Formula, how: &str) {
        let cell = at.to_string();
        let allowed = self
            .suite
            .allowed
            .iter()
            .any(|a| a.file == self.file && a.sheet == self.sheet && a.cells.contains(&cell.as_str()));
        if allowed {
            report.allowed_hits.insert((self.file.to_string(), self.sheet.to_string(), cell));
            return;
        }
        let written = if formula.anchor == at { String::new() } else { format!(" (as written at {})", formula.anchor) };
        report.failures.push(format!("{} {}!{cell} ={}{written}: {how}", self.file, self.sheet, formula.text));
    }

    /// A scalar must agree with the cell's cached value. A spilled array must match the
    /// cached values of every cell it covers. A workbook written before dynamic arrays
    /// instead intersects ranges with the formula's row or column; when the array does not
    /// match as a spill, that reading is tried. An array that matches neither way, where the
    /// cells it would cover are no spill (they hold formulas of their own, or nothing), is
    /// not judged: the file does not say how Excel read the formula.
    fn judge(&self, at: Pos, expr: &Expr) -> Verdict {
        let excel = self.cached(at);
        let ours = Ctx::new(&self.env, 0, at).eval(expr).unwrap_single();
        let Value::Array(a) = ours else {
            let ours = ours.blank_as_zero();
            if agrees(&ours, &excel) {
                return Verdict::Agrees;
            }
            return Verdict::Differs(format!("ours {ours:?}, Excel {excel:?}"));
        };
        if self.spill_matches(at, &a) {
            return Verdict::Agrees;
        }
        if self.legacy_readings(at, expr).iter().any(|v| !matches!(v, Value::Array(_)) && agrees(v, &excel)) {
            return Verdict::AgreesAsLegacy;
        }
        if !self.covers_spill(at, a.rows as u32, a.cols as u32) {
            return Verdict::Unjudged("array result in a legacy single-cell formula");
        }
        Verdict::Differs(format!("ours {}x{} array starting {:?}, Excel {excel:?}", a.rows, a.cols, a.data.first()))
    }

    fn cached(&self, p: Pos) -> Value {
        self.env.cells.get(&(p.row, p.col)).cloned().unwrap_or_default()
    }

    /// Whether every cell the array covers holds a cached value that agrees with it.
    fn spill_matches(&self, at: Pos, a: &ncsheet::eval::Array) -> bool {
        (0..a.rows).all(|r| {
            (0..a.cols).all(|c| {
                let cached = self.env.cells.get(&(at.row + r as u32, at.col + c as u32));
                let mine = a.get(r, c).clone().blank_as_zero();
                cached.is_some_and(|v| agrees(&mine, v))
            })
        })
    }

    /// The formula's value as Excel computed it before dynamic arrays, two ways: the
    /// reference the whole formula returns (`=A1:A9`, `=INDEX(A1:B9,0,1)`) intersected
    /// with the formula's row or column; and every multi-cell reference in it intersected
    /// (`=EXP(H:H)` in row 36 is `=EXP(H36)`). The second also rewrites the ranges of
    /// aggregates, so neither serves but for formulas whose dynamic-array result did not
    /// match.
    fn legacy_readings(&self, at: Pos, expr: &Expr) -> [Value; 2] {
        let mut ctx = Ctx::new(&self.env, 0, at);
        let whole = match ctx.operand(expr) {
            Operand::Ref(sheet, rect) if !rect.is_cell() => ctx.implicit_intersection(Operand::Ref(sheet, rect)),
            other => ctx.deref(other),
        };
        let each = Ctx::new(&self.env, 0, at).eval(&legacy(expr)).unwrap_single();
        [whole.unwrap_single().blank_as_zero(), each.blank_as_zero()]
    }

    /// Whether a `rows`×`cols` result at `at` covers an Excel 365 spill: cells holding
    /// cached values and no formulas of their own.
    fn covers_spill(&self, at: Pos, rows: u32, cols: u32) -> bool {
        (0..rows).all(|r| {
            (0..cols).all(|c| {
                let p = (at.row + r, at.col + c);
                (r == 0 && c == 0) || (!self.formulas.contains_key(&p) && self.env.cells.contains_key(&p))
            })
        })
    }

    /// Whether the formula reads a cell holding one of the suite's excused texts.
    fn reads_excused_text(&self, at: Pos, expr: &Expr) -> bool {
        let ctx = Ctx::new(&self.env, 0, at);
        let mut found = false;
        expr.visit_refs(&mut |r| {
            let Ok((_, rect)) = ctx.resolve(r) else {
                return;
            };
            let rect = ctx.clip_to_used(0, rect);
            found |= self.env.cells.range((rect.first.row, 0)..=(rect.last.row, u32::MAX)).any(|(&(_, c), v)| {
                (rect.first.col..=rect.last.col).contains(&c)
                    && matches!(v, Value::Text(t) if self.suite.excused_texts.contains(&&**t))
            });
        });
        found
    }
}

/// Why a formula is not checked: it calls what we lack or what Excel computed at another
/// moment, or reads what the sheet's cached values do not hold.
fn out_of_scope(expr: &Expr, text: &str) -> Option<String> {
    // LET's parameters parse as names; defined names are not loaded.
    let has_let = text.to_ascii_uppercase().contains("LET(");
    let mut why = None;
    expr.visit(&mut |e| match &e.kind {
        // Its cached value depends on when or where Excel computed it.
        ExprKind::Call(id, _) if spec(*id).reads != Outside::Nothing => {
            why.get_or_insert(format!("volatile: {}", spec(*id).name));
        }
        ExprKind::UnknownCall(name, _) => {
            why.get_or_insert(format!("function not implemented: {name}"));
        }
        ExprKind::Ref(r) if r.sheet != SheetRef::Current => {
            why.get_or_insert("reads another sheet".to_string());
        }
        ExprKind::Unary(UnaryOp::Spill, _) => {
            why.get_or_insert("reads a spill (A1#)".to_string());
        }
        // Its reference comes from text that may name a sheet, which the one-sheet
        // environment here does not have (tests/xlsx_conformance.rs checks it on the real
        // workbook).
        ExprKind::Call(id, _) if spec(*id).name == "INDIRECT" => {
            why.get_or_insert("reference from text: INDIRECT".to_string());
        }
        // They read the cells' formulas, which the cached values here do not hold.
        ExprKind::Call(id, _) if matches!(spec(*id).name, "FORMULATEXT" | "ISFORMULA" | "SUBTOTAL" | "AGGREGATE") => {
            why.get_or_insert(format!("reads formulas: {}", spec(*id).name));
        }
        // They count the workbook's sheets; the environment here holds one.
        ExprKind::Call(id, _) if matches!(spec(*id).name, "SHEET" | "SHEETS") => {
            why.get_or_insert(format!("reads the sheet list: {}", spec(*id).name));
        }
        ExprKind::Name(_) if !has_let => {
            why.get_or_insert("uses a defined name".to_string());
        }
        _ => {}
    });
    why
}

/// The formula with every multi-cell reference implicitly intersected with its cell's row
/// or column.
fn legacy(e: &Expr) -> Expr {
    let kind = match &e.kind {
        ExprKind::Ref(r) if !matches!(r.shape, RefShape::Cell(_)) => {
            ExprKind::Unary(UnaryOp::Implicit, Box::new(e.clone()))
        }
        ExprKind::Binary(BinOp::Range, ..) => ExprKind::Unary(UnaryOp::Implicit, Box::new(e.clone())),
        ExprKind::Paren(inner) => ExprKind::Paren(Box::new(legacy(inner))),
        ExprKind::Unary(op, inner) => ExprKind::Unary(*op, Box::new(legacy(inner))),
        ExprKind::Binary(op, a, b) => ExprKind::Binary(*op, Box::new(legacy(a)), Box::new(legacy(b))),
        ExprKind::Call(id, args) => ExprKind::Call(*id, args.iter().map(legacy).collect()),
        other => other.clone(),
    };
    Expr::new(kind, e.span)
}

/// The functions a formula calls, for the per-function table.
fn functions_in(expr: &Expr) -> BTreeSet<&'static str> {
    let mut names = BTreeSet::new();
    expr.visit(&mut |e| {
        if let ExprKind::Call(id, _) = e.kind {
            names.insert(spec(id).name);
        }
    });
    if names.is_empty() {
        names.insert("(operators only)");
    }
    names
}

#[derive(Clone, Copy, Default)]
struct Tally {
    checked: usize,
    passed: usize,
}

#[derive(Default)]
struct Report {
    per_file: BTreeMap<String, Tally>,
    per_function: BTreeMap<&'static str, Tally>,
    skipped: BTreeMap<String, usize>,
    legacy_intersections: usize,
    /// Differences excused by [`Suite::excused_texts`]; not counted as checked.
    excused: usize,
    /// Allowed differences met: (file, sheet, cell).
    allowed_hits: BTreeSet<(String, String, String)>,
    failures: Vec<String>,
}

impl Report {
    fn skip(&mut self, why: &str) {
        *self.skipped.entry(why.to_string()).or_default() += 1;
    }

    fn count(&mut self, file: &str, names: &BTreeSet<&'static str>, verdict: &Verdict) {
        let passed = usize::from(matches!(verdict, Verdict::Agrees | Verdict::AgreesAsLegacy));
        self.legacy_intersections += usize::from(matches!(verdict, Verdict::AgreesAsLegacy));
        let t = self.per_file.entry(file.to_string()).or_default();
        t.checked += 1;
        t.passed += passed;
        for name in names {
            let t = self.per_function.entry(name).or_default();
            t.checked += 1;
            t.passed += passed;
        }
    }

    fn total(&self) -> Tally {
        self.per_file
            .values()
            .fold(Tally::default(), |a, t| Tally { checked: a.checked + t.checked, passed: a.passed + t.passed })
    }

    fn print(&self, allowed: &[Allowed]) {
        println!("\nExcel corpus: formula cells checked / agreeing, per file");
        for (file, t) in &self.per_file {
            println!("  {:>5} / {:<5} {file}", t.checked, t.passed);
        }
        println!("\nper function (a formula counts for each function it calls)");
        for (name, t) in &self.per_function {
            println!("  {:>5} / {:<5} {name}", t.checked, t.passed);
        }
        println!("\nnot checked");
        for (why, n) in &self.skipped {
            println!("  {n:>5}  {why}");
        }
        self.print_allowed(allowed);
        let total = self.total();
        println!(
            "\ntotal: {} checked, {} agree ({} as legacy implicit intersection), {} allowed differences, \
             {} excused (texts we do not read as numbers)",
            total.checked,
            total.passed,
            self.legacy_intersections,
            self.allowed_hits.len(),
            self.excused
        );
        for f in &self.failures {
            println!("DIFFERS {f}");
        }
    }

    /// Each allowed cell, and whether it still differs (an entry that agrees now is stale).
    fn print_allowed(&self, allowed: &[Allowed]) {
        for a in allowed {
            for cell in a.cells {
                let hit = self.allowed_hits.contains(&(a.file.to_string(), a.sheet.to_string(), cell.to_string()));
                let state = if hit { "differs" } else { "now agrees: remove" };
                println!("  allowed {} {}!{cell} ({state}): {}", a.file, a.sheet, a.why);
            }
        }
    }
}
