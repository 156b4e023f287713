//! The milling program of a ball-end mill's finishing path (docs/domain.md §3), built on the NC
//! model so that any milling dialect writes it: to the clearance height, above the first
//! point, down at the feed, along each raster line; the link to the next line cuts unless
//! the options ask for a retract.

use nalgebra::{Point3, Vector3};

use super::apt::{ClKind, ClRecord, ClSpindle};
use super::program::{Block, FeedMode, Machine, Program, Spindle, SpindleDirection, Target, ToolChange};
use crate::geometry::ballpath::{BallPath, PathPoint};

/// Which point of the ball the program moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ProgrammedPoint {
    /// The ball's lowest point (centre − R in z), what a tool length set to the tip follows.
    #[default]
    Tip,
    Centre,
}

impl ProgrammedPoint {
    /// The programmed point of ball position `i`.
    pub fn of(self, path: &BallPath, i: usize) -> Point3<f64> {
        let p = &path.points[i];
        match self {
            ProgrammedPoint::Tip => p.tip(path.radius),
            ProgrammedPoint::Centre => p.centre,
        }
    }

    /// The highest programmed point of the path (−∞ for an empty one).
    pub fn highest(self, path: &BallPath) -> f64 {
        (0..path.points.len()).map(|i| self.of(path, i).z).fold(f64::NEG_INFINITY, f64::max)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallPathNcOptions {
    pub point: ProgrammedPoint,
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// The tool called at the start.
    pub tool: u32,
    /// Spindle speed, 1/min (M3).
    pub spindle: f64,
    /// Rapid up to the clearance height between lines instead of cutting across.
    pub retract: bool,
    /// Clearance height for approach, retracts and end; by default 5 mm over the highest
    /// programmed point, rounded up to a whole mm.
    pub clearance: Option<f64>,
    /// The rectangle the path covers (x and y ranges), for the program's blank.
    pub x: [f64; 2],
    pub y: [f64; 2],
    /// For the 5-axis cutter-location file: the tool axis inclined from the surface normal
    /// by these angles (degrees): `lead` along the feed (the axis leaning forwards), `tilt`
    /// across it (towards n × feed), so that the ball does not cut with its centre. 0, 0:
    /// the axis along the normal.
    pub lead_deg: f64,
    pub tilt_deg: f64,
}

/// The paper's program for `path`, named `name`. The points are written as they are: a path
/// for a dialect's decimals is the one `geometry::ballpath::ball_path_as_written` made, its
/// programmed points already on the grid and checked there (issue 32, scope 5).
pub fn ball_path_program(path: &BallPath, name: &str, o: &BallPathNcOptions) -> Program {
    let at = |i: usize| o.point.of(path, i);
    let clearance = o.clearance.unwrap_or((o.point.highest(path) + 5.0).ceil());
    let mut p = Program::new(name, Machine::Mill);
    p.blocks.reserve(path.points.len() + 4 * path.line_starts.len() + 8);
    // The stock, not the path: a lifted ball touches higher than the surface's lowest point.
    let [low, high] = path.surface_z;
    p.blank = Some(([o.x[0], o.y[0], low], [o.x[1], o.y[1], high]));
    let what = match o.point {
        ProgrammedPoint::Tip => "ball tip (centre - R in Z)",
        ProgrammedPoint::Centre => "ball centre",
    };
    p.push(Block::Comment(format!("ball-end mill R{}: programmed point is the {what}", path.radius)));
    let up = Target { z: Some(clearance), ..Target::default() };
    p.retract = Some(up);
    p.push(Block::FeedMode(FeedMode::PerMinute));
    p.push(Block::Tool(ToolChange::new(o.tool)));
    p.push(Block::Spindle(Spindle::Rpm { rpm: o.spindle, direction: SpindleDirection::Clockwise }));
    p.push(Block::Rapid(up));
    for (k, &start) in path.line_starts.iter().enumerate() {
        let end = path.line_starts.get(k + 1).copied().unwrap_or(path.points.len());
        if k == 0 || o.retract {
            if k > 0 {
                p.push(Block::Rapid(up));
            }
            let first = at(start);
            p.push(Block::Rapid(Target::xy(first.x, first.y)));
        }
        p.blocks.extend((start..end).map(|i| {
            let q = at(i);
            Block::Line { to: Target::xyz(q.x, q.y, q.z), feed: Some(o.feed) }
        }));
    }
    p
}

/// The tool axis of a ball position for a 5-axis cut: from the contact point to the ball's
/// centre, the outward surface normal there (a lifted ball touches where it was lifted to).
pub fn tool_axis(p: &PathPoint) -> Vector3<f64> {
    (p.centre - p.contact).normalize()
}

/// The tool tip of a ball-end mill standing along [`tool_axis`]: R from the centre back
/// along the axis, which is the contact point itself.
pub fn axial_tip(p: &PathPoint, radius: f64) -> Point3<f64> {
    p.centre - tool_axis(p) * radius
}

/// The tool axis inclined from the normal `n` by `lead` (radians, towards the feed `f`) and
/// `tilt` (across the feed, towards n × f): a = sin(tilt)·c + cos(tilt)·(cos(lead)·n +
/// sin(lead)·f), with f taken into the tangent plane. Then atan2(a·f, a·n) = lead and
/// asin(a·c) = tilt. Along the normal when the feed has no part in the tangent plane.
pub fn inclined_axis(n: Vector3<f64>, feed: Vector3<f64>, lead: f64, tilt: f64) -> Vector3<f64> {
    let along = feed - n * feed.dot(&n);
    if along.norm() <= 1e-12 * feed.norm().max(1e-300) {
        return n;
    }
    let f = along.normalize();
    let c = n.cross(&f);
    (c * tilt.sin() + (n * lead.cos() + f * lead.sin()) * tilt.cos()).normalize()
}

/// The feed direction at ball position `i` of the line `start..end`: towards the next centre,
/// or from the one before at the line's end.
fn feed_at(path: &BallPath, i: usize, start: usize, end: usize) -> Vector3<f64> {
    let c = |k: usize| path.points[k].centre;
    if i + 1 < end {
        c(i + 1) - c(i)
    } else if i > start {
        c(i) - c(i - 1)
    } else {
        Vector3::zeros()
    }
}

/// The same finishing path as an APT cutter-location file for a 5-axis post (`ncsheet
/// post`): each ball position a `GOTO` of the tool tip with the tool axis along the surface
/// normal, or inclined from it by `o.lead_deg`/`o.tilt_deg` ([`inclined_axis`]; the ball's
/// centre stays at contact + R·n, the tip R back along the axis), lines linked as in [`ball_path_program`] (`o.point` does not apply: a CL point is
/// the tip along the axis).
pub fn ball_path_cl(path: &BallPath, name: &str, o: &BallPathNcOptions) -> Vec<ClRecord> {
    let r = path.radius;
    let goto = |tip: Point3<f64>, axis: Vector3<f64>| ClKind::Goto { tip: tip.into(), axis: Some(axis.into()) };
    let inclined = o.lead_deg != 0.0 || o.tilt_deg != 0.0;
    // Every ball position's tool axis, the line it is on known.
    let mut axes = Vec::with_capacity(path.points.len());
    for (k, &start) in path.line_starts.iter().enumerate() {
        let end = path.line_starts.get(k + 1).copied().unwrap_or(path.points.len());
        axes.extend((start..end).map(|i| {
            let n = tool_axis(&path.points[i]);
            if inclined {
                inclined_axis(n, feed_at(path, i, start, end), o.lead_deg.to_radians(), o.tilt_deg.to_radians())
            } else {
                n
            }
        }));
    }
    // The ball's centre stays where it touches the surface; the tip is R back along the axis.
    let tip = |i: usize| path.points[i].centre - axes[i] * r;
    let highest = (0..path.points.len()).map(|i| tip(i).z).fold(f64::NEG_INFINITY, f64::max);
    let clearance = o.clearance.unwrap_or((highest + 5.0).ceil());
    let above = |i: usize| {
        let t = tip(i);
        goto(Point3::new(t.x, t.y, clearance), axes[i])
    };
    let axis_words = if inclined {
        format!("the surface normal inclined {}° along the feed and {}° across it", o.lead_deg, o.tilt_deg)
    } else {
        "the surface normal".to_string()
    };
    let mut kinds = vec![
        ClKind::PartNo(name.to_string()),
        ClKind::Comment(format!("ball-end mill R{r}: GOTO is the tool tip, the tool axis {axis_words}")),
        ClKind::UnitsMm,
        ClKind::Cutter { diameter: 2.0 * r, corner_radius: Some(r) },
        ClKind::MultiAxis(true),
        ClKind::LoadTool(o.tool),
        ClKind::Spindle(ClSpindle::Rpm { rpm: o.spindle, clockwise: true }),
        ClKind::Feedrate(o.feed),
    ];
    kinds.reserve(path.points.len() + 4 * path.line_starts.len() + 2);
    for (k, &start) in path.line_starts.iter().enumerate() {
        let end = path.line_starts.get(k + 1).copied().unwrap_or(path.points.len());
        if k == 0 || o.retract {
            if k > 0 {
                kinds.extend([ClKind::Rapid, above(start - 1)]);
            }
            kinds.extend([ClKind::Rapid, above(start)]);
        }
        kinds.extend((start..end).map(|i| goto(tip(i), axes[i])));
    }
    if !path.points.is_empty() {
        kinds.extend([ClKind::Rapid, above(path.points.len() - 1)]);
    }
    kinds.push(ClKind::End);
    kinds.into_iter().enumerate().map(|(i, kind)| ClRecord { line: i + 1, kind }).collect()
}
