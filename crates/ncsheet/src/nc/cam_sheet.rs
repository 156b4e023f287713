//! Cam design sheets and what a fitted cam is written as: the design sheet read from csv
//! text, the arcs as a coordinate table, and the SVG drawing a designer checks by eye (the
//! paper's plotter check). The NC program is built on the NC model in `nc::cam`. Text in and
//! out, no files: the command line reads and writes them.
//!
//! A design sheet has one segment per row, columns named in a header
//! `row,operation,disc,type,from_deg,to_deg,r_start,r_end` (any order; `row`, `operation` and
//! `disc` may be left out). Radii in mm, type "circle", "arch", "log" or "parab". The header
//! says the angles' unit: `from_deg,to_deg` in degrees, or `from_hundredths,to_hundredths` in
//! hundredths of a turn, as the paper's design sheets count them (× 3.6 gives degrees).

use std::f64::consts::TAU;
use std::fmt::Write;

use nalgebra::{Point2, Vector2};

use super::svg::{self, cross, fixed, polyline, scale_bar, Labels};
use crate::geometry::cam::{by_disc, fit_cam, Arc, CamError, CamFit, CamOptions, Piece, PieceKind, Segment, Turn};

const REQUIRED: [&str; 3] = ["type", "r_start", "r_end"];

/// The most rows a design sheet may have: a row is fitted in 1–2 ms (a release build), so the
/// limit keeps a sheet of one-arc rows within about 8 s (20,000 rows took 24 s); the paper's
/// sheets have a few dozen. The arcs a disc needs have their own limit, `MAX_CAM_ARCS`.
pub const MAX_SHEET_ROWS: usize = 4000;

/// The units a sheet may give its angles in: the header's two column names and how many
/// degrees one unit is.
const ANGLE_UNITS: [(&str, &str, f64); 2] = [("from_deg", "to_deg", 1.0), ("from_hundredths", "to_hundredths", 3.6)];

/// The segments of a design sheet, in the order written.
pub fn parse_sheet(text: &str) -> Result<Vec<Segment>, CamError> {
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(true).from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| CamError::Sheet { line: 1, message: format!("header: {e}") })?
        .iter()
        .map(|h| h.to_ascii_lowercase())
        .collect();
    let column = |name: &str| header.iter().position(|h| h == name);
    let needs = || format!("needs {}, and from_deg, to_deg or from_hundredths, to_hundredths", REQUIRED.join(", "));
    for name in REQUIRED {
        if column(name).is_none() {
            let message = format!("the header has no column '{name}' ({})", needs());
            return Err(CamError::Sheet { line: 1, message });
        }
    }
    let (from_col, to_col, degrees_per_unit) = angle_columns(&header)
        .map_err(|message| CamError::Sheet { line: 1, message: format!("{message} ({})", needs()) })?;
    let mut segments = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| CamError::Sheet {
            line: e.position().map_or(0, |p| p.line() as usize),
            message: e.to_string(),
        })?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        if record.iter().all(|f| f.is_empty()) {
            continue;
        }
        if segments.len() == MAX_SHEET_ROWS {
            let message =
                format!("the sheet has more than {MAX_SHEET_ROWS} rows, ncsheet's limit for a cam design sheet");
            return Err(CamError::Sheet { line, message });
        }
        let text = |name: &str| column(name).and_then(|i| record.get(i)).unwrap_or("").to_string();
        let number = |name: &str| {
            let field = text(name);
            field
                .parse::<f64>()
                .map_err(|_| CamError::Sheet { line, message: format!("{name} '{field}' is not a number") })
        };
        let row = text("row");
        let in_row = |error| CamError::Segment { row: format!("row {row} (line {line})"), error };
        let kind = PieceKind::parse(&text("type")).map_err(in_row)?;
        let (from, to) = (number(from_col)? * degrees_per_unit, number(to_col)? * degrees_per_unit);
        let (r_start, r_end) = (number("r_start")?, number("r_end")?);
        let piece = Piece::new(kind, r_start, from, r_end, to).map_err(in_row)?;
        segments.push(Segment { row: row.clone(), operation: text("operation"), disc: text("disc"), line, piece });
    }
    Ok(segments)
}

/// The header's angle columns and their unit in degrees: exactly one pair of
/// [`ANGLE_UNITS`] must be there, whole.
fn angle_columns(header: &[String]) -> Result<(&'static str, &'static str, f64), String> {
    let has = |name: &str| header.iter().any(|h| h == name);
    let mut found = None;
    for (from, to, unit) in ANGLE_UNITS {
        match (has(from), has(to)) {
            (true, true) if found.is_some() => {
                return Err("the header gives the angles twice, in degrees and in hundredths of a turn".into())
            }
            (true, true) => found = Some((from, to, unit)),
            (true, false) => return Err(format!("the header has '{from}' but no '{to}'")),
            (false, true) => return Err(format!("the header has '{to}' but no '{from}'")),
            (false, false) => {}
        }
    }
    found.ok_or_else(|| "the header has no angle columns".into())
}

/// Reads a design sheet and fits every disc on it, discs in order of first appearance. What
/// `ncsheet cam` runs, and what examples/cam_bench.rs times.
pub fn fit_design_sheet(text: &str, options: &CamOptions) -> Result<Vec<CamFit>, CamError> {
    let segments = parse_sheet(text)?;
    by_disc(&segments).iter().map(|(disc, segs)| fit_cam(disc, segs, options)).collect()
}

/// The header of [`arcs_csv`].
pub const CSV_HEADER: &str = "x0,y0,x1,y1,cx,cy,r,dir";

/// One line per arc: start, end, centre, radius (mm, 6 decimals) and the direction, `ccw`
/// or `cw`.
pub fn arcs_csv<'a>(arcs: impl IntoIterator<Item = &'a Arc>) -> String {
    let mut out = format!("{CSV_HEADER}\n");
    for a in arcs {
        let n = [a.start.x, a.start.y, a.end.x, a.end.y, a.centre.x, a.centre.y, a.radius];
        let fields: Vec<String> = n.iter().map(|v| fixed(*v, 6)).collect();
        let dir = if a.turn == Turn::Ccw { "ccw" } else { "cw" };
        let _ = writeln!(out, "{},{dir}", fields.join(","));
    }
    out
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgOptions {
    /// How many times the deviation is magnified; `None` draws the tolerance as 4 mm.
    pub magnify: Option<f64>,
    /// Drawing width in pixels.
    pub width: f64,
}

impl Default for SvgOptions {
    fn default() -> SvgOptions {
        SvgOptions { magnify: None, width: 900.0 }
    }
}

/// Points per degree of the theoretical curve in the drawing.
const SVG_SAMPLES_PER_DEG: f64 = 4.0;

/// The plotter check: the theoretical curve (thin black), the arcs (alternating blue and
/// green, numbered in cutting order), their centres (grey crosses; a centre outside the
/// drawing is shown as a short tick towards it) and the deviation magnified along the radius
/// (red): where the red line lies outside the black one, the arcs lie outside the curve.
/// The frame fits the drawn curve; axes through the cam centre carry angle marks every 30°,
/// a scale bar gives millimetres, and a legend under the drawing says what each colour is.
/// Labels are placed so that no two overlap (a label with no free place is left out).
pub fn svg_drawing(fit: &CamFit, options: &SvgOptions) -> String {
    let r_max = fit.segments.iter().map(|s| s.segment.piece.r0.max(s.segment.piece.r1)).fold(10.0, f64::max);
    let magnify = options.magnify.unwrap_or(4.0 / fit.tolerance);
    let curves: Vec<Vec<Point2<f64>>> = fit
        .segments
        .iter()
        .map(|s| {
            let piece = &s.segment.piece;
            let n = ((piece.phi1_deg - piece.phi0_deg).abs() * SVG_SAMPLES_PER_DEG).ceil().max(8.0) as usize;
            (0..=n).map(|i| piece.point(i as f64 / n as f64)).collect()
        })
        .collect();
    // The frame: the curve and the cam centre, with room for angle labels around.
    let (mut lo, mut hi) = (Point2::<f64>::origin(), Point2::<f64>::origin());
    for q in curves.iter().flatten() {
        lo = Point2::new(lo.x.min(q.x), lo.y.min(q.y));
        hi = Point2::new(hi.x.max(q.x), hi.y.max(q.y));
    }
    let unit = r_max / 25.0;
    let margin = 4.5 * unit;
    let (x0, x1, y0, y1) = (lo.x - margin, hi.x + margin, -hi.y - margin, -lo.y + margin);
    let font = unit * 0.9;
    let legend_lines = 5.0;
    let legend_h = (legend_lines + 1.5) * font * 1.4;
    let (w, h) = (x1 - x0, y1 - y0 + legend_h);
    let stroke = r_max / 600.0;
    let mut svg = String::new();
    let mut labels = Labels::new([x0, y0, x0 + w, y0 + h]);
    svg::begin(&mut svg, options.width, [x0, y0, w, h]);
    let title = format!(
        "disc {} | H = {} mm | {} arcs | deviation x{}",
        if fit.disc.is_empty() { "-" } else { &fit.disc },
        fit.tolerance,
        fit.n_arcs(),
        fixed(magnify, 0)
    );
    labels.place(&mut svg, &[Point2::new(x0 + font, y0 + 1.3 * font)], &title, font, "black", "start");
    axes(&mut svg, &mut labels, r_max, (x0, x1, y0, y1), stroke, font);
    for (s, curve) in fit.segments.iter().zip(&curves) {
        polyline(&mut svg, curve, stroke, "black");
        let magnified: Vec<Point2<f64>> = curve
            .iter()
            .map(|&q| {
                let dev = signed_deviation(&s.arcs, q);
                let out = if q.coords.norm() > 0.0 { q.coords.normalize() } else { Vector2::zeros() };
                q + out * (dev * magnify)
            })
            .collect();
        polyline(&mut svg, &magnified, stroke, "red");
    }
    for (i, a) in fit.arcs().enumerate() {
        let colour = if i % 2 == 0 { "#1f5fd0" } else { "#1a9a3a" };
        arc_path(&mut svg, a, 3.0 * stroke, colour);
        let mid = a.point_at(0.5);
        let towards_centre = (a.centre - mid).normalize();
        // Outward from the curve, farther and farther until the number finds a free place.
        let candidates: Vec<Point2<f64>> = (1..=8)
            .map(|k| mid - towards_centre * (unit * (0.8 + 0.7 * k as f64)))
            .map(|p| Point2::new(p.x, -p.y + 0.35 * font))
            .collect();
        labels.place(&mut svg, &candidates, &(i + 1).to_string(), 0.8 * font, colour, "middle");
        let inside = (x0..x1).contains(&a.centre.x) && (y0..y1).contains(&-a.centre.y);
        if inside {
            cross(&mut svg, a.centre, unit / 3.0, stroke, "grey");
        } else {
            let tick = mid + towards_centre * (2.0 * unit);
            polyline(&mut svg, &[mid, tick], stroke, "grey");
        }
    }
    // A bar about a fifth of the largest radius.
    scale_bar(&mut svg, &mut labels, r_max / 5.0, 1.0, (x0, y1), stroke, font);
    legend(&mut svg, &mut labels, magnify, (x0, y1 + 2.2 * font), stroke, font);
    svg.push_str("</svg>\n");
    svg
}

/// Axes through the cam centre and a mark every 30° on a circle just outside the curve.
fn axes(svg: &mut String, labels: &mut Labels, r_max: f64, frame: (f64, f64, f64, f64), stroke: f64, font: f64) {
    let (x0, x1, y0, y1) = frame;
    let _ = writeln!(
        svg,
        "<path d=\"M {x0:.3} 0 H {x1:.3} M 0 {y0:.3} V {y1:.3}\" stroke=\"#999\" stroke-width=\"{stroke:.4}\" stroke-dasharray=\"{:.3} {:.3}\"/>",
        6.0 * stroke,
        4.0 * stroke
    );
    let r = r_max * 1.04;
    for k in 0..12 {
        let deg = k as f64 * 30.0;
        let (sin, cos) = deg.to_radians().sin_cos();
        let (a, b) = (Point2::new(r * cos, r * sin), Point2::new((r + font) * cos, (r + font) * sin));
        if a.x < x0 || a.x > x1 || -a.y < y0 || -a.y > y1 {
            continue;
        }
        polyline(svg, &[a, b], stroke, "#666");
        let at = Point2::new((r + 2.2 * font) * cos, -(r + 2.2 * font) * sin + 0.35 * font);
        labels.place(svg, &[at], &format!("{deg:.0}°"), 0.8 * font, "#444", "middle");
    }
}

/// What each line of the drawing is, under it.
fn legend(svg: &mut String, labels: &mut Labels, magnify: f64, corner: (f64, f64), stroke: f64, font: f64) {
    let m = fixed(magnify, 0);
    let rows = [
        ("black", "theoretical cam curve"),
        ("#1f5fd0", "fitted arcs (blue and green by turns), numbered in cutting order"),
        ("grey", "arc centres (a tick points to a centre off the drawing)"),
        ("red", &*format!("deviation of the arcs from the curve, magnified x{m} along the radius")),
        ("white", "red outside black: the arcs cut outside the curve; inside: into it"),
    ];
    let (x, mut y) = corner;
    for (colour, text) in rows {
        if colour != "white" {
            let _ = writeln!(
                svg,
                "<path d=\"M {x:.3} {:.3} h {:.3}\" stroke=\"{colour}\" stroke-width=\"{:.4}\"/>",
                y - 0.3 * font,
                2.0 * font,
                3.0 * stroke
            );
        }
        labels.place(svg, &[Point2::new(x + 2.6 * font, y)], text, 0.8 * font, "black", "start");
        y += 1.4 * font;
    }
}

/// Distance from `q` to the nearest arc, positive where that arc passes outside the curve
/// (farther from its own centre side than q for a counter-clockwise arc).
fn signed_deviation(arcs: &[Arc], q: Point2<f64>) -> f64 {
    let nearest = arcs.iter().min_by(|a, b| a.distance(q).total_cmp(&b.distance(q)));
    nearest.map_or(0.0, |a| a.turn.sign() * (a.radius - (q - a.centre).norm()))
}

fn arc_path(svg: &mut String, a: &Arc, width: f64, colour: &str) {
    let sweep = a.sweep();
    // SVG's y axis points down, which mirrors the turning sense.
    let sweep_flag = if a.turn == Turn::Ccw { 0 } else { 1 };
    let mut d = format!("M {:.4} {:.4}", a.start.x, -a.start.y);
    // SVG cannot draw a full circle in one arc: split it.
    let pieces = if sweep > 0.9 * TAU { 2 } else { 1 };
    for k in 1..=pieces {
        let p = a.point_at(k as f64 / pieces as f64);
        let large = if sweep / pieces as f64 > std::f64::consts::PI { 1 } else { 0 };
        let _ = write!(d, " A {r:.4} {r:.4} 0 {large} {sweep_flag} {:.4} {:.4}", p.x, -p.y, r = a.radius);
    }
    let _ = writeln!(
        svg,
        "<path d=\"{d}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{width:.4}\" stroke-opacity=\"0.6\"/>"
    );
}
