//! NC dialects: how one control writes a [`Program`]. A dialect is a value implementing
//! [`Dialect`]; [`by_name`] is the one list the CLI's `--dialect` reads.
//!
//! Word-address controls (ISO/Fanuc, LinuxCNC, Sinumerik, NC31) share one writer configured
//! by a [`WordAddress`] table; Heidenhain's plain language has a writer of its own.

use std::fmt;

use super::format::NumberStyle;
use super::program::{Block, FeedMode, Machine, Program, Spindle, Target, ToolChange, ToolOffset};
use super::read::ReadError;

mod heidenhain;

/// The numbers a Heidenhain control reads, for its reader's refusals ([`check_values`]).
pub(crate) use heidenhain::format_for as plain_language_limits;
mod subprograms;
mod word_address;

pub use heidenhain::Heidenhain;
pub use word_address::{Family, WordAddress, ISO, LINUXCNC, NC31, NC81, SINUMERIK};

/// Something a dialect cannot write.
#[derive(Clone, Debug, PartialEq)]
pub struct NcError {
    pub dialect: &'static str,
    /// 1-based index of the block in the program model, when one block is at fault.
    pub block: Option<usize>,
    pub message: String,
}

impl fmt::Display for NcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.block {
            Some(b) => write!(f, "{} dialect, block {b}: {}", self.dialect, self.message),
            None => write!(f, "{} dialect: {}", self.dialect, self.message),
        }
    }
}

impl std::error::Error for NcError {}

/// A control's dialect. Every dialect is a `static` (see [`all`]), so a `&'static dyn Dialect`
/// is the value that names one across the layers: it can be shared between threads.
pub trait Dialect: Sync {
    /// The name `--dialect` takes.
    fn name(&self) -> &'static str;

    /// The smallest step the control's numbers resolve (mm).
    fn resolution(&self) -> f64;

    /// Whether the control runs programs for this machine (NC31 and plain language here do
    /// one kind each); the CLI lists a dialect only for commands whose programs it writes.
    fn writes(&self, machine: Machine) -> bool;

    /// The program as the control reads it, one block per line, ending in a newline.
    fn render(&self, program: &Program) -> Result<String, NcError>;

    /// Reads a program as this control does (`crates/ncsheet/src/nc/read.rs`), with the 1-based source line
    /// of each block; `machine` when known, else the reader decides from the program.
    fn read(&self, text: &str, machine: Option<Machine>) -> Result<(Program, Vec<usize>), ReadError>;

    /// [`read`](Dialect::read), and what the reading kept of `text` without running it, one
    /// note a line (a Fanuc file's subprograms that no call runs); the command line prints
    /// them on stderr.
    fn read_noted(
        &self,
        text: &str,
        machine: Option<Machine>,
    ) -> Result<(Program, Vec<usize>, Vec<String>), ReadError> {
        self.read(text, machine).map(|(program, lines)| (program, lines, Vec::new()))
    }
}

/// A dialect shows as its name.
impl fmt::Debug for dyn Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The dialects that write programs for `machine`, by name, in `all()`'s order.
pub fn names_for(machine: Machine) -> Vec<&'static str> {
    all().iter().filter(|d| d.writes(machine)).map(|d| d.name()).collect()
}

/// Every dialect, by the name the CLI uses.
pub fn all() -> [&'static dyn Dialect; 6] {
    [&ISO, &LINUXCNC, &SINUMERIK, &Heidenhain, &NC31, &NC81]
}

/// The writer of `name` when its control runs the cycles paper's subprograms (NC31, and NC81
/// with its words): `run --subprograms` writes with it.
pub fn with_subprograms(name: &str) -> Option<&'static WordAddress> {
    [&NC31, &NC81].into_iter().find(|d| d.name.eq_ignore_ascii_case(name))
}

pub fn by_name(name: &str) -> Option<&'static dyn Dialect> {
    all().into_iter().find(|d| d.name().eq_ignore_ascii_case(name))
}

pub fn names() -> Vec<&'static str> {
    all().iter().map(|d| d.name()).collect()
}

/// Where the tool is while a program is written: arcs need their start point.
#[derive(Clone, Copy, Debug, Default)]
struct Position {
    axes: [Option<f64>; 6],
}

impl Position {
    fn apply(&mut self, t: &Target) {
        for (i, v) in [t.x, t.y, t.z, t.a, t.b, t.c].into_iter().enumerate() {
            if v.is_some() {
                self.axes[i] = v;
            }
        }
    }

    fn x(&self) -> Option<f64> {
        self.axes[0]
    }

    /// The known axes as a point.
    fn target(&self) -> Target {
        let [x, y, z, a, b, c] = self.axes;
        Target { x, y, z, a, b, c }
    }

    fn y(&self) -> Option<f64> {
        self.axes[1]
    }

    fn z(&self) -> Option<f64> {
        self.axes[2]
    }
}

/// Arc centre offsets from the start point, as (address, value) in the machine's plane:
/// I/J on a mill; I (radius, though X is a diameter) and K on a lathe.
fn centre_offsets(machine: Machine, start: &Position, centre: &Target) -> Option<[(char, f64); 2]> {
    match machine {
        Machine::Mill => Some([('I', centre.x? - start.x()?), ('J', centre.y? - start.y()?)]),
        Machine::Lathe => Some([('I', (centre.x? - start.x()?) / 2.0), ('K', centre.z? - start.z()?)]),
    }
}

/// The end points of chords that follow an arc from `start` to `to` around `centre` within
/// `tolerance` (each chord's sagitta r·(1 − cos(θ/2)) at most that), the last the arc's own
/// end; in the machine's plane (a lathe's X a diameter), a helix's third axis evenly.
fn chords(
    machine: Machine,
    start: &Position,
    to: &Target,
    centre: &Target,
    direction: super::program::ArcDirection,
    tolerance: f64,
) -> Result<Vec<Target>, String> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err("the chord tolerance is not above the control's resolution".into());
    }
    let (sx, sy, sz) = (start.x(), start.y(), start.z());
    // Plane coordinates (u, v) and back: (X, Y) on a mill; (Z, X/2) on a lathe.
    let (s, e, c) = match machine {
        Machine::Mill => (
            (sx.ok_or("an arc from an unknown X")?, sy.ok_or("an arc from an unknown Y")?),
            (to.x.or(sx).unwrap_or_default(), to.y.or(sy).unwrap_or_default()),
            (centre.x.ok_or("an arc centre without X")?, centre.y.ok_or("an arc centre without Y")?),
        ),
        Machine::Lathe => (
            (sz.ok_or("an arc from an unknown Z")?, sx.ok_or("an arc from an unknown X")? / 2.0),
            (to.z.or(sz).unwrap_or_default(), to.x.or(sx).unwrap_or_default() / 2.0),
            (centre.z.ok_or("an arc centre without Z")?, centre.x.ok_or("an arc centre without X")? / 2.0),
        ),
    };
    let r = (s.0 - c.0).hypot(s.1 - c.1);
    let (a0, a1) = ((s.1 - c.1).atan2(s.0 - c.0), (e.1 - c.1).atan2(e.0 - c.0));
    let ccw = direction == super::program::ArcDirection::CounterClockwise;
    let mut sweep =
        if ccw { (a1 - a0).rem_euclid(std::f64::consts::TAU) } else { (a0 - a1).rem_euclid(std::f64::consts::TAU) };
    if sweep < 1e-12 {
        sweep = std::f64::consts::TAU;
    }
    // The widest chord angle whose sagitta is within the tolerance.
    let widest = if tolerance >= r { std::f64::consts::PI } else { 2.0 * (1.0 - tolerance / r).acos() };
    let n = (sweep / widest).ceil().max(1.0) as usize;
    let across = match machine {
        Machine::Mill => (sz, to.z),
        Machine::Lathe => (start.y(), to.y),
    };
    let mut points = Vec::with_capacity(n);
    for k in 1..=n {
        let t = k as f64 / n as f64;
        let a = if ccw { a0 + sweep * t } else { a0 - sweep * t };
        let (u, v) = if k == n { e } else { (c.0 + r * a.cos(), c.1 + r * a.sin()) };
        let third = match across {
            (Some(from), Some(to)) => Some(from + (to - from) * t),
            (_, to) if k == n => to,
            _ => None,
        };
        points.push(match machine {
            Machine::Mill => Target { x: Some(u), y: Some(v), z: third, ..Target::default() },
            Machine::Lathe => Target { z: Some(u), x: Some(2.0 * v), y: third, ..Target::default() },
        });
    }
    Ok(points)
}

/// The ends of the lines a control without circular interpolation (NC31) is written for an
/// arc from `start`, each within `tolerance` of the arc once written in steps of `resolution`
/// (the tolerance keeps one step in reserve for that), as the control's words write them. The
/// writer's chords and a macro's (`Nc.Chords`, for a subprogram that cuts the arc) are these.
pub fn arc_as_lines(
    machine: Machine,
    start: &Target,
    to: &Target,
    centre: &Target,
    direction: super::program::ArcDirection,
    tolerance: f64,
    resolution: f64,
) -> Result<Vec<Target>, String> {
    let mut from = Position::default();
    from.apply(start);
    chords(machine, &from, to, centre, direction, tolerance - resolution)
}

/// How far the end point of an arc may lie off the circle through its start around its
/// centre, as written (mm). LinuxCNC refuses arcs whose two radii differ by more than
/// 0.005 mm in mm mode, Fanuc by parameter 3410 (commonly 0.01–0.02 mm); a written arc
/// within 0.002 mm is cut as meant on either.
pub const ARC_TOLERANCE: f64 = 0.002;

/// The largest spindle speed word (S, 1/min) and tool number a control here takes.
const MAX_RPM: f64 = 99_999.0;
const MAX_TOOL: u32 = 99;
/// The longest dwell (s) we write: longer waits are a mistake in a program, not a dwell.
const MAX_DWELL: f64 = 9_999.0;

/// What a dialect can write: its number style at the program's precision and how many
/// digits a number may have in all (Fanuc: 8, so ±99999.999 at 3 decimals).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Format {
    numbers: NumberStyle,
    digits: usize,
}

impl Format {
    fn largest(&self) -> f64 {
        10f64.powi(self.digits.saturating_sub(self.numbers.decimals) as i32) - self.numbers.resolution()
    }

    fn printed(&self, v: f64) -> f64 {
        let step = self.numbers.resolution();
        (v / step).round() * step
    }

    /// A coordinate (or any length word) the control can read, else why not.
    /// The smallest step the control's numbers resolve (mm).
    pub(crate) fn resolution(&self) -> f64 {
        self.numbers.resolution()
    }

    pub(crate) fn length(&self, what: char, v: f64) -> Result<(), String> {
        if !v.is_finite() {
            return Err(format!("{what} is not a number ({v})"));
        }
        if v.abs() > self.largest() {
            return Err(format!(
                "{what}{v} does not fit the control's {} digits (at most {})",
                self.digits,
                self.numbers.write(self.largest())
            ));
        }
        Ok(())
    }

    pub(crate) fn feed(&self, f: f64) -> Result<(), String> {
        let style = feed_style(self.numbers);
        if !f.is_finite() || f < style.resolution() {
            return Err(format!("the feed F must be a number above 0 the control can write, not {f}"));
        }
        if f > self.largest() {
            return Err(format!("the feed F{f} does not fit the control's {} digits", self.digits));
        }
        Ok(())
    }
}

/// Checks a whole program against what the control reads before a word of it is written:
/// every number finite and within the format, feeds above 0, spindle speeds and tool numbers
/// in range, arcs whose end lies on their circle as written (within [`ARC_TOLERANCE`]), and
/// on a lathe a feed mode before the first feed (F0.1 is 0.1 mm/rev only after G95/G99).
/// The error is (1-based block, message).
fn check_program(program: &Program, format: Format) -> Result<(), (Option<usize>, String)> {
    let mut position = Position::default();
    let mut feed_mode: Option<FeedMode> = None;
    let mut turning = false;
    for (i, block) in program.blocks.iter().enumerate() {
        let at = |m: String| (Some(i + 1), m);
        check_block(block, program.machine, format, &position, &mut feed_mode).map_err(at)?;
        match block {
            Block::Spindle(s) => turning = *s != Spindle::Stop,
            Block::Line { .. } | Block::Arc { .. } if feed_mode == Some(FeedMode::PerRevolution) && !turning => {
                return Err(at(
                    "a feed per revolution with the spindle stopped does not move (Nc.Spindle first)".into()
                ));
            }
            _ => {}
        }
        let printed = |t: &Target| Target {
            x: t.x.map(|v| format.printed(v)),
            y: t.y.map(|v| format.printed(v)),
            z: t.z.map(|v| format.printed(v)),
            a: t.a.map(|v| format.printed(v)),
            b: t.b.map(|v| format.printed(v)),
            c: t.c.map(|v| format.printed(v)),
        };
        match block {
            Block::Rapid(t) | Block::Line { to: t, .. } | Block::Arc { to: t, .. } => position.apply(&printed(t)),
            _ => {}
        }
    }
    if let Some(t) = &program.retract {
        let none = Position::default();
        check_block(&Block::Rapid(*t), program.machine, format, &none, &mut feed_mode)
            .map_err(|m| (None, format!("the retract position: {m}")))?;
    }
    Ok(())
}

fn check_block(
    block: &Block,
    machine: Machine,
    format: Format,
    position: &Position,
    feed_mode: &mut Option<FeedMode>,
) -> Result<(), String> {
    check_values(block, machine, format)?;
    let needs_mode = |mode: &Option<FeedMode>| {
        if machine == Machine::Lathe && mode.is_none() {
            return Err("a lathe cut needs a feed mode first (per revolution or per minute: Nc.FeedPerRev)".to_string());
        }
        Ok(())
    };
    match block {
        Block::FeedMode(m) => *feed_mode = Some(*m),
        Block::Line { .. } => needs_mode(feed_mode)?,
        Block::Arc { to, centre, .. } => {
            needs_mode(feed_mode)?;
            check_arc(machine, format, position, to, centre)?;
        }
        _ => {}
    }
    Ok(())
}

/// What no control here takes in one block, whatever came before it: numbers past the
/// format, feeds, spindle speeds, tool and offset numbers and dwells out of range, constant
/// surface speed on a mill. The readers refuse the same in a hand-written program, at its
/// line and word ([`read_limits`]).
pub(crate) fn check_values(block: &Block, machine: Machine, format: Format) -> Result<(), String> {
    let target = |t: &Target| t.axes().try_for_each(|(l, v)| format.length(l, v));
    let feed = |f: &Option<f64>| f.map_or(Ok(()), |f| format.feed(f));
    let offset = |n: u32| -> Result<(), String> {
        if !(1..=MAX_TOOL).contains(&n) {
            return Err(format!("offset {n} is not an offset number from 1 to {MAX_TOOL} (no offset: Cancelled)"));
        }
        Ok(())
    };
    match block {
        Block::Spindle(s) => check_spindle(s, machine)?,
        Block::Tool(t) if !(1..=MAX_TOOL).contains(&t.number) => {
            return Err(format!("tool {} is not a tool number from 1 to {MAX_TOOL}", t.number));
        }
        Block::Tool(ToolChange { offset: ToolOffset::Number(n), .. }) | Block::LengthOffset(ToolOffset::Number(n)) => {
            offset(*n)?
        }
        Block::Rapid(t) => target(t)?,
        Block::Line { to, feed: f } => {
            target(to)?;
            feed(f)?;
        }
        Block::Arc { to, centre, feed: f, .. } => {
            target(to)?;
            target(centre)?;
            feed(f)?;
        }
        Block::Dwell(s) if !(s.is_finite() && *s > 0.0 && *s <= MAX_DWELL) => {
            return Err(format!("a dwell is a time above 0 and at most {MAX_DWELL} s, not {s}"));
        }
        Block::Words(words) => {
            for w in words {
                format.length(w.address.to_ascii_uppercase(), w.value)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// The format a word-address control of `family` reads (its writer's table at its own
/// precision), for [`check_values`] and [`Format::length`]/[`Format::feed`] in the reader.
pub(crate) fn read_limits(family: Family) -> Format {
    let table = match family {
        Family::Fanuc => &ISO,
        Family::LinuxCnc => &LINUXCNC,
        Family::Sinumerik => &SINUMERIK,
        Family::Nc31 => &NC31,
    };
    Format { numbers: table.numbers, digits: table.digits }
}

fn check_spindle(s: &Spindle, machine: Machine) -> Result<(), String> {
    match *s {
        Spindle::Stop => Ok(()),
        Spindle::Rpm { rpm, .. } if !(rpm.is_finite() && (1.0..=MAX_RPM).contains(&rpm)) => {
            Err(format!("a spindle speed is from 1 to {MAX_RPM} 1/min, not {rpm}"))
        }
        Spindle::Rpm { .. } => Ok(()),
        Spindle::SurfaceSpeed { .. } if machine != Machine::Lathe => {
            Err("constant surface speed (G96) is for lathes".into())
        }
        Spindle::SurfaceSpeed { metres_per_min: v, max_rpm, .. } => {
            if !(v.is_finite() && (1.0..=MAX_RPM).contains(&v)) {
                return Err(format!("a surface speed is from 1 to {MAX_RPM} m/min, not {v}"));
            }
            if !(max_rpm.is_finite() && (1.0..=MAX_RPM).contains(&max_rpm)) {
                return Err(format!("the spindle limit is from 1 to {MAX_RPM} 1/min, not {max_rpm}"));
            }
            Ok(())
        }
    }
}

/// An arc the control cuts as meant: a known start, a radius above the resolution, and its
/// end on the circle through the start within [`ARC_TOLERANCE`], all as written.
fn check_arc(machine: Machine, format: Format, start: &Position, to: &Target, centre: &Target) -> Result<(), String> {
    // The working plane in true lengths: XY on a mill; Z and the radius (X/2) on a lathe.
    let plane = |x: Option<f64>, y: Option<f64>, z: Option<f64>| match machine {
        Machine::Mill => Some((x?, y?)),
        Machine::Lathe => Some((z?, x? / 2.0)),
    };
    let Some(s) = plane(start.x(), start.y(), start.z()) else {
        return Err("an arc needs a known start point (a move before it that sets both plane axes)".into());
    };
    let p = |v: Option<f64>| v.map(|v| format.printed(v));
    let Some(c) = plane(p(centre.x), p(centre.y), p(centre.z)) else {
        return Err("an arc needs its centre in the working plane".into());
    };
    let end =
        Target { x: p(to.x).or(start.x()), y: p(to.y).or(start.y()), z: p(to.z).or(start.z()), ..Target::default() };
    let e = plane(end.x, end.y, end.z).expect("the start filled the plane");
    let r_start = (s.0 - c.0).hypot(s.1 - c.1);
    let r_end = (e.0 - c.0).hypot(e.1 - c.1);
    if r_start <= format.numbers.resolution() {
        return Err(tiny_arc_message(r_start, format.numbers.resolution()));
    }
    if (r_start - r_end).abs() > ARC_TOLERANCE {
        return Err(format!(
            "the arc's centre is {r_start:.4} mm from its start but {r_end:.4} mm from its end \
             (controls accept {ARC_TOLERANCE} mm)"
        ));
    }
    Ok(())
}

/// Why an arc whose centre is within the control's resolution of its start is refused (rs274:
/// "Zero-radius arc"), with its radius in digits enough to tell it from 0.
pub(crate) fn tiny_arc_message(radius: f64, resolution: f64) -> String {
    if radius == 0.0 {
        return "an arc of radius 0: its centre is its start point".into();
    }
    // Six significant digits: 0.001 stays 0.001, 1e-7 stays 1e-7.
    let shown = format!("{radius:.5e}").parse::<f64>().unwrap_or(radius);
    format!(
        "an arc of radius {shown} mm, not more than the {resolution} mm the control resolves: its centre is \
         written as its start point or next to it; write the move as a line or a larger arc"
    )
}

/// Comment text a control reads as a comment and nothing else: one line, no characters that
/// end the comment or start another, only `allowed` characters (others become spaces),
/// upper case when `upper`.
fn sanitise(text: &str, upper: bool, allowed: impl Fn(char) -> bool) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        let c = if upper { c.to_ascii_uppercase() } else { c };
        let keep = c.is_ascii() && !c.is_ascii_control() && allowed(c);
        let c = if keep { c } else { ' ' };
        if c == ' ' && out.ends_with(' ') {
            continue;
        }
        out.push(c);
    }
    out.trim().to_string()
}

/// A program name as a file name the control stores: letters, digits and `_`, starting with
/// a letter, upper case, at most `max` characters.
fn program_name(name: &str, max: usize) -> String {
    let mut out: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' }).take(max).collect();
    if !out.starts_with(|c: char| c.is_ascii_alphabetic()) {
        out.insert(0, 'P');
        out.truncate(max);
    }
    out
}

/// The number style a dialect writes feed rates in (they are not lengths; two decimals do).
fn feed_style(base: NumberStyle) -> NumberStyle {
    NumberStyle { decimals: base.decimals.min(3), ..base }
}
