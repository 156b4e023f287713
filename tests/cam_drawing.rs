//! The cam and arcfit drawings as a machinist reads them: rendered to PNG by rsvg-convert
//! (librsvg), with a legend, a scale bar and angle marks, and no two labels overlapping.
//! Label boxes are computed here from the SVG's text elements and DejaVu Sans' glyph widths.

use std::path::Path;
use std::process::Command;

fn ncsheet(dir: &Path, args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).current_dir(dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

fn rsvg_available() -> bool {
    let found = Command::new("rsvg-convert").arg("--version").output().is_ok();
    assert!(found || std::env::var_os("CI").is_none(), "rsvg-convert is missing on CI (librsvg2-bin)");
    found
}

/// The value of attribute `name` in one element's text.
fn attr<'a>(element: &'a str, name: &str) -> Option<&'a str> {
    let start = element.find(&format!(" {name}=\""))? + name.len() + 3;
    element[start..].split('"').next()
}

/// Every `<text>` element's box: x0, y0, x1, y1 in drawing units, and its text.
fn text_boxes(svg: &str) -> Vec<([f64; 4], String)> {
    svg.split("<text")
        .skip(1)
        .map(|rest| {
            let (element, after) = rest.split_once('>').unwrap();
            let text =
                after.split("</text>").next().unwrap().replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">");
            let num = |n: &str| attr(element, n).unwrap().parse::<f64>().unwrap();
            let (x, y, size) = (num("x"), num("y"), num("font-size"));
            // DejaVu Sans: digits 0.636 em wide, most letters narrower; cap height 0.73 em.
            let width = 0.6 * size * text.chars().count() as f64;
            let left = match attr(element, "text-anchor") {
                Some("middle") => x - width / 2.0,
                Some("end") => x - width,
                _ => x,
            };
            ([left, y - 0.73 * size, left + width, y + 0.2 * size], text)
        })
        .collect()
}

fn check_drawing(dir: &Path, svg: &str, name: &str) {
    let path = dir.join(format!("{name}.svg"));
    std::fs::write(&path, svg).unwrap();
    let png = dir.join(format!("{name}.png"));
    let out = Command::new("rsvg-convert").arg("-o").arg(&png).arg(&path).output().unwrap();
    assert!(out.status.success(), "rsvg-convert: {}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG") && bytes.len() > 10_000, "{name}: not a drawn PNG");
    let boxes = text_boxes(svg);
    let texts: Vec<&str> = boxes.iter().map(|(_, t)| t.as_str()).collect();
    assert!(texts.iter().any(|t| t.contains("theoretical cam curve")), "{name}: no legend: {texts:?}");
    // The magnification of the title (deviation xN) is explained in the legend.
    let title = texts.iter().find(|t| t.contains("deviation x")).expect("a title");
    let factor = title.rsplit("deviation x").next().unwrap();
    let explained = format!("magnified x{factor} along the radius");
    assert!(texts.iter().any(|t| t.contains(&explained)), "{name}: deviation not explained: {texts:?}");
    assert!(texts.iter().any(|t| t.ends_with(" mm") && t.len() < 8), "{name}: no scale bar: {texts:?}");
    assert!(texts.iter().any(|t| t.ends_with('°')), "{name}: no angle marks: {texts:?}");
    for (i, (a, ta)) in boxes.iter().enumerate() {
        for (b, tb) in &boxes[i + 1..] {
            let overlap = a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
            assert!(!overlap, "{name}: labels '{ta}' and '{tb}' overlap");
        }
    }
}

#[test]
fn cam_and_arcfit_drawings_have_a_legend_scale_angles_and_separate_labels() {
    if !rsvg_available() {
        eprintln!("skipped: rsvg-convert is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let sheet = format!("{}/sheets/cam-turret.csv", env!("CARGO_MANIFEST_DIR"));
    for tol in ["0.01", "0.001"] {
        let svg = ncsheet(dir.path(), &["cam", &sheet, "--tol", tol, "--partial", "--format", "svg"]);
        check_drawing(dir.path(), &svg, &format!("cam-{tol}"));
    }
    let svg = ncsheet(
        dir.path(),
        &[
            "arcfit", "--kind", "arch", "--r0", "79", "--phi0", "36", "--r1", "102", "--phi1", "160.2", "--tol",
            "0.01", "--format", "svg",
        ],
    );
    check_drawing(dir.path(), &svg, "arcfit");
    // The frame fits the piece: its drawing is not mostly empty below the curve.
    let view: Vec<f64> = attr(&svg, "viewBox").unwrap().split(' ').map(|v| v.parse().unwrap()).collect();
    assert!(view[3] < view[2], "arcfit frame {view:?} is taller than wide for a piece above the centre");
}
