//! Issue 33, scope 3: one-way rasters over docs/domain.md §3's bump (the paper's listing cuts
//! every line the same way, retracting and returning to the start of the next line). The
//! program text is read as a control reads it; the surface is the bump's closed form here.

use std::process::Command;

/// The shipped bump, z = 0.3·e^(−16x²−16y²) scaled 50× (sheets/eqcam-bump.csv).
const BUMP: &str = "15*EXP(-16*((x/50)^2+(y/50)^2))";
const R: f64 = 3.0;

fn bump(x: f64, y: f64) -> f64 {
    15.0 * (-16.0 * ((x / 50.0).powi(2) + (y / 50.0).powi(2))).exp()
}

fn program(extra: &[&str]) -> String {
    let args = [
        "ballpath",
        "--surface",
        BUMP,
        "--radius",
        "3",
        "--x=-25:25",
        "--y=-25:25",
        "--stepover",
        "5",
        "--step",
        "2.5",
        "--format",
        "iso",
        // Chords 2.5 mm long across the dome cut it by up to 0.2 mm: not what is checked here.
        "--gouge",
        "off",
    ];
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).args(extra).output().unwrap();
    assert!(out.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// Every move of a word-address program: rapid or not, from, to (modal G0/G1, absolute).
fn moves(text: &str) -> Vec<(bool, [f64; 3], [f64; 3])> {
    let mut at = [f64::NAN; 3];
    let mut rapid = true;
    let mut out = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('(') && !l.starts_with('%')) {
        let words: Vec<&str> = line.split_whitespace().collect();
        for w in &words {
            match *w {
                "G0" | "G00" => rapid = true,
                "G1" | "G01" => rapid = false,
                _ => {}
            }
        }
        let value = |letter: char| words.iter().find_map(|w| w.strip_prefix(letter)?.parse::<f64>().ok());
        let to = [value('X').unwrap_or(at[0]), value('Y').unwrap_or(at[1]), value('Z').unwrap_or(at[2])];
        if ['X', 'Y', 'Z'].iter().any(|&c| value(c).is_some()) {
            out.push((rapid, at, to));
            at = to;
        }
    }
    out
}

/// The highest point of the surface within R of the segment a–b in plan (sampled every
/// 0.25 mm along it and on a ring of radius R round each sample).
fn highest_under(a: [f64; 3], b: [f64; 3]) -> f64 {
    let a = if a[0].is_nan() { b } else { a };
    let n = (((b[0] - a[0]).hypot(b[1] - a[1])) / 0.25).ceil().max(1.0) as usize;
    let mut top = f64::MIN;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        let (x, y) = (a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t);
        for k in 0..=24 {
            let (r, angle) = (if k == 0 { 0.0 } else { R }, k as f64 * std::f64::consts::TAU / 24.0);
            top = top.max(bump(x + r * angle.cos(), y + r * angle.sin()));
        }
    }
    top
}

/// Checks a one-way program: every cutting move along the lines goes `way` (a unit vector in
/// plan), every rapid that moves in plan is at least 5 mm above the surface under the ball,
/// no rapid goes down, and every line is cut.
fn check_one_way(text: &str, way: [f64; 2], lines: usize) {
    let all = moves(text);
    let mut cuts_along = 0;
    for (rapid, from, to) in &all {
        let (dx, dy, dz) = (to[0] - from[0], to[1] - from[1], to[2] - from[2]);
        if *rapid {
            assert!(dz >= 0.0 || from[2].is_nan(), "a rapid down from {from:?} to {to:?}");
            if dx != 0.0 || dy != 0.0 {
                let clear = to[2] - highest_under(*from, *to);
                assert!(clear >= 5.0, "rapid {from:?} → {to:?} only {clear} mm above the surface");
            }
        } else if dx.hypot(dy) > 1e-9 {
            let along = (dx * way[0] + dy * way[1]) / dx.hypot(dy);
            // The tip leaves the line's plane where the normal tilts across it: mostly along.
            assert!(along > 0.9, "cut {from:?} → {to:?} does not run {way:?}");
            cuts_along += 1;
        }
    }
    let plunges = all.iter().filter(|(rapid, from, to)| !rapid && to[2] < from[2] && from[2] >= 20.0).count();
    assert_eq!(plunges, lines, "one plunge at the feed per line");
    assert!(cuts_along >= lines * 20, "{cuts_along} cutting moves");
}

#[test]
fn climb_and_conventional_cut_every_line_the_same_way_with_safe_rapids_between() {
    // 11 lines of constant x from −25 to 25; the next line lies towards +x, which climb (M3)
    // keeps on the right of the feed: +y. Conventional: −y. With --retract too: no alternation.
    check_one_way(&program(&["--direction", "climb"]), [0.0, 1.0], 11);
    check_one_way(&program(&["--direction", "climb", "--retract"]), [0.0, 1.0], 11);
    check_one_way(&program(&["--direction", "conventional"]), [0.0, -1.0], 11);
    // Lines of constant y step towards +y: climb runs −x, conventional +x.
    check_one_way(&program(&["--direction", "climb", "--lines", "y"]), [-1.0, 0.0], 11);
    check_one_way(&program(&["--direction", "conventional", "--lines", "y"]), [1.0, 0.0], 11);
}

#[test]
fn zigzag_stays_the_default_and_alternates() {
    let all = moves(&program(&[]));
    let ys: Vec<f64> = all
        .iter()
        .filter(|(rapid, f, t)| !rapid && (t[1] - f[1]).abs() > (t[0] - f[0]).abs())
        .map(|(_, f, t)| t[1] - f[1])
        .collect();
    assert!(ys.iter().any(|d| *d > 0.0) && ys.iter().any(|d| *d < 0.0));
    assert_eq!(program(&["--direction", "zigzag"]), program(&[]));
}
