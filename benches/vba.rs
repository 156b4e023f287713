//! ncsheet's macro interpreter benchmark (issue 31): the loops real automation modules run
//! (a bubble sort over a Variant array, Long arithmetic, string building, a column of cells,
//! calls of a small Function), each timed in statements a second. See benches/README.md.
//!
//!     cargo run --release --bin ncsheet-bench-vba -- [--sizes bubble-3000,loops-10000000,...]
//!         [--runs N]
//!
//! Each macro prints what it computed; the bench works the same out in Rust and stops at a
//! wrong value.

#[path = "sizes_and_runs.rs"]
mod sizes_and_runs;

use std::process::ExitCode;
use std::time::Instant;

use ncsheet::formula::Pos;
use ncsheet::workbook::Workbook;

const DEFAULT_SIZES: &[&str] = &["bubble-3000", "loops-10000000", "concat-100000", "cells-100000", "calls-1000000"];

/// The items the bubble sort sorts: a permutation of 1..=3000 for n = 3000 (3001 is prime).
fn bubble_item(i: u64) -> u64 {
    (i * 7919) % 3001
}

struct Case {
    name: String,
    kind: String,
    n: u64,
}

impl Case {
    fn parse(name: &str) -> Result<Case, String> {
        let (kind, n) = name.rsplit_once('-').ok_or_else(|| format!("bad case name {name:?}"))?;
        let n = n.parse().map_err(|_| format!("bad size in {name:?}"))?;
        if !["bubble", "loops", "concat", "cells", "calls", "textcompare"].contains(&kind) {
            return Err(format!("unknown case kind in {name:?} (bubble, loops, concat, cells, calls, textcompare)"));
        }
        Ok(Case { name: name.to_string(), kind: kind.to_string(), n })
    }

    /// The macro's source.
    fn source(&self) -> String {
        let n = self.n;
        match self.kind.as_str() {
            // The real module's shape: a Variant array passed to a Sub that swaps through
            // another Sub (BubbleSort2 of a public sorting module).
            "bubble" => format!(
                "Sub Main()\n    Dim a({n}), i As Long, check As Double\n    For i = 1 To {n}\n        a(i) = (i * 7919) Mod 3001\n    Next i\n    BubbleSort a\n    For i = 1 To {n}\n        check = check + i * a(i)\n    Next i\n    Debug.Print check\nEnd Sub\n\
                 Sub BubbleSort(l())\n    Dim i As Long, j As Long, Flag As Boolean\n    For i = 1 To UBound(l)\n        Flag = False\n        For j = UBound(l) - 1 To i Step -1\n            If l(j) > l(j + 1) Then\n                Call Swap(l, j, j + 1)\n                Flag = True\n            End If\n        Next j\n        If Not Flag Then Exit For\n    Next i\nEnd Sub\n\
                 Sub Swap(l(), ByVal i As Long, ByVal j As Long)\n    Dim t As Variant\n    t = l(i): l(i) = l(j): l(j) = t\nEnd Sub\n"
            ),
            "loops" => format!(
                "Sub Main()\n    Dim i As Long, j As Long, s As Long\n    For i = 1 To 1000\n        For j = 1 To {}\n            s = (s + i * j) Mod 1000003\n        Next j\n    Next i\n    Debug.Print s\nEnd Sub\n",
                n / 1000
            ),
            "concat" => format!(
                "Sub Main()\n    Dim s As String, i As Long\n    For i = 1 To {n}\n        s = s & Chr(65 + i Mod 26)\n    Next i\n    Debug.Print Len(s) & \" \" & Mid(s, {n}, 1)\nEnd Sub\n"
            ),
            "cells" => format!(
                "Sub Main()\n    Dim i As Long, total As Double\n    For i = 1 To {n}\n        total = total + Cells(i, 1).Value\n    Next i\n    Debug.Print total\nEnd Sub\n"
            ),
            // The searches a text-processing module makes with vbTextCompare, 100 times over a
            // text of N characters (s, then "XYZ" at its end), each reading it whole.
            "textcompare" => format!(
                "Sub Main()\n    Dim s As String, a, i As Long, total As Double\n    s = String({n}, \"a\") & \"XYZ\"\n    \
                 For i = 1 To 100\n        total = total + InStr(1, s, \"xyz\", vbTextCompare) + InStrRev(s, \"xyz\", -1, vbTextCompare)\n        \
                 a = Split(s, \"Y\", -1, vbTextCompare)\n        \
                 total = total + UBound(a) + Len(Replace(s, \"z\", \"q\", 1, -1, vbTextCompare))\n    Next i\n    \
                 Debug.Print total\nEnd Sub\n"
            ),
            _ => format!(
                "Function Twice(ByVal x As Long) As Long\n    Twice = x * 2 + 1\nEnd Function\n\
                 Sub Main()\n    Dim i As Long, total As Double\n    For i = 1 To {n}\n        total = total + Twice(i) Mod 7\n    Next i\n    Debug.Print total\nEnd Sub\n"
            ),
        }
    }

    /// What the macro must print, worked out here.
    fn expected(&self) -> String {
        let n = self.n;
        match self.kind.as_str() {
            "bubble" => {
                let mut items: Vec<u64> = (1..=n).map(bubble_item).collect();
                items.sort();
                let check: u64 = items.iter().enumerate().map(|(k, v)| (k as u64 + 1) * v).sum();
                check.to_string()
            }
            "loops" => {
                let mut s = 0u64;
                for i in 1..=1000 {
                    for j in 1..=n / 1000 {
                        s = (s + i * j) % 1_000_003;
                    }
                }
                s.to_string()
            }
            "concat" => format!("{n} {}", (b'A' + (n % 26) as u8) as char),
            "cells" => (n * (n + 1) / 2).to_string(),
            // InStr and InStrRev find "XYZ" at N + 1, Split gives two items (UBound 1), Replace
            // keeps the length N + 3.
            "textcompare" => (100 * ((n + 1) + (n + 1) + 1 + (n + 3))).to_string(),
            _ => (1..=n).map(|i| (2 * i + 1) % 7).sum::<u64>().to_string(),
        }
    }

    /// The workbook the macro runs on: column A holds 1..=n for `cells`.
    fn workbook(&self) -> Result<Workbook, String> {
        let mut wb = Workbook::with_sheet();
        if self.kind == "cells" {
            for i in 0..self.n as u32 {
                wb.set_input_deferred(0, Pos::new(i, 0), &(i + 1).to_string()).map_err(|e| e.to_string())?;
            }
            wb.recalculate();
        }
        Ok(wb)
    }
}

/// One timed run: the seconds and the statements the interpreter counted.
fn run_once(case: &Case) -> Result<(f64, u64), String> {
    let mut wb = case.workbook()?;
    let options = ncsheet::vba::RunOptions { max_statements: u64::MAX, ..ncsheet::vba::RunOptions::default() };
    let source = case.source();
    let start = Instant::now();
    let out = ncsheet::vba::run(&mut wb, &source, "bench.bas", &options).map_err(|e| format!("{}: {e}", case.name))?;
    let seconds = start.elapsed().as_secs_f64();
    let printed = out.printed.join("\n");
    let expected = case.expected();
    if printed.trim() != expected {
        return Err(format!("{}: the macro printed {printed:?}, expected {expected:?}", case.name));
    }
    Ok((seconds, out.statements))
}

fn main() -> ExitCode {
    sizes_and_runs::exit("ncsheet-bench-vba", run())
}

fn run() -> Result<(), String> {
    let args = sizes_and_runs::parse_args(DEFAULT_SIZES)?;
    let cases: Vec<Case> = args.sizes.iter().map(|s| Case::parse(s)).collect::<Result<_, _>>()?;
    println!("| case | statements | best of {} | statements/s |", args.runs);
    println!("|---|---|---|---|");
    for case in &cases {
        let mut best = (f64::MAX, 0);
        for _ in 0..args.runs {
            let (seconds, statements) = run_once(case)?;
            if seconds < best.0 {
                best = (seconds, statements);
            }
        }
        let (seconds, statements) = best;
        println!("| {} | {statements} | {seconds:.3} s | {:.2} M |", case.name, statements as f64 / seconds / 1e6);
    }
    Ok(())
}
