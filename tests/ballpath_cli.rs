//! `ncsheet ballpath` as a user runs it: csv and NC programs from the real binary, the ISO
//! program read back by LinuxCNC's `rs274` interpreter.

mod common;

use std::path::Path;
use std::process::Command;

use common::rs274::{self, Move};

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

fn ncsheet(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).current_dir(dir).output().unwrap();
    Run {
        code: out.status.code().unwrap(),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// A small path over a tilted plane z = 0.5x + 1 (slope 1/2 in x): 3 lines × 3 points.
const TILTED: &[&str] =
    &["ballpath", "--surface", "0.5*x+1", "--radius", "2", "--x", "0:4", "--y=-2:2", "--stepover", "2", "--step", "2"];

fn with(extra: &[&str]) -> Vec<String> {
    TILTED.iter().chain(extra).map(|s| s.to_string()).collect()
}

fn run(dir: &Path, args: &[String]) -> Run {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    ncsheet(dir, &args)
}

/// The csv rows as numbers.
fn csv_rows(text: &str) -> Vec<Vec<f64>> {
    text.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect()
}

#[test]
fn csv_has_centre_contact_and_tip() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), &with(&[]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert_eq!(r.stdout.lines().next(), Some("cx,cy,cz,px,py,pz,tx,ty,tz"));
    let rows = csv_rows(&r.stdout);
    assert_eq!(rows.len(), 9);
    // By hand: the normal of z = 0.5x + 1 is (−0.5, 0, 1)/√1.25, so the centre is the contact
    // point plus 2·(−0.4472, 0, 0.8944), the tip 2 below the centre.
    let n = 1.25f64.sqrt();
    for row in &rows {
        let [cx, cy, cz, px, py, pz, tx, ty, tz] = row[..] else { panic!("{row:?}") };
        assert!((pz - (0.5 * px + 1.0)).abs() < 1e-12);
        assert!((cx - (px - 1.0 / n)).abs() < 1e-12 && cy == py && (cz - (pz + 2.0 / n)).abs() < 1e-12);
        assert!(tx == cx && ty == cy && (tz - (cz - 2.0)).abs() < 1e-12);
    }
    // Zig-zag: the second line runs backwards.
    let ys: Vec<f64> = rows.iter().map(|r| r[4]).collect();
    assert_eq!(ys, [-2.0, 0.0, 2.0, 2.0, 0.0, -2.0, -2.0, 0.0, 2.0]);
}

#[test]
fn heidenhain_program_in_the_papers_form() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), &with(&["--format", "heidenhain", "--feed", "480", "-o", "bump.h"]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    let text = std::fs::read_to_string(dir.path().join("bump.h")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "0 BEGIN PGM BUMP MM");
    // The blank drawn for the control: the rectangle, from the lowest surface point (z = 1 at
    // x = 0) to the highest (z = 3 at x = 4).
    assert_eq!(lines[1], "1 BLK FORM 0.1 Z X+0.0000 Y-2.0000 Z+1.0000");
    assert_eq!(lines[2], "2 BLK FORM 0.2 X+4.0000 Y+2.0000 Z+3.0000");
    assert_eq!(lines[3], "3 ; ball-end mill R2: programmed point is the ball tip (centre - R in Z)");
    // Tool 1 at the default 3000 1/min; the spindle starts (M3) on the first move.
    assert_eq!(lines[4], "4 TOOL CALL 1 Z S3000");
    // Clearance: the highest tip is at x = 4 − 2/√1.25: z = 3 + 2/√1.25 − 2 = 2.789, + 5 → 8.
    assert_eq!(lines[5], "5 L Z+8.0000 FMAX M3");
    assert_eq!(lines[6], "6 L X-0.8944 Y-2.0000 FMAX");
    // First cut: contact (0, −2, 1), tip (−0.8944, −2, 1 + 1.7889 − 2).
    assert_eq!(lines[7], "7 L X-0.8944 Y-2.0000 Z+0.7889 F480");
    assert_eq!(lines[15], "15 L X+3.1056 Y+2.0000 Z+2.7889 F480");
    // The end: back to the clearance, compensation cancelled, spindle stopped.
    assert_eq!(lines[16], "16 L Z+8.0000 R0 FMAX M5");
    assert_eq!(lines[17], "17 END PGM BUMP MM");
    assert_eq!(lines.len(), 18);
}

#[test]
fn iso_programs_and_linuxcnc_reads_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), &with(&["--format", "iso"]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(r.stdout.starts_with("%\n(BALLPATH)\n"), "{}", r.stdout);
    // The tip at z 0.7889 is written higher by the reserve for 3 decimals on the plane's
    // slope 1/2 (docs/ballpath.md): 0.001·(1/2 + ½·√2/2) = 0.00085, so 0.7897 → 0.79.
    assert!(r.stdout.contains("G1 X-0.894 Y-2. Z0.79 F480."), "{}", r.stdout);
    std::fs::write(dir.path().join("iso.ngc"), &r.stdout).unwrap();

    let r = run(dir.path(), &with(&["--format", "linuxcnc", "--retract", "--program", "centre", "-o", "p.ngc"]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    let csv = csv_rows(&run(dir.path(), &with(&[])).stdout);
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    // The Fanuc-style ISO program (no O-number unless one is asked for) reads in LinuxCNC too,
    // and cuts through the programmed tips.
    let iso = rs274::moves(&dir.path().join("iso.ngc")).unwrap_or_else(|e| panic!("rs274 rejected iso:\n{e}"));
    // Milling feeds are per minute (G94: SET_FEED_MODE(0, 0)) before the first cut.
    for p in ["iso.ngc", "p.ngc"] {
        assert_eq!(rs274::feed_mode_at_first_cut(&dir.path().join(p)), Ok(Some(0)), "{p}");
    }
    let iso_feeds: Vec<[f64; 3]> = iso
        .iter()
        .filter_map(|m| match m {
            Move::Feed { x, y, z } => Some([*x, *y, *z]),
            _ => None,
        })
        .collect();
    assert_eq!(iso_feeds.len(), csv.len());
    // z higher by at most the reserve for 3 decimals on the slope 1/2 (0.00085 mm).
    let reserve = 0.001 * (0.5 + 0.5 * std::f64::consts::FRAC_1_SQRT_2);
    for (f, row) in iso_feeds.iter().zip(&csv) {
        for (k, (got, want)) in f.iter().zip(&row[6..9]).enumerate() {
            let above = if k == 2 { reserve } else { 0.0 };
            assert!(got - want >= -0.0005 - 1e-12 && got - want <= above + 0.0005 + 1e-12, "{f:?} vs tip {row:?}");
        }
    }
    let moves = rs274::moves(&dir.path().join("p.ngc")).unwrap_or_else(|e| panic!("rs274 rejected it:\n{e}"));
    let feeds: Vec<[f64; 3]> = moves
        .iter()
        .filter_map(|m| match m {
            Move::Feed { x, y, z } => Some([*x, *y, *z]),
            _ => None,
        })
        .collect();
    assert_eq!(feeds.len(), 9);
    for (f, row) in feeds.iter().zip(&csv) {
        for (k, (got, want)) in f.iter().zip(&row[0..3]).enumerate() {
            let above = if k == 2 { reserve } else { 0.0 };
            assert!(got - want >= -0.0005 - 1e-12 && got - want <= above + 0.0005 + 1e-12, "{f:?} vs centre {row:?}");
        }
    }
    // With --retract: up to the clearance after each line, over, down.
    let traverses = moves.iter().filter(|m| matches!(m, Move::Traverse { .. })).count();
    // Up, over the first line; up, over for the two others; up at the end.
    assert_eq!(traverses, 2 + 2 + 2 + 1);
}

#[test]
fn a_gouge_fails_with_where_and_how_deep_or_lifts() {
    let dir = tempfile::tempdir().unwrap();
    let groove = ["ballpath", "--surface", "-EXP(-(x^2)/4)", "--radius", "3", "--x=-1:1", "--y", "0:0"];
    let args: Vec<&str> = groove.iter().copied().chain(["--stepover", "1", "--step", "1"]).collect();
    let r = ncsheet(dir.path(), &args);
    assert_eq!(r.code, 1);
    assert!(r.stderr.starts_with("ncsheet: 3 ball positions and "), "{}", r.stderr);
    assert!(r.stderr.contains(" moves cut into the surface (up to 0."), "{}", r.stderr);
    assert!(r.stderr.contains("the ball touching (0.0000, 0.0000, -1.0000) cuts 0."), "{}", r.stderr);
    assert!(r.stderr.contains("--gouge lift"), "{}", r.stderr);
    let lifted: Vec<&str> = args.iter().copied().chain(["--gouge", "lift"]).collect();
    let r = ncsheet(dir.path(), &lifted);
    assert_eq!(r.code, 0);
    assert!(
        r.stderr.starts_with("ncsheet: lifted 3 ball positions clear of the surface and inserted points in "),
        "{}",
        r.stderr
    );
}

#[test]
fn a_surface_without_a_derivative_is_shown_with_a_caret() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["ballpath", "--surface", "1+VLOOKUP(x,A1:B2,2)", "--radius", "1", "--x", "0:1", "--y", "0:1"];
    let args: Vec<&str> = args.iter().copied().chain(["--stepover", "1", "--step", "1"]).collect();
    let r = ncsheet(dir.path(), &args);
    assert_eq!(r.code, 1);
    let want =
        "ncsheet: --surface: 1+VLOOKUP(x,A1:B2,2)\n                      ^ column 3: cannot differentiate VLOOKUP";
    assert!(r.stderr.starts_with(want), "{}", r.stderr);
}

#[test]
fn timings_are_split_into_compute_and_format() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), &with(&["--format", "heidenhain", "--timings", "-o", "t.h"]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    for word in ["points   9", "compute", "format", "write", "ns/point"] {
        assert!(r.stderr.contains(word), "{}", r.stderr);
    }
}

/// The command docs/ballpath.md gives for `sheets/eqcam-bump.h` (without `--format` and `-o`).
fn eqcam_bump() -> Vec<String> {
    common::cli::bump_ballpath("1", "1", "lift")
}

/// The bump by hand: height and gradient.
fn bump(x: f64, y: f64) -> (f64, f64, f64) {
    let e = 15.0 * (-0.0064 * (x * x + y * y)).exp();
    (e, -0.0128 * x * e, -0.0128 * y * e)
}

/// The exact drop-cutter height of a 3 mm ball over (cx, cy) on the bump's 50 mm square:
/// max of f + √(R² − d²) on a 24 × 24 grid under the footprint, the best refined uphill.
fn bump_drop(cx: f64, cy: f64) -> f64 {
    let r = 3.0;
    let g = |u: f64, v: f64| {
        let d2 = (u - cx).powi(2) + (v - cy).powi(2);
        if d2 > r * r || u.abs() > 25.0 || v.abs() > 25.0 {
            return f64::NEG_INFINITY;
        }
        bump(u, v).0 + (r * r - d2).sqrt()
    };
    let n = 24;
    let mut best = (f64::NEG_INFINITY, cx, cy);
    for i in 0..=n {
        for j in 0..=n {
            let (u, v) = (cx - r + 2.0 * r * i as f64 / n as f64, cy - r + 2.0 * r * j as f64 / n as f64);
            let (u, v) = (u.clamp(-25.0, 25.0), v.clamp(-25.0, 25.0));
            if g(u, v) > best.0 {
                best = (g(u, v), u, v);
            }
        }
    }
    let mut step = 2.0 * r / n as f64;
    while step > 1e-10 {
        let mut moved = false;
        for (du, dv) in
            [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.6, 0.8), (-0.6, -0.8), (0.8, -0.6), (-0.8, 0.6)]
        {
            let (u, v) = (best.1 + du * step, best.2 + dv * step);
            if g(u, v) > best.0 {
                (best, moved) = ((g(u, v), u, v), true);
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    best.0
}

/// The bump's program as its command writes it, checked against geometry computed here:
/// the raster's centres on the analytic normal, every programmed tip and every straight move
/// between them clear of the surface by the test's own drop-cutter, and the sheet spilling
/// the same first points.
#[test]
fn the_bump_program_is_exact_and_gouge_free() {
    let dir = tempfile::tempdir().unwrap();
    let with = |extra: &[&str]| eqcam_bump().into_iter().chain(extra.iter().map(|s| s.to_string())).collect::<Vec<_>>();
    let r = run(dir.path(), &with(&["--format", "heidenhain", "-o", "eqcam-bump.h"]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    let program = std::fs::read_to_string(dir.path().join("eqcam-bump.h")).unwrap();
    let r = run(dir.path(), &with(&[]));
    assert_eq!(r.code, 0, "{}", r.stderr);
    let rows = csv_rows(&r.stdout);
    // The raster's 51 × 51 contact points are all there, each ball on the analytic normal.
    let radius = 3.0;
    let mut on_grid = 0;
    for row in &rows {
        let [cx, cy, cz, px, py, pz, tx, ty, tz] = row[..] else { panic!("{row:?}") };
        let (f, fx, fy) = bump(px, py);
        assert!((pz - f).abs() < 1e-12, "{row:?}");
        assert!(tx == cx && ty == cy && (tz - (cz - radius)).abs() < 1e-12, "{row:?}");
        if px.fract() == 0.0 && py.fract() == 0.0 {
            on_grid += 1;
            let n = (1.0 + fx * fx + fy * fy).sqrt();
            let want = [px - radius * fx / n, py - radius * fy / n, pz + radius / n];
            for (got, want) in [cx, cy, cz].iter().zip(want) {
                assert!((got - want).abs() < 1e-12, "{row:?}: centre should be {want}");
            }
        }
    }
    assert!(on_grid >= 51 * 51, "{on_grid}");
    // The program's cutting blocks are the csv's tips at four decimals, z higher by at most
    // the reserve for them (0.0001·(1/2 + slope·√2/2); the bump's steepest slope is
    // 15·(32r/2500)·e^(−16r²/2500) at r = √(2500/32): 1.03).
    let tips: Vec<[f64; 3]> = program
        .lines()
        .filter(|l| l.ends_with(" F480"))
        .map(|l| {
            let words: Vec<&str> = l.split_whitespace().collect();
            let value = |w: &str| w[1..].parse::<f64>().unwrap();
            [value(words[2]), value(words[3]), value(words[4])]
        })
        .collect();
    assert_eq!(tips.len(), rows.len());
    for (tip, row) in tips.iter().zip(&rows) {
        for (k, (got, want)) in tip.iter().zip(&row[6..9]).enumerate() {
            let above = if k == 2 { 0.0001 * (0.5 + 1.03 * std::f64::consts::FRAC_1_SQRT_2) } else { 0.0 };
            assert!(*got - want >= -0.00005 - 1e-12 && *got - want <= above + 0.00005 + 1e-12, "{tip:?} vs {row:?}");
        }
    }
    // No programmed tip, and no point a quarter, half or three quarters along a move, more
    // than 1 µm (plus the program's rounding) below the drop-cutter height.
    let allowed = 0.001 + 0.0001;
    for (k, w) in tips.windows(2).enumerate() {
        for t in [0.0, 0.25, 0.5, 0.75] {
            let p: Vec<f64> = (0..3).map(|i| w[0][i] + t * (w[1][i] - w[0][i])).collect();
            let depth = bump_drop(p[0], p[1]) - radius - p[2];
            assert!(
                depth <= allowed,
                "block {k}: {t} of the way from {:?} to {:?} the tip is {depth} mm too low",
                w[0],
                w[1]
            );
        }
    }
    // The sheet spills the same tip points from row 13 on.
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let sheet = repo.join("sheets/eqcam-bump.csv");
    let r = ncsheet(dir.path(), &["eval", sheet.to_str().unwrap(), "A13:C14", "--format", "csv"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    for (line, row) in r.stdout.lines().zip(&rows) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        // The sheet prints 15 significant digits.
        for (got, want) in v.iter().zip(&row[6..9]) {
            assert!((got - want).abs() <= 1e-13 * (1.0 + want.abs()), "sheet {line} vs {row:?}");
        }
    }
}

#[test]
fn a_clearance_below_the_part_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bump = ["ballpath", "--surface", "15*EXP(-16*((x/50)^2+(y/50)^2))", "--radius", "3", "--x=-25:25"];
    let args: Vec<&str> = bump.iter().copied().chain(["--y=-25:25", "--stepover", "25", "--step", "25"]).collect();
    let refused: Vec<&str> =
        args.iter().copied().chain(["--gouge", "off", "--format", "iso", "--retract", "--clearance", "-100"]).collect();
    let r = ncsheet(dir.path(), &refused);
    assert_eq!(r.code, 1, "{}", r.stdout);
    // The top of the bump is at z = 15: the ball's tip there is the highest position.
    assert!(
        r.stderr.contains("--clearance -100 is below the highest ball position (its tip at z = 15.0000)"),
        "{}",
        r.stderr
    );
    assert!(r.stdout.is_empty());
    let fine: Vec<&str> =
        args.iter().copied().chain(["--gouge", "off", "--format", "iso", "--clearance", "15"]).collect();
    assert_eq!(ncsheet(dir.path(), &fine).code, 0);
}
