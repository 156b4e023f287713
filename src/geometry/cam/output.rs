//! What a fitted cam becomes: a coordinate table (csv), an NC milling program (ISO/Fanuc
//! style, as LinuxCNC reads it) and an SVG drawing for checking it by eye, like the paper's
//! plotter drawing. Pure functions returning strings.
//!
//! These are writers, not geometry: the csv goes to `src/io` and the NC program to `src/nc`,
//! behind the dialect layer, when those exist for cams. Keep them small until then.

use std::f64::consts::TAU;
use std::fmt::Write;

use nalgebra::{Point2, Vector2};

use super::arc::{Arc, Turn};
use super::profile::CamFit;

/// The header of [`arcs_csv`].
pub const CSV_HEADER: &str = "x0,y0,x1,y1,cx,cy,r,dir";

/// One line per arc: start, end, centre, radius (mm, 6 decimals), dir = 1 counter-clockwise,
/// −1 clockwise.
pub fn arcs_csv<'a>(arcs: impl IntoIterator<Item = &'a Arc>) -> String {
    let mut out = format!("{CSV_HEADER}\n");
    for a in arcs {
        let n = [a.start.x, a.start.y, a.end.x, a.end.y, a.centre.x, a.centre.y, a.radius];
        let fields: Vec<String> = n.iter().map(|v| fixed(*v, 6)).collect();
        let _ = writeln!(out, "{},{}", fields.join(","), a.turn.sign() as i32);
    }
    out
}

/// Cutter radius compensation for the NC program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compensation {
    /// The programmed path is the profile itself (the cutter's centre follows it).
    Off,
    /// G41, cutter left of the path.
    Left,
    /// G42, cutter right of the path: outside a cam cut counter-clockwise.
    Right,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NcOptions {
    /// Cutting feed, mm/min.
    pub feed: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed: f64,
    /// Spindle speed, 1/min (M3).
    pub spindle: f64,
    /// Clearance height above the disc.
    pub z_safe: f64,
    /// Cutting depth (negative: into the disc).
    pub z_cut: f64,
    /// Length of the straight radial lead-in and lead-out, from outside the profile.
    pub lead: f64,
    pub compensation: Compensation,
    /// Tool offset number for G41/G42 (D word).
    pub tool: u32,
}

impl Default for NcOptions {
    fn default() -> NcOptions {
        NcOptions {
            feed: 200.0,
            plunge_feed: 100.0,
            spindle: 1000.0,
            z_safe: 5.0,
            z_cut: -12.0,
            lead: 5.0,
            compensation: Compensation::Off,
            tool: 1,
        }
    }
}

/// NC program digits: the paper's machine resolves 0.1 µm.
const NC_DECIMALS: usize = 4;

/// Consecutive arcs farther apart than this (mm) get a straight move between them.
const GAP: f64 = 1e-6;

/// The milling program: G17 G21 G90, a radial lead-in from outside to the first arc's start,
/// every arc as G2/G3 with I J (centre relative to the arc's start, as written), straight G1
/// moves across gaps and steps of a partial cam, and a radial lead-out. I and J are taken from
/// the start point as printed, so the control's centre is within half a digit of the true one.
pub fn nc_program(fit: &CamFit, options: &NcOptions) -> String {
    let arcs: Vec<&Arc> = fit.arcs().collect();
    let mut w = NcWriter { out: String::new(), block: 0, at: Point2::origin() };
    w.out.push_str("%\n");
    let disc = if fit.disc.is_empty() { String::new() } else { format!(" DISC {}", fit.disc) };
    w.comment(&format!("NCSHEET CAM{disc}: {} ARCS, TOLERANCE {} MM", arcs.len(), fit.tolerance));
    w.block("G17 G21 G90 G40 G94");
    let (Some(first), Some(last)) = (arcs.first(), arcs.last()) else {
        w.block("M30");
        w.out.push_str("%\n");
        return w.out;
    };
    let outward = |p: Point2<f64>| if p.coords.norm() > 0.0 { p.coords.normalize() } else { Vector2::x() };
    let entry = first.start + outward(first.start) * options.lead;
    w.block(&format!("S{} M3", fixed(options.spindle, 0)));
    w.block(&format!("G0 Z{}", nc(options.z_safe)));
    w.block(&format!("G0 X{} Y{}", nc(entry.x), nc(entry.y)));
    w.at = round_point(entry);
    w.block(&format!("G1 Z{} F{}", nc(options.z_cut), fixed(options.plunge_feed, 0)));
    let comp = match options.compensation {
        Compensation::Off => String::new(),
        Compensation::Left => format!("G41 D{} ", options.tool),
        Compensation::Right => format!("G42 D{} ", options.tool),
    };
    w.line_to(first.start, &comp, &format!(" F{}", fixed(options.feed, 0)));
    let mut previous_end = first.start;
    for (i, a) in arcs.iter().enumerate() {
        if (a.start - previous_end).norm() > GAP {
            // A gap or step of a partial cam: straight across.
            w.line_to(a.start, "", "");
        }
        w.arc(a, i + 1);
        previous_end = a.end;
    }
    let exit = last.end + outward(last.end) * options.lead;
    let uncomp = if options.compensation == Compensation::Off { "" } else { "G40 " };
    w.line_to(exit, uncomp, "");
    w.block(&format!("G0 Z{}", nc(options.z_safe)));
    w.block("M5");
    w.block("M30");
    w.out.push_str("%\n");
    w.out
}

struct NcWriter {
    out: String,
    block: usize,
    /// The position as the control knows it: the last point as printed.
    at: Point2<f64>,
}

impl NcWriter {
    fn block(&mut self, words: &str) {
        self.block += 10;
        let _ = writeln!(self.out, "N{} {words}", self.block);
    }

    fn comment(&mut self, text: &str) {
        let _ = writeln!(self.out, "({})", text.replace(['(', ')'], ""));
    }

    fn line_to(&mut self, p: Point2<f64>, before: &str, after: &str) {
        self.block(&format!("{before}G1 X{} Y{}{after}", nc(p.x), nc(p.y)));
        self.at = round_point(p);
    }

    fn arc(&mut self, a: &Arc, number: usize) {
        let g = match a.turn {
            Turn::Ccw => "G3",
            Turn::Cw => "G2",
        };
        let (i, j) = (a.centre.x - self.at.x, a.centre.y - self.at.y);
        let words = format!("{g} X{} Y{} I{} J{}", nc(a.end.x), nc(a.end.y), nc(i), nc(j));
        self.block(&format!("{words} (ARC {number})"));
        self.at = round_point(a.end);
    }
}

fn round_point(p: Point2<f64>) -> Point2<f64> {
    let scale = 10f64.powi(NC_DECIMALS as i32);
    Point2::new((p.x * scale).round() / scale, (p.y * scale).round() / scale)
}

fn nc(v: f64) -> String {
    fixed(v, NC_DECIMALS)
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
