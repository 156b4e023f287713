//! A program's tool path as a backplot shows it: every move from a known position as a line
//! or an arc in true lengths (a lathe's X diameter halved to a radius), its bounding box with
//! the arcs' extreme points, and the SVG drawing of it in a chosen plane (rapids dashed, feeds
//! solid, arcs as SVG arcs, start and direction marked, a scale bar and a legend). Pure: the
//! command line reads the program and writes the drawing.

use std::f64::consts::{FRAC_PI_2, TAU};
use std::fmt::Write;

use nalgebra::Point2;

use super::program::{ArcDirection, Block, Machine, Program, Target};
use super::svg::{self, fixed, Labels};

/// Why a program cannot be plotted: the block at fault.
pub type PlotError = super::program::BlockError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveKind {
    Rapid,
    Feed,
}

/// The circle an arc runs on: its centre, and the plane it turns in as the indices (u, v) of
/// two axes (0 X, 1 Y, 2 Z) whose cross product is the plane's normal: (X, Y) on a mill
/// (G17), (Z, X) on a lathe (G18); `ccw` seen from the normal's tip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    pub centre: [f64; 3],
    pub axes: (usize, usize),
    pub ccw: bool,
}

/// One move, in true lengths (mm; a lathe's X as a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// 1-based block of the program model.
    pub block: usize,
    pub kind: MoveKind,
    pub from: [f64; 3],
    pub to: [f64; 3],
    pub arc: Option<Circle>,
}

/// Steps of a curve drawn as a polyline (an arc seen edge-on or a helix from the side).
const SAMPLE_STEP: f64 = TAU / 72.0;

impl Move {
    /// The arc's radius (from its start), start angle and sweep (rad, > 0, 2π for a full
    /// circle) in its plane.
    pub fn arc_angles(&self) -> Option<(f64, f64, f64)> {
        let c = self.arc?;
        let (u, v) = c.axes;
        let (su, sv) = (self.from[u] - c.centre[u], self.from[v] - c.centre[v]);
        let (eu, ev) = (self.to[u] - c.centre[u], self.to[v] - c.centre[v]);
        let (a0, a1) = (sv.atan2(su), ev.atan2(eu));
        let turn = if c.ccw { a1 - a0 } else { a0 - a1 };
        let mut sweep = turn.rem_euclid(TAU);
        // An end on its start is a full circle, as the controls read it.
        if sweep < 1e-12 {
            sweep = TAU;
        }
        Some((su.hypot(sv), a0, sweep))
    }

    /// The point at fraction `t` of the move; along an arc the axis across its plane moves
    /// in proportion (a helix).
    pub fn point(&self, t: f64) -> [f64; 3] {
        let mut p = lerp(self.from, self.to, t);
        if let (Some(c), Some((r, a0, sweep))) = (self.arc, self.arc_angles()) {
            let a = if c.ccw { a0 + t * sweep } else { a0 - t * sweep };
            p[c.axes.0] = c.centre[c.axes.0] + r * a.cos();
            p[c.axes.1] = c.centre[c.axes.1] + r * a.sin();
        }
        p
    }

    /// The smallest box holding the whole move: its ends and, on an arc, the points where
    /// it turns along an axis of its plane (every quarter of the circle it passes).
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = self.from;
        let mut hi = self.from;
        grow(&mut lo, &mut hi, self.to);
        if let (Some(c), Some((r, a0, sweep))) = (self.arc, self.arc_angles()) {
            // The quadrant points exactly, not through cos and sin of multiples of π/2.
            for (k, (cos, sin)) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)].into_iter().enumerate() {
                let theta = k as f64 * FRAC_PI_2;
                let along = if c.ccw { theta - a0 } else { a0 - theta }.rem_euclid(TAU);
                if along <= sweep {
                    let mut p = self.from;
                    p[c.axes.0] = c.centre[c.axes.0] + r * cos;
                    p[c.axes.1] = c.centre[c.axes.1] + r * sin;
                    // The axis across the plane stays within the ends' range.
                    grow(&mut lo, &mut hi, p);
                }
            }
        }
        (lo, hi)
    }
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t]
}

fn grow(lo: &mut [f64; 3], hi: &mut [f64; 3], p: [f64; 3]) {
    for i in 0..3 {
        lo[i] = lo[i].min(p[i]);
        hi[i] = hi[i].max(p[i]);
    }
}

/// The moves of a program in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Toolpath {
    pub machine: Machine,
    pub moves: Vec<Move>,
}

impl Toolpath {
    /// Where the path starts: the first position at which every axis the program uses is
    /// known (the moves before it go from wherever the machine stood).
    pub fn start(&self) -> Option<[f64; 3]> {
        self.moves.first().map(|m| m.from)
    }

    /// The box holding every move, arcs' extreme points included.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let mut moves = self.moves.iter();
        let (mut lo, mut hi) = moves.next()?.bounds();
        for m in moves {
            let (a, b) = m.bounds();
            grow(&mut lo, &mut hi, a);
            grow(&mut lo, &mut hi, b);
        }
        Some((lo, hi))
    }
}

/// The moves of `program` from the first fully known position on. An axis the program never
/// sets stays at 0 (Y on a lathe); a lathe's X is halved to a radius.
pub fn toolpath(program: &Program) -> Result<Toolpath, PlotError> {
    let lathe = program.machine == Machine::Lathe;
    let true_x = |t: &Target| t.x.map(|x| if lathe { x / 2.0 } else { x });
    let axes_of = |t: &Target| [true_x(t), t.y, t.z];
    let mut used = [false; 3];
    for b in &program.blocks {
        if let Block::Rapid(t) | Block::Line { to: t, .. } | Block::Arc { to: t, .. } = b {
            for (u, v) in used.iter_mut().zip(axes_of(t)) {
                *u |= v.is_some();
            }
        }
    }
    let mut at: [Option<f64>; 3] = [0, 1, 2].map(|i| (!used[i]).then_some(0.0));
    let mut moves = Vec::new();
    for (i, b) in program.blocks.iter().enumerate() {
        let (to, kind, arc) = match b {
            Block::Rapid(t) => (t, MoveKind::Rapid, None),
            Block::Line { to, .. } => (to, MoveKind::Feed, None),
            Block::Arc { direction, to, centre, .. } => (to, MoveKind::Feed, Some((direction, centre))),
            _ => continue,
        };
        let from = at;
        for (a, v) in at.iter_mut().zip(axes_of(to)) {
            if v.is_some() {
                *a = v;
            }
        }
        let (Some(from), Some(end)) = (known(from), known(at)) else { continue };
        let arc = match arc {
            None => None,
            Some((direction, centre)) => {
                let fail =
                    |what: &str| PlotError { block: Some(i + 1), message: format!("an arc centre without {what}") };
                let (axes, c) = if lathe {
                    let (cx, cz) = (true_x(centre).ok_or_else(|| fail("X"))?, centre.z.ok_or_else(|| fail("Z"))?);
                    ((2, 0), [cx, from[1], cz])
                } else {
                    let (cx, cy) = (centre.x.ok_or_else(|| fail("X"))?, centre.y.ok_or_else(|| fail("Y"))?);
                    ((0, 1), [cx, cy, from[2]])
                };
                Some(Circle { centre: c, axes, ccw: *direction == ArcDirection::CounterClockwise })
            }
        };
        moves.push(Move { block: i + 1, kind, from, to: end, arc });
    }
    Ok(Toolpath { machine: program.machine, moves })
}

fn known(p: [Option<f64>; 3]) -> Option<[f64; 3]> {
    Some([p[0]?, p[1]?, p[2]?])
}

/// The plane a backplot is drawn in, named by its horizontal axis first: `Xy` the view from
/// above a mill, `Xz` from its front, `Zx` a lathe's part profile (Z across, X up).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    Xy,
    Xz,
    Zx,
}

impl Plane {
    /// The axes drawn across and up (0 X, 1 Y, 2 Z).
    pub fn axes(self) -> (usize, usize) {
        match self {
            Plane::Xy => (0, 1),
            Plane::Xz => (0, 2),
            Plane::Zx => (2, 0),
        }
    }

    /// The plane a machine's programs are drawn in unless asked otherwise.
    pub fn for_machine(machine: Machine) -> Plane {
        match machine {
            Machine::Lathe => Plane::Zx,
            Machine::Mill => Plane::Xy,
        }
    }

    fn project(self, p: [f64; 3]) -> Point2<f64> {
        let (h, v) = self.axes();
        Point2::new(p[h], p[v])
    }
}

const RAPID_COLOUR: &str = "#d02020";
const FEED_COLOUR: &str = "#1f5fd0";
const MARK_COLOUR: &str = "#1a9a3a";
/// Direction arrows along the whole path.
const ARROWS: usize = 24;

/// The backplot of `path` in `plane`, titled `title`.
///
/// The path and its marks are drawn in millimetres inside groups scaled to the drawing's
/// units (`<g id="toolpath" transform="scale(k)">`), the frame, texts, scale bar and legend in
/// those units: k makes the drawing a few hundred units across, since renderers hint text
/// smaller than a unit badly.
pub fn svg_drawing(path: &Toolpath, plane: Plane, title: &str) -> Result<String, PlotError> {
    let (lo, hi) = path.bounds().ok_or_else(|| PlotError {
        block: None,
        message: "the program makes no move from a known position: nothing to plot".into(),
    })?;
    let (p0, p1) = (plane.project(lo), plane.project(hi));
    let size_mm = (p1.x - p0.x).max(p1.y - p0.y).max(1e-3);
    let k = 10f64.powf((200.0 / size_mm).log10().ceil().max(0.0));
    let size = size_mm * k;
    // A path flat in one direction of the view still gets a frame with some height.
    let pad = |a: f64, b: f64| ((size * 0.05 - (b - a) * k) / 2.0).max(0.0);
    let (px, py) = (pad(p0.x, p1.x), pad(p0.y, p1.y));
    let margin = size * 0.06;
    // The frame in drawing units (y down).
    let frame = [p0.x * k - px - margin, -p1.y * k - py - margin, p1.x * k + px + margin, -p0.y * k + py + margin];
    let font = size / 40.0;
    let stroke = size / 700.0;

    let names = axis_names(path.machine, plane);
    let (rapids, feeds) = (
        path.moves.iter().filter(|m| m.kind == MoveKind::Rapid).count(),
        path.moves.iter().filter(|m| m.kind == MoveKind::Feed).count(),
    );
    let titles = [
        format!("backplot: {title} ({rapids} rapid, {feeds} feed moves)"),
        format!(
            "plane {}: {} across, {} up; path {} {}…{}, {} {}…{} mm",
            names.plane,
            names.across,
            names.up,
            names.across_letter,
            fixed(p0.x, 3),
            fixed(p1.x, 3),
            names.up_letter,
            fixed(p0.y, 3),
            fixed(p1.y, 3)
        ),
    ];
    let legend_rows = [
        ("rapid", "rapid traverse (G0), dashed"),
        ("feed", "feed moves (G1 lines, G2/G3 arcs), solid"),
        ("start", "start of the path"),
        ("arrow", "direction of travel"),
    ];
    let title_size = 0.9 * font;
    let text_width = |size: f64, text: &str| 0.66 * size * text.chars().count() as f64;
    let widest = titles
        .iter()
        .map(|t| text_width(title_size, t) + 2.0 * font)
        .chain(legend_rows.iter().map(|(_, t)| text_width(0.8 * font, t) + 4.0 * font))
        .fold(0.0, f64::max);
    let x0 = frame[0];
    let w = (frame[2] - frame[0]).max(widest);
    let y0 = frame[1] - 3.2 * font;
    let legend_top = frame[3] + 2.8 * font;
    let y1 = legend_top + (legend_rows.len() as f64 + 0.5) * 1.4 * font;
    let h = y1 - y0;
    // At most 900 pixels across and 1200 down.
    let px_width = 900f64.min(1200.0 * w / h);

    let mut out = String::new();
    svg::begin(&mut out, px_width, [x0, y0, w, h]);
    let mut labels = Labels::new([x0, y0, x0 + w, y1]);
    for (n, t) in titles.iter().enumerate() {
        let at = Point2::new(x0 + font, y0 + (1.2 + 1.2 * n as f64) * font);
        labels.place(&mut out, &[at], t, title_size, "black", "start");
    }
    let _ = writeln!(
        out,
        "<rect id=\"frame\" x=\"{:.4}\" y=\"{:.4}\" width=\"{:.4}\" height=\"{:.4}\" fill=\"none\" stroke=\"#bbb\" stroke-width=\"{stroke:.4}\"/>",
        frame[0],
        frame[1],
        frame[2] - frame[0],
        frame[3] - frame[1]
    );
    if (frame[0]..frame[2]).contains(&0.0) && (frame[1]..frame[3]).contains(&0.0) {
        svg::cross(&mut out, Point2::origin(), font, stroke, "#999");
    }
    // From here to the marks, millimetres.
    let mm_stroke = stroke / k;
    let _ = writeln!(out, "<g id=\"toolpath\" transform=\"scale({k})\" fill=\"none\" stroke-linecap=\"round\">");
    for run in runs(&path.moves) {
        let mut d = String::new();
        let start = plane.project(run[0].from);
        let _ = write!(d, "M {:.4} {:.4}", start.x, -start.y);
        for m in run {
            segment_path(&mut d, m, plane);
        }
        let style = match run[0].kind {
            MoveKind::Rapid => format!(
                "stroke=\"{RAPID_COLOUR}\" stroke-width=\"{:.5}\" stroke-dasharray=\"{:.5} {:.5}\"",
                1.5 * mm_stroke,
                8.0 * mm_stroke,
                5.0 * mm_stroke
            ),
            MoveKind::Feed => format!("stroke=\"{FEED_COLOUR}\" stroke-width=\"{:.5}\"", 2.5 * mm_stroke),
        };
        let _ = writeln!(out, "<path d=\"{d}\" {style}/>");
    }
    let _ = writeln!(out, "</g>");
    let _ = writeln!(out, "<g id=\"marks\" transform=\"scale({k})\">");
    let start = plane.project(path.start().unwrap_or(lo));
    let _ = writeln!(
        out,
        "<circle cx=\"{:.4}\" cy=\"{:.4}\" r=\"{:.5}\" fill=\"none\" stroke=\"{MARK_COLOUR}\" stroke-width=\"{:.5}\"/>",
        start.x,
        -start.y,
        0.6 * font / k,
        2.0 * mm_stroke
    );
    for (at, dir) in arrow_places(&path.moves, plane) {
        arrow(&mut out, at, dir, 0.7 * font / k);
    }
    let _ = writeln!(out, "</g>");
    let s = Point2::new(start.x * k, -start.y * k);
    let places = [
        (Point2::new(s.x, s.y + 1.8 * font), "middle"),
        (Point2::new(s.x, s.y - 1.0 * font), "middle"),
        (Point2::new(s.x + 1.0 * font, s.y + 0.3 * font), "start"),
        (Point2::new(s.x - 1.0 * font, s.y + 0.3 * font), "end"),
    ];
    for (p, anchor) in places {
        let before = out.len();
        labels.place(&mut out, &[p], "start", 0.7 * font, MARK_COLOUR, anchor);
        if out.len() > before {
            break;
        }
    }
    svg::scale_bar(&mut out, &mut labels, size_mm / 5.0, k, (x0, legend_top - 0.6 * font), stroke, font);
    legend(&mut out, &mut labels, &legend_rows, (x0 + font, legend_top + font), stroke, font);
    out.push_str("</svg>\n");
    Ok(out)
}

struct AxisNames {
    plane: &'static str,
    across: &'static str,
    up: &'static str,
    across_letter: &'static str,
    up_letter: &'static str,
}

fn axis_names(machine: Machine, plane: Plane) -> AxisNames {
    let lathe = machine == Machine::Lathe;
    let x = if lathe { "X (radius = diameter / 2)" } else { "X" };
    let (name, across, up, a, u) = match plane {
        Plane::Xy => ("XY", x, "Y", "X", "Y"),
        Plane::Xz => ("XZ", x, "Z", "X", "Z"),
        Plane::Zx => ("ZX", "Z", x, "Z", "X"),
    };
    AxisNames { plane: name, across, up, across_letter: a, up_letter: u }
}

/// The moves split where the kind changes or the path jumps (a move after an unknown
/// position), each run one SVG path.
fn runs(moves: &[Move]) -> Vec<&[Move]> {
    let mut out = Vec::new();
    let mut first = 0;
    for i in 1..=moves.len() {
        let split = i == moves.len() || moves[i].kind != moves[i - 1].kind || moves[i].from != moves[i - 1].to;
        if split {
            out.push(&moves[first..i]);
            first = i;
        }
    }
    out
}

/// One move as SVG path commands from where the path stands: an arc seen in its own plane as
/// SVG arcs, any other arc as a polyline, a line as a line.
fn segment_path(d: &mut String, m: &Move, plane: Plane) {
    let end = plane.project(m.to);
    let (Some(c), Some((r, _, sweep))) = (m.arc, m.arc_angles()) else {
        let _ = write!(d, " L {:.4} {:.4}", end.x, -end.y);
        return;
    };
    let (h, v) = plane.axes();
    let seen_in_plane = (h, v) == c.axes || (v, h) == c.axes;
    if seen_in_plane {
        // Swapping the plane's axes mirrors the turning sense; SVG's y down mirrors it again.
        let ccw_seen = c.ccw == ((h, v) == c.axes);
        let sweep_flag = if ccw_seen { 0 } else { 1 };
        // SVG cannot draw a full circle in one arc: split it.
        let pieces = if sweep > 0.9 * TAU { 2 } else { 1 };
        for k in 1..=pieces {
            let p = plane.project(m.point(k as f64 / pieces as f64));
            let large = u8::from(sweep / pieces as f64 > std::f64::consts::PI);
            let _ = write!(d, " A {r:.4} {r:.4} 0 {large} {sweep_flag} {:.4} {:.4}", p.x, -p.y);
        }
    } else {
        let n = (sweep / SAMPLE_STEP).ceil().max(2.0) as usize;
        for k in 1..=n {
            let p = plane.project(m.point(k as f64 / n as f64));
            let _ = write!(d, " L {:.4} {:.4}", p.x, -p.y);
        }
    }
}

/// Places for direction arrows, evenly along the drawn path's length: the point and the
/// unit direction of travel there (in the view, y up).
fn arrow_places(moves: &[Move], plane: Plane) -> Vec<(Point2<f64>, nalgebra::Vector2<f64>)> {
    let pieces: Vec<(Point2<f64>, Point2<f64>)> = moves
        .iter()
        .flat_map(|m| {
            let n = m.arc_angles().map_or(1, |(_, _, sweep)| (sweep / SAMPLE_STEP).ceil().max(1.0) as usize);
            (0..n).map(move |k| {
                (plane.project(m.point(k as f64 / n as f64)), plane.project(m.point((k + 1) as f64 / n as f64)))
            })
        })
        .filter(|(a, b)| (b - a).norm() > 0.0)
        .collect();
    let total: f64 = pieces.iter().map(|(a, b)| (b - a).norm()).sum();
    if total == 0.0 {
        return Vec::new();
    }
    let spacing = total / ARROWS as f64;
    let mut out = Vec::new();
    let mut next = spacing / 2.0;
    let mut walked = 0.0;
    for (a, b) in pieces {
        let len = (b - a).norm();
        while next <= walked + len && out.len() < ARROWS {
            let dir = (b - a) / len;
            out.push((a + dir * (next - walked), dir));
            next += spacing;
        }
        walked += len;
    }
    out
}

/// A filled arrowhead at `at` pointing along `dir` (view coordinates, y up).
fn arrow(svg: &mut String, at: Point2<f64>, dir: nalgebra::Vector2<f64>, size: f64) {
    let normal = nalgebra::Vector2::new(-dir.y, dir.x);
    let tip = at + dir * (size / 2.0);
    let back = at - dir * (size / 2.0);
    let (l, r) = (back + normal * (size / 3.0), back - normal * (size / 3.0));
    let _ = writeln!(
        svg,
        "<path d=\"M {:.4} {:.4} L {:.4} {:.4} L {:.4} {:.4} Z\" fill=\"{MARK_COLOUR}\"/>",
        tip.x, -tip.y, l.x, -l.y, r.x, -r.y
    );
}

/// What each line and mark is, under the drawing.
fn legend(svg: &mut String, labels: &mut Labels, rows: &[(&str, &str)], corner: (f64, f64), stroke: f64, font: f64) {
    let (x, mut y) = corner;
    for (what, text) in rows {
        let mid = y - 0.3 * font;
        let _ = match *what {
            "rapid" => writeln!(
                svg,
                "<path d=\"M {x:.4} {mid:.4} h {:.4}\" stroke=\"{RAPID_COLOUR}\" stroke-width=\"{:.4}\" stroke-dasharray=\"{:.4} {:.4}\"/>",
                2.0 * font,
                1.5 * stroke,
                8.0 * stroke,
                5.0 * stroke
            ),
            "feed" => writeln!(
                svg,
                "<path d=\"M {x:.4} {mid:.4} h {:.4}\" stroke=\"{FEED_COLOUR}\" stroke-width=\"{:.4}\"/>",
                2.0 * font,
                2.5 * stroke
            ),
            "start" => writeln!(
                svg,
                "<circle cx=\"{:.4}\" cy=\"{mid:.4}\" r=\"{:.4}\" fill=\"none\" stroke=\"{MARK_COLOUR}\" stroke-width=\"{:.4}\"/>",
                x + font,
                0.4 * font,
                2.0 * stroke
            ),
            _ => {
                arrow(svg, Point2::new(x + font, -mid), nalgebra::Vector2::new(1.0, 0.0), 0.7 * font);
                Ok(())
            }
        };
        labels.place(svg, &[Point2::new(x + 2.6 * font, y)], text, 0.8 * font, "black", "start");
        y += 1.4 * font;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(from: [f64; 3], to: [f64; 3], centre: [f64; 3], ccw: bool) -> Move {
        Move { block: 1, kind: MoveKind::Feed, from, to, arc: Some(Circle { centre, axes: (0, 1), ccw }) }
    }

    #[test]
    fn an_arc_box_holds_the_quadrant_points_it_passes() {
        // From (10, 0) counter-clockwise to (-10, 0) around the origin: over the top, y up to 10.
        let (lo, hi) = arc([10.0, 0.0, 0.0], [-10.0, 0.0, 0.0], [0.0; 3], true).bounds();
        assert_eq!((lo, hi), ([-10.0, 0.0, 0.0], [10.0, 10.0, 0.0]));
        // The same ends clockwise go under: y down to -10.
        let (lo, hi) = arc([10.0, 0.0, 0.0], [-10.0, 0.0, 0.0], [0.0; 3], false).bounds();
        assert_eq!((lo, hi), ([-10.0, -10.0, 0.0], [10.0, 0.0, 0.0]));
    }

    #[test]
    fn an_end_on_the_start_is_a_full_circle() {
        let m = arc([5.0, 0.0, 1.0], [5.0, 0.0, 1.0], [0.0, 0.0, 1.0], false);
        assert_eq!(m.arc_angles().unwrap().2, TAU);
        assert_eq!(m.bounds(), ([-5.0, -5.0, 1.0], [5.0, 5.0, 1.0]));
    }
}
