//! `ncsheet nc …`: NC programs as a control runs them (docs/domain.md §4): the DDA interpolator's
//! table for one straight move, and a program's cycle time block by block (`nc plot` and
//! `nc check` are in `nc_plot.rs` and `nc_check.rs`).

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::ValueEnum;
use clap::{Args, Subcommand};
use ncsheet::nc::dda::{self, DdaRun};
use ncsheet::nc::dialect::{self, Dialect};
use ncsheet::nc::motion::{self, BlockTime, Rates};
use ncsheet::nc::read::detect;
use ncsheet::nc::{ArcDirection, Machine, Program};

use super::report::{Error, Result};

/// Run NC moves as a control does: the DDA interpolator's table, a program's cycle time,
/// its backplot and its check.
#[derive(Debug, Args)]
pub struct NcArgs {
    #[command(subcommand)]
    pub command: NcCommand,
    #[command(flatten)]
    pub timeout: super::limits::TimeoutArg,
}

#[derive(Debug, Subcommand)]
pub enum NcCommand {
    Dda(DdaArgs),
    Time(TimeArgs),
    Plot(super::nc_plot::PlotArgs),
    Check(super::nc_check::CheckArgs),
}

/// A dialect to read a program in: every one of `dialect::all()`, by its name.
#[derive(Clone, Copy, Debug)]
pub struct ReadDialect(pub &'static dyn Dialect);

impl ValueEnum for ReadDialect {
    fn value_variants<'a>() -> &'a [Self] {
        static ALL: OnceLock<Vec<ReadDialect>> = OnceLock::new();
        ALL.get_or_init(|| dialect::all().into_iter().map(ReadDialect).collect())
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()))
    }
}

/// A `--dialect` among `names` (from `dialect::all()`), read once into the dialect: clap
/// lists the names in the help and in its error for any other.
pub(super) fn dialect_parser(names: Vec<&'static str>) -> impl TypedValueParser<Value = &'static dyn Dialect> {
    PossibleValuesParser::new(names).map(|name| dialect::by_name(&name).expect("a name dialect::all() gave"))
}

/// Reads the program at `path` in `dialect`, or in the dialect its header, extension or words
/// tell when none is given (saying on stderr which and why): the model, each block's source
/// line, the file's name for messages (errors name the file, line and column, and the
/// dialects that would read it) and the dialect read.
pub(super) fn read_program(
    path: &Path,
    dialect: Option<ReadDialect>,
    machine: Option<MachineArg>,
) -> Result<(Program, Vec<usize>, String, &'static dyn Dialect)> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::User(format!("{name}: {e}")))?;
    let machine = machine.map(|m| match m {
        MachineArg::Lathe => Machine::Lathe,
        MachineArg::Mill => Machine::Mill,
    });
    let dialect = match dialect {
        Some(d) => d.0,
        None => {
            let extension = path.extension().and_then(|e| e.to_str());
            let guess = detect::guess(&text, extension);
            // No --dialect was given: the note says how to give one, not that one disagreed.
            eprintln!(
                "{name}: read as {} ({}); give --dialect to read it otherwise",
                guess.dialect.name(),
                guess.reason
            );
            guess.dialect
        }
    };
    let (program, lines, notes) = dialect.read_noted(&text, machine).map_err(|e| {
        let others = detect::readers_accepting(&text, dialect, machine);
        let read_as = dialect.name();
        let hint = match others.first() {
            Some(other) => format!(" (read as {read_as}; it reads as {}: --dialect {other})", others.join(", ")),
            None => format!(" (read as {read_as}; no other dialect reads it either)"),
        };
        Error::User(format!("{name}: {e}{hint}"))
    })?;
    for note in notes {
        eprintln!("{name}: {note}");
    }
    Ok((program, lines, name, dialect))
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MachineArg {
    Lathe,
    Mill,
}

/// A program's cycle time: every block from rest to rest on a trapezoidal velocity profile
/// (acceleration A to the programmed feed, a triangle when the block is too short), dwells
/// added; one row per moving block with its source line.
#[derive(Debug, Args)]
pub struct TimeArgs {
    /// The NC program (text as the dialect writes it)
    pub program: PathBuf,
    /// Path acceleration and deceleration, mm/s²
    #[arg(long)]
    pub accel: f64,
    /// Rapid traverse rate, mm/min
    #[arg(long)]
    pub rapid: f64,
    /// The control the program is written for; default: what its header, extension
    /// (.ngc, .mpf, .h, …) or words tell, else iso
    #[arg(long, value_enum)]
    pub dialect: Option<ReadDialect>,
    /// What the program is for; default: a lathe when G18 comes before the first move
    #[arg(long, value_enum)]
    pub machine: Option<MachineArg>,
}

/// Print the DDA linear interpolator's table for one straight move, clock by clock: each
/// axis's registers p and q and its pulses (the paper's table T8.1.1:
/// `nc dda --bits 4 --dx 16 --dy 8`).
#[derive(Debug, Args)]
pub struct DdaArgs {
    /// The move along X: in machine increments, or in mm when --increment is given
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub dx: f64,
    /// The move along Y
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub dy: f64,
    /// The move along Z (printed only when not 0)
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub dz: f64,
    /// The machine increment in mm (e.g. 0.001); then --dx/--dy/--dz are in mm
    #[arg(long)]
    pub increment: Option<f64>,
    /// Bits n of each axis's adder (2ⁿ clocks); default: the smallest with 2ⁿ ≥ the longest move
    #[arg(long)]
    pub bits: Option<u32>,
    /// Interpolate an arc (cw or ccw) from the start to --dx/--dy around the centre --i/--j
    /// (both from the start, as G2/G3 X Y I J)
    #[arg(long)]
    pub arc: Option<ArcArg>,
    /// The arc's centre along X from the start
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub i: f64,
    /// The arc's centre along Y from the start
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub j: f64,
    /// Write the table here instead of to stdout
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Replace a read-only or hard-linked OUT
    #[arg(long, requires = "output")]
    pub force: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ArcArg {
    Cw,
    Ccw,
}

pub fn run(args: NcArgs) -> Result<()> {
    match args.command {
        NcCommand::Dda(a) => dda_table(a),
        NcCommand::Time(a) => cycle_time(a),
        NcCommand::Plot(a) => super::nc_plot::run(a),
        NcCommand::Check(a) => super::nc_check::run(a),
    }
}

fn dda_table(args: DdaArgs) -> Result<()> {
    let user = |e: dda::DdaError| Error::User(e.to_string());
    let increment = args.increment.unwrap_or(1.0);
    if let Some(arc) = args.arc {
        return dda_arc(&args, arc, increment);
    }
    let mut axes = vec![('X', args.dx), ('Y', args.dy)];
    if args.dz != 0.0 {
        axes.push(('Z', args.dz));
    }
    let mut deltas = Vec::new();
    for (letter, v) in &axes {
        let n = dda::increments(*v, increment)
            .map_err(|e| Error::User(format!("--d{}: {e}", letter.to_ascii_lowercase())))?;
        deltas.push(n);
    }
    let bits = args.bits.unwrap_or_else(|| dda::bits_for(&deltas));
    let run = dda::linear(bits, &deltas).map_err(user)?;
    let letters: Vec<char> = axes.iter().map(|a| a.0).collect();
    let table = LinearTable::measure(&run, &letters);
    emit_streamed(args.output.as_deref(), args.force, |out| table.write(&run, out))
}

/// The circular interpolator's table: clock, per axis p, q and the step (±1), the position
/// from the centre. The arc is run twice, the clocks written as they come: first to count
/// the pulses and find that it reaches its end (so that nothing is written for an arc the
/// adders lose), then to write it.
fn dda_arc(args: &DdaArgs, arc: ArcArg, increment: f64) -> Result<()> {
    let count = |v: f64, what: &str| dda::increments(v, increment).map_err(|e| Error::User(format!("--{what}: {e}")));
    let (dx, dy, i, j) = (count(args.dx, "dx")?, count(args.dy, "dy")?, count(args.i, "i")?, count(args.j, "j")?);
    let (start, end) = ((-i, -j), (dx - i, dy - j));
    let direction = if arc == ArcArg::Cw { ArcDirection::Clockwise } else { ArcDirection::CounterClockwise };
    let bits = args.bits.unwrap_or_else(|| dda::bits_for_circle(start, end));
    let run = dda::circular(bits, start, end, direction).map_err(|e| Error::User(e.to_string()))?;
    let [px, py] = run.pulses().map_err(|e| Error::User(e.to_string()))?;
    emit_streamed(args.output.as_deref(), args.force, |out| {
        writeln!(out, "DDA arc: {} bits, from {start:?} to {end:?} around the centre", run.bits)?;
        writeln!(out, "clock  X p  X q  X step  Y p  Y q  Y step  x  y")?;
        for c in run.clocks() {
            let c = c.map_err(|e| io::Error::other(e.to_string()))?;
            let [x, y] = c.axes;
            writeln!(
                out,
                "{}  {}  {}  {}  {}  {}  {}  {}  {}",
                c.number, x.p, x.q, c.steps[0], y.p, y.q, c.steps[1], c.position.0, c.position.1
            )?;
        }
        writeln!(out, "pulses  X {px}  Y {py}")
    })
}

/// Text written as it is made, to OUT through the one atomic write (all of it or nothing)
/// or to stdout: a table of 2^24 clocks is about 1.2 GB, never held in memory.
fn emit_streamed(path: Option<&Path>, force: bool, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
    match path {
        Some(p) => ncsheet::io::atomic::write_file_with(p, ncsheet::io::atomic::Options { force }, write)
            .map_err(|e| ncsheet::io::Error::new(p, ncsheet::io::ErrorKind::Write(e)).into()),
        None => {
            let mut out = io::BufWriter::new(io::stdout().lock());
            write(&mut out)?;
            out.flush()?;
            Ok(())
        }
    }
}

/// The linear table as the paper lays it out: clock, then per axis p, q (`16-16=0` on an
/// overflow) and the pulse; a last row with each axis's pulse count. Every column is as wide
/// as its widest cell, right-aligned: the widths are measured by a first run of the adders
/// (lengths only), and the rows written by a second.
struct LinearTable {
    head: Vec<String>,
    widths: Vec<usize>,
    pulses: Vec<i64>,
}

impl LinearTable {
    fn measure(run: &DdaRun, letters: &[char]) -> LinearTable {
        let capacity = run.capacity();
        let mut head = vec!["clock".to_string()];
        for l in letters {
            head.extend([format!("{l} p"), format!("{l} q"), format!("{l} pulse")]);
        }
        // The header, the start row of zeros, the clock numbers and the pulses row's title.
        let mut widths: Vec<usize> = head.iter().map(String::len).collect();
        widths[0] = widths[0].max("pulses".len()).max(digits(capacity));
        let mut counts = vec![0i64; run.deltas.len()];
        for clock in run.clocks() {
            for (axis, a) in clock.axes.iter().enumerate() {
                let q = &mut widths[2 + 3 * axis];
                *q = (*q).max(q_text_len(a, capacity));
                counts[axis] += i64::from(a.pulse);
            }
        }
        let pulses: Vec<i64> = counts.iter().zip(&run.deltas).map(|(n, d)| n * d.signum()).collect();
        for (axis, n) in pulses.iter().enumerate() {
            let p = &mut widths[1 + 3 * axis];
            *p = (*p).max(digits(run.deltas[axis].unsigned_abs()));
            let pulse = &mut widths[3 + 3 * axis];
            *pulse = (*pulse).max(n.to_string().len());
        }
        LinearTable { head, widths, pulses }
    }

    fn write(&self, run: &DdaRun, out: &mut dyn Write) -> io::Result<()> {
        let capacity = run.capacity();
        writeln!(out, "DDA: {} bits, 2^{} = {capacity} clocks", run.bits, run.bits)?;
        let mut row = Row { widths: &self.widths, line: String::new(), column: 0 };
        for h in &self.head {
            row.cell(h);
        }
        row.end(out)?;
        for _ in &self.widths {
            row.cell(0);
        }
        row.end(out)?;
        let mut q = String::new();
        for clock in run.clocks() {
            row.cell(clock.number);
            for a in &clock.axes {
                q.clear();
                if a.pulse {
                    let _ = write!(q, "{}-{capacity}={}", a.sum, a.q);
                } else {
                    let _ = write!(q, "{}", a.q);
                }
                row.cell(a.p);
                row.cell(&q);
                row.cell(u8::from(a.pulse));
            }
            row.end(out)?;
        }
        row.cell("pulses");
        for n in &self.pulses {
            row.cell("");
            row.cell("");
            row.cell(n);
        }
        row.end(out)
    }
}

/// A row being written: each cell right-aligned in its column, two spaces between columns,
/// no spaces at the end.
struct Row<'a> {
    widths: &'a [usize],
    line: String,
    column: usize,
}

impl Row<'_> {
    fn cell(&mut self, value: impl std::fmt::Display) {
        if self.column > 0 {
            self.line.push_str("  ");
        }
        let width = self.widths[self.column];
        let _ = write!(self.line, "{value:>width$}");
        self.column += 1;
    }

    fn end(&mut self, out: &mut dyn Write) -> io::Result<()> {
        self.line.truncate(self.line.trim_end().len());
        self.line.push('\n');
        out.write_all(self.line.as_bytes())?;
        self.line.clear();
        self.column = 0;
        Ok(())
    }
}

/// The length of q as the table writes it: `sum-2ⁿ=q` on an overflow, else q.
fn q_text_len(a: &dda::AxisClock, capacity: u64) -> usize {
    if a.pulse {
        digits(a.sum) + digits(capacity) + digits(a.q) + 2
    } else {
        digits(a.q)
    }
}

/// Decimal digits of n.
fn digits(n: u64) -> usize {
    n.checked_ilog10().map_or(1, |d| d as usize + 1)
}

fn cycle_time(args: TimeArgs) -> Result<()> {
    let (program, lines, name, _) = read_program(&args.program, args.dialect, args.machine)?;
    let times = motion::program_times(&program, Rates { accel: args.accel, rapid: args.rapid }).map_err(|e| {
        let at = e.block.and_then(|b| lines.get(b - 1)).map(|l| format!(", line {l}")).unwrap_or_default();
        Error::User(format!("{name}{at}: {}", e.message))
    })?;
    let mut out = io::BufWriter::new(io::stdout().lock());
    out.write_all(time_table(&times, &lines).as_bytes())?;
    out.flush()?;
    Ok(())
}

fn time_table(times: &[BlockTime], lines: &[usize]) -> String {
    let mut text = format!(
        "{:>6}  {:<5}  {:>10}  {:>10}  {:>9}  {:>9}\n",
        "line", "move", "length mm", "feed/min", "peak mm/s", "time s"
    );
    for t in times {
        let line = lines.get(t.block - 1).copied().unwrap_or(0);
        let peak = t.profile.map(|p| format!("{:.3}", p.peak)).unwrap_or_default();
        text.push_str(&format!(
            "{line:>6}  {:<5}  {:>10.3}  {:>10.1}  {peak:>9}  {:>9.3}\n",
            t.kind, t.length, t.feed, t.time
        ));
    }
    // + 0.0 turns the empty sum's −0 into 0: an empty program takes "0.000 s", not "-0.000 s".
    let total: f64 = times.iter().map(|t| t.time).sum::<f64>() + 0.0;
    text.push_str(&format!("cycle time {total:.3} s ({}:{:06.3})\n", (total / 60.0).floor(), total % 60.0));
    text
}
