//! Hostile input, third round (issue 30): the variants the second round did not name.
//! Each class gives a clear error in its place, bounded in time and memory, never a panic,
//! an abort, a lost edit or a silent wrong value.

use std::io::{Read, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::thread;

use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;

/// What one run of the built binary gave back.
struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

/// `ncsheet ARGS` with nothing on stdin; a run killed by a signal (a crash) fails the test.
fn ncsheet(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the ncsheet binary runs");
    Run {
        code: out.status.code().unwrap_or_else(|| panic!("ncsheet was killed by a signal: {:?}", out.status)),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// An xlsx package with each part passed through `change(name, bytes)`.
fn rewrite_package(package: &[u8], change: &mut dyn FnMut(&str, Vec<u8>) -> Vec<u8>) -> Vec<u8> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(package)).unwrap();
    let mut out = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for i in 0..zip.len() {
        let mut entry = zip.by_index(i).unwrap();
        let name = entry.name().unwrap().to_string();
        let mut data = Vec::new();
        entry.read_to_end(&mut data).unwrap();
        out.start_file(name.as_str(), zip::write::SimpleFileOptions::default()).unwrap();
        out.write_all(&change(&name, data)).unwrap();
    }
    out.finish().unwrap().into_inner()
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

// ---------------------------------------------------------------------------------------
// Crashes: widths past u16

#[test]
fn format_codes_with_more_than_65535_zeros_show_their_number() {
    use ncsheet::eval::format::number_format::shown;
    // 70,000 exponent zeros: the exponent 4 written with 70,000 digits.
    let code = format!("0E+{}", "0".repeat(70_000));
    let text = shown(12345.0, Some(&code));
    assert_eq!(text.len(), "1E+".len() + 70_000);
    assert!(text.starts_with("1E+000") && text.ends_with("04"), "{}", &text[..20]);
    // An elapsed part of 70,000 s letters: 90 seconds as 70,000 digits.
    let code = format!("[{}]", "s".repeat(70_000));
    let text = shown(90.0 / 86_400.0, Some(&code));
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
