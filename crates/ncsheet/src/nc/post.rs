//! The APT post-processor for a 5-axis mill with an (A,B) swivel head (docs/domain.md §4,
//! Glavonjić): each cutter-location record becomes a block of the one program model.
//!
//! A GOTO's tool axis gives the head angles and the pivot through `geometry::head::head_ab`
//! (A = −asin(a_y), B = atan2(a_x, a_z), pivot = tip + H·a − H·k: the machine zero holds the
//! pivot length H along k, as the paper compensates it), written `G1 X… Y… Z… A… B…`. The same
//! axis is also reached by the other branch (180° − A, B + 180°) and by B ± 360°: the post
//! takes the one inside the head's limits whose B is nearest the previous block's, so B does
//! not jump. Refused, naming the record: a tool axis within a margin of the singular position
//! A = ±90° (where B is undefined), angles outside the limits, a cutting move that turns the
//! head further than the largest swing (the tool would leave the straight line between the
//! points), cutting with no feed or with the spindle stopped, circles not about Z.
//!
//! The program starts as the others ncsheet writes: feed per minute, the tool, the spindle,
//! then a rapid to the clearance height and over the first point with its angles; it ends
//! at the clearance height.

use std::fmt;

use nalgebra::{Point3, Vector3};

use super::apt::{ClKind, ClRecord, ClSpindle};
use super::dialect::ARC_TOLERANCE;
use super::program::{
    ArcDirection, Block, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange, ToolOffset,
};
use crate::geometry::head::head_ab;

/// The head's kinematics and what the machine allows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AbHead {
    /// H: pivot to tool tip (mm).
    pub pivot: f64,
    /// The A axis's travel (degrees), lowest and highest.
    pub a_limits: [f64; 2],
    /// The B axis's travel (degrees).
    pub b_limits: [f64; 2],
    /// Tool axes whose |A| comes within this many degrees of 90° are refused.
    pub singular_margin: f64,
    /// The largest turn of A or B (degrees) in one cutting move.
    pub max_swing: f64,
}

/// A: the paper's head does not reach ±90°; B: half a turn either way.
pub const DEFAULT_A_LIMITS: [f64; 2] = [-90.0, 90.0];
pub const DEFAULT_B_LIMITS: [f64; 2] = [-180.0, 180.0];
pub const DEFAULT_SINGULAR_MARGIN: f64 = 1.0;
pub const DEFAULT_MAX_SWING: f64 = 45.0;

impl AbHead {
    /// The head with pivot length `pivot` and the default limits.
    pub fn new(pivot: f64) -> AbHead {
        AbHead {
            pivot,
            a_limits: DEFAULT_A_LIMITS,
            b_limits: DEFAULT_B_LIMITS,
            singular_margin: DEFAULT_SINGULAR_MARGIN,
            max_swing: DEFAULT_MAX_SWING,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PostOptions {
    pub head: AbHead,
    /// Clearance height of the pivot for the approach and the end; by default 5 mm over the
    /// highest tool tip of the file, rounded up to a whole mm.
    pub clearance: Option<f64>,
    /// The tool called when the file loads none (LOADTL) before its first move.
    pub tool: Option<u32>,
    /// The spindle speed (1/min, clockwise) when the file starts none (SPINDL) before its
    /// first move.
    pub spindle: Option<f64>,
    /// Digits after the point of every number written (the dialect's own when `None`): an
    /// angle rounded to 0.0005° moves the tip by 3.5 µm at H = 400 mm.
    pub decimals: Option<usize>,
}

/// Why a CL file cannot be posted: the record (its line and word) when one is at fault.
#[derive(Clone, Debug, PartialEq)]
pub struct PostError {
    pub record: Option<(usize, &'static str)>,
    pub message: String,
}

impl fmt::Display for PostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.record {
            Some((line, word)) => write!(f, "line {line} ({word}): {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for PostError {}

fn at(record: &ClRecord, message: String) -> PostError {
    PostError { record: Some((record.line, record.word())), message }
}

fn general(message: String) -> PostError {
    PostError { record: None, message }
}

/// The part name of the file's first PARTNO, if any.
pub fn part_name(records: &[ClRecord]) -> Option<&str> {
    records.iter().find_map(|r| match &r.kind {
        ClKind::PartNo(t) if !t.is_empty() => Some(t.as_str()),
        _ => None,
    })
}

/// Head angles within this of each other are the same (the controls write 0.001°).
const SAME_ANGLE: f64 = 1e-6;

/// The program for an (A,B) head that cuts what `records` describe.
pub fn post_ab_head(records: &[ClRecord], name: &str, o: &PostOptions) -> Result<Program, PostError> {
    post_ab_head_traced(records, name, o).map(|(program, _)| program)
}

/// Which record of the CL file each block of a posted program came from, so that a block a
/// dialect cannot write is reported at the line the user wrote (`line 8 (GOTO)`), not by
/// its place in the program.
#[derive(Clone, Debug, Default)]
pub struct BlockSources {
    /// (the 0-based index of the first block a record made, its line, its word), in order.
    starts: Vec<(usize, usize, &'static str)>,
}

impl BlockSources {
    /// The line and word of the record that made block `block` (1-based, as
    /// [`crate::nc::dialect::NcError`] counts); `None` for the blocks the post writes itself
    /// before the first record's.
    pub fn record_of(&self, block: usize) -> Option<(usize, &'static str)> {
        let index = block.checked_sub(1)?;
        let after = self.starts.partition_point(|s| s.0 <= index);
        after.checked_sub(1).map(|i| (self.starts[i].1, self.starts[i].2))
    }
}

/// [`post_ab_head`], with the record each block came from.
pub fn post_ab_head_traced(
    records: &[ClRecord],
    name: &str,
    o: &PostOptions,
) -> Result<(Program, BlockSources), PostError> {
    check_head(&o.head)?;
    let clearance = clearance(records, o.clearance)?;
    let mut post = Post::new(name, o, clearance);
    post.start(records)?;
    let mut sources = BlockSources::default();
    for r in records {
        let first = post.program.blocks.len();
        post.record(r)?;
        if post.program.blocks.len() > first {
            sources.starts.push((first, r.line, r.word()));
        }
    }
    if let Some((line, ..)) = post.circle {
        return Err(PostError {
            record: Some((line, "CIRCLE")),
            message: "a CIRCLE without the GOTO that ends it".into(),
        });
    }
    Ok((post.program, sources))
}

fn check_head(h: &AbHead) -> Result<(), PostError> {
    if !(h.pivot.is_finite() && h.pivot >= 0.0) {
        return Err(general(format!("the pivot length H is a length of 0 or more (mm), not {}", h.pivot)));
    }
    for (axis, [low, high]) in [("A", h.a_limits), ("B", h.b_limits)] {
        if !(low.is_finite() && high.is_finite() && low < high) {
            return Err(general(format!("the {axis} limits {low}:{high} are not a range from low to high")));
        }
    }
    if !(h.singular_margin.is_finite() && (0.0..90.0).contains(&h.singular_margin)) {
        return Err(general(format!("the singular margin is from 0 to 90°, not {}", h.singular_margin)));
    }
    if !(h.max_swing.is_finite() && h.max_swing > 0.0) {
        return Err(general(format!("the largest swing is an angle above 0, not {}", h.max_swing)));
    }
    Ok(())
}

/// The clearance height: given (not below the highest tool tip) or 5 mm over it.
fn clearance(records: &[ClRecord], given: Option<f64>) -> Result<f64, PostError> {
    let highest = records
        .iter()
        .filter_map(|r| match r.kind {
            ClKind::Goto { tip, .. } => Some(tip[2]),
            _ => None,
        })
        .fold(f64::NEG_INFINITY, f64::max);
    if highest == f64::NEG_INFINITY {
        return Err(general("the CL file has no GOTO: nothing to post".into()));
    }
    match given {
        Some(c) if !(c.is_finite() && c >= highest) => Err(general(format!(
            "the clearance {c} is below the highest tool tip of the file (z = {highest}): the approach would run \
             through the part"
        ))),
        Some(c) => Ok(c),
        None => Ok((highest + 5.0).ceil()),
    }
}

/// Where the tool is after a GOTO: its tip, axis and head angles.
#[derive(Clone, Copy, Debug)]
struct Pose {
    tip: Point3<f64>,
    axis: Vector3<f64>,
    a: f64,
    b: f64,
}

/// A CIRCLE record's line, centre, axis and radius (if given), until its GOTO.
type PendingCircle = (usize, [f64; 3], [f64; 3], Option<f64>);

struct Post<'a> {
    o: &'a PostOptions,
    program: Program,
    clearance: f64,
    feed: Option<f64>,
    spindle_on: bool,
    last_rpm: Option<(f64, SpindleDirection)>,
    rapid_next: bool,
    /// A CIRCLE waiting for its GOTO: (line, centre, axis, radius if given).
    circle: Option<PendingCircle>,
    pose: Option<Pose>,
    ended: bool,
}

impl<'a> Post<'a> {
    fn new(name: &str, o: &'a PostOptions, clearance: f64) -> Post<'a> {
        let mut program = Program::new(name, Machine::Mill);
        program.precision = o.decimals;
        program.retract = Some(Target { z: Some(clearance), ..Target::default() });
        program.push(Block::Comment(format!(
            "(A,B) head, pivot H = {} mm. X Y Z: the pivot. A B: the head angles. Tool length offset cancelled \
             at the tool change",
            o.head.pivot
        )));
        program.push(Block::FeedMode(FeedMode::PerMinute));
        Post {
            o,
            program,
            clearance,
            feed: None,
            spindle_on: false,
            last_rpm: None,
            rapid_next: false,
            circle: None,
            pose: None,
            ended: false,
        }
    }

    /// The tool and spindle of the options when the file sets none before its first move.
    fn start(&mut self, records: &[ClRecord]) -> Result<(), PostError> {
        let first = records.iter().position(|r| matches!(r.kind, ClKind::Goto { .. })).expect("clearance found one");
        let before = &records[..first];
        if !before.iter().any(|r| matches!(r.kind, ClKind::LoadTool(_))) {
            let Some(tool) = self.o.tool else {
                return Err(at(&records[first], "no LOADTL before the first move: give the tool (--tool)".into()));
            };
            self.tool(tool);
        }
        if !before.iter().any(|r| matches!(r.kind, ClKind::Spindle(ClSpindle::Rpm { .. }))) {
            let Some(rpm) = self.o.spindle else {
                return Err(at(
                    &records[first],
                    "no SPINDL speed before the first move: give the spindle speed (--spindle)".into(),
                ));
            };
            self.spindle(ClSpindle::Rpm { rpm, clockwise: true });
        }
        Ok(())
    }

    /// The tool change, with the tool length offset cancelled: X Y Z are the pivot, whose
    /// length H the post has compensated already, so the table's length must not be added
    /// (a dialect that cannot cancel it refuses the program).
    fn tool(&mut self, number: u32) {
        self.program.push(Block::Tool(ToolChange { number, offset: ToolOffset::Cancelled }));
    }

    fn spindle(&mut self, s: ClSpindle) -> Option<()> {
        let block = match s {
            ClSpindle::Rpm { rpm, clockwise } => {
                let direction =
                    if clockwise { SpindleDirection::Clockwise } else { SpindleDirection::CounterClockwise };
                self.last_rpm = Some((rpm, direction));
                Spindle::Rpm { rpm, direction }
            }
            ClSpindle::On => {
                let (rpm, direction) = self.last_rpm?;
                Spindle::Rpm { rpm, direction }
            }
            ClSpindle::Off => Spindle::Stop,
        };
        self.spindle_on = block != Spindle::Stop;
        self.program.push(Block::Spindle(block));
        Some(())
    }

    fn record(&mut self, r: &ClRecord) -> Result<(), PostError> {
        if self.ended {
            return Ok(());
        }
        match &r.kind {
            ClKind::PartNo(t) => self.comment(format!("PARTNO {t}")),
            ClKind::Comment(t) => self.comment(t.clone()),
            ClKind::LoadTool(n) => self.tool(*n),
            ClKind::SelectTool(n) => self.comment(format!("next tool {n} (SELECT/TOOL)")),
            ClKind::Spindle(s) => {
                self.spindle(*s).ok_or_else(|| at(r, "SPINDL/ON with no speed given before".into()))?;
            }
            ClKind::Coolant(on) => {
                self.program.push(Block::Coolant(*on));
            }
            ClKind::Feedrate(f) => self.feed = Some(*f),
            ClKind::Rapid if self.circle.is_some() => return Err(at(r, "RAPID after a CIRCLE".into())),
            ClKind::Rapid => self.rapid_next = true,
            ClKind::Circle { .. } if self.rapid_next => return Err(at(r, "a CIRCLE after RAPID".into())),
            ClKind::Circle { centre, axis, radius } => self.circle = Some((r.line, *centre, *axis, *radius)),
            ClKind::Cutter { diameter, corner_radius } => self.comment(match corner_radius {
                Some(cr) => format!("cutter D{diameter} R{cr}"),
                None => format!("cutter D{diameter}"),
            }),
            ClKind::Goto { tip, axis } => self.goto(r, *tip, *axis)?,
            ClKind::From(_) | ClKind::MultiAxis(_) | ClKind::Tolerance(..) | ClKind::UnitsMm => {}
            ClKind::End => self.ended = true,
        }
        Ok(())
    }

    fn comment(&mut self, text: String) {
        if !text.trim().is_empty() {
            self.program.push(Block::Comment(text));
        }
    }

    fn goto(&mut self, r: &ClRecord, tip: [f64; 3], axis: Option<[f64; 3]>) -> Result<(), PostError> {
        let tip = Point3::from(tip);
        let axis = axis.map_or(Vector3::z(), Vector3::from);
        let pose = self.pose_at(tip, axis).map_err(|m| at(r, m))?;
        let target = self.target(&pose);
        if self.pose.is_none() {
            // After the approach the head stands at this point's angles.
            self.approach(&target);
            self.pose = Some(pose);
        }
        if std::mem::take(&mut self.rapid_next) {
            self.program.push(Block::Rapid(target));
            self.pose = Some(pose);
            return Ok(());
        }
        let Some(feed) = self.feed else {
            return Err(at(r, "a cutting move before any FEDRAT".into()));
        };
        if !self.spindle_on {
            return Err(at(r, "a cutting move with the spindle stopped (SPINDL/OFF before it)".into()));
        }
        let previous = self.pose.expect("the approach set a pose");
        let swing = (pose.a - previous.a).abs().max((pose.b - previous.b).abs());
        if swing > self.o.head.max_swing {
            return Err(at(
                r,
                format!(
                    "the head turns from A{:.3} B{:.3} to A{:.3} B{:.3} in one cutting move, more than {}° \
                     (--max-swing): the tool would leave the straight line between the points",
                    previous.a, previous.b, pose.a, pose.b, self.o.head.max_swing
                ),
            ));
        }
        let block = match self.circle.take() {
            Some((_, centre, circle_axis, radius)) => {
                let to = Target { a: None, b: None, ..target };
                self.arc(&previous, &pose, to, centre, circle_axis, radius, feed).map_err(|m| at(r, m))?
            }
            None => Block::Line { to: target, feed: Some(feed) },
        };
        self.program.push(block);
        self.pose = Some(pose);
        Ok(())
    }

    /// The head's angles and pivot for the tool at `tip` along `axis`, on the branch nearest
    /// the previous block's angles (the head's zero before the first).
    fn pose_at(&self, tip: Point3<f64>, axis: Vector3<f64>) -> Result<Pose, String> {
        let h = &self.o.head;
        let pose = head_ab(tip, axis, h.pivot).map_err(|e| e.to_string())?;
        if 90.0 - pose.a_deg.abs() < h.singular_margin {
            return Err(format!(
                "the tool axis ({:.6}, {:.6}, {:.6}) needs A = {:.3}°, within {}° of the head's singular position \
                 A = ±90° where B is undefined (--singular sets the margin)",
                axis.x, axis.y, axis.z, pose.a_deg, h.singular_margin
            ));
        }
        let (pa, pb) = self.pose.map_or((0.0, 0.0), |p| (p.a, p.b));
        let (a, b) = nearest_branch(pose.a_deg, pose.b_deg, (pa, pb), h).ok_or_else(|| {
            format!(
                "the tool axis ({:.6}, {:.6}, {:.6}) needs A = {:.3}°, B = {:.3}° (or A = {:.3}°, B = {:.3}°), \
                 outside the head's travel A {}…{}°, B {}…{}° (--a-limits, --b-limits)",
                axis.x,
                axis.y,
                axis.z,
                pose.a_deg,
                pose.b_deg,
                mirror(pose.a_deg),
                pose.b_deg + 180.0,
                h.a_limits[0],
                h.a_limits[1],
                h.b_limits[0],
                h.b_limits[1]
            )
        })?;
        Ok(Pose { tip, axis: axis.normalize(), a, b })
    }

    /// The programmed pivot and angles: pivot = tip + H·a − H·k (docs/domain.md §4).
    fn target(&self, pose: &Pose) -> Target {
        let p = pivot(pose.tip, pose.axis, self.o.head.pivot);
        Target { x: Some(p.x), y: Some(p.y), z: Some(p.z), a: Some(pose.a), b: Some(pose.b), c: None }
    }

    /// To the clearance height, then over the first point with its head angles.
    fn approach(&mut self, first: &Target) {
        self.program.push(Block::Rapid(Target { z: Some(self.clearance), ..Target::default() }));
        self.program.push(Block::Rapid(Target { z: None, ..*first }));
    }

    /// An arc about Z from `from` to `to` (the tool axis unchanged): the pivot runs the same
    /// circle shifted by H·(a_x, a_y).
    #[allow(clippy::too_many_arguments)]
    fn arc(
        &self,
        from: &Pose,
        to_pose: &Pose,
        to: Target,
        centre: [f64; 3],
        axis: [f64; 3],
        radius: Option<f64>,
        feed: f64,
    ) -> Result<Block, String> {
        if axis[0].abs() > 1e-6 || axis[1].abs() > 1e-6 {
            return Err(format!(
                "the CIRCLE's axis ({}, {}, {}) is not along Z: only arcs in the XY plane are written",
                axis[0], axis[1], axis[2]
            ));
        }
        if (from.axis - to_pose.axis).norm() > 1e-6 {
            return Err("the tool axis changes along a CIRCLE: the head cannot turn during an arc".into());
        }
        if (from.tip.z - to_pose.tip.z).abs() > 1e-6 {
            return Err("the CIRCLE's end is at another height than its start: helices are not written".into());
        }
        // A CIRCLE without its radius runs through its start point.
        let radius = radius.unwrap_or_else(|| (from.tip.x - centre[0]).hypot(from.tip.y - centre[1]));
        for (what, p) in [("start", from.tip), ("end", to_pose.tip)] {
            let r = (p.x - centre[0]).hypot(p.y - centre[1]);
            if (r - radius).abs() > ARC_TOLERANCE {
                return Err(format!(
                    "the arc's {what} is {r:.4} mm from the CIRCLE's centre, not its radius {radius} (within \
                     {ARC_TOLERANCE} mm)"
                ));
            }
        }
        let h = self.o.head.pivot;
        let shifted = Target::xy(centre[0] + h * from.axis.x, centre[1] + h * from.axis.y);
        let direction = if axis[2] > 0.0 { ArcDirection::CounterClockwise } else { ArcDirection::Clockwise };
        Ok(Block::Arc { direction, to, centre: shifted, feed: Some(feed) })
    }
}

/// The programmed pivot for the tool tip at `tip` along the unit `axis`, pivot length `h`.
fn pivot(tip: Point3<f64>, axis: Vector3<f64>, h: f64) -> Point3<f64> {
    Point3::new(tip.x + h * axis.x, tip.y + h * axis.y, tip.z + h * (axis.z - 1.0))
}

/// The other branch's A: R_X(180° − A) after R_Y(B + 180°) gives the same axis.
fn mirror(a: f64) -> f64 {
    if a >= 0.0 {
        180.0 - a
    } else {
        -180.0 - a
    }
}

/// Of the angle pairs that give the tool axis of (`a`, `b`) — both branches, B give or take
/// whole turns — the one inside the limits whose B is nearest `previous`'s, then whose A is.
fn nearest_branch(a: f64, b: f64, previous: (f64, f64), h: &AbHead) -> Option<(f64, f64)> {
    let inside = |v: f64, [low, high]: [f64; 2]| v >= low - SAME_ANGLE && v <= high + SAME_ANGLE;
    let mut best: Option<(f64, f64)> = None;
    for (a, b) in [(a, b), (mirror(a), b + 180.0)] {
        for turns in -2..=2 {
            let b = b + 360.0 * f64::from(turns);
            if !(inside(a, h.a_limits) && inside(b, h.b_limits)) {
                continue;
            }
            let key = |(a, b): (f64, f64)| ((b - previous.1).abs(), (a - previous.0).abs());
            if best.is_none_or(|old| key((a, b)) < key(old)) {
                best = Some((a, b));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nc::apt;

    fn options(h: f64) -> PostOptions {
        PostOptions { head: AbHead::new(h), clearance: None, tool: Some(1), spindle: Some(1000.0), decimals: None }
    }

    fn moves(p: &Program) -> Vec<Target> {
        p.blocks
            .iter()
            .filter_map(|b| match b {
                Block::Line { to, .. } => Some(*to),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn b_stays_continuous_across_the_half_turn() {
        // The tool axis turning in the XZ plane past −Z: B = atan2(a_x, a_z) jumps from +179°
        // to −179° there; with room in its limits the head keeps going to 181°.
        let axis = |deg: f64| {
            let t = deg.to_radians();
            format!("{:.9},0,{:.9}", t.sin(), t.cos())
        };
        let text = format!("FEDRAT/100\nGOTO/0,0,0,{}\nGOTO/0,0,0,{}\n", axis(179.0), axis(181.0));
        let mut o = options(0.0);
        o.head.b_limits = [-360.0, 360.0];
        let p = post_ab_head(&apt::read(&text).unwrap(), "T", &o).unwrap();
        let b: Vec<f64> = moves(&p).iter().map(|t| t.b.unwrap()).collect();
        assert!((b[0] - 179.0).abs() < 1e-6 && (b[1] - 181.0).abs() < 1e-6, "{b:?}");
    }

    #[test]
    fn the_half_turn_outside_the_limits_is_refused_by_the_swing() {
        let text = "FEDRAT/100\nGOTO/0,0,0,0.0174524064,0,-0.9998476952\nGOTO/0,0,0,-0.0174524064,0,-0.9998476952\n";
        let e = post_ab_head(&apt::read(text).unwrap(), "T", &options(0.0)).unwrap_err();
        assert_eq!(e.record, Some((3, "GOTO")), "{e}");
        assert!(e.message.contains("--max-swing"), "{e}");
    }

    #[test]
    fn cutting_needs_a_feed_and_a_turning_spindle() {
        let e = post_ab_head(&apt::read("GOTO/0,0,0\n").unwrap(), "T", &options(0.0)).unwrap_err();
        assert!(e.to_string().starts_with("line 1 (GOTO): a cutting move before any FEDRAT"), "{e}");
        let text = "FEDRAT/9\nRAPID\nGOTO/0,0,5\nSPINDL/OFF\nGOTO/0,0,0\n";
        let e = post_ab_head(&apt::read(text).unwrap(), "T", &options(0.0)).unwrap_err();
        assert_eq!(e.record, Some((5, "GOTO")), "{e}");
    }

    #[test]
    fn the_clearance_is_over_the_highest_tip() {
        let text = "FEDRAT/9\nGOTO/0,0,12.2\n";
        let p = post_ab_head(&apt::read(text).unwrap(), "T", &options(0.0)).unwrap();
        assert_eq!(p.retract, Some(Target { z: Some(18.0), ..Target::default() }));
        let mut o = options(0.0);
        o.clearance = Some(12.0);
        assert!(post_ab_head(&apt::read(text).unwrap(), "T", &o).is_err());
    }
}
