//! Backplots of the shipped examples (issue 15): the chamfer program of sheets/chamfer.bas,
//! the cam program of sheets/cam-turret.csv and the ball path over docs/domain.md §3's bump, each
//! drawn by `ncsheet nc plot` and rendered to PNG by rsvg-convert (librsvg). The drawn pixels
//! of the feed (solid blue) and rapid (dashed red) lines must span the box of the path computed
//! here from the program text by a separate reading (arcs sampled every 0.01°), and the chamfer
//! program's cut must be docs/domain.md §1's table row.

mod common;

use std::io::Read;
use std::path::Path;
use std::process::Command;

use common::cli::{ncsheet, Invocation};

fn rsvg_available() -> bool {
    let found = Command::new("rsvg-convert").arg("--version").output().is_ok();
    assert!(found || std::env::var_os("CI").is_none(), "rsvg-convert is missing on CI (librsvg2-bin)");
    found
}

fn sheet(name: &str) -> String {
    format!("{}/sheets/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// A box in the drawing's plane: (across min, up min, across max, up max).
type Box2 = [f64; 4];

fn grow(b: &mut Option<Box2>, h: f64, v: f64) {
    let n = b.get_or_insert([h, v, h, v]);
    *n = [n[0].min(h), n[1].min(v), n[2].max(h), n[3].max(v)];
}

/// The program's moves read here, apart from ncsheet's reader: G0-G3 modal, absolute, X Y Z,
/// I J (mill) or I K (lathe, I a radius) centre offsets; X halved on a lathe. Moves before
/// every axis the program uses is known go from where the machine stood and are not drawn.
/// Returns the boxes of (feed moves, all moves) in the plane (`axes` across, up: 0 X, 1 Y, 2 Z).
fn independent_boxes(text: &str, lathe: bool, axes: (usize, usize)) -> (Box2, Box2) {
    let word = |line: &str, l: char| -> Option<f64> {
        let i = line.find(l)?;
        let rest = &line[i + 1..];
        let end = rest.find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-')).unwrap_or(rest.len());
        rest[..end].parse().ok()
    };
    let blocks: Vec<String> = text
        .lines()
        .map(|l| {
            let mut s = l.to_string();
            while let (Some(a), Some(b)) = (s.find('('), s.find(')')) {
                s.replace_range(a..=b, "");
            }
            s
        })
        .collect();
    let used: Vec<bool> = ['X', 'Y', 'Z'].iter().map(|&l| blocks.iter().any(|b| word(b, l).is_some())).collect();
    let mut at: [Option<f64>; 3] = [0, 1, 2].map(|i| (!used[i]).then_some(0.0));
    let mut motion = 0;
    let (mut feeds, mut all) = (None, None);
    for b in &blocks {
        let gs: Vec<f64> = b.match_indices('G').filter_map(|(i, _)| word(&b[i..], 'G')).collect();
        for g in gs {
            if [0.0, 1.0, 2.0, 3.0].contains(&g) {
                motion = g as i32;
            }
        }
        let target: Vec<Option<f64>> =
            ['X', 'Y', 'Z'].iter().map(|&l| word(b, l).map(|v| if l == 'X' && lathe { v / 2.0 } else { v })).collect();
        if target.iter().all(Option::is_none) {
            continue;
        }
        let from = at;
        for i in 0..3 {
            at[i] = target[i].or(at[i]);
        }
        let (Some(f), Some(t)) = (known(from), known(at)) else { continue };
        let mut points = vec![f, t];
        if motion >= 2 {
            // The circle's plane (u, v) and centre; angles sampled every 0.01° along the turn.
            let (u, v, du, dv) =
                if lathe { (2, 0, word(b, 'K'), word(b, 'I')) } else { (0, 1, word(b, 'I'), word(b, 'J')) };
            let c = (f[u] + du.unwrap_or(0.0), f[v] + dv.unwrap_or(0.0));
            let r = (f[u] - c.0).hypot(f[v] - c.1);
            let a0 = (f[v] - c.1).atan2(f[u] - c.0);
            let a1 = (t[v] - c.1).atan2(t[u] - c.0);
            let ccw = motion == 3;
            let mut sweep = if ccw { a1 - a0 } else { a0 - a1 };
            while sweep <= 0.0 {
                sweep += std::f64::consts::TAU;
            }
            let n = (sweep.to_degrees() * 100.0).ceil() as usize;
            for k in 0..=n {
                let a = a0 + if ccw { 1.0 } else { -1.0 } * sweep * k as f64 / n as f64;
                let mut p = f;
                p[u] = c.0 + r * a.cos();
                p[v] = c.1 + r * a.sin();
                points.push(p);
            }
        }
        for p in points {
            grow(&mut all, p[axes.0], p[axes.1]);
            if motion != 0 {
                grow(&mut feeds, p[axes.0], p[axes.1]);
            }
        }
    }
    (feeds.expect("feed moves"), all.expect("moves"))
}

fn known(p: [Option<f64>; 3]) -> Option<[f64; 3]> {
    Some([p[0]?, p[1]?, p[2]?])
}

/// An RGBA or RGB PNG of 8 bits a channel, decoded: (width, height, channels, pixels).
fn decode_png(bytes: &[u8]) -> (usize, usize, usize, Vec<u8>) {
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    let (mut width, mut height, mut channels) = (0, 0, 0);
    let mut data = Vec::new();
    let mut i = 8;
    while i + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap()) as usize;
        let kind = &bytes[i + 4..i + 8];
        let body = &bytes[i + 8..i + 8 + len];
        match kind {
            b"IHDR" => {
                width = u32::from_be_bytes(body[0..4].try_into().unwrap()) as usize;
                height = u32::from_be_bytes(body[4..8].try_into().unwrap()) as usize;
                assert_eq!(body[8], 8, "8 bits a channel");
                channels = match body[9] {
                    6 => 4,
                    2 => 3,
                    t => panic!("colour type {t}"),
                };
                assert_eq!(body[12], 0, "not interlaced");
            }
            b"IDAT" => data.extend_from_slice(body),
            _ => {}
        }
        i += 12 + len;
    }
    let mut raw = Vec::new();
    flate2::read::ZlibDecoder::new(&data[..]).read_to_end(&mut raw).unwrap();
    let stride = width * channels;
    let mut out = vec![0u8; stride * height];
    for y in 0..height {
        let filter = raw[y * (stride + 1)];
        for x in 0..stride {
            let cur = raw[y * (stride + 1) + 1 + x];
            let a = if x >= channels { out[y * stride + x - channels] } else { 0 };
            let b = if y > 0 { out[(y - 1) * stride + x] } else { 0 };
            let c = if x >= channels && y > 0 { out[(y - 1) * stride + x - channels] } else { 0 };
            let predicted = match filter {
                0 => 0,
                1 => a,
                2 => b,
                3 => ((a as u16 + b as u16) / 2) as u8,
                4 => {
                    let p = a as i16 + b as i16 - c as i16;
                    let (pa, pb, pc) = ((p - a as i16).abs(), (p - b as i16).abs(), (p - c as i16).abs());
                    if pa <= pb && pa <= pc {
                        a
                    } else if pb <= pc {
                        b
                    } else {
                        c
                    }
                }
                f => panic!("PNG filter {f}"),
            };
            out[y * stride + x] = cur.wrapping_add(predicted);
        }
    }
    (width, height, channels, out)
}

/// The value of attribute `name` in the first element whose text starts with `start`.
fn attr(svg: &str, start: &str, name: &str) -> String {
    let element = &svg[svg.find(start).unwrap_or_else(|| panic!("no {start}"))..];
    let element = &element[..element.find('>').unwrap()];
    let at = element.find(&format!(" {name}=\"")).unwrap_or_else(|| panic!("no {name} in {element}")) + name.len() + 3;
    element[at..].split('"').next().unwrap().to_string()
}

fn numbers(text: &str) -> Vec<f64> {
    text.split([' ', ',']).filter(|s| !s.is_empty()).map(|s| s.parse().unwrap()).collect()
}

/// Pixel boxes (x0, y0, x1, y1) of the blue (feed) and of the blue-or-red (any move) pixels
/// inside the drawing's frame.
fn drawn_boxes(png: &Path, svg: &str) -> (Box2, Box2) {
    let (w, h, ch, px) = decode_png(&std::fs::read(png).unwrap());
    let view = numbers(&attr(svg, "<svg", "viewBox"));
    let (sx, sy) = (w as f64 / view[2], h as f64 / view[3]);
    let frame: Vec<f64> =
        ["x", "y", "width", "height"].iter().map(|a| attr(svg, "<rect id=\"frame\"", a).parse().unwrap()).collect();
    let fx0 = ((frame[0] - view[0]) * sx).ceil() as usize + 2;
    let fy0 = ((frame[1] - view[1]) * sy).ceil() as usize + 2;
    let fx1 = ((frame[0] + frame[2] - view[0]) * sx).floor() as usize - 2;
    let fy1 = ((frame[1] + frame[3] - view[1]) * sy).floor() as usize - 2;
    let (mut feed, mut any) = (None, None);
    for y in fy0..fy1.min(h) {
        for x in fx0..fx1.min(w) {
            let p = &px[(y * w + x) * ch..];
            let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
            let blue = b - r > 60 && b - g > 40;
            let red = r - g > 60 && r - b > 60;
            if blue {
                grow(&mut feed, x as f64, y as f64);
            }
            if blue || red {
                grow(&mut any, x as f64, y as f64);
            }
        }
    }
    (feed.expect("blue pixels"), any.expect("drawn pixels"))
}

/// A box in mm (across, up) as pixels of the PNG, through the drawing's view box and the
/// scale of its tool-path group.
fn to_pixels(b: Box2, svg: &str, png_width: f64) -> Box2 {
    let view = numbers(&attr(svg, "<svg", "viewBox"));
    let transform = attr(svg, "<g id=\"toolpath\"", "transform");
    let k: f64 = transform.trim_start_matches("scale(").trim_end_matches(')').parse().unwrap();
    let s = png_width / view[2];
    [(b[0] * k - view[0]) * s, (-b[3] * k - view[1]) * s, (b[2] * k - view[0]) * s, (-b[1] * k - view[1]) * s]
}

fn close_boxes(what: &str, got: Box2, want: Box2, tol: f64) {
    for i in 0..4 {
        assert!((got[i] - want[i]).abs() <= tol, "{what}: drawn {got:?}, the path's box is {want:?} (±{tol} px)");
    }
}

/// Plots `program` (`lathe` or mill, in `plane` if given), renders it and checks the boxes and
/// the legend; returns the SVG.
fn check_backplot(dir: &Path, name: &str, lathe: bool, plane: Option<&str>) -> String {
    let program = dir.join(format!("{name}.nc"));
    let text = std::fs::read_to_string(&program).unwrap();
    let svg_path = dir.join(format!("{name}.svg"));
    let mut args = vec!["nc", "plot", program.to_str().unwrap(), "-o", svg_path.to_str().unwrap()];
    if let Some(p) = plane {
        args.extend(["--plane", p]);
    }
    let run = ncsheet(&args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let png = dir.join(format!("{name}.png"));
    let out = Command::new("rsvg-convert").arg("-o").arg(&png).arg(&svg_path).output().unwrap();
    assert!(out.status.success(), "rsvg-convert: {}", String::from_utf8_lossy(&out.stderr));

    let axes = match plane.unwrap_or(if lathe { "zx" } else { "xy" }) {
        "xy" => (0, 1),
        "xz" => (0, 2),
        _ => (2, 0),
    };
    let (feed_mm, all_mm) = independent_boxes(&text, lathe, axes);
    let png_width: f64 = attr(&svg, "<svg", "width").parse().unwrap();
    let (feed_px, all_px) = drawn_boxes(&png, &svg);
    // Solid lines: the stroke's half width and antialiasing; dashed rapids may end in a gap.
    close_boxes(&format!("{name}: feed moves"), feed_px, to_pixels(feed_mm, &svg, png_width), 3.0);
    close_boxes(&format!("{name}: all moves"), all_px, to_pixels(all_mm, &svg, png_width), 3.0 + 0.01 * png_width);

    for legend in
        ["rapid traverse (G0)", "feed moves (G1 lines, G2/G3 arcs)", "start of the path", "direction of travel"]
    {
        assert!(svg.contains(&format!(">{legend}")), "{name}: no legend entry '{legend}'");
    }
    let scale =
        svg.split("<text").any(|t| t.split('>').nth(1).is_some_and(|s| s.trim_end_matches("</text").ends_with(" mm")));
    assert!(scale, "{name}: no scale bar");
    svg
}

#[test]
fn backplots_of_the_shipped_examples_span_their_paths() {
    if !rsvg_available() {
        eprintln!("skipped: rsvg-convert is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let at = Invocation { dir: Some(d), ..Invocation::default() };

    // The paper's macro on the paper's workbook: docs/domain.md §1's outer chamfer.
    let args = common::cli::outer_chamfer("iso", "chamfer.nc");
    let run = at.run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = std::fs::read_to_string(d.join("chamfer.nc")).unwrap();
    assert!(
        text.contains("X44.263 Z-4.6") && text.contains("X33.063 Z1."),
        "the chamfer cut of docs/domain.md §1:\n{text}"
    );
    check_backplot(d, "chamfer", true, None);

    let run =
        at.run(&["cam", &sheet("cam-turret.csv"), "--tol", "0.01", "--partial", "--format", "nc", "-o", "cam.nc"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let svg = check_backplot(d, "cam", false, None);
    // Arcs are drawn as SVG arcs, one (or two for a full circle) per G2/G3 block.
    let text = std::fs::read_to_string(d.join("cam.nc")).unwrap();
    let arcs = text.lines().filter(|l| l.split_whitespace().any(|w| ["G2", "G3", "G02", "G03"].contains(&w))).count();
    assert!(arcs > 10);
    assert_eq!(svg.matches(" A ").count(), arcs, "arcs drawn as SVG arcs");

    let mut args = common::cli::bump_ballpath("1", "1", "off");
    args.extend(["--format", "iso", "-o", "ball.nc"].map(String::from));
    let run = at.run(&args.iter().map(String::as_str).collect::<Vec<_>>());
    // (The README's path lifts the ball by at most 0.04 mm where a move dips: the drop-cutter
    // takes a minute in a test build and is not what is drawn here.)
    assert_eq!(run.code, 0, "{}", run.stderr);
    check_backplot(d, "ball", false, None);
    std::fs::copy(d.join("ball.nc"), d.join("ball-front.nc")).unwrap();
    check_backplot(d, "ball-front", false, Some("xz"));
}

#[test]
fn nc_plot_never_writes_over_its_program() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("p.nc");
    std::fs::write(&program, "G21 G17 G90\nT1 M6\nS1000 M3\nG94\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10\nM30\n").unwrap();
    let p = program.to_str().unwrap();
    let run = ncsheet(&["nc", "plot", p, "-o", p]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("refusing to overwrite"), "{}", run.stderr);
    assert!(std::fs::read_to_string(&program).unwrap().starts_with("G21"));
}

#[test]
fn nc_plot_names_the_line_it_cannot_read() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("p.nc");
    std::fs::write(&program, "G21 G17 G90\nG0 X0 Y0 Z5\nG1 X10 Q3 F100\n").unwrap();
    let out = dir.path().join("p.svg");
    let run = ncsheet(&["nc", "plot", program.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("line 3, column 8"), "{}", run.stderr);
    assert!(!out.exists(), "no drawing of a program that does not read");
}

#[test]
fn a_program_without_moves_has_nothing_to_plot() {
    let dir = tempfile::tempdir().unwrap();
    let program = dir.path().join("p.nc");
    std::fs::write(&program, "G21 G17 G90\nT1 M6\nS1000 M3\nM30\n").unwrap();
    let out = dir.path().join("p.svg");
    let run = ncsheet(&["nc", "plot", program.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("nothing to plot"), "{}", run.stderr);
    assert!(!out.exists());
}
