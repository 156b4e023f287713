//! Hostile input beyond issue 19's own examples: other formulas, functions and file parts of
//! the same classes (arrays past memory, loops counting to 1E+15, exponential matching,
//! a date past the calendar, a declared count nobody checks). Each gives a clear error in
//! its place, bounded in time and memory, never a panic or an abort.

mod common;

use std::io::{Cursor, Write};
use std::path::Path;

use ncsheet::eval::{Value, XlError, MAX_ARRAY_ITEMS};
use ncsheet::formula::address::parse_cell;
use ncsheet::formula::limits::MAX_NESTING;
use ncsheet::io::xlsx;
use ncsheet::vba::{self, ErrorKind, RunOptions};
use ncsheet::workbook::Workbook;

use common::sheet::eval_a1;

fn num(formula: &str) -> Value {
    eval_a1(formula).0
}

const NUM: Value = Value::Error(XlError::Num);

// ---------------------------------------------------------------------------------------
// Arrays past memory: #NUM! naming the limit, before anything is allocated

#[test]
fn arrays_broadcast_past_the_item_limit_are_num_naming_the_limit() {
    // Each of these asked for 24 GB to 26 TB and aborted the process.
    let cases = [
        "=ROWS(SEQUENCE(1048576)*SEQUENCE(1,16384))",
        "=ROWS(SEQUENCE(100000)&SEQUENCE(1,10000))",
        "=ROWS(SEQUENCE(1048576)=SEQUENCE(1,16384))",
        "=LET(s,SEQUENCE(1048576),ROWS(s*TRANSPOSE(s)))",
        "=ROWS(ATAN2(SEQUENCE(1048576),SEQUENCE(1,16384)))",
        "=ROWS(MAP(SEQUENCE(1048576)*SEQUENCE(1,100),LAMBDA(x,x)))",
        "=ROWS(EXPAND(1,100000,10000))",
        "=ROWS(EXPAND(1,1E+300,1))",
        // A whole-sheet array keeps its blanks as one value, but SUM would visit 17 billion.
        "=SUM(B:XFD*1)",
    ];
    for formula in cases {
        // The bound is the outcome, not a time: #NUM! with the limit's note, before anything
        // is allocated (the process aborted at the memory cap).
        let (value, problems, _) = eval_a1(formula);
        assert_eq!(value, NUM, "{formula}");
        assert!(
            problems.iter().any(|p| p.contains(&format!("more than ncsheet's limit of {MAX_ARRAY_ITEMS}"))),
            "{formula}: {problems:?}"
        );
    }
    // MUNIT past the limit, and IF lifted over a sheet-sized pair, are #NUM! too.
    assert_eq!(num("=ROWS(MUNIT(100000))"), NUM);
    assert_eq!(num("=ROWS(IF(SEQUENCE(1048576),SEQUENCE(1,16384)))"), NUM);
}

#[test]
fn arrays_within_the_limit_still_broadcast() {
    // 1,000 × 1,000 items: the sum of i*j over both is (500,500)².
    assert_eq!(num("=SUM(SEQUENCE(1000)*SEQUENCE(1,1000))"), Value::Number(500_500f64 * 500_500f64));
    assert_eq!(num("=ROWS(EXPAND(1,2000,2000))"), Value::Number(2000.0));
    assert_eq!(num("=SUM(MUNIT(1000))"), Value::Number(1000.0));
    // A whole column is 1,048,576 items, within the limit: blanks times one are 0.
    assert_eq!(num("=SUM(B:B*1)"), Value::Number(0.0));
    assert_eq!(num("=ROWS(B:B*1)"), Value::Number(1_048_576.0));
}

// ---------------------------------------------------------------------------------------
// Loops that counted to their argument

#[test]
fn combinatorics_of_huge_counts_overflow_to_num_at_once() {
    // C(1E+15, 5E+14) and its kin are far past 1.8E+308 (Excel: #NUM!); the loops counted
    // to 5E+14 first. LCM past 2^53 is #NUM! (Excel's documented bound).
    for formula in [
        "=COMBIN(1E+15,5E+14)",
        "=COMBINA(1E+15,5E+14)",
        "=PERMUT(1E+15,5E+14)",
        "=MULTINOMIAL(1E+15,5E+14)",
        "=FACTDOUBLE(1E+15)",
        "=LCM(SEQUENCE(1000))",
        "=LCM(1E+15,1E+15-1,1E+15-3)",
    ] {
        // #NUM! is the outcome of the overflow found first; the loops never ended.
        let (value, _, _) = eval_a1(formula);
        assert_eq!(value, NUM, "{formula}");
    }
    // Within range nothing changes: C(60,30) = 118264581564861424, FACTDOUBLE(10) = 3840.
    assert_eq!(num("=COMBIN(60,30)"), Value::Number(118_264_581_564_861_424.0));
    assert_eq!(num("=FACTDOUBLE(10)"), Value::Number(3840.0));
    assert_eq!(num("=LCM(SEQUENCE(20))"), Value::Number(232_792_560.0));
}

/// The smallest k with P(X ≤ k) ≥ alpha for X binomial(n, p), summed here term by term in
/// log space, apart from the code under test.
fn binomial_quantile(n: u64, p: f64, alpha: f64) -> u64 {
    let (lp, lq) = (p.ln(), (1.0 - p).ln());
    let mut log_pmf = n as f64 * lq;
    let mut log_total = f64::NEG_INFINITY;
    let mut terms = Vec::with_capacity(n as usize + 1);
    for k in 0..=n {
        terms.push(log_pmf);
        let m = log_total.max(log_pmf);
        log_total = m + ((log_total - m).exp() + (log_pmf - m).exp()).ln();
        log_pmf += ((n - k) as f64 / (k + 1) as f64).ln() + lp - lq;
    }
    let mut cumulative = f64::NEG_INFINITY;
    for (k, t) in terms.iter().enumerate() {
        let m = cumulative.max(*t);
        cumulative = m + ((cumulative - m).exp() + (t - m).exp()).ln();
        if (cumulative - log_total).exp() >= alpha {
            return k as u64;
        }
    }
    n
}

#[test]
fn binomial_quantiles_of_many_trials_answer_without_counting_every_trial() {
    // Counting the 10^15 trials one by one never ended; the answer is the outcome checked.
    let (value, _, _) = eval_a1("=BINOM.INV(1E+15,0.5,0.5)");
    // Symmetric: P(X ≤ n/2) ≥ 1/2 > P(X ≤ n/2 − 1).
    assert_eq!(value, Value::Number(5e14));
    let want = binomial_quantile(1_000_000, 0.3, 0.9) as f64;
    assert_eq!(num("=CRITBINOM(1000000,0.3,0.9)"), Value::Number(want));
    assert_eq!(num("=BINOM.INV(20000,0.25,0.01)"), Value::Number(binomial_quantile(20_000, 0.25, 0.01) as f64));
}

// ---------------------------------------------------------------------------------------
// Wildcards: no exponential backtracking

#[test]
fn wildcard_patterns_match_in_bounded_time() {
    let cases = [
        (r#"=SEARCH(REPT("*?",1000)&"b",REPT("a",32767))"#, Value::Error(XlError::Value)),
        (
            r#"=MATCH(REPT("*a",5000)&"b",{"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"},0)"#,
            Value::Error(XlError::NA),
        ),
        (r#"=XMATCH(REPT("*a",3000)&"b",REPT("a",32000),2)"#, Value::Error(XlError::NA)),
        (r#"=SEARCH(REPT("*a",100)&"*b",REPT("a",20000)&"b")"#, Value::Number(1.0)),
    ];
    for (formula, want) in cases {
        // Exponential backtracking never ended; the match's answer is the outcome checked.
        let (value, _, _) = eval_a1(formula);
        assert_eq!(value, want, "{formula}");
    }
}

#[test]
fn wildcards_still_find_what_excel_finds() {
    // Excel's documented examples and their kin: ? one character, * any run, ~ literal.
    let cases = [
        (r#"=SEARCH("b*d","abcxd")"#, 2.0),
        (r#"=SEARCH("?c","abc")"#, 2.0),
        (r#"=SEARCH("a*c","xxabxc")"#, 3.0),
        (r#"=SEARCH("c*","abc")"#, 3.0),
        (r#"=SEARCH("*","abc")"#, 1.0),
        (r#"=SEARCH("~*","ab*c")"#, 3.0),
        (r#"=MATCH("*a?c*",{"zzabd","xazcq"},0)"#, 2.0),
        (r#"=MATCH("a*",{"ba","ab"},0)"#, 2.0),
        (r#"=COUNTIF(A2:A3,"*")"#, 0.0),
    ];
    for (formula, want) in cases {
        assert_eq!(num(formula), Value::Number(want), "{formula}");
    }
    assert_eq!(num(r#"=SEARCH("b?","aab",2)"#), Value::Error(XlError::Value));
}

// ---------------------------------------------------------------------------------------
// Dates past the calendar

#[test]
fn month_arithmetic_past_the_calendar_is_num_not_a_panic() {
    for formula in ["=EDATE(1,1E+300)", "=EDATE(1,-1E+300)", "=EOMONTH(1,1E+300)", "=EOMONTH(1,-9.3E+18)"] {
        assert_eq!(num(formula), NUM, "{formula}");
    }
    // 2024-01-31 plus one month is the last day of February 2024: serial 45351.
    assert_eq!(num("=EDATE(45322,1)"), Value::Number(45351.0));
}

// ---------------------------------------------------------------------------------------
// xlsx: declared counts and array areas

/// A one-sheet package whose sheet data is `data`, with `extra` parts added.
fn package(data: &str, extra: &[(&str, &str)], shared_strings_related: bool) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    let mut put = |name: &str, text: &str| {
        zip.start_file(name, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    };
    const RELS: &str = "http://schemas.openxmlformats.org/officeDocument/2006/relationships";
    put(
        "_rels/.rels",
        &format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{RELS}/officeDocument" Target="xl/workbook.xml"/></Relationships>"#
        ),
    );
    put(
        "xl/workbook.xml",
        &format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" xmlns:r="{RELS}"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#
        ),
    );
    let strings = if shared_strings_related {
        format!(r#"<Relationship Id="rId2" Type="{RELS}/sharedStrings" Target="sharedStrings.xml"/>"#)
    } else {
        String::new()
    };
    put(
        "xl/_rels/workbook.xml.rels",
        &format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{RELS}/worksheet" Target="worksheets/sheet1.xml"/>{strings}</Relationships>"#
        ),
    );
    put(
        "xl/worksheets/sheet1.xml",
        &format!(
            r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>{data}</sheetData></worksheet>"#
        ),
    );
    for (name, text) in extra {
        put(name, text);
    }
    zip.finish().unwrap().into_inner()
}

fn shared_strings(unique_count: &str) -> String {
    format!(
        r#"<sst xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" count="{unique_count}" uniqueCount="{unique_count}"><si><t>a</t></si></sst>"#
    )
}

#[test]
fn a_shared_string_count_of_a_trillion_is_refused_naming_the_part() {
    // calamine reserved 24 TB for the declared count and aborted; it reads the table even
    // when no relationship names it.
    let data = r#"<row r="1"><c r="A1" t="s"><v>0</v></c></row>"#;
    for related in [true, false] {
        let sst = shared_strings("1000000000000");
        let bytes = package(data, &[("xl/sharedStrings.xml", &sst)], related);
        let err = xlsx::load_bytes(&bytes, Path::new("count.xlsx")).err().expect("refused").to_string();
        assert!(err.contains("xl/sharedStrings.xml"), "{err}");
        assert!(err.contains("uniqueCount says 1000000000000 strings but it holds 1"), "{err}");
    }
    // A count a writer got slightly wrong still loads, its string read.
    let sst = shared_strings("3");
    let imported = xlsx::load_bytes(&package(data, &[("xl/sharedStrings.xml", &sst)], true), Path::new("ok.xlsx"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(imported.workbook.value(0, parse_cell("A1").unwrap()), Value::from("a"));
}

#[test]
fn an_array_formula_over_the_whole_sheet_costs_the_cells_that_exist() {
    // `{=1}` entered over A1:XFD1048576 fills 17 billion cells: the existing ones hold it,
    // and the anchor computes without building them (it allocated 3 GiB and aborted).
    let data = r#"<row r="1"><c r="A1"><f t="array" ref="A1:XFD1048576">1+1</f><v>2</v></c><c r="B1"><v>2</v></c></row><row r="5"><c r="C5"><v>2</v></c></row>"#;
    let imported =
        xlsx::load_bytes(&package(data, &[], false), Path::new("whole.xlsx")).unwrap_or_else(|e| panic!("{e}"));
    let wb = &imported.workbook;
    for cell in ["A1", "B1", "C5"] {
        assert_eq!(wb.value(0, parse_cell(cell).unwrap()), Value::Number(2.0), "{cell}");
    }
    // One that would repeat a range over the whole sheet is past the array limit.
    let data = r#"<row r="1"><c r="A1"><f t="array" ref="A1:XFD1048576">B1:XFD1048576*2</f><v>0</v></c></row>"#;
    let imported =
        xlsx::load_bytes(&package(data, &[], false), Path::new("whole.xlsx")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(imported.workbook.value(0, parse_cell("A1").unwrap()), NUM);
}

// ---------------------------------------------------------------------------------------
// Macros: one-line Ifs nest too

fn run_macro(src: &str) -> Result<Vec<String>, vba::MacroError> {
    let mut wb = Workbook::with_sheet();
    Ok(vba::run(&mut wb, src, "deep.bas", &RunOptions::default())?.printed)
}

#[test]
fn one_line_ifs_nested_past_the_limit_are_syntax_errors_not_a_stack_overflow() {
    // 5,000 `If … Then` on one line (or over continued lines) overflowed the stack.
    let one_line = format!("Sub Main()\n{}Debug.Print 1\nEnd Sub\n", "If 1 > 0 Then ".repeat(5000));
    let continued = format!("Sub Main()\n{}Debug.Print 1\nEnd Sub\n", "If 1 > 0 Then _\n".repeat(5000));
    let column = MAX_NESTING * "If 1 > 0 Then ".len() + "If 1 > 0 ".len() + 1;
    for (src, place) in
        [(one_line, format!("deep.bas:2:{column}:")), (continued, format!("deep.bas:{}:", 2 + MAX_NESTING))]
    {
        let e = run_macro(&src).expect_err("refused");
        assert_eq!(e.kind, ErrorKind::Syntax, "{e}");
        assert!(e.to_string().starts_with(&place), "{e}");
        assert!(e.message.contains("blocks nested more than 255 levels"), "{e}");
    }
    let at_limit = format!("Sub Main()\n{}Debug.Print \"deep\"\nEnd Sub\n", "If 1 > 0 Then ".repeat(MAX_NESTING));
    assert_eq!(run_macro(&at_limit).unwrap(), vec!["deep"]);
}

#[test]
fn labels_and_procedures_are_found_by_name_in_any_case_among_many() {
    // Each label and each procedure name was searched for in a list (quadratic: 100,000
    // labels ran past 20 s); they are now found in one step, as VBA does, in any case.
    let labels: String = (0..2000).map(|i| format!("L{i}:\n")).collect();
    let src = format!("Sub Main()\n{labels} n = n + 1\n If n < 3 Then GoTo l0\n Debug.Print n\nEnd Sub\n");
    assert_eq!(run_macro(&src).unwrap(), vec![" 3 "]);
    let subs: String = (0..2000).map(|i| format!("Function F{i}()\n F{i} = {i}\nEnd Function\n")).collect();
    let src = format!("{subs}Sub Main()\n Debug.Print f1999() + F7()\nEnd Sub\n");
    assert_eq!(run_macro(&src).unwrap(), vec![" 2006 "]);
    let twice = run_macro("Sub Main()\nA1x:\nx = 1\na1X:\nEnd Sub\n").expect_err("a label defined twice");
    assert!(twice.message.contains("label a1X is defined twice"), "{twice}");
    let twice = run_macro("Sub Main()\nEnd Sub\nSub MAIN()\nEnd Sub\n").expect_err("a Sub defined twice");
    assert!(twice.message.contains("MAIN is defined twice"), "{twice}");
}
