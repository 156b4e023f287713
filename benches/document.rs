//! The edit path a user (or a browser) takes: open a generated .xlsx through the library's
//! `Document`, then edit its input cell, as `ncsheet set`, the repl and the workbench do.
//! Beside `ncsheet-bench` (the same workbooks built in memory from formula text), this says
//! what the file and the document add to an edit.
//!
//!     pip install openpyxl
//!     python3 benches/gen_workbooks.py --out /tmp/wb chain-1000000 fan-100000 grid-100000
//!     cargo run --release --bin ncsheet-bench-document -- /tmp/wb/chain-1000000.xlsx …
//!
//! For each file: the open (read, import, full computation) once, then 15 edits of the input
//! and 15 back, each checked against `gen_workbooks.py --spec` (best and median wall time,
//! and in parentheses the best and median of the thread's CPU time; the open's CPU time is
//! the process's, both of the reader's threads).

use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::Instant;

use ncsheet::document::{Document, OpenOptions};
use ncsheet::eval::Value;
use ncsheet::formula::address::parse_cell;

/// What `gen_workbooks.py --spec NAME` prints: last cell, edited cell, new value, the last
/// cell's value before and after the edit.
struct Spec {
    last: String,
    edit: String,
    edit_value: String,
    before: f64,
    after: f64,
}

fn spec_of(name: &str) -> Result<Spec, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/gen_workbooks.py");
    let out = Command::new("python3").arg(&script).args(["--spec", name]).output().map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&out.stdout);
    let f: Vec<&str> = text.split_whitespace().collect();
    let num = |i: usize| f.get(i).and_then(|s| s.parse::<f64>().ok()).ok_or(format!("--spec {name}: {text}"));
    Ok(Spec {
        last: f.first().ok_or("empty spec")?.to_string(),
        edit: f.get(1).ok_or("short spec")?.to_string(),
        edit_value: f.get(2).ok_or("short spec")?.to_string(),
        before: num(3)?,
        after: num(4)?,
    })
}

fn value(doc: &Document, cell: &str) -> f64 {
    match doc.workbook().value(0, parse_cell(cell).expect("cell")) {
        Value::Number(n) => n,
        _ => f64::NAN,
    }
}

fn check(doc: &Document, cell: &str, want: f64, when: &str) -> Result<(), String> {
    let got = value(doc, cell);
    let close = (got - want).abs() <= 1e-9 * want.abs().max(1.0);
    close.then_some(()).ok_or(format!("{cell} {when}: {got}, expected {want}"))
}

fn bench(file: &Path) -> Result<(), String> {
    let name = file.file_stem().and_then(|s| s.to_str()).ok_or("file name")?;
    let spec = spec_of(name)?;
    let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let (t, cpu) = (Instant::now(), cpu_seconds(CLOCK_PROCESS_CPUTIME_ID));
    let mut doc = Document::open(bytes, &OpenOptions::named(file)).map_err(|e| e.to_string())?;
    let open = t.elapsed().as_secs_f64();
    // The reader's two threads: the process's CPU time, what the open costs a busy machine.
    let open_cpu = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu;
    check(&doc, &spec.last, spec.before, "after the open")?;
    let pos = parse_cell(&spec.edit).ok_or("edit cell")?;
    let original = doc.workbook().input(0, pos).unwrap_or_default();
    let (mut times, mut cpu_times) = (Vec::new(), Vec::new());
    for _ in 0..15 {
        for (input, want) in [(spec.edit_value.as_str(), spec.after), (original.as_str(), spec.before)] {
            let (t, cpu) = (Instant::now(), cpu_seconds(CLOCK_THREAD_CPUTIME_ID));
            doc.set(0, pos, input).map_err(|p| p.text)?;
            times.push(t.elapsed().as_secs_f64());
            cpu_times.push(cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu);
            check(&doc, &spec.last, want, "after an edit")?;
        }
    }
    times.sort_by(f64::total_cmp);
    cpu_times.sort_by(f64::total_cmp);
    let ms = |s: &[f64], i: usize| format!("{:.2} ms ({:.2} ms)", s[i] * 1e3, cpu_times[i] * 1e3);
    let median = times.len() / 2;
    println!("| {name} | {open:.2} s ({open_cpu:.2} s) | {} | {} |", ms(&times, 0), ms(&times, median));
    Ok(())
}

use libc::{CLOCK_PROCESS_CPUTIME_ID, CLOCK_THREAD_CPUTIME_ID};

/// This thread's or process's CPU time: the machine is shared with other builds, and when it
/// is busy the CPU time is what the work costs (as `ncsheet-bench` prints it).
fn cpu_seconds(clock: libc::clockid_t) -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec, which `ts` is.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    if rc == 0 {
        ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
    } else {
        0.0
    }
}

fn main() -> ExitCode {
    println!("| workbook | open + compute (CPU) | edit, best (CPU) | edit, median (CPU) |\n|---|---|---|---|");
    for file in std::env::args().skip(1) {
        if let Err(e) = bench(Path::new(&file)) {
            eprintln!("ncsheet-bench-document: {e}");
            return ExitCode::FAILURE;
        }
    }
    ExitCode::SUCCESS
}
