//! xlsx import and export benchmark (binary `ncsheet-bench-xlsx`): grid-100000.xlsx as
//! `benches/gen_workbooks.py` writes it (openpyxl, formulas only, no cached values).
//!
//!     pip install openpyxl
//!     python3 benches/gen_workbooks.py --out /tmp/wb grid-100000
//!     cargo run --release --bin ncsheet-bench-xlsx -- /tmp/wb/grid-100000.xlsx
//!
//! Each figure runs in a child process of its own, so that its peak memory (VmHWM) is its own:
//! - `calamine`: calamine's bare read of every sheet's values and formulas;
//! - `load`: ncsheet's import and full recalculation (the last cell is checked against the
//!   script's `--spec`);
//! - `export`: ncsheet's xlsx export of the computed workbook (formulas with cached results);
//! - `writer`: rust_xlsxwriter alone writing the same cells (formula and result), the floor
//!   for an export.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use calamine::{open_workbook_auto, Reader};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;

const STEPS: [&str; 4] = ["calamine", "load", "export", "writer"];
/// K100000 of grid-100000, from `gen_workbooks.py --spec grid-100000`.
const EXPECTED_K100000: f64 = 100089.708058369;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.as_slice() {
        [step, file] if STEPS.contains(&step.as_str()) => child(step, Path::new(file)),
        [file] => parent(Path::new(file)),
        _ => Err("usage: ncsheet-bench-xlsx GRID.xlsx".to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ncsheet-bench-xlsx: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs each step three times in a child process and prints the best time and its memory.
fn parent(file: &Path) -> Result<(), String> {
    let me = std::env::current_exe().map_err(|e| e.to_string())?;
    println!("| step | best of 3 | peak memory |\n|---|---|---|");
    for step in STEPS {
        let mut best: Option<(f64, u64)> = None;
        for _ in 0..3 {
            let out = Command::new(&me).arg(step).arg(file).output().map_err(|e| e.to_string())?;
            if !out.status.success() {
                return Err(format!("{step}: {}", String::from_utf8_lossy(&out.stderr)));
            }
            let text = String::from_utf8_lossy(&out.stdout);
            let mut fields = text.split_whitespace();
            let seconds: f64 = fields.next().and_then(|s| s.parse().ok()).ok_or("no time")?;
            let kib: u64 = fields.next().and_then(|s| s.parse().ok()).ok_or("no memory")?;
            if best.is_none_or(|(b, _)| seconds < b) {
                best = Some((seconds, kib));
            }
        }
        let (seconds, kib) = best.expect("three runs");
        println!("| {step} | {seconds:.3} s | {} MiB |", kib / 1024);
    }
    Ok(())
}

/// One step: prints its time in seconds and the process's peak resident memory in KiB.
fn child(step: &str, file: &Path) -> Result<(), String> {
    let start = Instant::now();
    match step {
        "calamine" => calamine_read(file)?,
        "load" => {
            let wb = ncsheet::io::xlsx::load(file).map_err(|e| e.to_string())?.workbook;
            check(&wb)?;
        }
        "export" => {
            let wb = ncsheet::io::xlsx::load(file).map_err(|e| e.to_string())?.workbook;
            let out = temp_path("export");
            let start = Instant::now();
            ncsheet::io::xlsx::save(&wb, &out).map_err(|e| e.to_string())?;
            let elapsed = start.elapsed().as_secs_f64();
            let _ = std::fs::remove_file(&out);
            println!("{elapsed} {}", peak_kib());
            return Ok(());
        }
        "writer" => {
            let wb = ncsheet::io::xlsx::load(file).map_err(|e| e.to_string())?.workbook;
            let start = Instant::now();
            bare_write(&wb)?;
            println!("{} {}", start.elapsed().as_secs_f64(), peak_kib());
            return Ok(());
        }
        _ => unreachable!("step names are checked"),
    }
    println!("{} {}", start.elapsed().as_secs_f64(), peak_kib());
    Ok(())
}

fn calamine_read(file: &Path) -> Result<(), String> {
    let mut book = open_workbook_auto(file).map_err(|e| e.to_string())?;
    for name in book.sheet_names() {
        let values = book.worksheet_range(&name).map_err(|e| e.to_string())?;
        let formulas = book.worksheet_formula(&name).map_err(|e| e.to_string())?;
        std::hint::black_box((values.get_size(), formulas.get_size()));
    }
    Ok(())
}

fn check(wb: &ncsheet::workbook::Workbook) -> Result<(), String> {
    match wb.value(0, parse_cell("K100000").ok_or("cell")?) {
        Value::Number(n) if (n - EXPECTED_K100000).abs() <= 1e-9 * EXPECTED_K100000 => Ok(()),
        other => Err(format!("K100000 is {other:?}, gen_workbooks.py --spec says {EXPECTED_K100000}")),
    }
}

/// rust_xlsxwriter writing every cell of sheet 1 as ncsheet's export does: constants as
/// numbers, formulas with their results.
fn bare_write(wb: &ncsheet::workbook::Workbook) -> Result<(), String> {
    let mut book = rust_xlsxwriter::Workbook::new();
    let sheet = book.add_worksheet();
    for (pos, value) in wb.values(0) {
        let (row, col) = (pos.row, pos.col as u16);
        let number = match value {
            Value::Number(n) => n,
            _ => 0.0,
        };
        let written = match wb.formula(0, pos) {
            Some(f) => sheet.write_formula(row, col, rust_xlsxwriter::Formula::new(f).set_result(number.to_string())),
            None => sheet.write_number(row, col, number),
        };
        written.map_err(|e| e.to_string())?;
    }
    let out = temp_path("writer");
    book.save(&out).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_file(&out);
    Ok(())
}

fn temp_path(what: &str) -> PathBuf {
    std::env::temp_dir().join(format!("ncsheet-bench-{what}-{}.xlsx", std::process::id()))
}

fn peak_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}
