//! A program's tool path as a backplot shows it: every move from a known position as a line
//! or an arc in true lengths (a lathe's X diameter halved to a radius), its bounding box with
//! the arcs' extreme points, and the SVG drawing of it in a chosen plane (rapids dashed, feeds
//! solid, arcs as SVG arcs, start and direction marked, a scale bar and a legend; a grid with
//! graduations in mm, the Z0 face, the stock when known, feeds coloured by depth in a plan
//! view). A path of any length is thinned to what the drawing's pixels can show (lines that
//! deviate less than half a pixel are merged) and written in paths of bounded length. Pure:
//! the command line reads the program and writes the drawing.

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
    svg_drawing_with(path, plane, title, &Extras::default())
}

/// What a backplot shows besides the path, when the caller knows it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Extras {
    /// The stock's box (lowest and highest corner, mm; a lathe's X as a radius).
    pub stock: Option<([f64; 3], [f64; 3])>,
    /// The finished part's outline in the drawing's plane, a closed polygon (mm; a lathe's
    /// X as a radius); empty when not known.
    pub part: Vec<[f64; 3]>,
}

/// The backplot of `path` in `plane` with the stock of `extras` drawn behind it.
pub fn svg_drawing_with(path: &Toolpath, plane: Plane, title: &str, extras: &Extras) -> Result<String, PlotError> {
    let (mut lo, mut hi) = path.bounds().ok_or_else(|| PlotError {
        block: None,
        message: "the program makes no move from a known position: nothing to plot".into(),
    })?;
    let (path_lo, path_hi) = (lo, hi);
    if let Some((a, b)) = extras.stock {
        grow(&mut lo, &mut hi, a);
        grow(&mut lo, &mut hi, b);
    }
    for &p in &extras.part {
        grow(&mut lo, &mut hi, p);
    }
    // Feeds coloured by depth where the view looks along Z and the path goes up and down.
    let depth = (plane == Plane::Xy && path_hi[2] - path_lo[2] > 1e-9).then_some((path_lo[2], path_hi[2]));
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
    let depth_row = depth.map(|(z0, z1)| {
        format!("feeds coloured by depth: Z {} mm (dark) to {} mm (light)", fixed(z0, 3), fixed(z1, 3))
    });
    let mut legend_rows = vec![
        ("rapid", "rapid traverse (G0), dashed"),
        ("feed", "feed moves (G1 lines, G2/G3 arcs), solid"),
        ("start", "start of the path"),
        ("arrow", "direction of travel"),
    ];
    if let Some(row) = &depth_row {
        legend_rows.push(("depth", row.as_str()));
    }
    if extras.stock.is_some() {
        legend_rows.push(("stock", "the stock"));
    }
    if !extras.part.is_empty() {
        legend_rows.push(("part", "the finished part's outline"));
    }
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
    // Below the frame: the graduations' numbers, then the scale bar, then the legend.
    let legend_top = frame[3] + 3.8 * font;
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
    if let Some(stock) = extras.stock {
        stock_box(&mut out, stock, plane, k, stroke);
    }
    part_outline(&mut out, &extras.part, plane, k, stroke);
    graduations(&mut out, frame, k, font, stroke, &names);
    z0_face(&mut out, frame, plane, font, stroke);
    if (frame[0]..frame[2]).contains(&0.0) && (frame[1]..frame[3]).contains(&0.0) {
        svg::cross(&mut out, Point2::origin(), font, stroke, "#999");
    }
    // From here to the marks, millimetres.
    let mm_stroke = stroke / k;
    let _ = writeln!(out, "<g id=\"toolpath\" transform=\"scale({k})\" fill=\"none\" stroke-linecap=\"round\">");
    // Half a pixel of the drawing, in mm: what thinning may move a line by.
    let tolerance = 0.5 * w / px_width / k;
    let band = |m: &Move| match (m.kind, depth) {
        (MoveKind::Feed, Some(range)) => depth_band(0.5 * (m.from[2] + m.to[2]), range),
        _ => 0,
    };
    for run in runs_by(&path.moves, band) {
        let style = match (run[0].kind, depth) {
            (MoveKind::Rapid, _) => format!(
                "stroke=\"{RAPID_COLOUR}\" stroke-width=\"{:.5}\" stroke-dasharray=\"{:.5} {:.5}\"",
                1.5 * mm_stroke,
                8.0 * mm_stroke,
                5.0 * mm_stroke
            ),
            (MoveKind::Feed, None) => format!("stroke=\"{FEED_COLOUR}\" stroke-width=\"{:.5}\"", 2.5 * mm_stroke),
            (MoveKind::Feed, Some(_)) => {
                format!("stroke=\"{}\" stroke-width=\"{:.5}\"", depth_colour(band(&run[0])), 2.5 * mm_stroke)
            }
        };
        write_run(&mut out, run, plane, tolerance, &style);
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

/// The moves split where the kind or `band` changes or the path jumps (a move after an
/// unknown position), each run drawn in one style.
fn runs_by(moves: &[Move], band: impl Fn(&Move) -> usize) -> Vec<&[Move]> {
    let mut out = Vec::new();
    let mut first = 0;
    for i in 1..=moves.len() {
        let split = i == moves.len()
            || moves[i].kind != moves[i - 1].kind
            || moves[i].from != moves[i - 1].to
            || band(&moves[i]) != band(&moves[i - 1]);
        if split {
            out.push(&moves[first..i]);
            first = i;
        }
    }
    out
}

/// The most segments one `<path>` holds: renderers refuse attributes of many megabytes.
const SEGMENTS_PER_PATH: usize = 2000;

/// One run as `<path>`s in `style`: straight moves thinned to `tolerance` (mm) in the view,
/// arcs as they are, a new path every [`SEGMENTS_PER_PATH`] segments.
fn write_run(out: &mut String, run: &[Move], plane: Plane, tolerance: f64, style: &str) {
    let mut d = String::new();
    let mut segments = 0;
    let mut at = plane.project(run[0].from);
    let mut flush = |d: &mut String, segments: &mut usize, at: Point2<f64>, more: bool| {
        if *segments > 0 {
            let _ = writeln!(out, "<path d=\"{d}\" {style}/>");
        }
        d.clear();
        *segments = 0;
        if more {
            let _ = write!(d, "M {:.4} {:.4}", at.x, -at.y);
        }
    };
    flush(&mut d, &mut segments, at, true);
    let mut i = 0;
    while i < run.len() {
        if run[i].arc.is_some() {
            segment_path(&mut d, &run[i], plane);
            at = plane.project(run[i].to);
            segments += 1;
            i += 1;
        } else {
            let straight = run[i..].iter().take_while(|m| m.arc.is_none()).count();
            let mut points = vec![at];
            points.extend(run[i..i + straight].iter().map(|m| plane.project(m.to)));
            for p in thinned(&points, tolerance).into_iter().skip(1) {
                let _ = write!(d, " L {:.4} {:.4}", p.x, -p.y);
                at = p;
                segments += 1;
                if segments >= SEGMENTS_PER_PATH {
                    flush(&mut d, &mut segments, at, true);
                }
            }
            i += straight;
        }
        if segments >= SEGMENTS_PER_PATH {
            flush(&mut d, &mut segments, at, true);
        }
    }
    flush(&mut d, &mut segments, at, false);
}

/// The points of a polyline that keep it within `tolerance` of itself (Douglas–Peucker):
/// the ends always, a point between only where leaving it out would move the line further.
pub fn thinned(points: &[Point2<f64>], tolerance: f64) -> Vec<Point2<f64>> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut spans = vec![(0, points.len() - 1)];
    while let Some((a, b)) = spans.pop() {
        let (pa, pb) = (points[a], points[b]);
        let chord = pb - pa;
        let length = chord.norm();
        let distance = |p: Point2<f64>| {
            if length == 0.0 {
                (p - pa).norm()
            } else {
                (chord.x * (p.y - pa.y) - chord.y * (p.x - pa.x)).abs() / length
            }
        };
        let far = (a + 1..b).map(|i| (i, distance(points[i]))).fold((a, 0.0), |m, x| if x.1 > m.1 { x } else { m });
        if far.1 > tolerance {
            keep[far.0] = true;
            spans.push((a, far.0));
            spans.push((far.0, b));
        }
    }
    points.iter().zip(keep).filter(|(_, k)| *k).map(|(p, _)| *p).collect()
}

/// Bands of depth a plan view colours feeds in.
const DEPTH_BANDS: usize = 8;

/// The band (0 the deepest) of depth `z` in the path's range of Z.
fn depth_band(z: f64, (z0, z1): (f64, f64)) -> usize {
    let t = ((z - z0) / (z1 - z0)).clamp(0.0, 1.0);
    ((t * DEPTH_BANDS as f64) as usize).min(DEPTH_BANDS - 1)
}

/// A band's colour: dark blue deep, through teal, to light yellow high.
fn depth_colour(band: usize) -> String {
    let stops = [(0.05, 0.1, 0.45), (0.0, 0.55, 0.6), (0.95, 0.85, 0.25)];
    let t = band as f64 / (DEPTH_BANDS - 1) as f64 * 2.0;
    let (a, b, f) = if t <= 1.0 { (stops[0], stops[1], t) } else { (stops[1], stops[2], t - 1.0) };
    let mix = |x: f64, y: f64| (255.0 * (x + (y - x) * f)).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

const STOCK_FILL: &str = "#f3ecd9";
const STOCK_COLOUR: &str = "#9a8a5a";
const PART_FILL: &str = "#d9d9d9";
const PART_COLOUR: &str = "#333";
const GRID_COLOUR: &str = "#e4e4e4";
const FACE_COLOUR: &str = "#555";

/// The stock's box as the view sees it, behind everything else.
fn stock_box(out: &mut String, (a, b): ([f64; 3], [f64; 3]), plane: Plane, k: f64, stroke: f64) {
    let (p, q) = (plane.project(a), plane.project(b));
    let _ = writeln!(
        out,
        "<rect id=\"stock\" x=\"{:.4}\" y=\"{:.4}\" width=\"{:.4}\" height=\"{:.4}\" fill=\"{STOCK_FILL}\" stroke=\"{STOCK_COLOUR}\" stroke-width=\"{:.4}\"/>",
        p.x.min(q.x) * k,
        -p.y.max(q.y) * k,
        (q.x - p.x).abs() * k,
        (q.y - p.y).abs() * k,
        stroke
    );
}

/// The part's outline as a closed path (`id="part"`) over the stock, in drawing units.
fn part_outline(out: &mut String, outline: &[[f64; 3]], plane: Plane, k: f64, stroke: f64) {
    if outline.len() < 2 {
        return;
    }
    let mut d = String::new();
    for (i, &p) in outline.iter().enumerate() {
        let q = plane.project(p);
        let _ = write!(d, "{} {:.4} {:.4} ", if i == 0 { "M" } else { "L" }, q.x * k, -q.y * k);
    }
    let _ = writeln!(
        out,
        "<path id=\"part\" d=\"{d}Z\" fill=\"{PART_FILL}\" stroke=\"{PART_COLOUR}\" stroke-width=\"{:.4}\"/>",
        2.0 * stroke
    );
}

/// A round step (1, 2 or 5 times a power of ten) that cuts `span` into about 5 to 10 parts.
fn grid_step(span: f64) -> f64 {
    let rough = span / 8.0;
    let power = 10f64.powf(rough.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * power).find(|&s| s >= rough).unwrap_or(10.0 * power)
}

/// A grid over the frame at a round step in mm, numbered under the frame (across) and inside
/// its left edge (up), with the axes named.
fn graduations(out: &mut String, frame: [f64; 4], k: f64, font: f64, stroke: f64, names: &AxisNames) {
    let (across, up) = ((frame[0] / k, frame[2] / k), (-frame[3] / k, -frame[1] / k));
    let step = grid_step((across.1 - across.0).max(up.1 - up.0));
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let ticks = |(a, b): (f64, f64)| {
        let first = (a / step).ceil() as i64;
        let last = (b / step).floor() as i64;
        (first..=last).map(move |i| i as f64 * step)
    };
    let size = 0.6 * font;
    let _ = writeln!(out, "<g id=\"grid\" stroke=\"{GRID_COLOUR}\" stroke-width=\"{stroke:.4}\">");
    for v in ticks(across) {
        let _ = writeln!(out, "<path d=\"M {:.4} {:.4} V {:.4}\"/>", v * k, frame[1], frame[3]);
    }
    for v in ticks(up) {
        let _ = writeln!(out, "<path d=\"M {:.4} {:.4} H {:.4}\"/>", frame[0], -v * k, frame[2]);
    }
    let _ = writeln!(out, "</g>");
    let _ = writeln!(out, "<g id=\"graduations\" font-family=\"sans-serif\" font-size=\"{size:.4}\" fill=\"#555\">");
    for v in ticks(across) {
        let _ = writeln!(
            out,
            "<text x=\"{:.4}\" y=\"{:.4}\" text-anchor=\"middle\">{}</text>",
            v * k,
            frame[3] + 1.1 * size,
            fixed(v, decimals)
        );
    }
    for v in ticks(up) {
        let _ = writeln!(
            out,
            "<text x=\"{:.4}\" y=\"{:.4}\" text-anchor=\"start\">{}</text>",
            frame[0] + 0.3 * size,
            -v * k - 0.3 * size,
            fixed(v, decimals)
        );
    }
    let _ = writeln!(
        out,
        "<text x=\"{:.4}\" y=\"{:.4}\" text-anchor=\"end\" font-weight=\"bold\">{} mm</text>",
        frame[2],
        frame[3] + 2.2 * size,
        names.across_letter
    );
    let _ = writeln!(
        out,
        "<text x=\"{:.4}\" y=\"{:.4}\" text-anchor=\"start\" font-weight=\"bold\">{} mm</text>",
        frame[0] + 0.3 * size,
        frame[1] + 1.2 * size,
        names.up_letter
    );
    let _ = writeln!(out, "</g>");
}

/// The Z0 face (the part's front face, where a program's Z counts from) as a dash-dotted
/// line, in a view that shows Z and where the frame reaches it.
fn z0_face(out: &mut String, frame: [f64; 4], plane: Plane, font: f64, stroke: f64) {
    let style = format!(
        "stroke=\"{FACE_COLOUR}\" stroke-width=\"{:.4}\" stroke-dasharray=\"{:.4} {:.4} {:.4} {:.4}\"",
        1.5 * stroke,
        6.0 * stroke,
        3.0 * stroke,
        1.0 * stroke,
        3.0 * stroke
    );
    let size = 0.6 * font;
    match plane {
        Plane::Zx if frame[0] < 0.0 && 0.0 < frame[2] => {
            let _ = writeln!(out, "<path id=\"z0\" d=\"M 0 {:.4} V {:.4}\" {style}/>", frame[1], frame[3]);
            let _ = writeln!(
                out,
                "<text x=\"{:.4}\" y=\"{:.4}\" font-family=\"sans-serif\" font-size=\"{size:.4}\" fill=\"{FACE_COLOUR}\">Z0</text>",
                0.3 * size,
                frame[1] + 2.4 * size
            );
        }
        Plane::Xz if frame[1] < 0.0 && 0.0 < frame[3] => {
            let _ = writeln!(out, "<path id=\"z0\" d=\"M {:.4} 0 H {:.4}\" {style}/>", frame[0], frame[2]);
            let _ = writeln!(
                out,
                "<text x=\"{:.4}\" y=\"{:.4}\" text-anchor=\"end\" font-family=\"sans-serif\" font-size=\"{size:.4}\" fill=\"{FACE_COLOUR}\">Z0</text>",
                frame[2] - 0.3 * size,
                -0.3 * size
            );
        }
        _ => {}
    }
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
            "depth" => {
                let step = 2.0 * font / DEPTH_BANDS as f64;
                for b in 0..DEPTH_BANDS {
                    let _ = writeln!(
                        svg,
                        "<rect x=\"{:.4}\" y=\"{:.4}\" width=\"{:.4}\" height=\"{:.4}\" fill=\"{}\"/>",
                        x + b as f64 * step,
                        mid - 0.3 * font,
                        step,
                        0.6 * font,
                        depth_colour(b)
                    );
                }
                Ok(())
            }
            "stock" => writeln!(
                svg,
                "<rect x=\"{x:.4}\" y=\"{:.4}\" width=\"{:.4}\" height=\"{:.4}\" fill=\"{STOCK_FILL}\" stroke=\"{STOCK_COLOUR}\" stroke-width=\"{:.4}\"/>",
                mid - 0.3 * font,
                2.0 * font,
                0.6 * font,
                stroke
            ),
            "part" => writeln!(
                svg,
                "<rect x=\"{x:.4}\" y=\"{:.4}\" width=\"{:.4}\" height=\"{:.4}\" fill=\"{PART_FILL}\" stroke=\"{PART_COLOUR}\" stroke-width=\"{:.4}\"/>",
                mid - 0.3 * font,
                2.0 * font,
                0.6 * font,
                2.0 * stroke
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
