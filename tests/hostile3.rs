//! Hostile input, third round (issue 30): the variants the second round did not name.
//! Each class gives a clear error in its place, bounded in time and memory, never a panic,
//! an abort, a lost edit or a silent wrong value.

mod common;

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::thread;

use common::cli::ncsheet;
use common::sheet::eval_a1;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;

/// An xlsx package with each part passed through `change(name, bytes)`.
fn rewrite_package(package: &[u8], change: &mut dyn FnMut(&str, Vec<u8>) -> Vec<u8>) -> Vec<u8> {
    let options = zip::write::SimpleFileOptions::default();
    common::rewrite_package(package, options, change).finish().unwrap().into_inner()
}

// ---------------------------------------------------------------------------------------
// Lost data: concurrent in-place edits

/// Eight `set --in-place` of different cells of one workbook at once: each edit either
/// lands or its process fails saying why; none reports "saved" and is lost.
fn concurrent_edits_all_land(file: &Path) {
    let edits: Vec<(String, f64)> = (1..=8).map(|i| (format!("C{i}"), f64::from(i) * 11.0)).collect();
    let runs: Vec<_> = thread::scope(|s| {
        let handles: Vec<_> = edits
            .iter()
            .map(|(cell, value)| {
                let arg = format!("{cell}={value}");
                let f = file.to_str().unwrap().to_string();
                s.spawn(move || ncsheet(&["set", &f, &arg, "--in-place"]))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let wb = ncsheet::io::load(file).unwrap();
    for ((cell, value), run) in edits.iter().zip(&runs) {
        let landed = wb.value(0, parse_cell(cell).unwrap()) == Value::Number(*value);
        if run.code == 0 {
            assert!(run.stderr.contains("saved"), "{}", run.stderr);
            assert!(landed, "{cell}={value} reported saved but is lost: {}", run.stderr);
        } else {
            assert!(run.stderr.contains("changed since ncsheet read it"), "{cell}: {}", run.stderr);
        }
    }
}

#[test]
fn concurrent_in_place_edits_of_a_csv_never_lose_one_silently() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("book.csv");
    std::fs::write(&file, "1,2\n3,4\n").unwrap();
    concurrent_edits_all_land(&file);
}

#[test]
fn concurrent_in_place_edits_of_an_xlsx_never_lose_one_silently() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("book.csv");
    std::fs::write(&csv, "1,2\n3,4\n").unwrap();
    let file = dir.path().join("book.xlsx");
    let made = ncsheet(&["set", csv.to_str().unwrap(), "A1=5", "-o", file.to_str().unwrap()]);
    assert_eq!(made.code, 0, "{}", made.stderr);
    concurrent_edits_all_land(&file);
}

/// A `set OTHER -o FILE` beside `set FILE … --in-place` edits of the same file: the `-o` save
/// waits for an edit under way and the edits after it read what it wrote, so when it reports
/// "saved" its cell is in the file at the end. (It landed between an edit's check and its
/// rename and was replaced, both reporting "saved", in 53 of 150 tries.)
#[test]
fn a_save_with_o_beside_in_place_edits_of_its_file_is_never_lost() {
    let dir = tempfile::tempdir().unwrap();
    let (file, other) = (dir.path().join("book.csv"), dir.path().join("other.csv"));
    std::fs::write(&other, "0,0,0,0\n").unwrap();
    let (f, o) = (file.to_str().unwrap(), other.to_str().unwrap());
    for round in 0..10 {
        std::fs::write(&file, "1,2,3,4\n").unwrap();
        let runs: Vec<_> = thread::scope(|s| {
            let mut handles = vec![s.spawn(move || ncsheet(&["set", o, "D1=99", "-o", f]))];
            for cell in ["A1=5", "B1=6"] {
                handles.push(s.spawn(move || ncsheet(&["set", f, cell, "--in-place"])));
            }
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert_eq!(runs[0].code, 0, "{}", runs[0].stderr);
        let wb = ncsheet::io::load(&file).unwrap();
        assert_eq!(wb.value(0, parse_cell("D1").unwrap()), Value::Number(99.0), "round {round}: -o's save is lost");
    }
}

// ---------------------------------------------------------------------------------------
// Crashes: widths past u16

#[test]
fn format_codes_with_more_than_65535_zeros_show_their_number() {
    use ncsheet::eval::dates::DateSystem;
    use ncsheet::eval::format::number_format::shown;
    // 70,000 exponent zeros: the exponent 4 written with 70,000 digits.
    let code = format!("0E+{}", "0".repeat(70_000));
    let text = shown(12345.0, Some(&code), DateSystem::From1900);
    assert_eq!(text.len(), "1E+".len() + 70_000);
    assert!(text.starts_with("1E+000") && text.ends_with("04"), "{}", &text[..20]);
    // An elapsed part of 70,000 s letters: 90 seconds as 70,000 digits.
    let code = format!("[{}]", "s".repeat(70_000));
    let text = shown(90.0 / 86_400.0, Some(&code), DateSystem::From1900);
    assert_eq!(text.len(), 70_000);
    assert!(text.ends_with("090"), "{}", &text[text.len() - 5..]);
}

#[test]
fn info_lists_names_longer_than_65535_characters() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("book.xlsx");
    let name = format!("n{}", "a".repeat(70_000));
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    wb.define_name("placeholder", "=5", None).unwrap();
    wb.define_name("short", "=6", None).unwrap();
    ncsheet::io::save(&wb, &file).unwrap();
    // Excel's names stop at 255 characters and ncsheet's writer keeps to that: the long one
    // is put in the package's workbook.xml by hand, as a hostile file would hold it.
    let package = std::fs::read(&file).unwrap();
    let mut rename = |part: &str, bytes: Vec<u8>| {
        if part != "xl/workbook.xml" {
            return bytes;
        }
        String::from_utf8(bytes).unwrap().replace("placeholder", &name).into_bytes()
    };
    std::fs::write(&file, rewrite_package(&package, &mut rename)).unwrap();
    let run = ncsheet(&["info", file.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains(&format!("{name}  =5")), "{}", &run.stdout[run.stdout.len() - 300..]);
    assert!(run.stdout.contains("short  "));
}

// ---------------------------------------------------------------------------------------
// Formulas: one sheet, one cell

fn value(formula: &str) -> Value {
    eval_a1(formula).0
}

const NUM: Value = Value::Error(ncsheet::eval::XlError::Num);

// ---------------------------------------------------------------------------------------
// Runaway: loops that stepped a float past 2^53, quadratic holidays

#[test]
fn cumulative_sums_past_two_to_the_53_end() {
    // P(X ≤ n) is 1 whatever the population: 1E+16 terms were summed one by one.
    let (v, _, _) = eval_a1("=HYPGEOM.DIST(1E+16,1E+16,1E+16,2E+16,TRUE)");
    assert_eq!(v, Value::Number(1.0));
    // Near 1E+18, j + 1 == j: the old loops never ended. 0.5^(1E+18) is 0.
    let (v, _, _) = eval_a1("=BINOM.DIST.RANGE(1E+18,0.5,1E+18)");
    assert_eq!(v, Value::Number(0.0));
    let (v, _, _) = eval_a1("=ISNUMBER(CUMIPMT(0.1,1E+17,100,1E+17,1E+17,0))");
    assert!(matches!(v, Value::Bool(_)), "{v:?}");
    // Both tails past the step limit: #NUM!, never a sum of 1E+16 terms.
    let (v, _, _) = eval_a1("=HYPGEOM.DIST(5E+15,1E+16,1E+16,2E+16,TRUE)");
    assert_eq!(v, NUM);
}

#[test]
fn workday_is_not_quadratic_in_its_holidays() {
    // 100,000 holidays, every one a Saturday (serial 7 is Saturday 7 January 1900): they
    // change nothing, so 100,000 working days from Monday serial 2 are 20,000 weeks later.
    let (v, _, _) = eval_a1("=WORKDAY(2,100000,SEQUENCE(100000,1,7,7))");
    assert_eq!(v, Value::Number(2.0 + 7.0 * 20_000.0));
    // NETWORKDAYS over the same span: 100,000 working days (Monday to Friday inclusive).
    let (v, _, _) = eval_a1("=NETWORKDAYS(2,139999,SEQUENCE(100000,1,7,7))");
    assert_eq!(v, Value::Number(100_000.0));
}

// ---------------------------------------------------------------------------------------
// Silently wrong numbers

#[test]
fn no_function_result_is_infinite_or_nan() {
    // Excel: MEDIAN(1E+308,1E+308) is 1E+308; GROWTH and TREND that overflow are #NUM!.
    assert_eq!(value("=MEDIAN(1E+308,1E+308)"), Value::Number(1e308));
    assert_eq!(value("=GROWTH({1,2},{1,2},2000)"), NUM);
    assert_eq!(value("=TREND({1E+308,-1E+308},{1,2},{3})"), NUM);
    assert_eq!(value("=ISNUMBER(GROWTH({1,2},{1,2},2000))"), Value::Bool(false));
    // Inside an array result too.
    assert_eq!(value("=INDEX(GROWTH({1,2},{1,2},{1,2000}),1,2)"), NUM);
}

#[test]
fn numbers_at_the_edges_of_doubles() {
    assert_eq!(value("=ROUNDDOWN(1E+308,-300)"), Value::Number(1e308));
    assert_eq!(value("=ROUNDUP(1.5E+300,-300)"), Value::Number(2e300));
    // Excel keeps no subnormal numbers: 1E-320 is 0 whichever its sign.
    assert_eq!(value("=1E-320>0"), Value::Bool(false));
    assert_eq!(value("=-1E-320<0"), Value::Bool(false));
    assert_eq!(value("=1E-320=0"), Value::Bool(true));
    // Typed into a cell, as in Excel, it is 0 too.
    let wb = sheet(&[("A1", "1E-320".to_string()), ("B1", "=A1>0".to_string()), ("C1", "=-A1<0".to_string())]);
    assert_eq!(wb.value(0, parse_cell("B1").unwrap()), Value::Bool(false));
    assert_eq!(wb.value(0, parse_cell("C1").unwrap()), Value::Bool(false));
}

/// Means, spreads and interpolations of numbers near the largest double: each is finite
/// where the exact result is. Expected values are exact arithmetic on the doubles (Python's
/// `fractions`: `float(Fraction(1e308) / 3)` is 3.333333333333333e+307, the mean absolute
/// deviation of 1e308, 1e308, -1e308 is 8/9 of 1e308, 8.888888888888889e+307) and, for
/// `SKEW`, scale-free algebra: the skew of (a, a, -a) is -√3 for every a > 0. Excel shows
/// AVERAGE(1E+308,1E+308) as 1E+308 (LibreOffice 7 overflows: `#NUM!`).
#[test]
fn means_and_percentiles_near_the_largest_double_are_finite() {
    let big = "{1E+308,1E+308}";
    for mean in [
        format!("=AVERAGE({big})"),
        format!("=AVERAGEA({big})"),
        format!("=TRIMMEAN({big},0)"),
        format!("=HARMEAN({big})"),
    ] {
        assert_eq!(value(&mean), Value::Number(1e308), "{mean}");
    }
    for spread in [format!("=AVEDEV({big})"), format!("=STDEV({big})")] {
        assert_eq!(value(&spread), Value::Number(0.0), "{spread}");
    }
    // The functions that take only ranges, over A1:A2.
    let over_range = ["=AVERAGEIF(A1:A2,\">0\")", "=SUBTOTAL(1,A1:A2)", "=AGGREGATE(1,4,A1:A2)", "=SUBTOTAL(7,A1:A2)"];
    let mut cells = vec![("A1", "1E+308".to_string()), ("A2", "1E+308".to_string())];
    cells.extend(["B1", "B2", "B3", "B4"].into_iter().zip(over_range.map(String::from)));
    let wb = sheet(&cells);
    for (cell, expected) in [("B1", 1e308), ("B2", 1e308), ("B3", 1e308), ("B4", 0.0)] {
        assert_eq!(wb.value(0, parse_cell(cell).unwrap()), Value::Number(expected), "{cell}");
    }
    let mixed = "{1E+308,1E+308,-1E+308}";
    assert_eq!(value(&format!("=AVERAGE({mixed})")), Value::Number(3.333333333333333e307));
    let close = |formula: &str, exact: f64| match value(formula) {
        // A few roundings of the mean, the deviations and their powers: within 1E-14.
        Value::Number(x) => assert!(((x - exact) / exact).abs() < 1e-14, "{formula}: {x} for {exact}"),
        other => panic!("{formula}: {other:?}"),
    };
    close(&format!("=AVEDEV({mixed})"), 8.888888888888889e307);
    close(&format!("=SKEW({mixed})"), -3f64.sqrt());
    // Halfway between -1E+308 and 1E+308 is 0, and 0 lies halfway.
    let wide = "{-1E+308,1E+308}";
    assert_eq!(value(&format!("=PERCENTILE({wide},0.5)")), Value::Number(0.0));
    assert_eq!(value(&format!("=QUARTILE({wide},2)")), Value::Number(0.0));
    assert_eq!(value(&format!("=PERCENTILE({wide},0.25)")), Value::Number(-5e307));
    assert_eq!(value(&format!("=PERCENTILE.EXC({mixed},0.5)")), Value::Number(1e308));
    assert_eq!(value(&format!("=PERCENTRANK({wide},0)")), Value::Number(0.5));
    assert_eq!(value(&format!("=PERCENTRANK.EXC({wide},0)")), Value::Number(0.5));
}

// ---------------------------------------------------------------------------------------
// Memory: arrays sized from an argument are checked before they are built

#[test]
fn arrays_sized_by_an_argument_are_num_naming_the_limit() {
    let cases = [
        "=ROWS(WRAPCOLS({1,2,3},1E+15))",
        "=ROWS(WRAPROWS({1,2,3},1E+15))",
        "=ROWS(WRAPROWS({1,2,3},20000000))",
        "=ROWS(VSTACK(SEQUENCE(1,16384),SEQUENCE(1048576)))",
        "=ROWS(HSTACK(SEQUENCE(1048576),SEQUENCE(1,16384)))",
        "=ROWS(MAKEARRAY(5000,5000,LAMBDA(r,c,1)))",
    ];
    for formula in cases {
        let (v, notes, _) = eval_a1(formula);
        assert_eq!(v, NUM, "{formula}");
        assert!(notes.iter().any(|n| n.contains("more than ncsheet's limit of 16777216")), "{formula}: {notes:?}");
    }
    // Within the limit they still build.
    assert_eq!(value("=ROWS(WRAPCOLS(SEQUENCE(10),4))"), Value::Number(4.0));
    assert_eq!(value("=COLUMNS(WRAPROWS(SEQUENCE(10),4,0))"), Value::Number(4.0));
    assert_eq!(value("=ROWS(VSTACK(SEQUENCE(3),SEQUENCE(1,4)))"), Value::Number(4.0));
    assert_eq!(value("=SUM(MAKEARRAY(3,4,LAMBDA(r,c,r*c)))"), Value::Number(60.0));
}

#[test]
fn show_refuses_a_range_past_its_cell_limit() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("two.csv");
    std::fs::write(&file, "1,2\n").unwrap();
    for range in ["A1:XFD1048576", "A1:J1000000"] {
        let run = ncsheet(&["show", file.to_str().unwrap(), range]);
        assert_ne!(run.code, 0);
        assert!(run.stderr.contains("more than the 100000 `show` describes at once"), "{}", run.stderr);
        assert!(run.stdout.is_empty());
    }
    let run = ncsheet(&["show", file.to_str().unwrap(), "A1:B2"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
}

#[test]
fn the_repl_refuses_a_range_past_the_print_limit() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("two.csv");
    std::fs::write(&file, "1,2\n").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["repl", file.to_str().unwrap()])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(b"A1:XFD1048576\nshow A1:XFD1048576\nA1\n").unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.code().is_some(), "killed: {:?}", out.status);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("more than the 10000000 ncsheet prints at once"), "{stderr}");
    assert!(stderr.contains("more than the 100000 `show` describes at once"), "{stderr}");
}

// ---------------------------------------------------------------------------------------
// Runaway: a file's own iteration count

#[test]
fn iteration_counts_past_excels_maximum_are_held_to_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cycle.xlsx");
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    wb.set_input(0, parse_cell("A1").unwrap(), "=B1+1").unwrap();
    wb.set_input(0, parse_cell("B1").unwrap(), "=A1+1").unwrap();
    ncsheet::io::save(&wb, &file).unwrap();
    let package = std::fs::read(&file).unwrap();
    let mut iterate = |part: &str, bytes: Vec<u8>| {
        if part != "xl/workbook.xml" {
            return bytes;
        }
        let text = String::from_utf8(bytes).unwrap();
        let calc = r#"<calcPr iterate="1" iterateCount="2147483647" iterateDelta="0"/>"#;
        let text = match text.find("<calcPr") {
            Some(at) => {
                let end = at + text[at..].find("/>").unwrap() + 2;
                format!("{}{calc}{}", &text[..at], &text[end..])
            }
            None => text.replace("</workbook>", &format!("{calc}</workbook>")),
        };
        text.into_bytes()
    };
    std::fs::write(&file, rewrite_package(&package, &mut iterate)).unwrap();
    let info = ncsheet(&["info", file.to_str().unwrap()]);
    assert!(info.stdout.contains("at most 32767"), "{}", info.stdout);
    assert!(!info.stdout.contains("does not iterate"), "{}", info.stdout);
    // The bound is the count `info` reports above (Excel's 32,767), not a time measured here.
    let run = ncsheet(&["eval", file.to_str().unwrap(), "A1:B1"]);
    assert!(run.code == 0 || !run.stderr.is_empty(), "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------
// Silently wrong: positions read as dependencies

/// A sheet with `cells` typed in, recalculated.
fn sheet(cells: &[(&str, String)]) -> ncsheet::workbook::Workbook {
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    for (cell, input) in cells {
        wb.set_input_deferred(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    wb.recalculate();
    wb
}

#[test]
fn a_running_balance_through_index_of_its_own_column_is_no_cycle() {
    // B2 = A2, then B3 = INDEX(B:B,ROW()-1)+A3 filled down 5,000 rows: each row adds its A,
    // so B(n) is the sum 1 + 2 + … + (n-1) of the A column (A(n) = n - 1).
    let rows = 5_001;
    let mut cells = vec![("A2".to_string(), "1".to_string()), ("B2".to_string(), "=A2".to_string())];
    for r in 3..=rows {
        cells.push((format!("A{r}"), (r - 1).to_string()));
        cells.push((format!("B{r}"), "=INDEX(B:B,ROW()-1)+A".to_string() + &r.to_string()));
    }
    let cells: Vec<(&str, String)> = cells.iter().map(|(c, i)| (c.as_str(), i.clone())).collect();
    let mut wb = sheet(&cells);
    let n = (rows - 1) as f64;
    assert_eq!(wb.value(0, parse_cell(&format!("B{rows}")).unwrap()), Value::Number(n * (n + 1.0) / 2.0));
    assert!(wb.problems().is_empty(), "{:?}", wb.problems().first().map(|p| p.render()));
    // An edit high up reaches the bottom: the cells INDEX returned are its links.
    wb.set_input(0, parse_cell("A2").unwrap(), "101").unwrap();
    assert_eq!(wb.value(0, parse_cell(&format!("B{rows}")).unwrap()), Value::Number(n * (n + 1.0) / 2.0 + 100.0));
    // A real cycle through INDEX is still one, named. (It keeps the value of its one
    // computation before its reach was known, where Excel, which links C:C, shows 0.)
    let wb = sheet(&[("C1", "=INDEX(C:C,1)+1".to_string())]);
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!C1".to_string()]]);
}

/// Rows of the running balances through lookups (one more than the 1,448 from which the
/// forward INDEX ledger failed).
const LEDGER_ROWS: u32 = 1_500;

/// The ledger's amounts: row (or column) `k` adds this; the balance at `n` is their sum to `n`.
fn amount(k: u32) -> f64 {
    ((k * 7) % 11) as f64
}

/// A workbook of running balances, each line's balance its amount plus the balance a lookup
/// of the line before finds: on Sheet1 down the rows by VLOOKUP (C), LOOKUP (D),
/// INDEX/MATCH (E) and XLOOKUP (F); on Sheet2 along the columns by HLOOKUP; and in Sheet1!G1
/// a lookup that finds its own cell, a true cycle.
fn write_lookup_ledgers(path: &Path) {
    use rust_xlsxwriter::Formula;
    let mut book = rust_xlsxwriter::Workbook::new();
    let down = book.add_worksheet();
    down.set_formula_result_default("");
    let n = LEDGER_ROWS;
    for r in 1..=n {
        let row = r - 1;
        down.write_number(row, 0, r as f64).unwrap();
        down.write_number(row, 1, amount(r)).unwrap();
        let formulas = if r == 1 {
            ["B1".to_string(), "B1".to_string(), "B1".to_string(), "B1".to_string()]
        } else {
            [
                format!("VLOOKUP(A{r}-1,$A:$C,3,FALSE)+B{r}"),
                format!("LOOKUP(A{r}-1,$A$1:$A${n},D$1:D${n})+B{r}"),
                format!("INDEX(E:E,MATCH(A{r}-1,$A:$A,0))+B{r}"),
                format!("_xlfn.XLOOKUP(A{r}-1,$A:$A,F:F)+B{r}"),
            ]
        };
        for (col, f) in (2..).zip(formulas) {
            down.write_formula(row, col, Formula::new(f)).unwrap();
        }
    }
    down.write_formula(0, 6, Formula::new("VLOOKUP(1,$A$1:$G$1,7,FALSE)+1")).unwrap();
    let along = book.add_worksheet();
    along.set_formula_result_default("");
    for c in 1..=n {
        let (col, name) = ((c - 1) as u16, ncsheet::formula::address::column_name(c - 1));
        along.write_number(0, col, c as f64).unwrap();
        along.write_number(1, col, amount(c)).unwrap();
        let f = if c == 1 { "A2".to_string() } else { format!("HLOOKUP({name}1-1,$1:$3,3,FALSE)+{name}2") };
        along.write_formula(2, col, Formula::new(f)).unwrap();
    }
    book.save(path).unwrap();
}

/// LibreOffice (headless, recalculating on load; required on CI) computes every ledger but
/// XLOOKUP's (LibreOffice 7 has none), and its results are the sums of the amounts: a lookup
/// reads the column it searches and only the cell it returns, so none is a cycle. The lookup
/// finding its own cell is one for both (LibreOffice: Err:522).
#[test]
fn running_balances_through_lookups_are_no_cycle_as_libreoffice_computes_them() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("ledgers.xlsx");
    write_lookup_ledgers(&file);
    let ours = ncsheet::io::xlsx::load(&file).unwrap();
    let wb = &ours.workbook;
    let mut balance = 0.0;
    for k in 1..=LEDGER_ROWS {
        balance += amount(k);
        for col in ["C", "D", "E", "F"] {
            assert_eq!(wb.value(0, parse_cell(&format!("{col}{k}")).unwrap()), Value::Number(balance), "{col}{k}");
        }
        let along = ncsheet::formula::address::Pos::new(2, k - 1);
        assert_eq!(wb.value(1, along), Value::Number(balance), "Sheet2 column {k}");
    }
    assert_eq!(wb.cycles(), vec![vec!["Sheet1!G1".to_string()]]);
    let Some(recalculated) = common::libreoffice_recalculated(&file, dir.path()) else {
        eprintln!("skipped the comparison with LibreOffice: soffice is not installed");
        return;
    };
    let theirs = ncsheet::io::xlsx::load(&recalculated).unwrap();
    let mut compared = 0;
    for cached in &theirs.cached {
        let place = format!("sheet {} {}", cached.sheet, cached.pos);
        match (cached.sheet, cached.pos.col) {
            (0, 5) => continue,
            (0, 6) => assert!(matches!(cached.value, Value::Error(_)), "{place}: {:?}", cached.value),
            _ => assert_eq!(wb.value(cached.sheet, cached.pos), cached.value, "{place}"),
        }
        compared += 1;
    }
    assert_eq!(compared, 4 * LEDGER_ROWS as usize + 1, "LibreOffice's results of every ledger");
}

#[test]
fn row_and_columns_over_their_own_spill_range_spill() {
    // Excel spills these: they read where the range is, not what it holds.
    let wb = sheet(&[("A1", "=ROW(A1:A3)".to_string()), ("B1", "=COLUMN(B1:D1)".to_string())]);
    assert_eq!(wb.value(0, parse_cell("A3").unwrap()), Value::Number(3.0));
    assert_eq!(wb.value(0, parse_cell("D1").unwrap()), Value::Number(4.0));
    let wb = sheet(&[("A1", "=SEQUENCE(ROWS(A1:A4))".to_string())]);
    assert_eq!(wb.value(0, parse_cell("A4").unwrap()), Value::Number(4.0));
    let wb = sheet(&[("A1", "=SEQUENCE(1,COLUMNS(A1:E1))*10".to_string())]);
    assert_eq!(wb.value(0, parse_cell("E1").unwrap()), Value::Number(50.0));
}

// ---------------------------------------------------------------------------------------
// Files: cells a hostile or damaged sheet part stores

/// An xlsx whose first sheet's cells are `sheet_data` (the inside of `<sheetData>`).
fn book_with_cells(dir: &Path, sheet_data: &str) -> std::path::PathBuf {
    let file = dir.join("cells.xlsx");
    let mut wb = ncsheet::workbook::Workbook::with_sheet();
    wb.set_input(0, parse_cell("A1").unwrap(), "1").unwrap();
    ncsheet::io::save(&wb, &file).unwrap();
    let package = std::fs::read(&file).unwrap();
    let mut cells = |part: &str, bytes: Vec<u8>| {
        if part != "xl/worksheets/sheet1.xml" {
            return bytes;
        }
        let text = String::from_utf8(bytes).unwrap();
        let (start, end) = (text.find("<sheetData").unwrap(), text.find("</sheetData>").unwrap());
        format!("{}<sheetData>{sheet_data}{}", &text[..start], &text[end..]).into_bytes()
    };
    std::fs::write(&file, rewrite_package(&package, &mut cells)).unwrap();
    file
}

#[test]
fn a_shared_formula_moved_past_the_sheets_edge_reads_ref() {
    let dir = tempfile::tempdir().unwrap();
    // B1048575 holds =A1048576*2 shared down to B1048576, whose copy reads one row below
    // the last: Excel's copy is =#REF!*2.
    let file = book_with_cells(
        dir.path(),
        r#"<row r="1048575"><c r="B1048575"><f t="shared" ref="B1048575:B1048576" si="0">A1048576*2</f><v>6</v></c></row><row r="1048576"><c r="A1048576"><v>3</v></c><c r="B1048576"><f t="shared" si="0"/><v>0</v></c></row>"#,
    );
    let wb = ncsheet::io::load(&file).unwrap();
    assert_eq!(wb.value(0, parse_cell("B1048575").unwrap()), Value::Number(6.0));
    assert_eq!(wb.value(0, parse_cell("B1048576").unwrap()), Value::Error(ncsheet::eval::XlError::Ref));
    // A copy that stays on the sheet still moves: C1:C2 = A1*2, A2*2.
    let file = book_with_cells(
        dir.path(),
        r#"<row r="1"><c r="A1"><v>3</v></c><c r="C1"><f t="shared" ref="C1:C2" si="0">A1*2</f><v>6</v></c></row><row r="2"><c r="A2"><v>5</v></c><c r="C2"><f t="shared" si="0"/><v>10</v></c></row>"#,
    );
    let wb = ncsheet::io::load(&file).unwrap();
    assert_eq!(wb.value(0, parse_cell("C2").unwrap()), Value::Number(10.0));
}

/// A second text for one `si` does not replace the first: the first is the master
/// (ECMA-376 Part 1 §18.3.1.40, "the first formula in a group of shared formulas is saved in
/// the f element"). LibreOffice 7 reads this sheet as B1 =A1+1, B2 =A2+1, B3 =A3+1, values
/// 2, 3, 4 (`soffice --convert-to csv`; its fods shows the three formulas): the second text
/// (`A2*100`) made B3 =A3*100, 300.
#[test]
fn a_second_text_for_one_shared_index_does_not_replace_its_master() {
    let dir = tempfile::tempdir().unwrap();
    let file = book_with_cells(
        dir.path(),
        r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1"><f t="shared" ref="B1:B3" si="0">A1+1</f><v>0</v></c></row><row r="2"><c r="A2"><v>2</v></c><c r="B2"><f t="shared" ref="B2:B3" si="0">A2*100</f><v>0</v></c></row><row r="3"><c r="A3"><v>3</v></c><c r="B3"><f t="shared" si="0"/><v>0</v></c></row>"#,
    );
    let imported = ncsheet::io::xlsx::load(&file).unwrap();
    let wb = &imported.workbook;
    for (cell, libreoffice) in [("B1", 2.0), ("B2", 3.0), ("B3", 4.0)] {
        assert_eq!(wb.value(0, parse_cell(cell).unwrap()), Value::Number(libreoffice), "{cell}");
    }
    let said = imported.notes.join("\n");
    assert!(said.contains("xl/worksheets/sheet1.xml: cell Sheet1!B2") && said.contains("si=\"0\""), "{said}");
}

/// A copy whose master is nowhere in the sheet keeps its cached value, and the note names
/// the part, the cell and the index, so that the damaged group can be found in the file.
#[test]
fn a_shared_copy_without_its_master_names_the_part_cell_and_index() {
    let dir = tempfile::tempdir().unwrap();
    let file = book_with_cells(
        dir.path(),
        r#"<row r="1"><c r="A1"><v>1</v></c><c r="B1"><f t="shared" si="7"/><v>5</v></c></row>"#,
    );
    let imported = ncsheet::io::xlsx::load(&file).unwrap();
    assert_eq!(imported.workbook.value(0, parse_cell("B1").unwrap()), Value::Number(5.0));
    let said = imported.notes.join("\n");
    assert!(said.contains("xl/worksheets/sheet1.xml: cell Sheet1!B1: ") && said.contains("si=\"7\""), "{said}");
}

#[test]
fn numbers_past_the_largest_double_and_indexes_past_u32_are_named() {
    let dir = tempfile::tempdir().unwrap();
    for (cells, says) in [
        (r#"<row r="1"><c r="A1"><v>1e400</v></c></row>"#, "A1"),
        (r#"<row r="1"><c r="A1" t="n"><v>-1E+309</v></c></row>"#, "past the largest number"),
        (
            r#"<row r="1"><c r="A1"><f t="shared" ref="A1:A2" si="4294967296">B1</f><v>0</v></c></row><row r="2"><c r="A2"><f t="shared" si="4294967296"/><v>0</v></c></row>"#,
            "si=\"4294967296\"",
        ),
    ] {
        let file = book_with_cells(dir.path(), cells);
        let e = match ncsheet::io::load(&file) {
            Ok(_) => panic!("{cells}: read without a word"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(says), "{e}");
    }
}

#[test]
fn damaged_parts_are_named_with_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let file = book_with_cells(dir.path(), r#"<row r="1"><c r="A1"><v>1</v></c></row>"#);
    let package = std::fs::read(&file).unwrap();
    let utf16 = |t: String| {
        let mut v = vec![0xFF, 0xFE];
        t.encode_utf16().for_each(|u| v.extend(u.to_le_bytes()));
        v
    };
    let cut = |t: String| t.as_bytes()[..t.len() / 2].to_vec();
    type Spoil<'a> = &'a dyn Fn(String) -> Vec<u8>;
    let probes: [(&str, Spoil, &str); 4] = [
        ("xl/worksheets/sheet1.xml", &utf16, "the part is encoded in UTF-16"),
        ("xl/styles.xml", &utf16, "the part is encoded in UTF-16"),
        ("xl/styles.xml", &cut, "the XML is not well-formed"),
        ("xl/workbook.xml", &cut, "the XML is not well-formed"),
    ];
    for (target, change, says) in probes {
        let mut f = |part: &str, bytes: Vec<u8>| {
            if part == target {
                change(String::from_utf8(bytes).unwrap())
            } else {
                bytes
            }
        };
        std::fs::write(&file, rewrite_package(&package, &mut f)).unwrap();
        let e = ncsheet::io::load(&file).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains(&format!("{target}: ")) && e.contains(says), "{target}: {e}");
    }
}

#[test]
fn a_long_cycle_is_named_in_a_short_line() {
    // A1 = A2, A2 = A3, …, A5000 = A1: one cycle of 5,000 cells.
    let cells: Vec<(String, String)> =
        (1..=5000).map(|r| (format!("A{r}"), format!("=A{}", if r == 5000 { 1 } else { r + 1 }))).collect();
    let cells: Vec<(&str, String)> = cells.iter().map(|(c, i)| (c.as_str(), i.clone())).collect();
    let wb = sheet(&cells);
    let lines: Vec<String> = wb.problems().iter().map(|p| p.render()).collect();
    let cycle = lines.iter().find(|l| l.contains("circular reference")).expect("the cycle is reported");
    assert!(cycle.len() < 400, "{} bytes", cycle.len());
    assert!(cycle.contains("(4988 more cells)") && cycle.contains("(5000 cells in all)"), "{cycle}");
    // A short one is named whole.
    let wb = sheet(&[("A1", "=B1".to_string()), ("B1", "=A1".to_string())]);
    let lines: Vec<String> = wb.problems().iter().map(|p| p.render()).collect();
    assert!(lines.iter().any(|l| l.ends_with("Sheet1!A1 -> Sheet1!B1")), "{lines:?}");
}

#[test]
fn a_macro_stopped_deep_in_recursion_says_each_caller_once() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("b.csv");
    std::fs::write(&book, "1,2\n").unwrap();
    let bas = dir.path().join("rec.bas");
    std::fs::write(&bas, "Sub Main()\n    Recurse 1\nEnd Sub\nSub Recurse(n)\n    Recurse n + 1\nEnd Sub\n").unwrap();
    let run = ncsheet(&["run", book.to_str().unwrap(), bas.to_str().unwrap(), "--max-depth", "10000"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.len() < 2_000, "{} bytes", run.stderr.len());
    assert!(run.stderr.contains("in Sub Recurse (called at line 5, column 5) ("), "{}", run.stderr);
    assert!(run.stderr.contains("in Sub Main"), "{}", run.stderr);
}

#[test]
fn texts_past_excels_limit_say_so() {
    for formula in [
        "=SUBSTITUTE(REPT(\"a\",30000),\"a\",\"aa\")",
        "=CONCAT(REPT(\"a\",20000),REPT(\"a\",20000))",
        "=TEXTJOIN(\",\",TRUE,REPT(\"a\",20000),REPT(\"a\",20000))",
        "=REPT(\"a\",20000)&REPT(\"a\",20000)",
        "=LEN(SUBSTITUTE(REPT(\"a\",30000),\"a\",\"aa\"))",
    ] {
        let (v, notes, _) = eval_a1(formula);
        assert_eq!(v, Value::Error(ncsheet::eval::XlError::Value), "{formula}");
        assert!(notes.iter().any(|n| n.contains("longer than the 32767 characters")), "{formula}: {notes:?}");
    }
}

#[test]
fn arrays_of_long_texts_stop_at_their_byte_limit() {
    // 2^24 items are allowed, but not 2^24 texts of 30,000 characters (500 GB).
    let cases = [
        "=ROWS(REPT(\"x\",30000)&SEQUENCE(4096,4096))",
        "=ROWS(SEQUENCE(4096,4096)&REPT(\"x\",30000))",
        "=ROWS(REPT(\"x\",30000+0*SEQUENCE(4096,4096)))",
        "=LET(a,SEQUENCE(4096,4096),b,a&REPT(\"y\",30000),ROWS(b))",
        "=ROWS(SEQUENCE(4096)&REPT(\"x\",30000)&SEQUENCE(1,4096))",
    ];
    for formula in cases {
        let (v, notes, _) = eval_a1(formula);
        assert_eq!(v, NUM, "{formula}");
        assert!(notes.iter().any(|n| n.contains("texts hold more than 256 MiB")), "{formula}: {notes:?}");
    }
    // Short texts over as many items still work.
    assert_eq!(value("=ROWS(\"ab\"&SEQUENCE(1000,1000))"), Value::Number(1000.0));
}

/// `Array()` with more items than a call takes (255, docs/limits.md) says the limit and how
/// to build a longer array, not "takes at least 0 arguments".
#[test]
fn array_with_more_items_than_a_call_takes_names_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("w.csv");
    std::fs::write(&book, "a,b\n1,2\n").unwrap();
    for items in [256, 200_000] {
        let list = vec!["1"; items].join(",");
        let bas = dir.path().join("array.bas");
        std::fs::write(&bas, format!("Sub Main()\n  Dim a\n  a = Array({list})\nEnd Sub\n")).unwrap();
        let run = ncsheet(&["run", book.to_str().unwrap(), bas.to_str().unwrap()]);
        assert_ne!(run.code, 0);
        assert!(
            run.stderr.contains(&format!("Array takes at most 255 arguments, not {items}")),
            "{}",
            &run.stderr[..300]
        );
        assert!(run.stderr.contains("array.bas:3:"), "{}", &run.stderr[..300]);
    }
}
