//! Hostile input (issue 30): variants of each class that nobody tuned the fixes for — other
//! functions of the same family, other spellings, other parts. Each gives a clear error in
//! its place, bounded in time and memory, never a panic, an abort or a silent wrong value.

mod common;

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::parse_cell;
use ncsheet::workbook::Workbook;

/// A sheet with `cells` typed in, recalculated.
fn sheet(cells: &[(String, String)]) -> Workbook {
    let mut wb = Workbook::with_sheet();
    for (cell, input) in cells {
        wb.set_input_deferred(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    wb.recalculate();
    wb
}

fn get(wb: &Workbook, cell: &str) -> Value {
    wb.value(0, parse_cell(cell).unwrap())
}

// ---------------------------------------------------------------------------------------
// Silently wrong: OFFSET's starting reference read as a dependency

/// A ledger of `last` rows: A(n) = n - 1 from row 2, B2 = A2 and B(n) = `step(n)` below it,
/// so that B(n) is the running sum 1 + 2 + … + (n - 1) = n(n - 1)/2.
fn ledger(last: u32, step: &dyn Fn(u32) -> String) -> Workbook {
    let mut cells = vec![("A2".to_string(), "1".to_string()), ("B2".to_string(), "=A2".to_string())];
    for r in 3..=last {
        cells.push((format!("A{r}"), (r - 1).to_string()));
        cells.push((format!("B{r}"), step(r)));
    }
    sheet(&cells)
}

fn running_sum(n: u32) -> Value {
    Value::Number(f64::from(n) * f64::from(n - 1) / 2.0)
}

#[test]
fn a_running_balance_through_offset_of_its_own_column_is_no_cycle() {
    let forms: [(&str, &dyn Fn(u32) -> String); 3] = [
        ("OFFSET(B3,-1,0)", &|r| format!("=OFFSET(B{r},-1,0)+A{r}")),
        ("OFFSET(B:B,ROW()-2,0,1)", &|r| format!("=OFFSET(B:B,ROW()-2,0,1)+A{r}")),
        ("OFFSET($B$1,ROW()-2,0)", &|r| format!("=OFFSET($B$1,ROW()-2,0)+A{r}")),
    ];
    let last = 5_001;
    for (form, step) in forms {
        let mut wb = ledger(last, step);
        for n in [3, 1_500, last] {
            assert_eq!(get(&wb, &format!("B{n}")), running_sum(n), "{form}: B{n}");
        }
        assert!(wb.problems().is_empty(), "{form}: {:?}", wb.problems().first().map(|p| p.render()));
        // An edit at the top reaches the bottom: the cells OFFSET reached are its links.
        wb.set_input(0, parse_cell("A2").unwrap(), "101").unwrap();
        let Value::Number(sum) = running_sum(last) else { unreachable!() };
        assert_eq!(get(&wb, &format!("B{last}")), Value::Number(sum + 100.0), "{form}");
    }
    // Summed from the bottom up, each row reading the one below through its own column (the
    // order a cycle's cells are settled in is the worst for it): C(n) = C(n+1) + A(n),
    // C5001 = A5001 = 5000.
    let mut cells = vec![("C5001".to_string(), "=A5001".to_string())];
    for r in 2..=last {
        cells.push((format!("A{r}"), (r - 1).to_string()));
        if r < last {
            cells.push((format!("C{r}"), format!("=OFFSET(C:C,ROW(),0,1)+A{r}")));
        }
    }
    let wb = sheet(&cells);
    assert_eq!(get(&wb, "C2"), running_sum(last));
    assert!(wb.problems().is_empty(), "{:?}", wb.problems().first().map(|p| p.render()));
}

#[test]
fn offset_still_finds_a_real_cycle_and_excels_ref() {
    // The cell OFFSET (INDEX, INDIRECT) reaches is the formula's own: a cycle, as in Excel,
    // and named. Its cell shows 0, as `=C1+1` does and Excel does for a circular formula
    // just entered (support.microsoft.com, "Remove or allow a circular reference": the last
    // calculated value or zero), not the 1 of its one computation reading itself as blank.
    let forms = [
        "=OFFSET(C2,-1,0)+1",
        "=OFFSET(C:C,0,0,1)+1",
        "=SUM(OFFSET($C$1,0,0))+1",
        "=INDEX(C:C,1)+1",
        "=INDIRECT(\"C1\")+1",
        "=C1+1",
    ];
    for formula in forms {
        let wb = sheet(&[("C1".to_string(), formula.to_string())]);
        assert_eq!(wb.cycles(), vec![vec!["Sheet1!C1".to_string()]], "{formula}");
        assert_eq!(get(&wb, "C1"), Value::Number(0.0), "{formula}");
    }
    // B:B moved down one row runs past the sheet's last row: #REF! in Excel, not a cycle.
    let wb = sheet(&[("A3".to_string(), "2".to_string()), ("B3".to_string(), "=OFFSET(B:B,ROW()-2,0)+A3".to_string())]);
    assert_eq!(get(&wb, "B3"), Value::Error(XlError::Ref));
}

// ---------------------------------------------------------------------------------------
// Arrays sized by their arguments: other builders than the ones the item limit named

const NUM: Value = Value::Error(XlError::Num);

#[test]
fn arrays_built_from_picks_and_splits_are_num_naming_the_limit() {
    let cases = [
        // 16,000 picks of a row of 16,384 items: 262,144,000 items.
        "=ROWS(CHOOSEROWS(SEQUENCE(1,16384),SEQUENCE(16000,1,1,0)))",
        "=ROWS(CHOOSECOLS(SEQUENCE(16384),SEQUENCE(1,16000,1,0)))",
        // Picks given in several arguments add up: 3 × 4,096 rows of 4,096.
        "=ROWS(CHOOSEROWS(SEQUENCE(4096,4096),SEQUENCE(4096),SEQUENCE(4096),SEQUENCE(4096)))",
        // 16,384 rows (semicolons) padded to the first row's 16,384 parts (commas).
        "=ROWS(TEXTSPLIT(REPT(\",\",16383)&REPT(\";\",16383),\",\",\";\"))",
    ];
    for formula in cases {
        let (v, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(v, NUM, "{formula}");
        assert!(notes.iter().any(|n| n.contains("more than ncsheet's limit of 16777216")), "{formula}: {notes:?}");
    }
    // Within the limit they still build (Excel's results).
    let value = |f: &str| common::sheet::eval_a1(f).0;
    assert_eq!(value("=SUM(CHOOSEROWS({1,2;3,4;5,6},3,-3))"), Value::Number(5.0 + 6.0 + 1.0 + 2.0));
    assert_eq!(value("=SUM(CHOOSECOLS({1,2,3;4,5,6},{3,1}))"), Value::Number(3.0 + 1.0 + 6.0 + 4.0));
    assert_eq!(value("=COLUMNS(TEXTSPLIT(\"a,b,c;d\",\",\",\";\"))"), Value::Number(3.0));
    assert_eq!(value("=ROWS(TEXTSPLIT(\"a,b,c;d\",\",\",\";\"))"), Value::Number(2.0));
}

// ---------------------------------------------------------------------------------------
// Counts past i64: OFFSET's move and size

/// SEQUENCE past a sheet's rows or columns is #VALUE! (Excel: calc_tests' SEQUENCE.xlsx and
/// the sheet's 1,048,576 × 16,384), and the note says why (issue 30: it said nothing).
#[test]
fn a_sequence_past_the_sheets_rows_or_columns_is_value_naming_the_limit() {
    for formula in ["=ROWS(SEQUENCE(1048577))", "=ROWS(SEQUENCE(1,16385))", "=ROWS(SEQUENCE(2^24))"] {
        let (v, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(v, Value::Error(XlError::Value), "{formula}");
        assert!(notes.iter().any(|n| n.contains("1048576 rows or 16384 columns")), "{formula}: {notes:?}");
    }
    let (v, _, _) = common::sheet::eval_a1("=ROWS(SEQUENCE(1048576))");
    assert_eq!(v, Value::Number(1_048_576.0));
}

/// RANDARRAY builds from a size as SEQUENCE does and shares its check: past a sheet's
/// 1,048,576 rows or 16,384 columns (Excel's specifications and limits) it is #VALUE! with
/// the same note (issue 30: `RANDARRAY(16000000)` was accepted, 16 million numbers made).
#[test]
fn a_randarray_past_the_sheets_rows_or_columns_is_value_as_sequence() {
    for formula in ["=ROWS(RANDARRAY(16000000))", "=ROWS(RANDARRAY(1,16385))", "=ROWS(RANDARRAY(1048577,1))"] {
        let (v, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(v, Value::Error(XlError::Value), "{formula}");
        assert!(
            notes.iter().any(|n| n.contains("RANDARRAY has more than the 1048576 rows or 16384 columns")),
            "{formula}: {notes:?}"
        );
    }
    // A sheet's full width and a whole column within the item limit still build.
    assert_eq!(common::sheet::eval_a1("=COLUMNS(RANDARRAY(1,16384))").0, Value::Number(16_384.0));
    assert_eq!(common::sheet::eval_a1("=ROWS(RANDARRAY(1048576))").0, Value::Number(1_048_576.0));
}

#[test]
fn offset_by_counts_past_the_sheet_is_ref() {
    // 1E+300 rows down, or a height of 1E+300 from row 5: far off the sheet (the count was
    // cast to the largest i64 and overflowed when added).
    let reference = Value::Error(XlError::Ref);
    for formula in [
        "=OFFSET(A2,1E+300,0)",
        "=OFFSET(A2,-1E+300,0)",
        "=OFFSET(A5,0,0,1E+300)",
        "=OFFSET(A5,-3,0,-1E+300)",
        "=OFFSET(B5,0,-1E+300,1,-1E+300)",
        "=OFFSET(A5,0,2,1,1E+300)",
    ] {
        assert_eq!(common::sheet::eval_a1(formula).0, reference, "{formula}");
    }
    // A negative height reaches up from the moved corner (Excel: OFFSET(A5,0,0,-3) is A3:A5).
    assert_eq!(common::sheet::eval_a1("=ROWS(OFFSET(A5,0,0,-3))").0, Value::Number(3.0));
}

// ---------------------------------------------------------------------------------------
// Macros: GoSubs nested with blocks between them

/// GoSubs that each return, nested 100,000 deep through an `If` (block or one-line) between
/// two of them: VBA's error 28, "Out of stack space", never an overflow of the native stack
/// (800 such levels aborted the process: the limit counted GoSubs, not the frames of the
/// blocks between them).
#[test]
fn gosubs_nested_inside_blocks_stop_with_error_28() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("wb.csv"), "1\n").unwrap();
    let one_line =
        "Sub Main()\n    Dim i As Long\n    GoSub Down\n    Debug.Print i\n    Exit Sub\nDown:\n    i = i + 1\n\
                    \x20   If i < 100000 Then GoSub Down\n    Return\nEnd Sub\n";
    let blocks = "Sub Main()\n    Dim i As Long, j As Long\n    GoSub Down\n    Exit Sub\nDown:\n    i = i + 1\n\
                  \x20   If i < 100000 Then\n        If True Then\n            For j = 1 To 1\n                Select Case 1\n\
                  \x20                   Case 1\n                        Do\n                            GoSub Down\n\
                  \x20                           Exit Do\n                        Loop\n                End Select\n\
                  \x20           Next\n        End If\n    End If\n    Return\nEnd Sub\n";
    for (name, source) in [("one_line.bas", one_line), ("blocks.bas", blocks)] {
        std::fs::write(dir.path().join(name), source).unwrap();
        let run = common::cli::Invocation { dir: Some(dir.path()), ..Default::default() }.run(&["run", "wb.csv", name]);
        assert_eq!(run.code, 1, "{name}: {}", run.stderr);
        assert!(run.stderr.contains("Out of stack space (run-time error 28)"), "{name}: {}", run.stderr);
    }
    // A hundred nested GoSubs with their Returns still run to the end.
    std::fs::write(dir.path().join("hundred.bas"), one_line.replace("100000", "100")).unwrap();
    let run =
        common::cli::Invocation { dir: Some(dir.path()), ..Default::default() }.run(&["run", "wb.csv", "hundred.bas"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    // Debug.Print writes to standard error, as it happens.
    assert_eq!(run.stderr.lines().next().map(str::trim), Some("100"), "{}", run.stderr);
}

// ---------------------------------------------------------------------------------------
// Files: attributes past their types that the xlsx reader's library adds up

/// A one-sheet xlsx with `before_data` ahead of `<sheetData>` and cell A1 in a style of
/// format code `code`.
fn book(dir: &std::path::Path, name: &str, before_data: &str, code: &str) -> std::path::PathBuf {
    use std::io::Write;
    let ns = r#"xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main""#;
    let rels = "http://schemas.openxmlformats.org/officeDocument/2006/relationships";
    let parts = [
        (
            "[Content_Types].xml",
            r#"<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/><Override PartName="/xl/styles.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.styles+xml"/></Types>"#.to_string(),
        ),
        (
            "_rels/.rels",
            format!(r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{rels}/officeDocument" Target="xl/workbook.xml"/></Relationships>"#),
        ),
        (
            "xl/workbook.xml",
            format!(r#"<?xml version="1.0" encoding="UTF-8"?><workbook {ns} xmlns:r="{rels}"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#),
        ),
        (
            "xl/_rels/workbook.xml.rels",
            format!(r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="{rels}/worksheet" Target="worksheets/sheet1.xml"/><Relationship Id="rId2" Type="{rels}/styles" Target="styles.xml"/></Relationships>"#),
        ),
        (
            "xl/worksheets/sheet1.xml",
            format!(r#"<?xml version="1.0" encoding="UTF-8"?><worksheet {ns}>{before_data}<sheetData><row r="1"><c r="A1" s="1"><v>2</v></c><c r="B1"><f>A1*3</f></c></row></sheetData></worksheet>"#),
        ),
        (
            "xl/styles.xml",
            format!(r#"<?xml version="1.0" encoding="UTF-8"?><styleSheet {ns}><numFmts count="1"><numFmt numFmtId="200" formatCode="{code}"/></numFmts><fonts count="1"><font><sz val="11"/></font></fonts><fills count="1"><fill><patternFill patternType="none"/></fill></fills><borders count="1"><border/></borders><cellStyleXfs count="1"><xf numFmtId="0" fontId="0" fillId="0" borderId="0"/></cellStyleXfs><cellXfs count="2"><xf numFmtId="0" fontId="0" fillId="0" borderId="0" xfId="0"/><xf numFmtId="200" fontId="0" fillId="0" borderId="0" xfId="0" applyNumberFormat="1"/></cellXfs></styleSheet>"#),
        ),
    ];
    let file = dir.join(name);
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&file).unwrap());
    for (part, text) in parts {
        zip.start_file(part, zip::write::SimpleFileOptions::default()).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    }
    zip.finish().unwrap();
    file
}

#[test]
fn a_dimension_past_u32_and_a_format_of_300_brackets_read_without_a_panic() {
    // Both overflowed in the xlsx reader's library (a row number summed in a u32, brackets
    // counted in a u8): a panic in a debug build. Neither is read for what it says: the
    // cells are the sheet's, and the code is a text shown as written.
    let dir = tempfile::tempdir().unwrap();
    let wide = book(dir.path(), "dimension.xlsx", r#"<dimension ref="A1:XFD99999999999"/>"#, "0.00");
    let brackets = book(dir.path(), "brackets.xlsx", "", &format!("{}0", "[".repeat(300)));
    for file in [wide, brackets] {
        let wb = ncsheet::io::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        assert_eq!(get(&wb, "B1"), Value::Number(6.0), "{}", file.display());
    }
}

// ---------------------------------------------------------------------------------------
// Runaway: a regression over thousands of variables

#[test]
fn a_fit_past_its_work_limit_is_num_naming_it() {
    // 1,000 observations of 5,000 variables: an SVD of 5·10^9 multiply-adds ran for minutes.
    for formula in
        ["=ROWS(LINEST(SEQUENCE(1000),SEQUENCE(1000,5000)))", "=ROWS(TREND(SEQUENCE(1000),SEQUENCE(1000,5000)))"]
    {
        let (v, notes, _) = common::sheet::eval_a1(formula);
        assert_eq!(v, NUM, "{formula}");
        assert!(notes.iter().any(|n| n.contains("more work than ncsheet's limit")), "{formula}: {notes:?}");
    }
    // y = 2x + 1 over 1,000 points still fits (slope then intercept, as Excel lists them).
    let (v, _, _) = common::sheet::eval_a1("=INDEX(LINEST(2*SEQUENCE(1000)+1,SEQUENCE(1000)),1,1)");
    let Value::Number(slope) = v else { panic!("{v:?}") };
    assert!((slope - 2.0).abs() < 1e-9, "{slope}");
}

// ---------------------------------------------------------------------------------------
// Unclear errors: relationships and attributes that calamine refuses without naming a part

#[test]
fn damaged_relationships_and_entities_in_attributes_name_their_part() {
    let dir = tempfile::tempdir().unwrap();
    let file = book(dir.path(), "spoiled.xlsx", "", "0.00");
    let package = std::fs::read(&file).unwrap();
    let cut = |t: &str| t[..t.len() - 40].to_string();
    type Spoil<'a> = &'a dyn Fn(&str) -> String;
    let probes: [(&str, Spoil, &str); 5] = [
        ("xl/styles.xml", &|t| t.replace(r#"formatCode="0.00""#, r#"formatCode="&nope;""#), "unknown entity &nope;"),
        ("xl/workbook.xml", &|t| t.replace(r#"name="Sheet1""#, r#"name="&zz;""#), "unknown entity &zz;"),
        ("xl/_rels/workbook.xml.rels", &|t| t.replace("worksheets/sheet1.xml", "&q;"), "unknown entity &q;"),
        ("xl/_rels/workbook.xml.rels", &cut, "the XML is not well-formed"),
        ("_rels/.rels", &cut, "the XML is not well-formed"),
    ];
    for (target, spoil, says) in probes {
        let mut change = |part: &str, bytes: Vec<u8>| {
            if part == target {
                spoil(std::str::from_utf8(&bytes).unwrap()).into_bytes()
            } else {
                bytes
            }
        };
        let options = zip::write::SimpleFileOptions::default();
        let spoiled = common::xlsx::rewrite_package(&package, options, &mut change).finish().unwrap().into_inner();
        std::fs::write(&file, spoiled).unwrap();
        let e = ncsheet::io::load(&file).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains(&format!("{target}: ")) && e.contains(says), "{target}: {e}");
    }
}

// ---------------------------------------------------------------------------------------
// Runaway: UNIQUE compared every row with every distinct row before it

#[test]
fn unique_is_not_quadratic_in_its_rows() {
    // A million distinct rows: half a million million comparisons before (100,000 took 27 s).
    let (v, _, _) = common::sheet::eval_a1("=ROWS(UNIQUE(SEQUENCE(1000000)))");
    assert_eq!(v, Value::Number(1e6));
    // Rows equal as `=` finds them: text without regard to case, 1 apart from "1" and TRUE.
    let count = |f: &str| common::sheet::eval_a1(f).0;
    assert_eq!(count(r#"=ROWS(UNIQUE({"a";"A";"É";"é";1;TRUE;"1";1}))"#), Value::Number(5.0));
    assert_eq!(count(r#"=ROWS(UNIQUE({"a";"A";"b"},,TRUE))"#), Value::Number(1.0));
    assert_eq!(count(r#"=COLUMNS(UNIQUE({1,"x",1,"X",2},TRUE))"#), Value::Number(3.0));
}

// ---------------------------------------------------------------------------------------
// Silently wrong: distributions whose parameters pass what their series resolve

#[test]
fn distributions_past_what_their_functions_resolve_are_num_not_noise() {
    // Shapes of 1E+16: the continued fractions stopped unconverged after 10,000 steps, and
    // ln Γ terms of 10^17 cancelled to noise. Each was a number: F.DIST -795023 (a
    // probability), BETA.DIST 1, HYPGEOMDIST 1.5E+111, NEGBINOM.DIST 1,
    // BETA.INV 0.49999979, T.DIST 0.5 (df / (df + 1) rounded to 1).
    for formula in [
        "=F.DIST(1,1E16,1E16,TRUE)",
        "=BETA.DIST(0.5,1E16,1E16,TRUE)",
        "=HYPGEOMDIST(5E15,1E16,1E16,2E16)",
        "=NEGBINOM.DIST(1E16,1E16,0.5,TRUE)",
        "=BETA.INV(0.5,1E16,1E16)",
        "=T.DIST(1,1E16,TRUE)",
    ] {
        assert_eq!(common::sheet::eval_a1(formula).0, NUM, "{formula}");
    }
    // The binomial quantile, two standard deviations off before, is the normal law's there
    // (p = ½: no skew; the next term is of order 1/n): the least k with
    // Φ((k + ½ − np)/σ) ≥ 0.999, σ = √(9E15/4), Φ⁻¹(0.999) = 3.0902323061678135415, worked
    // out to 40 digits apart from this code: np + σ·3.0902… − ½ = 4500000146582588.2979.
    assert_eq!(common::sheet::eval_a1("=CRITBINOM(9E15,0.5,0.999)").0, Value::Number(4500000146582589.0));
    // BINOM.DIST.RANGE, 0 before, reads the same law: P(X ≤ n/2) for n = 2E16 is
    // Φ(½/σ) = ½ + φ(0)·½/σ to 10^-25, σ = √(5E15).
    let half_step = 0.5 / 5e15_f64.sqrt();
    let want = 0.5 + half_step / (2.0 * std::f64::consts::PI).sqrt();
    let Value::Number(got) = common::sheet::eval_a1("=BINOM.DIST.RANGE(2E16,0.5,0,1E16)").0 else { panic!("a number") };
    assert!((got - want).abs() <= 1e-12, "BINOM.DIST.RANGE(2E16,0.5,0,1E16): {got} against {want}");
    // Large but resolved parameters keep their values, against closed forms apart from this
    // code: C(2m, m) / 4^m = (1 - 1/(8m)) / √(πm) for m = 500,000 (Stirling), and the t
    // distribution's expansion Φ(t) - φ(t)(t³ + t) / (4 df) at t = 1, df = 10^6.
    // (To 1e-8: ln Γ(10^6) is 1.3·10^7, so its rounding alone is about 3e-9 of the result.)
    let close = |formula: &str, want: f64| {
        let Value::Number(got) = common::sheet::eval_a1(formula).0 else { panic!("{formula}") };
        assert!((got - want).abs() <= 1e-8 * want, "{formula}: {got} against {want}");
    };
    let m = 500_000.0_f64;
    close("=BINOM.DIST(500000,1000000,0.5,FALSE)", (1.0 - 1.0 / (8.0 * m)) / (std::f64::consts::PI * m).sqrt());
    let (phi, density) = (0.841_344_746_068_542_9, 0.241_970_724_519_143_37);
    close("=T.DIST(1,1000000,TRUE)", phi - density * 2.0 / 4e6);
}

#[test]
fn nper_at_a_rate_near_zero_keeps_its_periods() {
    // As the rate goes to 0, NPER goes to -(pv + fv) / pmt: 1,000 payments of 1 for a loan of
    // 1,000. At 1E-300 the ratio of the balances rounded to 1, and NPER was 0.
    for formula in ["=NPER(1E-300,-1,1000)", "=NPER(1E-17,-1,1000)"] {
        let Value::Number(n) = common::sheet::eval_a1(formula).0 else { panic!("{formula}") };
        assert!((n - 1000.0).abs() < 1e-9, "{formula}: {n}");
    }
}
