//! Excel as the oracle for the logical, lookup, text and information functions.
//!
//! The workbooks under `calc_tests/` of the IronCalc corpus (see
//! /work/shared/excel-corpus/README.md) were saved by Excel with the value of every
//! formula cached next to it. For each formula that uses only functions we implement and
//! reads only its own sheet, this test loads every cell's cached value into a [`MapEnv`],
//! evaluates the formula at its own position and compares with what Excel cached:
//! numbers to 1e-9 relative, text, booleans and errors exactly.
//!
//! Run with `cargo test --test excel_corpus_text -- --nocapture` for the per-file and
//! per-function tables. The corpus lives outside the repository; without it the test
//! reports that and passes. Set `NCSHEET_EXCEL_CORPUS` to its `ironcalc` folder to use
//! another copy, and `NCSHEET_CORPUS_VERBOSE=1` to list every formula left unchecked.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use std::fs::File;
use std::io::BufReader;

use calamine::{open_workbook, CellErrorType, Data, Range, Reader, Xlsx, XlsxFormulaMetadata};
use ncsheet::eval::functions::{spec, Registry};
use ncsheet::eval::testing::MapEnv;
use ncsheet::eval::{Array, Ctx, Operand, Value, XlError};
use ncsheet::formula::ast::{Expr, ExprKind, SheetRef};
use ncsheet::formula::{parse_formula, ParseContext, Pos};

/// Folders and files in scope: the function tests, and the templates (real sheets, whose
/// formulas count where they use only what we implement).
const SOURCES: &[&str] = &[
    "calc_tests/LOGICAL",
    "calc_tests/LOOKUP_AND_REFERENCE",
    "calc_tests/TEXT",
    "calc_tests/INFORMATION",
    "calc_tests/logical.xlsx",
    "calc_tests/simple_functions.xlsx",
    "templates",
];

/// Their cached values depend on when or where Excel computed them.
const VOLATILE: &[&str] = &["NOW", "TODAY", "RAND", "RANDBETWEEN", "RANDARRAY", "INFO"];

/// Not saved by Excel (the README lists it): its cached values are no oracle.
const NOT_EXCEL: &[&str] = &["XMATCH_arrays.xlsx"];

/// Cells where we knowingly differ from Excel: file, cells (of any sheet), why. Keep this
/// short: a disagreement in scope is a bug to fix, not a line to add here.
const ALLOWED: &[(&str, &[&str], &str)] = &[
    // The argument cells hold #CALC! and #SPILL!, which the file stores as #VALUE! plus
    // rich-value metadata that calamine does not read.
    ("calc_tests/INFORMATION/ERROR.TYPE.xlsx", &["B8", "B14"], "argument is #CALC!/#SPILL! stored as #VALUE!"),
    // XMATCH's match mode 3 (regular expressions) is not implemented: #VALUE!.
    ("calc_tests/LOOKUP_AND_REFERENCE/XMATCH.xlsx", &["D6", "D7", "B14"], "XMATCH regular-expression mode"),
    // Day-first dates (the workbook is en-GB, Excel Online): "10-12-1999" and "2/3/2023" are
    // read month first, as in the US.
    ("calc_tests/TEXT/T_VALUE_VALUETOTEXT.xlsx", &["I5", "C15"], "VALUE of day-first date text"),
];

#[derive(Default)]
struct Tally {
    checked: usize,
    passed: usize,
}

#[derive(Default)]
struct Report {
    files: BTreeMap<String, Tally>,
    functions: BTreeMap<String, Tally>,
    skipped: BTreeMap<String, usize>,
    failures: Vec<String>,
    allowed_hits: BTreeSet<(String, String)>,
}

impl Report {
    fn skip(&mut self, why: impl Into<String>) {
        *self.skipped.entry(why.into()).or_default() += 1;
    }
}

#[test]
fn excel_cached_values_agree() {
    let Some(root) = common::corpus::root() else { return };
    let root = root.as_path();
    let mut report = Report::default();
    for file in workbooks(root) {
        check_workbook(root, &file, &mut report);
    }
    print_report(&report);
    let total: usize = report.files.values().map(|t| t.checked).sum();
    assert!(total >= 500, "only {total} cells checked: is the corpus complete?");
    assert!(report.failures.is_empty(), "{} formula cells disagree with Excel (listed above)", report.failures.len());
}

fn workbooks(root: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for source in SOURCES {
        let path = root.join(source);
        if path.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(&path)
                .expect("corpus folder")
                .map(|e| e.expect("folder entry").path())
                .filter(|p| p.extension().is_some_and(|e| e == "xlsx"))
                .collect();
            found.sort();
            files.extend(found);
        } else {
            files.push(path);
        }
    }
    files.retain(|p| !NOT_EXCEL.iter().any(|n| p.ends_with(n)));
    files
}

fn check_workbook(root: &Path, path: &Path, report: &mut Report) {
    let name = path.strip_prefix(root).unwrap_or(path).display().to_string();
    let mut workbook: Xlsx<BufReader<File>> = open_workbook(path).expect("corpus workbook opens");
    report.files.entry(name.clone()).or_default();
    for sheet in workbook.sheet_names() {
        let (Ok(values), Some(formulas)) = (workbook.worksheet_range(&sheet), sheet_formulas(&mut workbook, &sheet))
        else {
            report.skip("sheet calamine cannot read");
            continue;
        };
        SheetCheck::new(&name, &sheet, &values, formulas).run(report);
    }
}

/// A formula cell: the formula text and the cell it was written for. A shared formula
/// (one formula filled over a range) is stored once, at its anchor; our trees keep
/// relative references as offsets, so the anchor's tree evaluated at each cell is that
/// cell's formula.
struct FormulaCell {
    text: String,
    anchor: Pos,
}

fn sheet_formulas(workbook: &mut Xlsx<BufReader<File>>, sheet: &str) -> Option<BTreeMap<(u32, u32), FormulaCell>> {
    let mut reader = workbook.worksheet_cells_reader(sheet).ok()?;
    let mut anchors: BTreeMap<usize, (String, Pos)> = BTreeMap::new();
    let mut cells = BTreeMap::new();
    while let Some(record) = reader.next_cell_with_formula_metadata().ok()? {
        let pos = Pos::new(record.pos.0, record.pos.1);
        let cell = match record.formula {
            Some(XlsxFormulaMetadata::Normal { formula }) => FormulaCell { text: formula, anchor: pos },
            Some(XlsxFormulaMetadata::Shared { shared_index, formula, .. }) => {
                anchors.insert(shared_index, (formula.clone(), pos));
                FormulaCell { text: formula, anchor: pos }
            }
            Some(XlsxFormulaMetadata::SharedDerived { shared_index }) => {
                let Some((text, anchor)) = anchors.get(&shared_index) else {
                    continue;
                };
                FormulaCell { text: text.clone(), anchor: *anchor }
            }
            _ => continue,
        };
        if !cell.text.is_empty() {
            cells.insert(record.pos, cell);
        }
    }
    Some(cells)
}

/// One sheet: its cached values as an environment and its formulas by position.
struct SheetCheck<'a> {
    file: &'a str,
    sheet: &'a str,
    env: MapEnv,
    formulas: BTreeMap<(u32, u32), FormulaCell>,
}

impl<'a> SheetCheck<'a> {
    fn new(
        file: &'a str,
        sheet: &'a str,
        values: &Range<Data>,
        formulas: BTreeMap<(u32, u32), FormulaCell>,
    ) -> SheetCheck<'a> {
        let mut env = MapEnv::default();
        if let Some((r0, c0)) = values.start() {
            for (r, c, data) in values.used_cells() {
                env.cells.insert((r0 + r as u32, c0 + c as u32), cached_value(data));
            }
        }
        SheetCheck { file, sheet, env, formulas }
    }

    fn run(&self, report: &mut Report) {
        for (&(row, col), cell) in &self.formulas {
            let at = Pos::new(row, col);
            let text = &cell.text;
            let checked = self.parse(text, cell.anchor).and_then(|expr| Ok((self.outcome(&expr, at)?, expr)));
            let (outcome, expr) = match checked {
                Ok(pair) => pair,
                Err(why) => {
                    if std::env::var_os("NCSHEET_CORPUS_VERBOSE").is_some() {
                        println!("skip {} [{}] {at} ={text}: {why}", self.file, self.sheet);
                    }
                    report.skip(why);
                    continue;
                }
            };
            let shown =
                if cell.anchor == at { format!("={text}") } else { format!("={text} (as written at {})", cell.anchor) };
            self.record(report, at, &shown, &expr, outcome);
        }
    }

    /// The formula's tree, or why it is out of scope.
    fn parse(&self, text: &str, at: Pos) -> Result<Expr, String> {
        let expr = parse_formula(text, &ParseContext { at, functions: &Registry, sheet: &|_| None })
            .map_err(|_| "formula we do not parse".to_string())?;
        let mut why = None;
        let has_let = text.to_ascii_uppercase().contains("LET(");
        expr.visit(&mut |e| match &e.kind {
            ExprKind::Call(id, _) if VOLATILE.contains(&spec(*id).name) => {
                why.get_or_insert(format!("volatile: {}", spec(*id).name));
            }
            ExprKind::UnknownCall(name, _) if VOLATILE.contains(&&**name) => {
                why.get_or_insert(format!("volatile: {name}"));
            }
            ExprKind::UnknownCall(name, _) => {
                why.get_or_insert(format!("function not implemented: {name}"));
            }
            ExprKind::Ref(r) if r.sheet != SheetRef::Current => {
                why.get_or_insert("reads another sheet".to_string());
            }
            ExprKind::Name(_) if !has_let => {
                why.get_or_insert("uses a defined name".to_string());
            }
            _ => {}
        });
        match why {
            Some(why) => Err(why),
            None => Ok(expr),
        }
    }

    /// Evaluates at the formula's own cell and pairs each result cell with Excel's.
    fn outcome(&self, expr: &Expr, at: Pos) -> Result<Vec<(Pos, Value, Value)>, String> {
        let mut ctx = Ctx::new(&self.env, 0, at);
        let operand = ctx.operand(expr);
        let result = match operand {
            Operand::Ref(_, rect) if !rect.is_cell() && !self.spills(at, rect.rows(), rect.cols()) => {
                // A legacy (non-array) formula shows the cell in line with it.
                ctx.implicit_intersection(Operand::Ref(0, rect))
            }
            other => ctx.deref(other),
        };
        let result = result.unwrap_single();
        let Value::Array(array) = result else {
            return Ok(vec![(at, self.cached(at), result.blank_as_zero())]);
        };
        if !self.spills(at, array.rows as u32, array.cols as u32) {
            return Err("array result in a legacy single-cell formula".into());
        }
        Ok(spilled_cells(at, &array).map(|(p, v)| (p, self.cached(p), v.blank_as_zero())).collect())
    }

    /// Whether a `rows`×`cols` result anchored at `at` was an Excel 365 spill: the cells
    /// it covers hold cached values and no formulas of their own. Otherwise the formula
    /// is a legacy one (the file does not say which) and Excel showed a single value.
    fn spills(&self, at: Pos, rows: u32, cols: u32) -> bool {
        (0..rows).all(|r| {
            (0..cols).all(|c| {
                let p = (at.row + r, at.col + c);
                (r == 0 && c == 0) || (!self.formulas.contains_key(&p) && self.env.cells.contains_key(&p))
            })
        })
    }

    fn cached(&self, p: Pos) -> Value {
        self.env.cells.get(&(p.row, p.col)).cloned().unwrap_or_default()
    }

    fn record(&self, report: &mut Report, at: Pos, text: &str, expr: &Expr, cells: Vec<(Pos, Value, Value)>) {
        let mismatch = cells.iter().find(|(_, want, got)| !agrees(want, got));
        let passed = mismatch.is_none();
        let file = report.files.entry(self.file.to_string()).or_default();
        file.checked += 1;
        file.passed += usize::from(passed);
        for name in functions_in(expr) {
            let tally = report.functions.entry(name).or_default();
            tally.checked += 1;
            tally.passed += usize::from(passed);
        }
        let Some((p, want, got)) = mismatch else {
            return;
        };
        let cell = at.to_string();
        let allowed = ALLOWED.iter().any(|(f, cells, _)| *f == self.file && cells.contains(&cell.as_str()));
        if allowed {
            report.allowed_hits.insert((self.file.into(), cell));
            return;
        }
        report.failures.push(format!(
            "{} [{}] {} {}  (cell {}): Excel {:?}, ours {:?}",
            self.file, self.sheet, cell, text, p, want, got
        ));
    }
}

fn spilled_cells(at: Pos, array: &Array) -> impl Iterator<Item = (Pos, Value)> + '_ {
    (0..array.rows).flat_map(move |r| {
        (0..array.cols).map(move |c| {
            let p = Pos::new(at.row + r as u32, at.col + c as u32);
            (p, array.get(r, c).clone())
        })
    })
}

fn functions_in(expr: &Expr) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    expr.visit(&mut |e| {
        if let ExprKind::Call(id, _) = e.kind {
            names.insert(spec(id).name.to_string());
        }
    });
    if names.is_empty() {
        names.insert("(operators only)".into());
    }
    names
}

fn cached_value(data: &Data) -> Value {
    match data {
        Data::Int(i) => Value::Number(*i as f64),
        Data::Float(f) => Value::Number(*f),
        Data::String(s) => Value::text(s.as_str()),
        Data::Bool(b) => Value::Bool(*b),
        Data::DateTime(d) => Value::Number(d.as_f64()),
        Data::DateTimeIso(s) | Data::DurationIso(s) => Value::text(s.as_str()),
        Data::Error(e) => Value::Error(match e {
            CellErrorType::Div0 => XlError::Div0,
            CellErrorType::NA => XlError::NA,
            CellErrorType::Name => XlError::Name,
            CellErrorType::Null => XlError::Null,
            CellErrorType::Num => XlError::Num,
            CellErrorType::Ref => XlError::Ref,
            CellErrorType::Value => XlError::Value,
            CellErrorType::GettingData => XlError::GettingData,
        }),
        Data::Empty => Value::Blank,
    }
}

/// Excel's cached value against ours. A formula whose result is "" may be cached with
/// no value at all; an error may be cached as its text.
fn agrees(want: &Value, got: &Value) -> bool {
    match (want, got) {
        (Value::Number(a), Value::Number(b)) => a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()),
        (Value::Blank, Value::Text(s)) => s.is_empty(),
        (Value::Text(s), Value::Error(e)) => **s == *e.as_str(),
        _ => want == got,
    }
}

fn print_report(report: &Report) {
    println!("\nExcel corpus: formula cells checked / agreeing, per file");
    for (file, t) in &report.files {
        println!("  {:>4} / {:<4} {file}", t.checked, t.passed);
    }
    println!("\nper function (a formula counts for each function it calls)");
    for (name, t) in &report.functions {
        println!("  {:>4} / {:<4} {name}", t.checked, t.passed);
    }
    println!("\nnot checked");
    for (why, n) in &report.skipped {
        println!("  {n:>5}  {why}");
    }
    for (file, cells, why) in ALLOWED {
        for cell in *cells {
            let hit = report.allowed_hits.contains(&(file.to_string(), cell.to_string()));
            let state = if hit { "differs" } else { "now agrees: remove" };
            println!("  allowed {file} {cell} ({state}): {why}");
        }
    }
    let (checked, passed) = report.files.values().fold((0, 0), |(c, p), t| (c + t.checked, p + t.passed));
    println!("\ntotal: {checked} checked, {passed} agree");
    for f in &report.failures {
        println!("DIFF {f}");
    }
}
