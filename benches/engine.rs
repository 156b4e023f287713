//! ncsheet's engine benchmark: builds the workbooks of `shared/bench/gen_workbooks.py` in
//! memory from formula text, computes them, edits one input and checks the results against
//! the script's expectations. See benches/README.md.
//!
//!     cargo run --release --bin ncsheet-bench -- [--sizes grid-100000,chain-1000000,...]
//!         [--runs N] [--builds N] [--spec PATH | --no-spec]
//!
//! Each workbook is measured in a child process of its own so that its memory figures are
//! not mixed with another's.

use std::fmt::Write as _;
use std::process::{Command, ExitCode};
use std::time::{Duration, Instant};

use ncsheet::eval::Value;
use ncsheet::formula::Pos;
use ncsheet::workbook::Workbook;

const DEFAULT_SIZES: &[&str] = &["chain-100000", "chain-1000000", "grid-100000", "fan-100000"];
const DEFAULT_SPEC: &str = "/work/shared/bench/gen_workbooks.py";

/// The formulas of each grid row, column B to K, as in gen_workbooks.py (`{r}` = row number).
const GRID: [&str; 10] = [
    "SIN(A{r}*PI()/180)+COS(A{r})",
    "B{r}*2+SQRT(ABS(A{r}))",
    "IF(C{r}>1,C{r}-1,C{r}+1)",
    "ATAN2(A{r}+1,B{r}+2)",
    "POWER(C{r},2)+D{r}",
    "ROUND(E{r},3)",
    "MAX(B{r}:G{r})",
    "SUM(B{r}:H{r})",
    "DEGREES(ATAN(I{r}/1000))",
    "J{r}+A{r}",
];

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Chain,
    Grid,
    Fan,
}

struct Bench {
    name: String,
    kind: Kind,
    n: u32,
}

impl Bench {
    fn parse(name: &str) -> Result<Bench, String> {
        let (kind, n) = name.split_once('-').ok_or_else(|| format!("bad workbook name {name:?}"))?;
        let kind = match kind {
            "chain" => Kind::Chain,
            "grid" => Kind::Grid,
            "fan" => Kind::Fan,
            _ => return Err(format!("unknown workbook kind in {name:?} (chain, grid, fan)")),
        };
        let n: u32 = n.parse().map_err(|_| format!("bad size in {name:?}"))?;
        if !(2..=1_000_000).contains(&n) {
            return Err(format!("size of {name:?} must be 2 to 1000000"));
        }
        Ok(Bench { name: name.to_string(), kind, n })
    }

    /// Writes every cell of the workbook with `set_input_deferred`; returns the formula count.
    fn build(&self, wb: &mut Workbook) -> usize {
        let mut text = String::with_capacity(64);
        let mut formulas = 0;
        let put = |wb: &mut Workbook, row: u32, col: u32, text: &str| {
            wb.set_input_deferred(0, Pos::new(row - 1, col), text).expect("benchmark formula parses");
        };
        for r in 1..=self.n {
            match self.kind {
                Kind::Chain => {
                    text.clear();
                    if r == 1 {
                        text.push('1');
                    } else {
                        let _ = write!(text, "=A{}+1", r - 1);
                        formulas += 1;
                    }
                    put(wb, r, 0, &text);
                }
                Kind::Grid => {
                    text.clear();
                    let _ = write!(text, "{r}");
                    put(wb, r, 0, &text);
                    for (i, f) in GRID.iter().enumerate() {
                        text.clear();
                        text.push('=');
                        push_row_formula(&mut text, f, r);
                        put(wb, r, i as u32 + 1, &text);
                    }
                    formulas += GRID.len();
                }
                Kind::Fan => {
                    if r == 1 {
                        put(wb, 1, 0, "1");
                    }
                    text.clear();
                    let _ = write!(text, "=$A$1*{r}+SIN($A$1)");
                    put(wb, r, 1, &text);
                    formulas += 1;
                }
            }
        }
        formulas
    }

    /// What gen_workbooks.py --spec prints: last cell, edited cell, new value, the last
    /// cell's value before and after the edit.
    fn spec(&self) -> Spec {
        let n = self.n;
        match self.kind {
            Kind::Chain => Spec {
                last: Pos::new(n - 1, 0),
                edit: Pos::new(0, 0),
                edit_value: 2.0,
                expect: n as f64,
                expect_after: n as f64 + 1.0,
            },
            Kind::Grid => Spec {
                last: Pos::new(n - 1, 10),
                edit: Pos::new(n - 1, 0),
                edit_value: n as f64 + 1.0,
                expect: grid_row(n as f64),
                expect_after: grid_row(n as f64 + 1.0),
            },
            Kind::Fan => Spec {
                last: Pos::new(n - 1, 1),
                edit: Pos::new(0, 0),
                edit_value: 2.0,
                expect: n as f64 + 1f64.sin(),
                expect_after: 2.0 * n as f64 + 2f64.sin(),
            },
        }
    }

    /// The input value the edit toggles back to.
    fn original_value(&self) -> f64 {
        match self.kind {
            Kind::Grid => self.n as f64,
            Kind::Chain | Kind::Fan => 1.0,
        }
    }
}

fn push_row_formula(out: &mut String, template: &str, r: u32) {
    let mut parts = template.split("{r}");
    out.push_str(parts.next().unwrap_or(""));
    for p in parts {
        let _ = write!(out, "{r}");
        out.push_str(p);
    }
}

struct Spec {
    last: Pos,
    edit: Pos,
    edit_value: f64,
    expect: f64,
    expect_after: f64,
}

/// Column K of a grid row with input `a`, as gen_workbooks.py computes it.
fn grid_row(a: f64) -> f64 {
    let b = (a * std::f64::consts::PI / 180.0).sin() + a.cos();
    let c = b * 2.0 + a.abs().sqrt();
    let d = if c > 1.0 { c - 1.0 } else { c + 1.0 };
    let e = (b + 2.0).atan2(a + 1.0);
    let f = c.powi(2) + d;
    let g = ((e.abs() * 1000.0 + 0.5).floor() / 1000.0).copysign(e);
    let h = [b, c, d, e, f, g].into_iter().fold(f64::MIN, f64::max);
    let i = b + c + d + e + f + g + h;
    let j = (i / 1000.0).atan().to_degrees();
    j + a
}

fn close(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want.abs().max(1.0)
}

/// Checks our expectations against the script's `--spec` output, when the script runs.
fn cross_check_spec(script: &str, bench: &Bench) -> Result<(), String> {
    let out = match Command::new("python3").arg(script).arg("--spec").arg(&bench.name).output() {
        Ok(o) if o.status.success() => o,
        _ => {
            eprintln!("note: could not run python3 {script}; using the built-in port of its expectations");
            return Ok(());
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    let fields: Vec<&str> = text.split_whitespace().collect();
    let spec = bench.spec();
    let num = |i: usize| fields.get(i).and_then(|s| s.parse::<f64>().ok());
    let ok = fields.len() == 5
        && fields[0] == spec.last.to_string()
        && fields[1] == spec.edit.to_string()
        && num(2) == Some(spec.edit_value)
        && num(3).is_some_and(|v| close(v, spec.expect, 1e-13))
        && num(4).is_some_and(|v| close(v, spec.expect_after, 1e-13));
    if ok {
        Ok(())
    } else {
        Err(format!(
            "{}: gen_workbooks.py --spec says {:?}, the bench expects {} {} {} {} {}",
            bench.name,
            text.trim(),
            spec.last,
            spec.edit,
            spec.edit_value,
            spec.expect,
            spec.expect_after
        ))
    }
}

fn check(wb: &Workbook, pos: Pos, want: f64, what: &str) -> Result<(), String> {
    match wb.value(0, pos) {
        Value::Number(v) if close(v, want, 1e-9) => Ok(()),
        v => Err(format!("{what}: {pos} = {v:?}, expected {want}")),
    }
}

/// `VmRSS` or `VmHWM` of this process in bytes.
fn proc_status(field: &str) -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix(field)?.strip_prefix(':')?.trim().strip_suffix("kB")?.trim().parse::<u64>().ok())
        .map_or(0, |kb| kb * 1024)
}

/// One workbook's figures (seconds and bytes), as the child prints them for the parent.
#[derive(Default, Debug)]
struct Figures {
    formulas: usize,
    distinct: usize,
    build: f64,
    compute: f64,
    total: f64,
    edit_best: f64,
    edit_median: f64,
    rss_bytes: u64,
    hwm_bytes: u64,
}

impl Figures {
    fn to_line(&self) -> String {
        format!(
            "FIGURES {} {} {} {} {} {} {} {} {}",
            self.formulas,
            self.distinct,
            self.build,
            self.compute,
            self.total,
            self.edit_best,
            self.edit_median,
            self.rss_bytes,
            self.hwm_bytes
        )
    }

    fn from_line(line: &str) -> Option<Figures> {
        let f: Vec<&str> = line.strip_prefix("FIGURES ")?.split(' ').collect();
        let x = |i: usize| f.get(i)?.parse::<f64>().ok();
        let u = |i: usize| f.get(i)?.parse::<u64>().ok();
        Some(Figures {
            formulas: u(0)? as usize,
            distinct: u(1)? as usize,
            build: x(2)?,
            compute: x(3)?,
            total: x(4)?,
            edit_best: x(5)?,
            edit_median: x(6)?,
            rss_bytes: u(7)?,
            hwm_bytes: u(8)?,
        })
    }
}

/// Measures one workbook in this process.
fn run_child(bench: &Bench, runs: usize, builds: usize) -> Result<Figures, String> {
    let spec = bench.spec();
    let mut fig = Figures { total: f64::MAX, build: f64::MAX, compute: f64::MAX, ..Figures::default() };
    let mut kept = None;
    for i in 0..builds.max(1) {
        // Drop the previous copy first, so the memory figures are those of one workbook.
        drop(kept.take());
        let rss0 = proc_status("VmRSS");
        let hwm0 = proc_status("VmHWM");
        let t0 = Instant::now();
        let mut wb = Workbook::with_sheet();
        let formulas = bench.build(&mut wb);
        let t1 = Instant::now();
        wb.recalculate();
        let t2 = Instant::now();
        if i == 0 {
            fig.rss_bytes = proc_status("VmRSS").saturating_sub(rss0);
            fig.hwm_bytes = proc_status("VmHWM").saturating_sub(hwm0);
            let (cells, distinct) = wb.formula_counts();
            if cells != formulas {
                return Err(format!("{}: {cells} formula cells, expected {formulas}", bench.name));
            }
            fig.formulas = formulas;
            fig.distinct = distinct;
        }
        fig.build = fig.build.min((t1 - t0).as_secs_f64());
        fig.compute = fig.compute.min((t2 - t1).as_secs_f64());
        fig.total = fig.total.min((t2 - t0).as_secs_f64());
        check(&wb, spec.last, spec.expect, &format!("{} after the full computation", bench.name))?;
        kept = Some(wb);
    }
    let mut wb = kept.expect("built once");
    let mut times = Vec::with_capacity(runs);
    let edit_text = format!("{}", spec.edit_value);
    let back_text = format!("{}", bench.original_value());
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        wb.set_input(0, spec.edit, &edit_text).map_err(|e| e.to_string())?;
        times.push(t.elapsed());
        check(&wb, spec.last, spec.expect_after, &format!("{} after the edit", bench.name))?;
        // Back to the original input (timed as well: it is the same amount of work).
        let t = Instant::now();
        wb.set_input(0, spec.edit, &back_text).map_err(|e| e.to_string())?;
        times.push(t.elapsed());
        check(&wb, spec.last, spec.expect, &format!("{} after undoing the edit", bench.name))?;
    }
    times.sort();
    fig.edit_best = times[0].as_secs_f64();
    fig.edit_median = times[times.len() / 2].as_secs_f64();
    Ok(fig)
}

fn seconds(s: f64) -> String {
    let d = Duration::from_secs_f64(s);
    if d >= Duration::from_secs(1) {
        format!("{:.2} s", s)
    } else if d >= Duration::from_millis(1) {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

/// The targets: (workbook, build+compute, one edit).
fn target(name: &str) -> (Option<f64>, Option<f64>) {
    match name {
        "grid-100000" => (Some(0.4), Some(50e-6)),
        "chain-1000000" => (None, Some(40e-3)),
        "fan-100000" => (None, Some(8e-3)),
        _ => (None, None),
    }
}

const BYTES_PER_FORMULA_TARGET: f64 = 100.0;

struct Args {
    sizes: Vec<String>,
    runs: usize,
    builds: usize,
    spec: Option<String>,
    child: Option<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args { sizes: Vec::new(), runs: 15, builds: 3, spec: Some(DEFAULT_SPEC.to_string()), child: None };
    let mut it = std::env::args().skip(1).peekable();
    while let Some(a) = it.next() {
        let mut value = |what: &str| it.next().ok_or_else(|| format!("{what} needs a value"));
        match a.as_str() {
            "--sizes" => {
                args.sizes.extend(value("--sizes")?.split(',').filter(|s| !s.is_empty()).map(str::to_string));
                while let Some(more) = it.next_if(|s| !s.starts_with("--")) {
                    args.sizes.extend(more.split(',').filter(|s| !s.is_empty()).map(str::to_string));
                }
            }
            "--runs" => args.runs = value("--runs")?.parse().map_err(|_| "--runs takes a number")?,
            "--builds" => args.builds = value("--builds")?.parse().map_err(|_| "--builds takes a number")?,
            "--spec" => args.spec = Some(value("--spec")?),
            "--no-spec" => args.spec = None,
            "--child" => args.child = Some(value("--child")?),
            "-h" | "--help" => {
                println!(
                    "ncsheet-bench [--sizes NAME,...] [--runs N] [--builds N] [--spec gen_workbooks.py | --no-spec]\n\
                     NAME = chain-N | grid-N | fan-N (default: {})",
                    DEFAULT_SIZES.join(",")
                );
                std::process::exit(0);
            }
            other => return Err(format!("unknown argument {other:?} (try --help)")),
        }
    }
    if args.sizes.is_empty() {
        args.sizes = DEFAULT_SIZES.iter().map(|s| s.to_string()).collect();
    }
    Ok(args)
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("ncsheet-bench: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    if let Some(name) = &args.child {
        let fig = run_child(&Bench::parse(name)?, args.runs, args.builds)?;
        println!("{}", fig.to_line());
        return Ok(());
    }
    let benches = args.sizes.iter().map(|s| Bench::parse(s)).collect::<Result<Vec<_>, _>>()?;
    if let Some(script) = &args.spec {
        if std::path::Path::new(script).exists() {
            for b in &benches {
                cross_check_spec(script, b)?;
            }
            println!("expectations agree with {script} --spec");
        }
    }
    println!(
        "{} build(s) per workbook, best kept; {} edits (and as many undos) per workbook",
        args.builds,
        args.runs * 2
    );
    println!(
        "{:<14} {:>9} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9} {:>9}",
        "workbook", "formulas", "parsed", "build", "compute", "total", "edit best", "edit med", "B/formula", "peak MiB"
    );
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut failures = Vec::new();
    for b in &benches {
        let out = Command::new(&exe)
            .args(["--child", &b.name, "--runs", &args.runs.to_string(), "--builds", &args.builds.to_string()])
            .output()
            .map_err(|e| e.to_string())?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        let Some(fig) = stdout.lines().find_map(Figures::from_line).filter(|_| out.status.success()) else {
            return Err(format!("{} failed: {}", b.name, String::from_utf8_lossy(&out.stderr).trim()));
        };
        let per_formula = fig.rss_bytes as f64 / fig.formulas as f64;
        println!(
            "{:<14} {:>9} {:>8} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9.0} {:>9.0}",
            b.name,
            fig.formulas,
            fig.distinct,
            seconds(fig.build),
            seconds(fig.compute),
            seconds(fig.total),
            seconds(fig.edit_best),
            seconds(fig.edit_median),
            per_formula,
            fig.hwm_bytes as f64 / (1 << 20) as f64,
        );
        let (total_target, edit_target) = target(&b.name);
        if let Some(t) = total_target.filter(|&t| fig.total > t) {
            failures.push(format!("{}: build+compute {} > target {}", b.name, seconds(fig.total), seconds(t)));
        }
        if let Some(t) = edit_target.filter(|&t| fig.edit_best > t) {
            failures.push(format!("{}: edit {} > target {}", b.name, seconds(fig.edit_best), seconds(t)));
        }
        if b.kind == Kind::Grid && per_formula > BYTES_PER_FORMULA_TARGET {
            failures.push(format!("{}: {per_formula:.0} bytes per formula > target 100", b.name));
        }
    }
    println!("all results checked against gen_workbooks.py's expectations");
    if failures.is_empty() {
        println!("every target met");
    } else {
        for f in failures {
            println!("target missed: {f}");
        }
    }
    Ok(())
}
