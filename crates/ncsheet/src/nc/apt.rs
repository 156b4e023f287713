//! APT cutter-location files (CLF, docs/domain.md §4): what a CAM system writes for a
//! post-processor. Read from text into [`ClRecord`]s and written back, no file IO.
//!
//! A record is `WORD/arg,arg,…` (or a bare `WORD`); a line ending in `$` continues on the
//! next one, `$$` starts a comment to the end of the line, blanks are insignificant outside
//! text, words are read in any case. Lengths are millimetres (`UNITS/MM`; inch files are
//! refused, not converted), feeds mm/min. Understood:
//!
//! - `GOTO/x,y,z[,i,j,k]`: the tool tip at (x, y, z), the tool axis along (i, j, k), a unit
//!   vector; without it the axis is +Z (the paper: a 3-axis CLF leaves it out).
//! - `RAPID` (the next GOTO is a rapid), `FEDRAT/f[,MMPM]`, `SPINDL/[RPM,]n[,CLW|CCLW]`,
//!   `SPINDL/ON|OFF`, `COOLNT/ON|FLOOD|MIST|THRU|OFF`, `LOADTL/n` and the CAM systems'
//!   `LOAD/TOOL,n` (a tool change; `ADJUST,m`, another length register, is refused: the
//!   post's pivot has the length in it), `SELECT/TOOL,n` (the next tool made ready: no
//!   change, kept as a comment).
//! - `CIRCLE/xc,yc,zc,i,j,k,r[,…]` (the APT canonical circle): the next GOTO runs along this
//!   circle, counter-clockwise about the axis (i, j, k); values after the radius (tolerances,
//!   cutter) are not used. `CIRCLE/xc,yc,zc,i,j,k` without the radius, as some CAM systems
//!   write it: the radius is the start point's distance from the centre.
//! - `PARTNO text`, `PPRINT text`, `$$ text`: kept as comments; `CUTTER/d[,r,…]`,
//!   `MULTAX[/ON|OFF]`, `UNITS/MM` (or `UNIT/MM`; `INCHES` is refused, not converted), `INTOL/t`, `OUTTOL/t`, `TOLER/t`, `FROM/x,y,z`: read and
//!   kept; `FINI` and `END` end the file.
//!
//! Anything else is an [`AptError`] naming the line and column, never skipped.

use std::fmt::Write as _;

/// A spindle record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClSpindle {
    /// Speed in 1/min, clockwise (`CLW`) or not (`CCLW`).
    Rpm {
        rpm: f64,
        clockwise: bool,
    },
    /// `SPINDL/ON`: the last speed again.
    On,
    Off,
}

/// What one record says.
#[derive(Clone, Debug, PartialEq)]
pub enum ClKind {
    PartNo(String),
    /// `PPRINT` text or a `$$` comment line.
    Comment(String),
    Goto {
        tip: [f64; 3],
        axis: Option<[f64; 3]>,
    },
    From([f64; 3]),
    Rapid,
    /// mm/min.
    Feedrate(f64),
    Spindle(ClSpindle),
    Coolant(bool),
    LoadTool(u32),
    /// `SELECT/TOOL,n`: tool n made ready for the next change.
    SelectTool(u32),
    Circle {
        centre: [f64; 3],
        axis: [f64; 3],
        /// `None` when the record leaves it out: the start point's distance from the centre.
        radius: Option<f64>,
    },
    /// Diameter and, when given, corner radius.
    Cutter {
        diameter: f64,
        corner_radius: Option<f64>,
    },
    MultiAxis(bool),
    /// `INTOL`, `OUTTOL` or `TOLER` (the word) and its value.
    Tolerance(&'static str, f64),
    UnitsMm,
    /// `FINI` or `END`: nothing after it is read.
    End,
}

/// A record and the line it starts on (1-based).
#[derive(Clone, Debug, PartialEq)]
pub struct ClRecord {
    pub line: usize,
    pub kind: ClKind,
}

impl ClRecord {
    /// The record's major word, for messages that name it.
    pub fn word(&self) -> &'static str {
        match self.kind {
            ClKind::PartNo(_) => "PARTNO",
            ClKind::Comment(_) => "PPRINT",
            ClKind::Goto { .. } => "GOTO",
            ClKind::From(_) => "FROM",
            ClKind::Rapid => "RAPID",
            ClKind::Feedrate(_) => "FEDRAT",
            ClKind::Spindle(_) => "SPINDL",
            ClKind::Coolant(_) => "COOLNT",
            ClKind::LoadTool(_) => "LOADTL",
            ClKind::SelectTool(_) => "SELECT",
            ClKind::Circle { .. } => "CIRCLE",
            ClKind::Cutter { .. } => "CUTTER",
            ClKind::MultiAxis(_) => "MULTAX",
            ClKind::Tolerance(w, _) => w,
            ClKind::UnitsMm => "UNITS",
            ClKind::End => "FINI",
        }
    }
}

/// A record that cannot be read: where (1-based line and column) and why, as for an NC
/// program.
pub type AptError = super::read::ReadError;

/// How far a GOTO's tool axis may be from unit length: CAM systems print 6 or more digits.
const UNIT_TOLERANCE: f64 = 1e-3;

/// Reads a whole CL file.
pub fn read(text: &str) -> Result<Vec<ClRecord>, AptError> {
    let mut records = Vec::new();
    for statement in statements(text)? {
        if statement.comment.is_none() && statement.chars.iter().all(|c| c.0.is_whitespace()) {
            continue;
        }
        let record = parse_record(&statement)?;
        let end = record.kind == ClKind::End;
        records.push(record);
        if end {
            break;
        }
    }
    Ok(records)
}

/// One logical record: its characters, each with the line and column it came from.
struct Statement {
    chars: Vec<(char, usize, usize)>,
    /// A `$$` comment that was the whole line.
    comment: Option<(usize, String)>,
}

/// Splits the text into records: `$$` comments dropped (kept when alone on a line), lines
/// ending in `$` joined to the next.
fn statements(text: &str) -> Result<Vec<Statement>, AptError> {
    let mut out = Vec::new();
    let mut current: Vec<(char, usize, usize)> = Vec::new();
    let mut continued = false;
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let (code, comment) = match raw.find("$$") {
            Some(at) => (&raw[..at], Some(raw[at + 2..].trim().to_string())),
            None => (raw, None),
        };
        let trimmed = code.trim_end();
        let continues = trimmed.ends_with('$');
        let body = if continues { &trimmed[..trimmed.len() - 1] } else { trimmed };
        if !continued && body.trim().is_empty() {
            if let Some(c) = comment.filter(|c| !c.is_empty()) {
                out.push(Statement { chars: Vec::new(), comment: Some((line, c)) });
            }
            continued = continues;
            continue;
        }
        current.extend(body.chars().enumerate().map(|(k, c)| (c, line, k + 1)));
        continued = continues;
        if !continues {
            out.push(Statement { chars: std::mem::take(&mut current), comment: None });
        }
    }
    if continued && !current.is_empty() {
        return Err(AptError {
            line: last_line,
            column: 1,
            message: "the last record ends in `$` (continued) but no line follows".into(),
        });
    }
    Ok(out)
}

/// A piece of a record with the place it starts.
struct Piece {
    text: String,
    line: usize,
    column: usize,
}

impl Piece {
    fn error(&self, message: String) -> AptError {
        AptError { line: self.line, column: self.column, message }
    }

    fn upper(&self) -> String {
        self.text.to_ascii_uppercase()
    }

    fn number(&self, what: &str) -> Result<f64, AptError> {
        let t = &self.text;
        let plausible = t.chars().all(|c| c.is_ascii_digit() || "+-.eE".contains(c)) && !t.is_empty();
        match t.parse::<f64>() {
            Ok(v) if plausible && v.is_finite() => Ok(v),
            _ => Err(self.error(format!("{what}: '{t}' is not a number"))),
        }
    }
}

/// The text of `chars` from `from` on, blanks removed, cut at commas, each piece with its
/// place.
fn arguments(chars: &[(char, usize, usize)], at: (usize, usize)) -> Vec<Piece> {
    let mut out = Vec::new();
    let mut piece = Piece { text: String::new(), line: at.0, column: at.1 };
    let mut started = false;
    for &(c, line, column) in chars {
        if c == ',' {
            out.push(std::mem::replace(&mut piece, Piece { text: String::new(), line, column: column + 1 }));
            started = false;
            continue;
        }
        if c.is_whitespace() {
            continue;
        }
        if !started {
            piece.line = line;
            piece.column = column;
            started = true;
        }
        piece.text.push(c);
    }
    out.push(piece);
    out
}

fn parse_record(s: &Statement) -> Result<ClRecord, AptError> {
    if let Some((line, text)) = &s.comment {
        return Ok(ClRecord { line: *line, kind: ClKind::Comment(text.clone()) });
    }
    let chars = &s.chars;
    let start = chars.iter().position(|c| !c.0.is_whitespace()).expect("blank records are skipped");
    let (_, line, column) = chars[start];
    let word_end = chars[start..].iter().position(|c| !c.0.is_ascii_alphanumeric()).map_or(chars.len(), |k| start + k);
    let word: String = chars[start..word_end].iter().map(|c| c.0.to_ascii_uppercase()).collect();
    let head = Piece { text: word.clone(), line, column };
    let rest = &chars[word_end..];
    let kind = match word.as_str() {
        "PARTNO" | "PPRINT" | "REMARK" => {
            let text: String = rest.iter().map(|c| c.0).collect();
            let text = text.trim().trim_start_matches('/').trim().to_string();
            if word == "PARTNO" {
                ClKind::PartNo(text)
            } else {
                ClKind::Comment(text)
            }
        }
        "RAPID" | "FINI" | "END" => {
            bare(&head, rest)?;
            if word == "RAPID" {
                ClKind::Rapid
            } else {
                ClKind::End
            }
        }
        "MULTAX" if rest.iter().all(|c| c.0.is_whitespace()) => ClKind::MultiAxis(true),
        _ => {
            let args = slash_arguments(&head, rest)?;
            major(&head, &args)?
        }
    };
    Ok(ClRecord { line, kind })
}

/// A record without arguments: nothing may follow its word but an empty `/` (`RAPID/`, as
/// some CAM systems write it).
fn bare(head: &Piece, rest: &[(char, usize, usize)]) -> Result<(), AptError> {
    let mut rest = rest.iter().filter(|c| !c.0.is_whitespace()).peekable();
    rest.next_if(|c| c.0 == '/');
    match rest.next() {
        None => Ok(()),
        Some(&(c, line, column)) => {
            Err(AptError { line, column, message: format!("{} takes no arguments, found '{c}'", head.text) })
        }
    }
}

/// The arguments after `WORD/`.
fn slash_arguments(head: &Piece, rest: &[(char, usize, usize)]) -> Result<Vec<Piece>, AptError> {
    let slash = rest.iter().position(|c| !c.0.is_whitespace());
    match slash.map(|k| (k, rest[k])) {
        Some((k, ('/', line, column))) => Ok(arguments(&rest[k + 1..], (line, column + 1))),
        Some((_, (c, line, column))) => {
            Err(AptError { line, column, message: format!("'{c}' after {}: a record is WORD/arguments", head.text) })
        }
        None if is_known(&head.text) => Err(head.error(format!("{} needs arguments after '/'", head.text))),
        None => Err(unknown(head)),
    }
}

const KNOWN: &[&str] = &[
    "GOTO", "FROM", "FEDRAT", "SPINDL", "COOLNT", "LOADTL", "LOAD", "SELECT", "CIRCLE", "CUTTER", "MULTAX", "UNITS",
    "UNIT", "INTOL", "OUTTOL", "TOLER",
];

fn is_known(word: &str) -> bool {
    KNOWN.contains(&word)
}

fn unknown(head: &Piece) -> AptError {
    let word = if head.text.is_empty() { "(nothing)".to_string() } else { head.text.clone() };
    head.error(format!(
        "unknown record {word}: the post reads GOTO, RAPID, FEDRAT, SPINDL, COOLNT, LOADTL, LOAD/TOOL, \
         SELECT/TOOL, CIRCLE, PARTNO, PPRINT, CUTTER, MULTAX, UNITS/MM, INTOL, OUTTOL, TOLER, FROM, FINI and END"
    ))
}

fn major(head: &Piece, args: &[Piece]) -> Result<ClKind, AptError> {
    let word = head.text.as_str();
    Ok(match word {
        "GOTO" => goto(args)?,
        "FROM" => ClKind::From(point(head, args, 3)?),
        "FEDRAT" => ClKind::Feedrate(feedrate(args)?),
        "SPINDL" => ClKind::Spindle(spindle(head, args)?),
        "COOLNT" => ClKind::Coolant(coolant(head, args)?),
        "LOADTL" => ClKind::LoadTool(tool(args)?),
        "LOAD" => ClKind::LoadTool(tool_word(head, args)?),
        "SELECT" => ClKind::SelectTool(tool_word(head, args)?),
        "CIRCLE" => circle(head, args)?,
        "CUTTER" => cutter(args)?,
        "MULTAX" => match single_word(head, args)?.as_str() {
            "ON" => ClKind::MultiAxis(true),
            "OFF" => ClKind::MultiAxis(false),
            _ => return Err(args[0].error("MULTAX is ON or OFF".into())),
        },
        "UNITS" | "UNIT" => match single_word(head, args)?.as_str() {
            "MM" => ClKind::UnitsMm,
            other => {
                return Err(args[0]
                    .error(format!("UNITS/{other}: only millimetre CL files are read (write the CL file in mm)")))
            }
        },
        "INTOL" => ClKind::Tolerance("INTOL", numbers(head, args, 1)?[0]),
        "OUTTOL" => ClKind::Tolerance("OUTTOL", numbers(head, args, 1)?[0]),
        "TOLER" => ClKind::Tolerance("TOLER", numbers(head, args, 1)?[0]),
        _ => return Err(unknown(head)),
    })
}

/// Exactly `n` numbers.
fn numbers(head: &Piece, args: &[Piece], n: usize) -> Result<Vec<f64>, AptError> {
    if args.len() != n {
        let at = args.get(n).unwrap_or(&args[args.len() - 1]);
        return Err(at.error(format!("{} takes {n} numbers, found {} arguments", head.text, args.len())));
    }
    args.iter().enumerate().map(|(k, a)| a.number(&format!("{} argument {}", head.text, k + 1))).collect()
}

fn point(head: &Piece, args: &[Piece], n: usize) -> Result<[f64; 3], AptError> {
    let v = numbers(head, args, n)?;
    Ok([v[0], v[1], v[2]])
}

fn single_word(head: &Piece, args: &[Piece]) -> Result<String, AptError> {
    if args.len() != 1 {
        return Err(args[args.len() - 1].error(format!("{} takes one word", head.text)));
    }
    Ok(args[0].upper())
}

fn goto(args: &[Piece]) -> Result<ClKind, AptError> {
    if args.len() != 3 && args.len() != 6 {
        let at = args.get(6).unwrap_or(&args[args.len() - 1]);
        return Err(at.error(format!(
            "GOTO takes x,y,z or x,y,z,i,j,k (tip and unit tool axis), found {} arguments",
            args.len()
        )));
    }
    let v: Vec<f64> = args
        .iter()
        .zip(["x", "y", "z", "i", "j", "k"])
        .map(|(a, what)| a.number(&format!("GOTO {what}")))
        .collect::<Result<_, _>>()?;
    let tip = [v[0], v[1], v[2]];
    if args.len() == 3 {
        return Ok(ClKind::Goto { tip, axis: None });
    }
    let axis = [v[3], v[4], v[5]];
    let length = axis.iter().map(|c| c * c).sum::<f64>().sqrt();
    if (length - 1.0).abs() > UNIT_TOLERANCE {
        return Err(args[3].error(format!("the tool axis (i, j, k) has length {length:.6}, not 1")));
    }
    Ok(ClKind::Goto { tip, axis: Some(axis) })
}

fn feedrate(args: &[Piece]) -> Result<f64, AptError> {
    let (value, unit) = match args {
        [v] => (v, None),
        [v, u] if u.upper() != "MMPM" && u.number("").is_err() => (v, Some(u)),
        [v, _] if v.number("").is_ok() => (v, None),
        [u, v] => (v, Some(u)),
        _ => return Err(args[args.len() - 1].error("FEDRAT takes a feed and at most a unit (MMPM)".into())),
    };
    if let Some(u) = unit.filter(|u| u.upper() != "MMPM") {
        return Err(u.error(format!(
            "FEDRAT unit {}: the post writes feeds in mm/min (MMPM); per-revolution and inch feeds are not read",
            u.text
        )));
    }
    let f = value.number("FEDRAT")?;
    if f <= 0.0 {
        return Err(value.error(format!("a feed is above 0, not {f}")));
    }
    Ok(f)
}

fn spindle(head: &Piece, args: &[Piece]) -> Result<ClSpindle, AptError> {
    let mut rpm = None;
    let mut clockwise = true;
    for a in args {
        match a.upper().as_str() {
            "ON" if args.len() == 1 => return Ok(ClSpindle::On),
            "OFF" if args.len() == 1 => return Ok(ClSpindle::Off),
            "RPM" => {}
            "CLW" => clockwise = true,
            "CCLW" => clockwise = false,
            "SFM" | "SMM" => {
                return Err(a.error("SPINDL in surface speed: a mill's post writes a speed in 1/min (RPM)".into()))
            }
            _ if rpm.is_none() => rpm = Some(a.number("SPINDL speed")?),
            _ => return Err(a.error(format!("SPINDL: '{}' is not RPM, CLW, CCLW, ON or OFF", a.text))),
        }
    }
    match rpm {
        Some(rpm) if rpm > 0.0 => Ok(ClSpindle::Rpm { rpm, clockwise }),
        Some(rpm) => Err(args[0].error(format!("a spindle speed is above 0, not {rpm}"))),
        None => Err(head.error("SPINDL needs a speed, ON or OFF".into())),
    }
}

fn coolant(head: &Piece, args: &[Piece]) -> Result<bool, AptError> {
    match single_word(head, args)?.as_str() {
        "ON" | "FLOOD" | "MIST" | "THRU" => Ok(true),
        "OFF" => Ok(false),
        _ => Err(args[0].error(format!("COOLNT: '{}' is not ON, FLOOD, MIST, THRU or OFF", args[0].text))),
    }
}

fn tool(args: &[Piece]) -> Result<u32, AptError> {
    if args.len() != 1 {
        return Err(args[args.len() - 1].error("LOADTL takes the tool number only".into()));
    }
    tool_number("LOADTL", &args[0])
}

fn tool_number(what: &str, arg: &Piece) -> Result<u32, AptError> {
    let n = arg.number(what)?;
    if n.fract() != 0.0 || !(1.0..=u32::MAX as f64).contains(&n) {
        return Err(arg.error(format!("{what}: {n} is not a tool number")));
    }
    Ok(n as u32)
}

/// `LOAD/TOOL,n` or `SELECT/TOOL,n`: the tool number.
fn tool_word(head: &Piece, args: &[Piece]) -> Result<u32, AptError> {
    let what = format!("{}/TOOL", head.text);
    if args[0].upper() != "TOOL" {
        return Err(args[0].error(format!("{}/{} is not read ({what},n is)", head.text, args[0].text)));
    }
    match args {
        [_, n] => tool_number(&what, n),
        [_, _, adjust, ..] if adjust.upper() == "ADJUST" => Err(adjust.error(format!(
            "{what},n,ADJUST: a length register is not read, the post writes the pivot with the tool length in it"
        ))),
        [_] => Err(args[0].error(format!("{what} needs the tool number"))),
        _ => Err(args[2].error(format!("{what} takes the tool number only"))),
    }
}

fn circle(head: &Piece, args: &[Piece]) -> Result<ClKind, AptError> {
    if args.len() < 6 {
        return Err(args[args.len() - 1]
            .error(format!("CIRCLE takes xc,yc,zc,i,j,k[,r] (centre, axis, radius), found {} arguments", args.len())));
    }
    let n = args.len().min(7);
    let v = numbers(head, &args[..n], n)?;
    for a in &args[n..] {
        a.number("CIRCLE")?;
    }
    let axis = [v[3], v[4], v[5]];
    let length = axis.iter().map(|c| c * c).sum::<f64>().sqrt();
    if (length - 1.0).abs() > UNIT_TOLERANCE {
        return Err(args[3].error(format!("the circle's axis (i, j, k) has length {length:.6}, not 1")));
    }
    let radius = v.get(6).copied();
    if let Some(r) = radius.filter(|r| *r <= 0.0) {
        return Err(args[6].error(format!("a circle's radius is above 0, not {r}")));
    }
    Ok(ClKind::Circle { centre: [v[0], v[1], v[2]], axis, radius })
}

fn cutter(args: &[Piece]) -> Result<ClKind, AptError> {
    let v: Vec<f64> = args.iter().map(|a| a.number("CUTTER")).collect::<Result<_, _>>()?;
    if v[0] <= 0.0 {
        return Err(args[0].error(format!("a cutter diameter is above 0, not {}", v[0])));
    }
    Ok(ClKind::Cutter { diameter: v[0], corner_radius: v.get(1).copied() })
}

/// The records as a CL file, one per line, numbers as short as read back exactly.
pub fn write(records: &[ClRecord]) -> String {
    let mut out = String::with_capacity(48 * records.len());
    for r in records {
        write_record(&mut out, &r.kind);
        out.push('\n');
    }
    out
}

fn write_record(out: &mut String, kind: &ClKind) {
    let list = |v: &[f64]| v.iter().map(|n| format!("{n}")).collect::<Vec<_>>().join(",");
    let _ = match kind {
        ClKind::PartNo(t) => write!(out, "PARTNO {}", one_line(t)),
        ClKind::Comment(t) => write!(out, "PPRINT {}", one_line(t)),
        ClKind::Goto { tip, axis: None } => write!(out, "GOTO/{}", list(tip)),
        ClKind::Goto { tip, axis: Some(a) } => write!(out, "GOTO/{},{}", list(tip), list(a)),
        ClKind::From(p) => write!(out, "FROM/{}", list(p)),
        ClKind::Rapid => write!(out, "RAPID"),
        ClKind::Feedrate(f) => write!(out, "FEDRAT/{f},MMPM"),
        ClKind::Spindle(ClSpindle::Rpm { rpm, clockwise }) => {
            write!(out, "SPINDL/RPM,{rpm},{}", if *clockwise { "CLW" } else { "CCLW" })
        }
        ClKind::Spindle(ClSpindle::On) => write!(out, "SPINDL/ON"),
        ClKind::Spindle(ClSpindle::Off) => write!(out, "SPINDL/OFF"),
        ClKind::Coolant(on) => write!(out, "COOLNT/{}", if *on { "ON" } else { "OFF" }),
        ClKind::LoadTool(n) => write!(out, "LOADTL/{n}"),
        ClKind::SelectTool(n) => write!(out, "SELECT/TOOL,{n}"),
        ClKind::Circle { centre, axis, radius: Some(r) } => write!(out, "CIRCLE/{},{},{r}", list(centre), list(axis)),
        ClKind::Circle { centre, axis, radius: None } => write!(out, "CIRCLE/{},{}", list(centre), list(axis)),
        ClKind::Cutter { diameter, corner_radius: None } => write!(out, "CUTTER/{diameter}"),
        ClKind::Cutter { diameter, corner_radius: Some(r) } => write!(out, "CUTTER/{diameter},{r}"),
        ClKind::MultiAxis(on) => write!(out, "MULTAX/{}", if *on { "ON" } else { "OFF" }),
        ClKind::Tolerance(w, t) => write!(out, "{w}/{t}"),
        ClKind::UnitsMm => write!(out, "UNITS/MM"),
        ClKind::End => write!(out, "FINI"),
    };
}

/// Text that stays one record: no line breaks, no `$` (continuation or comment).
fn one_line(text: &str) -> String {
    text.chars().map(|c| if c.is_control() || c == '$' { ' ' } else { c }).collect::<String>().trim().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<ClKind> {
        read(text).unwrap().into_iter().map(|r| r.kind).collect()
    }

    #[test]
    fn reads_a_five_axis_goto_and_a_three_axis_one() {
        assert_eq!(
            kinds("GOTO/1,2.5,-3,0,0.6,0.8\ngoto / 4 , 5 , 6\n"),
            vec![
                ClKind::Goto { tip: [1.0, 2.5, -3.0], axis: Some([0.0, 0.6, 0.8]) },
                ClKind::Goto { tip: [4.0, 5.0, 6.0], axis: None },
            ]
        );
    }

    #[test]
    fn a_dollar_continues_a_record_and_two_start_a_comment() {
        let text = "$$ from the CAM\nGOTO/1,2,3,$\n 0,0,1 $$ tilted\nFINI\nGOTO/9,9,9\n";
        let records = read(text).unwrap();
        assert_eq!(records[0].kind, ClKind::Comment("from the CAM".into()));
        assert_eq!(
            records[1],
            ClRecord { line: 2, kind: ClKind::Goto { tip: [1.0, 2.0, 3.0], axis: Some([0.0, 0.0, 1.0]) } }
        );
        assert_eq!(records[2].kind, ClKind::End);
        assert_eq!(records.len(), 3, "nothing after FINI is read");
    }

    #[test]
    fn machine_records_read_their_words() {
        let text = "PARTNO SPHERE 1\nLOADTL/3\nSPINDL/RPM,2500,CCLW\nFEDRAT/MMPM,300\nFEDRAT/200\nCOOLNT/FLOOD\n\
                    RAPID\nCIRCLE/0,0,5,0,0,-1,10,0.01,0.01,6,3\nCUTTER/6,3\nMULTAX\nSPINDL/OFF\n";
        assert_eq!(
            kinds(text),
            vec![
                ClKind::PartNo("SPHERE 1".into()),
                ClKind::LoadTool(3),
                ClKind::Spindle(ClSpindle::Rpm { rpm: 2500.0, clockwise: false }),
                ClKind::Feedrate(300.0),
                ClKind::Feedrate(200.0),
                ClKind::Coolant(true),
                ClKind::Rapid,
                ClKind::Circle { centre: [0.0, 0.0, 5.0], axis: [0.0, 0.0, -1.0], radius: Some(10.0) },
                ClKind::Cutter { diameter: 6.0, corner_radius: Some(3.0) },
                ClKind::MultiAxis(true),
                ClKind::Spindle(ClSpindle::Off),
            ]
        );
    }

    /// The records as a CAM system's APT output writes them (aamorim1913/AptPostProcessor,
    /// parts-tools/boss.apt): `PARTNO/1`, `UNIT/MM`, the 7-parameter `CUTTER`, `LOAD/TOOL,1`,
    /// `SELECT/TOOL,5`, `SPINDL/12000,RPM,CLW`, and `CIRCLE` with centre and axis only.
    #[test]
    fn a_cam_systems_records_read() {
        let text = "PARTNO/1\nUNIT/MM\nCUTTER/6.,0,3.,0,0,0,51.\nLOAD/TOOL,1\nSELECT/TOOL,5\n\
                    SPINDL/12000,RPM,CLW\nCIRCLE/95.,44.249705,-3.,0,0,-1.\n";
        assert_eq!(
            kinds(text),
            vec![
                ClKind::PartNo("1".into()),
                ClKind::UnitsMm,
                ClKind::Cutter { diameter: 6.0, corner_radius: Some(0.0) },
                ClKind::LoadTool(1),
                ClKind::SelectTool(5),
                ClKind::Spindle(ClSpindle::Rpm { rpm: 12000.0, clockwise: true }),
                ClKind::Circle { centre: [95.0, 44.249705, -3.0], axis: [0.0, 0.0, -1.0], radius: None },
            ]
        );
        for (bad, column, says) in [
            ("UNIT/INCHES\n", 6, "millimetre"),
            ("LOAD/TOOL,4,ADJUST,1\n", 13, "ADJUST"),
            ("LOAD/TURRET,1\n", 6, "LOAD/TOOL,n"),
            ("SELECT/TOOL\n", 8, "tool number"),
            ("CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0\n", 1, "unknown record CSYS"),
            ("INSERT/Stock Size X95.\n", 1, "unknown record INSERT"),
        ] {
            let e = read(bad).unwrap_err();
            assert_eq!((e.line, e.column), (1, column), "{bad}: {e}");
            assert!(e.message.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = read("GOTO/1,2,3\nGOTO/1,2,x3\n").unwrap_err();
        assert_eq!((e.line, e.column), (2, 10), "{e}");
        let e = read("LOADTL/1\n  TLAXIS/0,0,1\n").unwrap_err();
        assert_eq!((e.line, e.column), (2, 3), "{e}");
        assert!(e.message.contains("unknown record TLAXIS"), "{e}");
        let e = read("GOTO/1,2,3,$\n0,0.5,0.5\n").unwrap_err();
        assert_eq!((e.line, e.column), (2, 1), "the axis starts on the continuation line: {e}");
        let e = read("FEDRAT/10,IPM\n").unwrap_err();
        assert_eq!((e.line, e.column), (1, 11), "{e}");
        let e = read("UNITS/INCHES\n").unwrap_err();
        assert!(e.message.contains("millimetre"), "{e}");
        let e = read("GOTO/1,2\n").unwrap_err();
        assert!(e.message.contains("found 2 arguments"), "{e}");
        let e = read("GOTO/1,2,3,$\n").unwrap_err();
        assert!(e.message.contains("no line follows"), "{e}");
        assert!(read("RAPID 5\n").is_err());
        assert!(read("RAPID/5\n").is_err());
        assert_eq!(kinds("RAPID/\nFINI\n"), vec![ClKind::Rapid, ClKind::End]);
    }

    #[test]
    fn written_records_read_back_the_same() {
        let records = read(
            "PARTNO P\nLOADTL/2\nSPINDL/RPM,3000,CLW\nFEDRAT/480,MMPM\nRAPID\nGOTO/0.1,-2,3e-7,0.6,0,0.8\n\
             CIRCLE/1,2,3,0,0,1,4.5\nGOTO/5.5,2,3\nCOOLNT/OFF\nFINI\n",
        )
        .unwrap();
        let again = read(&write(&records)).unwrap();
        assert_eq!(again, records);
    }
}
