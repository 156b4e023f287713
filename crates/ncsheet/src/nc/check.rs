//! What a programmer checks before a program runs: arcs whose end is off the circle through
//! their start, cuts with no feed mode, feed, turning spindle or tool before them, cuts with no
//! tool offset in force (coordinates of the spindle, not the tip), cuts from an
//! unknown position, moves below a stated Z, rapids through the stock (other than straight
//! out of a cut) and cuts below its bottom. Each finding names the block of the program model; the command line turns it into
//! a line. Pure: the geometry is the backplot's.

use super::backplot::{toolpath, Move, MoveKind, PlotError};
use super::program::{Block, Compensation, FeedMode, Machine, Program, Spindle, Target, ToolOffset};

/// How far an arc's end may lie off the circle through its start and around its centre, in mm,
/// unless asked otherwise: ncsheet's own writers refuse more (docs/dialects.md). It is
/// stricter than LinuxCNC 2.9, which refuses an arc only past 0.02·√2 mm
/// (`CENTER_ARC_RADIUS_TOLERANCE_MM`) and 0.1 % of the radius together.
pub const ARC_TOLERANCE_MM: f64 = 0.002;

/// LinuxCNC's limits on an arc's radius difference in a mm program: absolute and relative,
/// both exceeded for an error (its interpreter's defaults, as rs274 2.9 applies them).
const LINUXCNC_ARC_ABS_MM: f64 = 0.02 * std::f64::consts::SQRT_2;
const LINUXCNC_ARC_REL: f64 = 0.001;

/// What to check beyond the program's own consistency.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckOptions<'a> {
    /// Arc end off its circle, mm.
    pub tolerance: f64,
    /// No point of any move below this Z.
    pub min_z: Option<f64>,
    /// The stock as (lowest corner, highest corner) in program coordinates (a lathe's X a
    /// diameter; Y is not used on a lathe): no rapid through it, no cut below its bottom.
    pub stock: Option<([f64; 3], [f64; 3])>,
    /// Tool diameters (mm) by tool number, from the control's tool table: compensation entry
    /// moves are checked against the radius as LinuxCNC checks them. Empty: not checked.
    pub tool_diameters: &'a [(u32, f64)],
    /// The feed mode the control is in before the program sets one ([`power_on_feed_mode`]):
    /// a cut needs no G94 where the control powers on in it.
    pub power_on_feed_mode: Option<FeedMode>,
}

impl Default for CheckOptions<'_> {
    fn default() -> Self {
        CheckOptions {
            tolerance: ARC_TOLERANCE_MM,
            min_z: None,
            stock: None,
            tool_diameters: &[],
            power_on_feed_mode: None,
        }
    }
}

/// The feed mode a control of `dialect` is in at power on and after a reset, for `machine`:
/// feed per minute on every mill here (LinuxCNC's documented start-up modes G17 G21/G20 G40
/// G49 G80 G90 G94; a Fanuc mill's G94 unless parameter 3402 says otherwise; Sinumerik's
/// reset value of the feed group, G94; plain language has only F in mm/min), and per
/// revolution on NC31 (and NC81, written with its words), which has no other. A lathe's mode depends on the machine's set-up
/// (a Fanuc lathe's parameter, LinuxCNC's start-up code), so a lathe cut needs its own.
pub fn power_on_feed_mode(dialect: &dyn crate::nc::dialect::Dialect, machine: Machine) -> Option<FeedMode> {
    match (dialect.name(), machine) {
        ("nc31" | "nc81", _) => Some(FeedMode::PerRevolution),
        (_, Machine::Mill) => Some(FeedMode::PerMinute),
        (_, Machine::Lathe) => None,
    }
}

/// One thing found, at a block of the program model (1-based).
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    pub block: usize,
    pub message: String,
}

/// Everything found in `program`, in block order.
pub fn check(program: &Program, options: &CheckOptions<'_>) -> Result<Vec<Finding>, PlotError> {
    let path = toolpath(program)?;
    let mut findings = state_findings(program, &path.moves, options.power_on_feed_mode.is_some());
    if !options.tool_diameters.is_empty() {
        findings.extend(compensation_entries(program, &path.moves, options.tool_diameters));
    }
    let stock = options.stock.map(|s| true_box(program.machine, s));
    for m in &path.moves {
        let mut say = |message: String| findings.push(Finding { block: m.block, message });
        if let Some(message) = arc_off_circle(m, options.tolerance) {
            say(message);
        }
        let (lo, _) = m.bounds();
        if let Some(z) = options.min_z.filter(|z| lo[2] < *z) {
            say(format!("the move goes down to Z{}, below --min-z {}", mm(lo[2]), mm(z)));
        }
        if let Some((s_lo, s_hi)) = stock {
            if m.kind == MoveKind::Rapid && crosses_inside(m.from, m.to, s_lo, s_hi) && !is_retract(m, program.machine)
            {
                say("a rapid move through the stock (G0 in material)".into());
            }
            if m.kind == MoveKind::Feed && lo[2] < s_lo[2] {
                say(format!("the cut goes down to Z{}, below the stock's bottom Z{}", mm(lo[2]), mm(s_lo[2])));
            }
        }
    }
    findings.sort_by_key(|f| f.block);
    Ok(findings)
}

/// The machine's state at each cut: feed mode, feed, spindle and tool set before it, and a
/// known position to cut from. Each missing thing is said once, at the first cut without it
/// (the spindle again at the first cut after each stop).
fn state_findings(program: &Program, moves: &[Move], feed_mode_at_power_on: bool) -> Vec<Finding> {
    let mut out = Vec::new();
    let mut feed_mode = feed_mode_at_power_on;
    // A program that tilts a head (A/B) without tool-tip control positions the head's pivot:
    // the tool's length is in its coordinates (the post's pivot = tip + H·axis), so the
    // control's length offset is off on purpose.
    let pivot_program = program.blocks.iter().any(moves_head);
    let mut feed = false;
    let mut tool = false;
    // Whether the tool's offset is in force; said once after each change that cancels it.
    let mut offset = true;
    let mut said_offset = false;
    let mut turning = false;
    let mut said = [false; 4];
    let mut said_spindle = false;
    let mut drawn = vec![false; program.blocks.len() + 1];
    for m in moves {
        drawn[m.block] = true;
    }
    for (i, b) in program.blocks.iter().enumerate() {
        let block = i + 1;
        let mut say = |message: &str| out.push(Finding { block, message: message.to_string() });
        match b {
            Block::FeedMode(_) => feed_mode = true,
            Block::Tool(t) => {
                tool = true;
                offset = t.offset != ToolOffset::Cancelled;
                said_offset = false;
            }
            Block::LengthOffset(o) => {
                offset = *o != ToolOffset::Cancelled;
                said_offset = false;
            }
            Block::Spindle(s) => {
                turning = !matches!(s, Spindle::Stop);
                // After a stop, the next cut without a start is said again.
                said_spindle &= turning;
            }
            Block::Line { feed: f, .. } | Block::Arc { feed: f, .. } => {
                feed |= f.is_some();
                let checks = [
                    (feed_mode, "a cut with no feed mode (G94/G95, G98/G99 on a Fanuc lathe) set before it"),
                    (feed, "a cut with no feed F programmed before it"),
                    (tool, "a cut with no tool selected (T) before it"),
                    (drawn[block], "a cut from an unknown position (no move has set every axis before it)"),
                ];
                for (k, (ok, message)) in checks.into_iter().enumerate() {
                    if !ok && !said[k] {
                        said[k] = true;
                        say(message);
                    }
                }
                if tool && !offset && !said_offset && !pivot_program {
                    said_offset = true;
                    say("a cut with no tool offset in force (a tool change without G43, or G49, D0, T0100): the \
                         coordinates are the spindle's point, the tool tip is its length below them");
                }
                if !turning && !said_spindle {
                    said_spindle = true;
                    say("a cut with the spindle not turning (no M3/M4 with S since the start or the last M5)");
                }
            }
            _ => {}
        }
    }
    out
}

/// Cutter compensation turned on is taken up along the next move in the plane; LinuxCNC
/// refuses that entry move when it is not longer than the tool's radius ("Length of cutter
/// compensation entry move is not greater than the tool radius"), and a tool the table does
/// not hold has no radius to compensate by.
fn compensation_entries(program: &Program, moves: &[Move], diameters: &[(u32, f64)]) -> Vec<Finding> {
    let mut out = Vec::new();
    let mut tool = None;
    let mut entering = false;
    for (i, b) in program.blocks.iter().enumerate() {
        let block = i + 1;
        match b {
            Block::Tool(t) => tool = Some(t.number),
            Block::Compensation(Compensation::Off) => entering = false,
            Block::Compensation(_) => {
                entering = true;
                // The radius comes from the program's own register (G41 D21) or the tool's.
                let entry = program.radius_offset.or(tool);
                let known = entry.is_some_and(|t| diameters.iter().any(|(n, _)| *n == t));
                if !known {
                    let which = match (program.radius_offset, tool) {
                        (Some(d), _) => format!("register D{d}"),
                        (None, Some(t)) => format!("tool T{t}"),
                        (None, None) => "no tool".to_string(),
                    };
                    out.push(Finding {
                        block,
                        message: format!("cutter compensation with {which}, which the tool table does not hold"),
                    });
                    entering = false;
                }
            }
            Block::Line { .. } | Block::Arc { .. } if entering => {
                let Some(m) = moves.iter().find(|m| m.block == block) else { continue };
                let planar = (m.to[0] - m.from[0]).hypot(m.to[1] - m.from[1]);
                if planar == 0.0 {
                    continue;
                }
                entering = false;
                let radius = program
                    .radius_offset
                    .or(tool)
                    .and_then(|t| diameters.iter().find(|(n, _)| *n == t))
                    .map_or(0.0, |(_, d)| d / 2.0);
                if planar <= radius {
                    out.push(Finding {
                        block,
                        message: format!(
                            "the cutter compensation entry move is {} mm long, not longer than the tool's radius {} \
                             mm (LinuxCNC refuses it)",
                            mm(planar),
                            mm(radius)
                        ),
                    });
                }
            }
            _ => {}
        }
    }
    out
}

/// A LinuxCNC tool table (`.tbl`): `T1 P1 D10 Z50 ;comment`, one tool a line, as (tool
/// number, diameter) in the table's units. A line without T or D holds no diameter; any
/// other word is the table's own (pocket, offsets, angles).
pub fn read_tool_table(text: &str) -> Result<Vec<(u32, f64)>, String> {
    let mut tools = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let code = line.split(';').next().unwrap_or("");
        let mut number = None;
        let mut diameter = None;
        for word in code.split_whitespace() {
            let (letter, value) = word.split_at(1);
            let bad = || format!("line {}: `{word}` is not a tool table word (T1, P1, D10, Z50 …)", i + 1);
            match letter.to_ascii_uppercase().as_str() {
                "T" => number = Some(value.parse::<u32>().map_err(|_| bad())?),
                "D" => {
                    diameter = Some(value.parse::<f64>().ok().filter(|d| d.is_finite() && *d >= 0.0).ok_or_else(bad)?)
                }
                _ => {}
            }
        }
        if let (Some(t), Some(d)) = (number, diameter) {
            tools.push((t, d));
        }
    }
    Ok(tools)
}

/// Whether a move sets a head's tilt (A or B).
fn moves_head(block: &Block) -> bool {
    let tilts = |t: &Target| t.a.is_some() || t.b.is_some();
    match block {
        Block::Rapid(t) | Block::Line { to: t, .. } | Block::Arc { to: t, .. } => tilts(t),
        _ => false,
    }
}

/// Why an arc's end is off the circle through its start, if it is by more than `tolerance`.
fn arc_off_circle(m: &Move, tolerance: f64) -> Option<String> {
    let c = m.arc?;
    let (u, v) = c.axes;
    let r_start = (m.from[u] - c.centre[u]).hypot(m.from[v] - c.centre[v]);
    let r_end = (m.to[u] - c.centre[u]).hypot(m.to[v] - c.centre[v]);
    let off = (r_end - r_start).abs();
    if off <= tolerance {
        return None;
    }
    let linuxcnc = off > LINUXCNC_ARC_ABS_MM && off > LINUXCNC_ARC_REL * r_start.max(r_end);
    Some(format!(
        "the arc's end is {} mm off the circle through its start (radius {} at the start, {} at the end; \
         tolerance {} mm); LinuxCNC {} it",
        mm(off),
        mm(r_start),
        mm(r_end),
        tolerance,
        if linuxcnc { "refuses" } else { "accepts" }
    ))
}

/// The stock in the backplot's true lengths: a lathe's X diameters halved, its Y any.
fn true_box(machine: Machine, (lo, hi): ([f64; 3], [f64; 3])) -> ([f64; 3], [f64; 3]) {
    match machine {
        Machine::Lathe => ([lo[0] / 2.0, f64::NEG_INFINITY, lo[2]], [hi[0] / 2.0, f64::INFINITY, hi[2]]),
        Machine::Mill => (lo, hi),
    }
}

/// A rapid straight out of a cut: only along the axis the tool leaves the part by (+Z on a
/// mill, +X on a lathe). Where a cut left the tool inside the stated stock, the material
/// above it is gone, so this is not a rapid through the stock.
fn is_retract(m: &Move, machine: Machine) -> bool {
    let axis = if machine == Machine::Lathe { 0 } else { 2 };
    (0..3).all(|i| if i == axis { m.to[i] >= m.from[i] } else { m.to[i] == m.from[i] })
}

/// Whether the straight move from `a` to `b` passes through the box's inside (touching a face
/// is not inside).
fn crosses_inside(a: [f64; 3], b: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> bool {
    const EPS: f64 = 1e-6;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        let (l, h) = (lo[i] + EPS, hi[i] - EPS);
        let d = b[i] - a[i];
        if d == 0.0 {
            if a[i] <= l || a[i] >= h {
                return false;
            }
        } else {
            let (ta, tb) = ((l - a[i]) / d, (h - a[i]) / d);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
    }
    t0 < t1
}

/// A length to 0.1 µm, trailing zeros dropped.
fn mm(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}
