//! The pieces every ncsheet drawing is made of (the cam drawing of `cam_sheet`, the backplot
//! of `backplot`): the document's frame, lines in drawing millimetres with y up, a scale bar,
//! and text labels placed so that no two overlap. Text out; the command line writes the file.

use std::fmt::Write;

use nalgebra::Point2;

/// Opens a drawing whose view box is `[x0, y0, w, h]` in SVG units (mm, y down), `width`
/// pixels wide, on a white ground.
pub fn begin(svg: &mut String, width: f64, view: [f64; 4]) {
    let [x0, y0, w, h] = view;
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0}\" height=\"{:.0}\" viewBox=\"{x0:.3} {y0:.3} {w:.3} {h:.3}\" font-family=\"sans-serif\">",
        width,
        width * h / w
    );
    let _ = writeln!(svg, "<rect x=\"{x0:.3}\" y=\"{y0:.3}\" width=\"{w:.3}\" height=\"{h:.3}\" fill=\"white\"/>");
}

/// A bar of a round length (1, 2 or 5 × 10ⁿ mm, the longest not above `target` mm), drawn at
/// `per_mm` drawing units a millimetre, its left end one font size right of `corner` and
/// above it, labelled in mm.
pub fn scale_bar(
    svg: &mut String,
    labels: &mut Labels,
    target: f64,
    per_mm: f64,
    corner: (f64, f64),
    stroke: f64,
    font: f64,
) {
    let power = 10f64.powf(target.log10().floor());
    let length = [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * power).rfind(|&l| l <= target).unwrap_or(power);
    let (x, y) = (corner.0 + font, corner.1 - font);
    let _ = writeln!(
        svg,
        "<path d=\"M {x:.3} {:.3} V {y:.3} H {:.3} V {:.3}\" fill=\"none\" stroke=\"black\" stroke-width=\"{:.4}\"/>",
        y - 0.5 * font,
        x + length * per_mm,
        y - 0.5 * font,
        2.0 * stroke
    );
    // A bar below 1 mm needs the digits of its power of ten.
    let decimals = (-power.log10().round()).max(0.0) as usize;
    labels.place(
        svg,
        &[Point2::new(x + length * per_mm + 0.5 * font, y)],
        &format!("{} mm", fixed(length, decimals)),
        0.8 * font,
        "black",
        "start",
    );
}

/// Text labels placed so that none overlaps another: each takes the first of its candidate
/// places whose box (estimated from the font size) is free and inside the drawing.
pub struct Labels {
    boxes: Vec<[f64; 4]>,
    bounds: [f64; 4],
}

impl Labels {
    /// Labels inside `bounds` (x0, y0, x1, y1 in SVG units).
    pub fn new(bounds: [f64; 4]) -> Labels {
        Labels { boxes: Vec::new(), bounds }
    }

    /// Writes `text` at the first free place of `candidates`; a label with no free place is
    /// left out.
    pub fn place(
        &mut self,
        svg: &mut String,
        candidates: &[Point2<f64>],
        text: &str,
        size: f64,
        colour: &str,
        anchor: &str,
    ) {
        for at in candidates {
            let b = text_box(at.x, at.y, size, text, anchor);
            let inside =
                b[0] >= self.bounds[0] && b[1] >= self.bounds[1] && b[2] <= self.bounds[2] && b[3] <= self.bounds[3];
            if inside && self.boxes.iter().all(|o| !boxes_overlap(o, &b)) {
                self.boxes.push(b);
                let _ = writeln!(
                    svg,
                    "<text x=\"{:.3}\" y=\"{:.3}\" font-size=\"{size:.3}\" fill=\"{colour}\" text-anchor=\"{anchor}\">{}</text>",
                    at.x,
                    at.y,
                    xml(text)
                );
                return;
            }
        }
    }
}

/// The box a text covers (x0, y0, x1, y1), with a sans-serif glyph taken as 0.66 em wide
/// (DejaVu Sans digits are 0.636 em), from above the cap height to below the baseline.
fn text_box(x: f64, y: f64, size: f64, text: &str, anchor: &str) -> [f64; 4] {
    let width = 0.66 * size * text.chars().count() as f64;
    let left = match anchor {
        "middle" => x - width / 2.0,
        "end" => x - width,
        _ => x,
    };
    [left, y - 0.85 * size, left + width, y + 0.25 * size]
}

fn boxes_overlap(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// A polyline through drawing points (y up).
pub fn polyline(svg: &mut String, points: &[Point2<f64>], width: f64, colour: &str) {
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

/// A cross at a drawing point (y up).
pub fn cross(svg: &mut String, c: Point2<f64>, size: f64, width: f64, colour: &str) {
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

/// Text as XML character data.
pub fn xml(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// `v` with `decimals` digits, never "-0".
pub fn fixed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}
