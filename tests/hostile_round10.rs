//! Hostile input (issue 30), session 24: variants of the issue's classes in containers,
//! commands and readers the earlier rounds did not reach. What each test expects comes from
//! outside our code: IEEE 754 (the bits of an infinity and a NaN), Excel's rule that a cell
//! holds only finite numbers and no subnormal one (docs/limits.md, "numbers", the rule the
//! issue states for typed numbers), and POSIX's pipes.

mod common;

use std::path::Path;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;
use ncsheet::io::{self, Format};
use ncsheet::workbook::Workbook;

/// The corpus's 53433.xls, whose first NUMBER record (BIFF8 record 0x0203, 14 bytes: row,
/// column, format, then the IEEE 754 double) holds 12.234 in D5.
fn xls_with_d5(value: f64) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/excel-corpus/xls/53433.xls");
    let mut bytes = std::fs::read(&path).unwrap();
    let header = [0x03, 0x02, 0x0E, 0x00];
    let at = bytes.windows(4).position(|w| w == header).expect("a NUMBER record");
    assert_eq!(&bytes[at + 4..at + 8], &[4, 0, 3, 0], "the record is D5's (row 4, column 3, 0-based)");
    assert_eq!(f64::from_le_bytes(bytes[at + 10..at + 18].try_into().unwrap()), 12.234);
    bytes[at + 10..at + 18].copy_from_slice(&value.to_le_bytes());
    bytes
}

#[test]
fn an_xls_number_that_is_infinite_or_nan_is_refused_naming_the_cell() {
    // The cell was written out as 0 and computed on: a value the file never held.
    let good = io::open_bytes(xls_with_d5(12.234), Path::new("hostile.xls"), Format::Xls, None).unwrap();
    let d5 = parse_cell("D5").unwrap();
    assert_eq!(good.workbook.value(0, d5), Value::Number(12.234));
    for (value, shown) in [(f64::INFINITY, "inf"), (f64::NEG_INFINITY, "-inf"), (f64::NAN, "NaN")] {
        let refused = io::open_bytes(xls_with_d5(value), Path::new("hostile.xls"), Format::Xls, None);
        let message = refused.err().unwrap_or_else(|| panic!("{shown} was read")).to_string();
        assert!(message.contains("hostile.xls") && message.contains("cell D5 stores"), "{message}");
        assert!(message.contains(shown), "{message}");
    }
}

/// An OpenDocument spreadsheet (tests/data/ods) whose first `office:value="1"` is `value`.
fn ods_with(value: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ods/defined_names.ods");
    let package = std::fs::read(path).unwrap();
    let options = zip::write::SimpleFileOptions::default();
    let mut change = |name: &str, data: Vec<u8>| {
        if name != "content.xml" {
            return data;
        }
        let text = String::from_utf8(data).unwrap();
        assert!(text.contains(r#"office:value="1""#));
        text.replacen(r#"office:value="1""#, &format!(r#"office:value="{value}""#), 1).into_bytes()
    };
    common::xlsx::rewrite_package(&package, options, &mut change).finish().unwrap().into_inner()
}

#[test]
fn an_ods_number_past_the_largest_double_or_nan_is_refused_naming_the_cell() {
    assert!(io::open_bytes(ods_with("2"), Path::new("hostile.ods"), Format::Ods, None).is_ok());
    for value in ["1e400", "-1E999", "NaN", "inf"] {
        let refused = io::open_bytes(ods_with(value), Path::new("hostile.ods"), Format::Ods, None);
        let message = refused.err().unwrap_or_else(|| panic!("{value} was read")).to_string();
        assert!(message.contains("hostile.ods") && message.contains("stores"), "{value}: {message}");
        assert!(message.contains("no number a cell holds"), "{value}: {message}");
    }
}

#[test]
fn a_stored_subnormal_number_is_zero_as_a_typed_one_is() {
    // `-1E-320<0` is FALSE when typed (Excel keeps no subnormal); a file's `<v>-1e-320</v>`
    // made it TRUE. Written by our writer, then its stored 2 replaced.
    let mut wb = Workbook::with_sheet();
    for (cell, input) in [("A1", "2"), ("B1", "=A1<0"), ("C1", "=A1>0")] {
        wb.set_input(0, parse_cell(cell).unwrap(), input).unwrap();
    }
    let package = ncsheet::io::xlsx::to_bytes(&wb, &ncsheet::io::xlsx::Layout::default()).unwrap();
    let options = zip::write::SimpleFileOptions::default();
    for stored in ["-1e-320", "1E-310", "4.9e-324"] {
        let mut change = |name: &str, data: Vec<u8>| {
            if name != "xl/worksheets/sheet1.xml" {
                return data;
            }
            let text = String::from_utf8(data).unwrap();
            assert!(text.contains("<v>2</v>"), "{text}");
            text.replacen("<v>2</v>", &format!("<v>{stored}</v>"), 1).into_bytes()
        };
        let bytes = common::xlsx::rewrite_package(&package, options, &mut change).finish().unwrap().into_inner();
        let opened = io::open_bytes(bytes, Path::new("tiny.xlsx"), Format::Xlsx, None).unwrap();
        let get = |cell: &str| opened.workbook.value(0, parse_cell(cell).unwrap());
        assert_eq!(get("A1"), Value::Number(0.0), "{stored}");
        assert_eq!((get("B1"), get("C1")), (Value::Bool(false), Value::Bool(false)), "{stored}");
    }
}

/// Runs `script` in bash in a folder holding `two.csv`, with `$NCSHEET` the binary; its
/// exit code and the file `errors.txt` the script may write.
fn in_bash(script: &str) -> (i32, String) {
    let dir = std::env::temp_dir().join(format!("ncsheet-pipe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("two.csv"), "a,b\n1,2\n").unwrap();
    let _ = std::fs::remove_file(dir.join("errors.txt"));
    let status = std::process::Command::new("bash")
        .arg("-c")
        .arg(script)
        .env("NCSHEET", env!("CARGO_BIN_EXE_ncsheet"))
        .current_dir(&dir)
        .status()
        .unwrap();
    (status.code().unwrap_or(-1), std::fs::read_to_string(dir.join("errors.txt")).unwrap_or_default())
}

/// `ncsheet ARGS` with its standard output, and its standard error too when `errors_too`,
/// going to a reader that stops after 10 bytes; the exit code and what the command wrote to
/// standard error otherwise.
fn into_closed_pipe(args: &str, errors_too: bool) -> (i32, String) {
    let redirect = if errors_too { "2>&1" } else { "2>errors.txt" };
    in_bash(&format!("\"$NCSHEET\" {args} {redirect} | head -c 10 >/dev/null; exit ${{PIPESTATUS[0]}}"))
}

#[test]
fn csv_output_to_a_reader_that_stops_ends_quietly_as_the_table_does() {
    // A reader closing the pipe (`| head`) has all it wanted: the table and json formats end
    // with exit code 0 and say nothing. Through the csv writer the broken pipe was an error
    // (exit 1, "cannot write the output"), and with standard error on the same pipe the
    // report of it panicked (exit 101).
    for errors_too in [false, true] {
        let (code, said) = into_closed_pipe("eval two.csv A1:J200000 --format csv", errors_too);
        assert_eq!((code, said.as_str()), (0, ""), "standard error on the pipe: {errors_too}");
    }
    assert_eq!(into_closed_pipe("eval two.csv A1:J200000", true).0, 0);
}

#[test]
fn an_error_reported_to_a_closed_pipe_keeps_its_exit_code() {
    // The reader is gone before the command writes (POSIX: a write to a pipe with no reader
    // fails with EPIPE): the report of a missing file could not be written and panicked
    // (exit 101, as for a crash); the exit code still says what happened.
    let (code, _) = in_bash("(sleep 0.3; \"$NCSHEET\" eval missing.csv) 2>&1 | true; exit ${PIPESTATUS[0]}");
    assert_eq!(code, 1);
}

#[test]
fn an_array_of_a_type_counts_its_records_fields_against_the_item_limit() {
    // docs/limits.md, "macro array items": 10,000,000 by default. 20,000 records of a Type of
    // 1,000 Doubles are 2·10^7 values; the limit saw 20,000 items, and 100,000 such records
    // (10^8 values) aborted at the memory cap.
    let big = format!("Type Big\n{}End Type\n", (0..1000).map(|i| format!("    f{i} As Double\n")).collect::<String>());
    let src = format!("{big}Sub Main()\n    Dim a(1 To 20000) As Big\nEnd Sub\n");
    let Err(refused) = common::vba::run_module(&src) else { panic!("the Dim passes the limit") };
    let message = refused.to_string();
    assert!(message.contains("20000 records of 1000 fields each") && message.contains("10000000"), "{message}");
    // Within the limit (5·10^6 values) the records are there, each field its default.
    let printed = common::vba::printed_after(
        &big,
        "    Dim a(1 To 5000) As Big\n    a(5000).f999 = 2\n    Debug.Print a(5000).f999 + a(1).f999",
    );
    assert_eq!(printed, [" 2 "]);
}

#[test]
fn a_record_of_nested_types_is_refused_before_it_is_made() {
    // docs/limits.md, "macro array items" and "nesting of Types in a record". A Type of two
    // fields of the Type before it, 39 deep, is 2^39 Doubles: `Dim v As T39` aborted at the
    // memory cap while the record was made, where an array of such records was refused.
    let doubling: String =
        (1..40).map(|i| format!("Type T{i}\n    a As T{}\n    b As T{}\nEnd Type\n", i - 1, i - 1)).collect();
    let src = format!("Type T0\n    x As Double\nEnd Type\n{doubling}Sub Main()\n    Dim v As T39\nEnd Sub\n");
    let Err(refused) = common::vba::run_module(&src) else { panic!("a record of 2^39 values was made") };
    let message = refused.to_string();
    assert!(message.contains("a T39 holds 549755813888 values") && message.contains("10000000"), "{message}");
    // A chain of Types each holding the one before overflowed the stack (exit 134) at 20,000;
    // 255 levels are made, 256 refused.
    let chain = |n: usize| -> String {
        let types: String = (1..=n).map(|i| format!("Type T{i}\n    a As T{}\nEnd Type\n", i - 1)).collect();
        format!("Type T0\n    x As Double\nEnd Type\n{types}")
    };
    let deepest = vec!["a"; 255].join(".");
    let printed = common::vba::printed_after(
        &chain(255),
        &format!("    Dim v As T255\n    v.{deepest}.x = 3\n    Debug.Print v.{deepest}.x"),
    );
    assert_eq!(printed, [" 3 "]);
    let src = format!("{}Sub Main()\n    Dim v As T256\nEnd Sub\n", chain(256));
    let Err(refused) = common::vba::run_module(&src) else { panic!("Types nested 256 deep were made") };
    assert!(refused.to_string().contains("a T256 nests Types more than 255 deep"), "{refused}");
}

#[test]
fn many_types_and_a_type_of_many_fields_are_declared_in_linear_time() {
    // Each field's name was compared with every field before it, and each `As T` looked for
    // T among all the Types: 100,000 fields took 25 s and 50,000 Types 10 s, growing with
    // the square of their number (5·10^9 comparisons). A module of both, 200,000 lines, is
    // read now (not timed: a quadratic reading again would be a hang the test run's limit ends).
    let fields: String = (0..100_000).map(|i| format!("    f{i} As Double\n")).collect();
    let types: String = (0..100_000).map(|i| format!("Type T{i}\n    a As Long\nEnd Type\n")).collect();
    let src = format!(
        "Type Wide\n{fields}End Type\n{types}Sub Main()\n    Dim w As Wide, t As T99999\n    w.f99999 = 4\n    \
         t.a = 3\n    Debug.Print w.f99999 * t.a\nEnd Sub\n"
    );
    let out = common::vba::run_module(&src).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.printed, [" 12 "]);
}

#[test]
fn val_of_a_number_past_a_doubles_range_is_overflow() {
    // Microsoft's Val function reference, "Exceptions": OverflowException, error number 6,
    // when InputStr is too large. It was `#NUM!` handed on as a value: written into a cell,
    // or "d cannot hold #NUM! (type mismatch)" at an assignment.
    let mut wb = Workbook::with_sheet();
    let message = common::vba::main_fails(&mut wb, "    Dim d As Double\n    d = Val(\"1e400\")");
    assert!(message.contains("Overflow") && message.contains("run-time error 6"), "{message}");
    let printed = common::vba::run_main(
        &mut wb,
        "    On Error Resume Next\n    Range(\"A1\").Value = Val(\"-1E+999\")\n    Debug.Print Err.Number\n    \
         Debug.Print Val(\"1.5e308\") / 1E+308; Val(\"1e-400\")",
    );
    assert_eq!(printed, [" 6 ", " 1.5  0 "]);
    assert_eq!(wb.value(0, parse_cell("A1").unwrap()), Value::Blank);
}
