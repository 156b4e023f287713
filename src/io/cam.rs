//! Cam design sheets and what a fitted cam is written as: the design sheet read from csv
//! text, the arcs as a coordinate table, and the SVG drawing a designer checks by eye (the
//! paper's plotter check). The NC program is built on the NC model in `nc::cam`.
//!
//! A design sheet has one segment per row, columns named in a header
//! `row,operation,disc,type,from_deg,to_deg,r_start,r_end` (any order; `row`, `operation` and
//! `disc` may be left out). Angles in degrees, radii in mm, type "circle", "arch" or "log".

use std::f64::consts::TAU;
use std::fmt::Write;

use nalgebra::{Point2, Vector2};

use crate::geometry::cam::{by_disc, fit_cam, Arc, CamError, CamFit, CamOptions, Piece, PieceKind, Segment, Turn};

const REQUIRED: [&str; 5] = ["type", "from_deg", "to_deg", "r_start", "r_end"];

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
    for name in REQUIRED {
        if column(name).is_none() {
            let message = format!("the header has no column '{name}' (needs {})", REQUIRED.join(", "));
            return Err(CamError::Sheet { line: 1, message });
        }
    }
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
        let (from, to, r_start, r_end) = (number("from_deg")?, number("to_deg")?, number("r_start")?, number("r_end")?);
        let piece = Piece::new(kind, r_start, from, r_end, to).map_err(in_row)?;
        segments.push(Segment { row: row.clone(), operation: text("operation"), disc: text("disc"), line, piece });
    }
    Ok(segments)
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
pub fn svg_drawing(fit: &CamFit, options: &SvgOptions) -> String {
    let r_max = fit.segments.iter().map(|s| s.segment.piece.r0.max(s.segment.piece.r1)).fold(10.0, f64::max);
    let half = r_max * 1.2;
    let magnify = options.magnify.unwrap_or(4.0 / fit.tolerance);
    let stroke = half / 500.0;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{w}\" viewBox=\"{} {} {} {}\">",
        -half,
        -half,
        2.0 * half,
        2.0 * half,
        w = options.width
    );
    let _ = writeln!(
        svg,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"white\"/>",
        -half,
        -half,
        2.0 * half,
        2.0 * half
    );
    let title = format!(
        "disc {} | H = {} mm | {} arcs | deviation x{}",
        if fit.disc.is_empty() { "-" } else { &fit.disc },
        fit.tolerance,
        fit.n_arcs(),
        fixed(magnify, 0)
    );
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\">{}</text>",
        -half * 0.97,
        -half * 0.92,
        half / 30.0,
        xml(&title)
    );
    // The cam centre.
    cross(&mut svg, Point2::origin(), half / 40.0, stroke, "black");
    for s in &fit.segments {
        let piece = &s.segment.piece;
        let n = ((piece.phi1_deg - piece.phi0_deg).abs() * SVG_SAMPLES_PER_DEG).ceil().max(8.0) as usize;
        let curve: Vec<Point2<f64>> = (0..=n).map(|i| piece.point(i as f64 / n as f64)).collect();
        polyline(&mut svg, &curve, stroke, "black");
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
        let label = mid - towards_centre * (half / 25.0);
        let _ = writeln!(
            svg,
            "<text x=\"{:.3}\" y=\"{:.3}\" font-size=\"{:.3}\" fill=\"{colour}\" text-anchor=\"middle\">{}</text>",
            label.x,
            -label.y,
            half / 45.0,
            i + 1
        );
        if a.centre.x.abs() < half && a.centre.y.abs() < half {
            cross(&mut svg, a.centre, half / 80.0, stroke, "grey");
        } else {
            let tick = mid + towards_centre * (half / 12.0);
            polyline(&mut svg, &[mid, tick], stroke, "grey");
        }
    }
    svg.push_str("</svg>\n");
    svg
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

fn polyline(svg: &mut String, points: &[Point2<f64>], width: f64, colour: &str) {
    let mut pts = String::new();
    for p in points {
        let _ = write!(pts, "{:.4},{:.4} ", p.x, -p.y);
    }
    let _ = writeln!(
        svg,
        "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{width:.4}\"/>",
        pts.trim_end()
    );
}

fn cross(svg: &mut String, c: Point2<f64>, size: f64, width: f64, colour: &str) {
    let (x, y) = (c.x, -c.y);
    let _ = writeln!(
        svg,
        "<path d=\"M {:.4} {y:.4} H {:.4} M {x:.4} {:.4} V {:.4}\" stroke=\"{colour}\" stroke-width=\"{width:.4}\"/>",
        x - size,
        x + size,
        y - size,
        y + size
    );
}

fn xml(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// `v` with `decimals` digits, never "-0".
fn fixed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}
