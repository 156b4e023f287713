//! ncsheet's engine benchmark: builds the workbooks of `benches/gen_workbooks.py` in
//! memory from formula text, computes them, edits one input and checks the results against
//! the script's expectations. See benches/README.md.
//!
//!     cargo run --release --bin ncsheet-bench -- [--sizes grid-100000,chain-1000000,...]
//!         [--runs N] [--builds N] [--spec PATH | --no-spec]
//!
//! Each workbook is measured in a child process of its own so that its memory figures are
//! not mixed with another's.

use std::process::{Command, ExitCode};
use std::time::Instant;

use ncsheet::eval::Value;
use ncsheet::formula::Pos;
use ncsheet::workbook::Workbook;

const DEFAULT_SIZES: &[&str] = &["chain-100000", "chain-1000000", "grid-100000", "fan-100000"];
/// gen_workbooks.py, in `shared/` beside the repository.
fn default_spec() -> String {
    format!("{}/benches/gen_workbooks.py", env!("CARGO_MANIFEST_DIR"))
}

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
    Mean,
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
            "mean" => Kind::Mean,
            _ => return Err(format!("unknown workbook kind in {name:?} (chain, grid, fan, mean)")),
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
        let grid: Vec<Vec<&str>> = GRID.iter().map(|f| f.split("{r}").collect()).collect();
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
                        text.push_str("=A");
                        push_u32(&mut text, r - 1);
                        text.push_str("+1");
                        formulas += 1;
                    }
                    put(wb, r, 0, &text);
                }
                Kind::Grid => {
                    text.clear();
                    push_u32(&mut text, r);
                    put(wb, r, 0, &text);
                    for (i, f) in grid.iter().enumerate() {
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
                    text.push_str("=$A$1*");
                    push_u32(&mut text, r);
                    text.push_str("+SIN($A$1)");
                    put(wb, r, 1, &text);
                    formulas += 1;
                }
                Kind::Mean => {
                    // A = 1..N, and in B1 the mean of them all: the edit recomputes one
                    // AVERAGE over N ordinary numbers, the mean's hot path.
                    text.clear();
                    push_u32(&mut text, r);
                    put(wb, r, 0, &text);
                    if r == self.n {
                        text.clear();
                        text.push_str("=AVERAGE(A1:A");
                        push_u32(&mut text, r);
                        text.push(')');
                        put(wb, 1, 1, &text);
                        formulas += 1;
                    }
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
            Kind::Mean => Spec {
                last: Pos::new(0, 1),
                edit: Pos::new(0, 0),
                edit_value: 2.0,
                expect: (n as f64 + 1.0) / 2.0,
                expect_after: (n as f64 + 1.0) / 2.0 + 1.0 / n as f64,
            },
        }
    }

    /// The input value the edit toggles back to.
    fn original_value(&self) -> f64 {
        match self.kind {
            Kind::Grid => self.n as f64,
            Kind::Chain | Kind::Fan | Kind::Mean => 1.0,
        }
    }
}

/// Appends `n` in decimal (cheaper than `write!`, so that the harness costs little).
fn push_u32(out: &mut String, n: u32) {
    let mut buf = [0u8; 10];
    let mut i = buf.len();
    let mut n = n;
    loop {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    for &d in &buf[i..] {
        out.push(d as char);
    }
}

fn push_row_formula(out: &mut String, parts: &[&str], r: u32) {
    out.push_str(parts[0]);
    for p in &parts[1..] {
        push_u32(out, r);
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

/// Wall-clock and this thread's CPU time. On a loaded machine the CPU time is what the work
/// costs; the wall time includes waiting for a core.
#[derive(Clone, Copy)]
struct Stamp {
    wall: Instant,
    cpu: f64,
}

#[repr(C)]
struct Timespec {
    tv_sec: i64,
    tv_nsec: i64,
}

extern "C" {
    fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
}

/// Linux's `CLOCK_THREAD_CPUTIME_ID`.
const CLOCK_THREAD_CPUTIME_ID: i32 = 3;

fn thread_cpu_seconds() -> f64 {
    let mut ts = Timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec, which `ts` is (64-bit Linux layout).
    let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc == 0 {
        ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
    } else {
        0.0
    }
}

impl Stamp {
    fn now() -> Stamp {
        Stamp { wall: Instant::now(), cpu: thread_cpu_seconds() }
    }

    /// (wall, cpu) seconds since `self`.
    fn since(self, earlier: Stamp) -> Time {
        Time { wall: (self.wall - earlier.wall).as_secs_f64(), cpu: self.cpu - earlier.cpu }
    }
}

/// A measured duration: wall-clock and CPU seconds.
#[derive(Clone, Copy, Debug)]
struct Time {
    wall: f64,
    cpu: f64,
}

impl Time {
    const MAX: Time = Time { wall: f64::MAX, cpu: f64::MAX };

    fn min(self, other: Time) -> Time {
        Time { wall: self.wall.min(other.wall), cpu: self.cpu.min(other.cpu) }
    }
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
#[derive(Debug)]
struct Figures {
    formulas: usize,
    distinct: usize,
    build: Time,
    compute: Time,
    total: Time,
    edit_best: Time,
    edit_median: Time,
    rss_bytes: u64,
    hwm_bytes: u64,
}

impl Figures {
    fn to_line(&self) -> String {
        let t = |t: Time| format!("{} {}", t.wall, t.cpu);
        format!(
            "FIGURES {} {} {} {} {} {} {} {} {}",
            self.formulas,
            self.distinct,
            t(self.build),
            t(self.compute),
            t(self.total),
            t(self.edit_best),
            t(self.edit_median),
            self.rss_bytes,
            self.hwm_bytes
        )
    }

    fn from_line(line: &str) -> Option<Figures> {
        let f: Vec<&str> = line.strip_prefix("FIGURES ")?.split(' ').collect();
        let x = |i: usize| f.get(i)?.parse::<f64>().ok();
        let t = |i: usize| Some(Time { wall: x(i)?, cpu: x(i + 1)? });
        let u = |i: usize| f.get(i)?.parse::<u64>().ok();
        Some(Figures {
            formulas: u(0)? as usize,
            distinct: u(1)? as usize,
            build: t(2)?,
            compute: t(4)?,
            total: t(6)?,
            edit_best: t(8)?,
            edit_median: t(10)?,
            rss_bytes: u(12)?,
            hwm_bytes: u(13)?,
        })
    }
}

/// Measures one workbook in this process.
fn run_child(bench: &Bench, runs: usize, builds: usize) -> Result<Figures, String> {
    let spec = bench.spec();
    let mut fig = Figures {
        formulas: 0,
        distinct: 0,
        build: Time::MAX,
        compute: Time::MAX,
        total: Time::MAX,
        edit_best: Time::MAX,
        edit_median: Time::MAX,
        rss_bytes: 0,
        hwm_bytes: 0,
    };
    let mut kept = None;
    for i in 0..builds.max(1) {
        // Drop the previous copy first, so the memory figures are those of one workbook.
        drop(kept.take());
        let rss0 = proc_status("VmRSS");
        let hwm0 = proc_status("VmHWM");
        let t0 = Stamp::now();
        let mut wb = Workbook::with_sheet();
        let formulas = bench.build(&mut wb);
        let t1 = Stamp::now();
        wb.recalculate();
        let t2 = Stamp::now();
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
        fig.build = fig.build.min(t1.since(t0));
        fig.compute = fig.compute.min(t2.since(t1));
        fig.total = fig.total.min(t2.since(t0));
        check(&wb, spec.last, spec.expect, &format!("{} after the full computation", bench.name))?;
        kept = Some(wb);
    }
    let mut wb = kept.expect("built once");
    let mut times = Vec::with_capacity(runs * 2);
    let edit_text = format!("{}", spec.edit_value);
    let back_text = format!("{}", bench.original_value());
    for _ in 0..runs.max(1) {
        let t = Stamp::now();
        wb.set_input(0, spec.edit, &edit_text).map_err(|e| e.to_string())?;
        times.push(Stamp::now().since(t));
        check(&wb, spec.last, spec.expect_after, &format!("{} after the edit", bench.name))?;
        // Back to the original input (timed as well: it is the same amount of work).
        let t = Stamp::now();
        wb.set_input(0, spec.edit, &back_text).map_err(|e| e.to_string())?;
        times.push(Stamp::now().since(t));
        check(&wb, spec.last, spec.expect, &format!("{} after undoing the edit", bench.name))?;
    }
    let mut walls: Vec<f64> = times.iter().map(|t| t.wall).collect();
    let mut cpus: Vec<f64> = times.iter().map(|t| t.cpu).collect();
    walls.sort_by(f64::total_cmp);
    cpus.sort_by(f64::total_cmp);
    fig.edit_best = Time { wall: walls[0], cpu: cpus[0] };
    fig.edit_median = Time { wall: walls[walls.len() / 2], cpu: cpus[cpus.len() / 2] };
    Ok(fig)
}

fn seconds(s: f64) -> String {
    if s >= 1.0 {
        format!("{:.2} s", s)
    } else if s >= 1e-3 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{:.1} µs", s * 1e6)
    }
}

/// `wall (cpu)`.
fn both(t: Time) -> String {
    format!("{} ({})", seconds(t.wall), seconds(t.cpu))
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
    let mut args = Args { sizes: Vec::new(), runs: 15, builds: 3, spec: Some(default_spec()), child: None };
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
                     NAME = chain-N | grid-N | fan-N | mean-N (default: {})",
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
        } else {
            println!("{script} not found: expectations from the bench's port of it");
        }
    }
    println!(
        "{} build(s) per workbook, best kept; {} edits (and as many undos) per workbook",
        args.builds,
        args.runs * 2
    );
    println!("times: wall-clock (this thread's CPU time in parentheses)");
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
        println!("{}: {} formula cells, {} distinct formulas (copies count once)", b.name, fig.formulas, fig.distinct);
        println!("  build (set_input_deferred of every cell) {}", both(fig.build));
        println!("  full computation (recalculate)           {}", both(fig.compute));
        println!("  build + full computation                 {}", both(fig.total));
        println!(
            "  one edit ({} := {}) best {}, median {}",
            b.spec().edit,
            b.spec().edit_value,
            both(fig.edit_best),
            both(fig.edit_median)
        );
        println!(
            "  memory: {:.0} bytes per formula cell (resident growth {:.1} MiB, peak growth {:.1} MiB)",
            per_formula,
            fig.rss_bytes as f64 / (1 << 20) as f64,
            fig.hwm_bytes as f64 / (1 << 20) as f64,
        );
        let (total_target, edit_target) = target(&b.name);
        if let Some(t) = total_target.filter(|&t| fig.total.wall > t) {
            failures.push(format!("{}: build+compute {} > target {}", b.name, seconds(fig.total.wall), seconds(t)));
        }
        if let Some(t) = edit_target.filter(|&t| fig.edit_best.wall > t) {
            failures.push(format!("{}: edit {} > target {}", b.name, seconds(fig.edit_best.wall), seconds(t)));
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
