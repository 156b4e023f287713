//! Hostile input (issue 30), the fourth round's findings (session 16): each test is a class
//! the round reached, with sizes the old code would take far too long over (untimed).

mod common;

use ncsheet::eval::{Value, XlError};
use ncsheet::formula::address::Pos;
use ncsheet::workbook::{ProblemKind, Workbook};

/// A formula copied down 20,000 rows that does not parse (its `SUM(` is never closed after
/// 400 references): every copy was parsed again, where a formula that parses is parsed once
/// for all its copies; a shared formula of a few KB over 100,000 cells of an xlsx took
/// minutes. Each copy is refused once per text shape now, every cell still with its own
/// problem and the caret at its own text's place (the end, where the `)` is missing).
#[test]
fn copies_of_a_formula_that_does_not_parse_are_each_refused_at_their_own_place() {
    let rows = 20_000;
    let mut csv = String::new();
    for r in 1..=rows {
        csv.push_str(&format!("\"=SUM(B{r}{}\"\n", format!(",B{r}").repeat(400)));
    }
    let wb = ncsheet::io::csv::read(csv.as_bytes()).unwrap();
    let problems = wb.problems();
    assert_eq!(problems.len(), rows);
    for p in &problems {
        let row = p.pos.row + 1;
        let typed = format!("=SUM(B{row}{}", format!(",B{row}").repeat(400));
        assert_eq!(p.text, typed);
        // The parser stops at the end of each copy's own text, whatever the row's digits,
        // which the message shows at the `(` that is never closed.
        assert!(matches!(&p.kind, ProblemKind::Parse(_)), "{:?}", p.kind);
        assert_eq!(p.span.unwrap().start as usize, typed.len(), "row {row}");
        assert!(p.render().contains("^ column 5: this ( is never closed"), "row {row}: {}", p.render());
    }
}

/// The same at a place past the references, so that it moves with their lengths: `+)` after
/// 300 references to its own row is "expected a value" at the `)`, the last byte of each
/// copy's own text (rows 9 and 10 share the key, their texts differ in length).
#[test]
fn a_copied_parse_error_after_references_points_into_each_copy() {
    let mut csv = String::new();
    for r in 1..=120 {
        csv.push_str(&format!("\"={}+)\"\n", vec![format!("C{r}"); 300].join("+")));
    }
    let wb = ncsheet::io::csv::read(csv.as_bytes()).unwrap();
    let problems = wb.problems();
    assert_eq!(problems.len(), 120);
    for p in problems {
        assert!(matches!(&p.kind, ProblemKind::Parse(m) if m.contains("expected")), "{:?}", p.kind);
        assert_eq!(p.span.unwrap().start as usize, p.text.len() - 1, "{}", p.text);
    }
}

/// The items MAP, SCAN, BYROW, BYCOL and MAKEARRAY make from their LAMBDA's results count
/// against the 256 MiB (2^28 bytes) every array's texts may hold, as the items of operators
/// and lifted functions do: `MAP(SEQUENCE(200000),LAMBDA(x,REPT("q",32767)))` asked for
/// 6.5 GB and aborted. 8,192 texts of 32,767 characters are 268,427,264 bytes, within the
/// limit; 8,193 are 268,460,031, past 268,435,456.
#[test]
fn texts_a_lambda_helper_makes_count_against_the_array_text_limit() {
    let rept = "REPT(\"q\",32767)";
    let cases = [
        (format!("=ROWS(MAP(SEQUENCE(8192),LAMBDA(x,{rept})))"), Value::Number(8192.0)),
        (format!("=ROWS(MAP(SEQUENCE(8193),LAMBDA(x,{rept})))"), Value::Error(XlError::Num)),
        (format!("=ROWS(SCAN(\"\",SEQUENCE(8193),LAMBDA(a,x,{rept})))"), Value::Error(XlError::Num)),
        (format!("=ROWS(BYROW(SEQUENCE(8193),LAMBDA(x,{rept})))"), Value::Error(XlError::Num)),
        (format!("=COLUMNS(BYCOL(SEQUENCE(1,8193),LAMBDA(x,{rept})))"), Value::Error(XlError::Num)),
        (format!("=ROWS(MAKEARRAY(8193,1,LAMBDA(r,c,{rept})))"), Value::Error(XlError::Num)),
        (format!("=ROWS(MAKEARRAY(8192,1,LAMBDA(r,c,{rept})))"), Value::Number(8192.0)),
    ];
    for (formula, want) in cases {
        let mut wb = Workbook::with_sheet();
        wb.set_input_deferred(0, Pos::new(0, 0), &formula).unwrap();
        wb.recalculate();
        assert_eq!(wb.value(0, Pos::new(0, 0)), want, "{formula}");
        if want == Value::Error(XlError::Num) {
            let notes: Vec<String> = wb.problems().iter().map(|p| p.message()).collect();
            assert!(notes.iter().any(|m| m.contains("texts hold more than 256 MiB")), "{formula}: {notes:?}");
        }
    }
}

/// A macro writing 200,000 files into its --out-dir looked for each name among all the files
/// written before it (past 30 s); names are found by a map now. Two files whose names differ
/// only in case are one (Windows' names, as VBA's), also after a `Kill` of an earlier one.
#[test]
fn a_macro_writing_many_files_finds_each_by_its_name() {
    use ncsheet::vba::{self, FileAccess, RunOptions};
    use std::rc::Rc;
    let files = FileAccess {
        out_dir: Some("out".into()),
        inputs: Vec::new(),
        read_out_dir: Rc::new(|_| Ok(None)),
        list_out_dir: Rc::new(|| Ok(Vec::new())),
        modified_out_dir: Rc::new(|_| Ok(None)),
    };
    let options = RunOptions { files: Some(files), ..RunOptions::default() };
    let src =
        "Sub Main()\nFor i = 1 To 200000\nOpen \"f\" & i & \".txt\" For Output As #1\nPrint #1, i\nClose #1\nNext\n\
               Kill \"f1.txt\"\nOpen \"F7.TXT\" For Append As #1\nPrint #1, \"more\"\nClose #1\nEnd Sub\n";
    let out = vba::run(&mut Workbook::with_sheet(), src, "Module1.bas", &options).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.files.len(), 199_999);
    let seventh = out.files.iter().find(|(n, _)| n == "f7.txt").expect("f7.txt");
    assert_eq!(String::from_utf8_lossy(&seventh.1), " 7 \r\nmore\r\n");
    let last = out.files.last().unwrap();
    assert_eq!((last.0.as_str(), String::from_utf8_lossy(&last.1).as_ref()), ("f200000.txt", " 200000 \r\n"));
}

/// A macro that stops after writing 1,000 files says so naming the first ten and counting
/// the rest, where the note named every one (200,000 names made one line of 2.5 MB).
#[test]
fn the_note_of_files_not_written_names_the_first_ten() {
    let dir = tempfile::tempdir().unwrap();
    let book = dir.path().join("book.csv");
    let bas = dir.path().join("macro.bas");
    std::fs::write(&book, "1\n").unwrap();
    std::fs::write(
        &bas,
        "Sub Main()\nFor i = 1 To 1000\nOpen \"f\" & i & \".txt\" For Output As #1\nClose #1\nNext\nErr.Raise 5\nEnd Sub\n",
    )
    .unwrap();
    std::fs::create_dir(dir.path().join("out")).unwrap();
    let out = dir.path().join("out");
    let r = common::cli::ncsheet(&[
        "run",
        book.to_str().unwrap(),
        bas.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(r.code, 1, "{}", r.stderr);
    let names: Vec<String> = (1..=10).map(|i| format!("f{i}.txt")).collect();
    let note = format!("so its files were not written: {} and 990 more\n", names.join(", "));
    assert!(r.stderr.contains(&note), "{}", r.stderr);
    assert!(std::fs::read_dir(&out).unwrap().next().is_none());
}
