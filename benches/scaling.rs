//! ncsheet's scaling benchmark: workbooks whose work used to grow with the square of their
//! size (issue 19), built in memory at several sizes and timed, so that a curve shows the
//! growth. See benches/README.md.
//!
//!     cargo run --release --bin ncsheet-bench-scaling -- [--sizes circ-80000,offset-200000,...]
//!         [--runs N]
//!
//! Each case is checked: a wrong value stops the bench.

#[path = "sizes_and_runs.rs"]
mod sizes_and_runs;

use std::process::ExitCode;
use std::time::Instant;

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::Pos;
use ncsheet::workbook::Workbook;

/// Each kind at a quarter, a half and the full size of the case.
const DEFAULT_SIZES: &[&str] = &[
    "circ-20000",
    "circ-40000",
    "circ-80000",
    "circ-200000",
    "circ-edits-20000",
    "circ-edits-40000",
    "circ-edits-80000",
    "circ-edits-200000",
    "offset-50000",
    "offset-100000",
    "offset-200000",
    "offset-edits-50000",
    "offset-edits-100000",
    "offset-edits-200000",
    "self-offset-50000",
    "self-offset-100000",
    "self-offset-200000",
    "far-csv-50000",
    "far-csv-100000",
    "far-csv-200000",
    "sheets-25000",
    "sheets-50000",
    "sheets-100000",
    "xlsx-sheets-25000",
    "xlsx-sheets-50000",
    "xlsx-sheets-100000",
    "indirect-50000",
    "indirect-100000",
    "indirect-200000",
    "indirect-edit-50000",
    "indirect-edit-100000",
    "indirect-edit-200000",
    "indirect-rewrite-50000",
    "indirect-rewrite-100000",
    "indirect-rewrite-200000",
    "far-csv-load-262144",
    "far-csv-load-524288",
    "far-csv-load-1048576",
    "macro-timeout-250000",
    "macro-timeout-500000",
    "macro-timeout-1000000",
];

/// Edits timed in each `indirect-edit` case.
const EDITS: u32 = 10;
/// The `--timeout` of the `macro-timeout` cases.
const MACRO_SECONDS: f64 = 1.0;

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// A column filled down with a formula that reads its own cell: `=Ak+1` in Ak, each
    /// cell a circular reference of its own.
    Circ,
    /// The same column written one cell at a time, each edit recalculating (as a macro or
    /// the repl fills it).
    CircEdits,
    /// A1 = 1, Ak = `OFFSET(A(k-1),0,0)+1`: every reference made at run time.
    Offset,
    /// The same column written one cell at a time, each edit recalculating.
    OffsetEdits,
    /// A1 = 1, Ak = `OFFSET(Ak,-1,0)+1`: each cell moves its own reference to the cell above.
    SelfOffset,
    /// N numbers in column A and one cell at XFD1048576, exported as csv.
    FarCsv,
    /// N sheets added one by one, each with its number in A1, and one formula reading the
    /// last by name and through INDIRECT.
    Sheets,
    /// The same workbook saved as .xlsx and loaded.
    XlsxSheets,
    /// A1 = 1, Ak = `INDIRECT("A"&(ROW()-1))+1`: a chain of volatile run-time references.
    Indirect,
    /// That chain built, then 10 edits of a cell it does not read, each recomputing every
    /// volatile cell (as Excel does): the time is of the edits, proportional to N.
    IndirectEdit,
    /// That chain built, then each of its formulas replaced by another INDIRECT one without
    /// recalculating, then computed once (a file reread, a pasted column).
    IndirectRewrite,
    /// A csv file whose one cell is at row N, column XFD (N-1 empty lines, then 16,383
    /// commas and a number; a MiB at N = 1,048,576), loaded and A1 read (`ncsheet eval FILE A1`).
    FarCsvLoad,
    /// A macro evaluating `SUM(SEQUENCE(N))` in an endless loop under a 1 s `--timeout`:
    /// the time is when it stopped.
    MacroTimeout,
    /// N numbers in column A, `=SUM(A:A)` in B1 and `=Ak*2` in C1:C1000, then ten columns
    /// inserted at A one at a time (a macro's `Columns(1).Insert` in a loop): the time is of
    /// the insertions.
    InsertColumns,
    /// N formulas `=Bk+1` in column A, each linking a blank cell, then a defined name added,
    /// which relinks the whole graph and recomputes every formula: the time is of that.
    Relink,
}

struct Case {
    name: String,
    kind: Kind,
    n: u32,
}

impl Case {
    fn parse(name: &str) -> Result<Case, String> {
        let (kind, n) = name.rsplit_once('-').ok_or_else(|| format!("bad case name {name:?}"))?;
        let kind = match kind {
            "circ" => Kind::Circ,
            "circ-edits" => Kind::CircEdits,
            "offset" => Kind::Offset,
            "offset-edits" => Kind::OffsetEdits,
            "self-offset" => Kind::SelfOffset,
            "far-csv" => Kind::FarCsv,
            "sheets" => Kind::Sheets,
            "xlsx-sheets" => Kind::XlsxSheets,
            "indirect" => Kind::Indirect,
            "indirect-edit" => Kind::IndirectEdit,
            "indirect-rewrite" => Kind::IndirectRewrite,
            "far-csv-load" => Kind::FarCsvLoad,
            "macro-timeout" => Kind::MacroTimeout,
            "insert-columns" => Kind::InsertColumns,
            "relink" => Kind::Relink,
            _ => return Err(format!("unknown case kind in {name:?} (circ, circ-edits, offset, offset-edits, self-offset, far-csv, sheets, xlsx-sheets, indirect, indirect-edit, indirect-rewrite, far-csv-load, macro-timeout, insert-columns, relink)")),
        };
        let n: u32 = n.parse().ok().filter(|&n| n >= 2).ok_or_else(|| format!("bad size in {name:?}"))?;
        Ok(Case { name: name.to_string(), kind, n })
    }
}

fn at(row: u32, col: u32) -> Pos {
    Pos::new(row, col)
}

fn set(wb: &mut Workbook, sheet: u16, pos: Pos, text: &str) -> Result<(), String> {
    wb.set_input_deferred(sheet, pos, text).map_err(|e| e.to_string())
}

/// Builds and computes the case's workbook; returns it for checking. `file` is the case's
/// input file, written before timing (xlsx-sheets, far-csv-load).
fn build(case: &Case, file: Option<&std::path::Path>) -> Result<Workbook, String> {
    match case.kind {
        Kind::Circ => {
            let mut wb = Workbook::with_sheet();
            for k in 1..=case.n {
                set(&mut wb, 0, at(k - 1, 0), &format!("=A{k}+1"))?;
            }
            wb.recalculate();
            Ok(wb)
        }
        Kind::CircEdits => {
            let mut wb = Workbook::with_sheet();
            for k in 1..=case.n {
                wb.set_input(0, at(k - 1, 0), &format!("=A{k}+1")).map_err(|e| e.to_string())?;
            }
            Ok(wb)
        }
        Kind::Offset => {
            let mut wb = Workbook::with_sheet();
            set(&mut wb, 0, at(0, 0), "1")?;
            for k in 2..=case.n {
                set(&mut wb, 0, at(k - 1, 0), &format!("=OFFSET(A{},0,0)+1", k - 1))?;
            }
            wb.recalculate();
            Ok(wb)
        }
        Kind::OffsetEdits => {
            let mut wb = Workbook::with_sheet();
            wb.set_input(0, at(0, 0), "1").map_err(|e| e.to_string())?;
            for k in 2..=case.n {
                let formula = format!("=OFFSET(A{},0,0)+1", k - 1);
                wb.set_input(0, at(k - 1, 0), &formula).map_err(|e| e.to_string())?;
            }
            Ok(wb)
        }
        Kind::SelfOffset => {
            let mut wb = Workbook::with_sheet();
            set(&mut wb, 0, at(0, 0), "1")?;
            for k in 2..=case.n {
                set(&mut wb, 0, at(k - 1, 0), &format!("=OFFSET(A{k},-1,0)+1"))?;
            }
            wb.recalculate();
            Ok(wb)
        }
        Kind::FarCsv => {
            let mut wb = Workbook::with_sheet();
            for k in 1..=case.n {
                set(&mut wb, 0, at(k - 1, 0), &k.to_string())?;
            }
            set(&mut wb, 0, at(1_048_575, 16_383), "7")?;
            wb.recalculate();
            let what = ncsheet::io::Export { sheet: 0, range: None, content: ncsheet::io::Content::Values };
            let mut bytes = Vec::new();
            ncsheet::io::csv::write(&wb, &what, &mut bytes).map_err(|e| e.to_string())?;
            // About a MiB of line ends and commas, and the numbers: not 17 billion fields.
            if bytes.len() > 4 << 20 {
                return Err(format!("{}: the csv has {} bytes", case.name, bytes.len()));
            }
            Ok(wb)
        }
        Kind::Sheets => {
            let wb = sheets_book(case.n)?;
            Ok(wb)
        }
        Kind::XlsxSheets | Kind::FarCsvLoad => {
            let path = file.expect("the input file is written before timing");
            ncsheet::io::load(path).map_err(|e| e.to_string())
        }
        Kind::Indirect => {
            let mut wb = indirect_chain(case.n)?;
            wb.recalculate();
            Ok(wb)
        }
        Kind::IndirectEdit | Kind::IndirectRewrite | Kind::InsertColumns | Kind::Relink => {
            Err("timed in parts (timed_part)".to_string())
        }
        Kind::MacroTimeout => {
            let source = format!(
                "Sub Main()\n    Dim s\n    Do\n        s = Evaluate(\"SUM(SEQUENCE({}))\")\n    Loop\nEnd Sub\n",
                case.n
            );
            let mut wb = Workbook::with_sheet();
            let options = ncsheet::vba::RunOptions {
                deadline: Some(ncsheet::vba::Deadline::after(MACRO_SECONDS)),
                ..ncsheet::vba::RunOptions::default()
            };
            match ncsheet::vba::run(&mut wb, &source, "loop.bas", &options) {
                Err(e) if e.message.contains("--timeout") => Ok(wb),
                Err(e) => Err(format!("{}: stopped by {e:?}, not the time limit", case.name)),
                Ok(_) => Err(format!("{}: an endless loop ended", case.name)),
            }
        }
    }
}

/// A1 = 1 and Ak = `INDIRECT("A"&(ROW()-1))+1` for k up to n, not computed.
fn indirect_chain(n: u32) -> Result<Workbook, String> {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, 0, at(0, 0), "1")?;
    for k in 2..=n {
        set(&mut wb, 0, at(k - 1, 0), "=INDIRECT(\"A\"&(ROW()-1))+1")?;
    }
    Ok(wb)
}

/// The cases whose timed part follows an untimed setup: the setup's workbook, then the
/// timed work on it.
fn timed_part(case: &Case) -> Result<Option<(Workbook, f64)>, String> {
    match case.kind {
        Kind::InsertColumns => return insert_columns(case.n).map(Some),
        Kind::Relink => return relink(case.n).map(Some),
        Kind::IndirectEdit | Kind::IndirectRewrite => {}
        _ => return Ok(None),
    }
    let n = case.n;
    let mut wb = indirect_chain(n)?;
    wb.recalculate();
    let start = Instant::now();
    match case.kind {
        Kind::IndirectEdit => {
            for k in 1..=EDITS {
                wb.set_input(0, at(0, 1), &k.to_string()).map_err(|e| e.to_string())?;
            }
        }
        Kind::IndirectRewrite => {
            // The same chain, written as a reference to the column and the row above.
            for k in 2..=n {
                set(&mut wb, 0, at(k - 1, 0), "=INDIRECT(\"R[-1]C\",FALSE)+1")?;
            }
            wb.recalculate();
        }
        _ => unreachable!("checked above"),
    }
    Ok(Some((wb, start.elapsed().as_secs_f64())))
}

/// [`Kind::InsertColumns`]: the book built and computed, then the insertions timed.
fn insert_columns(n: u32) -> Result<(Workbook, f64), String> {
    let mut wb = Workbook::with_sheet();
    for k in 1..=n {
        set(&mut wb, 0, at(k - 1, 0), &k.to_string())?;
    }
    set(&mut wb, 0, at(0, 1), "=SUM(A:A)")?;
    for k in 1..=1000.min(n) {
        set(&mut wb, 0, at(k - 1, 2), &format!("=A{k}*2"))?;
    }
    wb.recalculate();
    let start = Instant::now();
    for _ in 0..EDITS {
        wb.shift_cells(0, ncsheet::workbook::SheetEdit::columns(0, 1, true)).map_err(|e| e.to_string())?;
    }
    Ok((wb, start.elapsed().as_secs_f64()))
}

/// [`Kind::Relink`]: the column built and computed, then the name's relinking timed.
fn relink(n: u32) -> Result<(Workbook, f64), String> {
    let mut wb = Workbook::with_sheet();
    for k in 1..=n {
        set(&mut wb, 0, at(k - 1, 0), &format!("=B{k}+1"))?;
    }
    wb.recalculate();
    let start = Instant::now();
    wb.define_name("Rate", "2", None).map_err(|e| e.to_string())?;
    Ok((wb, start.elapsed().as_secs_f64()))
}

/// A csv file whose only cell is a number at row `rows`, column XFD.
fn far_csv_file(rows: u32) -> Result<std::path::PathBuf, String> {
    let path = std::env::temp_dir().join(format!("ncsheet-bench-scaling-{}.csv", std::process::id()));
    let mut text = "\n".repeat(rows as usize - 1);
    text.push_str(&",".repeat(16_383));
    text.push_str("7\n");
    std::fs::write(&path, text).map_err(|e| e.to_string())?;
    Ok(path)
}

fn sheets_book(n: u32) -> Result<Workbook, String> {
    let mut wb = Workbook::new();
    for k in 1..=n {
        let id = wb.add_sheet(&format!("S{k}")).map_err(|e| e.to_string())?;
        set(&mut wb, id, at(0, 0), &k.to_string())?;
    }
    set(&mut wb, 0, at(0, 1), &format!("=S{n}!A1+INDIRECT(\"s{n}!A1\")"))?;
    wb.recalculate();
    Ok(wb)
}

fn check(case: &Case, wb: &Workbook) -> Result<(), String> {
    let n = case.n;
    let fail = |what: String| Err(format!("{}: {what}", case.name));
    match case.kind {
        Kind::Circ | Kind::CircEdits => {
            for row in [0, n / 2, n - 1] {
                if wb.value(0, at(row, 0)) != Value::Error(XlError::Circ) {
                    return fail(format!("A{} is {:?}, not #CIRC!", row + 1, wb.value(0, at(row, 0))));
                }
            }
            if wb.cycles().len() != n as usize {
                return fail(format!("{} circular references reported, not {n}", wb.cycles().len()));
            }
        }
        Kind::Offset | Kind::OffsetEdits | Kind::SelfOffset | Kind::FarCsv | Kind::Indirect => {
            let last = wb.value(0, at(n - 1, 0));
            if last != Value::Number(n as f64) {
                return fail(format!("A{n} is {last:?}, not {n}"));
            }
        }
        Kind::Sheets | Kind::XlsxSheets => {
            if wb.sheet_len() != n as usize {
                return fail(format!("{} sheets, not {n}", wb.sheet_len()));
            }
            let got = wb.value(0, at(0, 1));
            if got != Value::Number(2.0 * n as f64) {
                return fail(format!("S1!B1 is {got:?}, not {}", 2 * n));
            }
        }
        Kind::IndirectEdit | Kind::IndirectRewrite => {
            let last = wb.value(0, at(n - 1, 0));
            if last != Value::Number(n as f64) {
                return fail(format!("A{n} is {last:?}, not {n}"));
            }
            if case.kind == Kind::IndirectEdit && wb.value(0, at(0, 1)) != Value::Number(EDITS as f64) {
                return fail(format!("B1 is {:?}, not {EDITS}", wb.value(0, at(0, 1))));
            }
        }
        Kind::FarCsvLoad => {
            let far = wb.value(0, at(n - 1, 16_383));
            if far != Value::Number(7.0) || !wb.value(0, at(0, 0)).is_blank() {
                return fail(format!("XFD{n} is {far:?}, A1 {:?}", wb.value(0, at(0, 0))));
            }
        }
        Kind::MacroTimeout => {}
        Kind::InsertColumns => {
            // Each insertion moved the columns one right: A's numbers are in K now.
            let (sum, last) = (wb.value(0, at(0, 11)), wb.value(0, at(n - 1, 10)));
            let total = n as f64 * (n as f64 + 1.0) / 2.0;
            if sum != Value::Number(total) || last != Value::Number(n as f64) {
                return fail(format!("L1 is {sum:?}, not {total}; K{n} {last:?}, not {n}"));
            }
        }
        Kind::Relink => {
            let last = wb.value(0, at(n - 1, 0));
            if last != Value::Number(1.0) || wb.cell_count() != 2 * n as usize {
                return fail(format!("A{n} is {last:?}, not 1; {} cells, not {}", wb.cell_count(), 2 * n));
            }
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    sizes_and_runs::exit("ncsheet-bench-scaling", run())
}

fn run() -> Result<(), String> {
    let args = sizes_and_runs::parse_args(DEFAULT_SIZES)?;
    let cases: Vec<Case> = args.sizes.iter().map(|s| Case::parse(s)).collect::<Result<_, _>>()?;
    println!("| case | size | best of {} | per item |", args.runs);
    println!("|---|---|---|---|");
    for case in &cases {
        let file = match case.kind {
            Kind::XlsxSheets => {
                let path = std::env::temp_dir().join(format!("ncsheet-bench-scaling-{}.xlsx", std::process::id()));
                ncsheet::io::save(&sheets_book(case.n)?, &path).map_err(|e| e.to_string())?;
                Some(path)
            }
            Kind::FarCsvLoad => Some(far_csv_file(case.n)?),
            _ => None,
        };
        let mut best = f64::MAX;
        for _ in 0..args.runs {
            let (wb, seconds) = match timed_part(case)? {
                Some(timed) => timed,
                None => {
                    let start = Instant::now();
                    let wb = build(case, file.as_deref())?;
                    (wb, start.elapsed().as_secs_f64())
                }
            };
            best = best.min(seconds);
            check(case, &wb)?;
        }
        if let Some(path) = &file {
            let _ = std::fs::remove_file(path);
        }
        let kind = case.name.rsplit_once('-').map_or("", |(k, _)| k);
        println!("| {kind} | {} | {:.3} s | {:.2} µs |", case.n, best, best * 1e6 / case.n as f64);
    }
    Ok(())
}
