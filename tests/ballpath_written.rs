//! The ball path's program as written keeps the tolerance the user gave (issue 32, scope 5):
//! each program text, in every dialect `ballpath` offers, is read here (its own small reader
//! of the blocks our writers emit), and the ball is followed along every written cutting move
//! at dense samples against a drop-cutter written here, apart from the code: the surface is a
//! plain f64 function of the same formula, and the drop-cutter height over a point is the
//! highest f(u, v) + √(R² − d²) over a grid under the ball's footprint (inside the part's
//! rectangle), refined uphill from the best nodes. That height is never above the exact one,
//! so a ball found more than the tolerance below it is a real gouge.
//!
//! The surfaces are used by no other test: a steep sine wall, the flank of a cone, a tilted
//! plane with a curved crest, a ridge across the raster; balls from 1 to 10 mm.

mod common;

use std::collections::HashMap;

use common::cli::ncsheet;

/// A surface, the rectangle and the raster: the program is asked for with these options.
struct Case {
    formula: &'static str,
    f: fn(f64, f64) -> f64,
    radius: f64,
    x: [f64; 2],
    y: [f64; 2],
    /// The rest of the command line: spacing, lines, gouge handling, tolerance.
    options: &'static str,
    /// `--gouge-tol`, which the options give.
    tol: f64,
    /// The programmed point is the ball's centre (`--program centre`), else its tip.
    centre: bool,
}

/// Every dialect `ballpath --format` offers, as its refusal of an unknown one lists them.
fn dialects() -> Vec<String> {
    let run = ncsheet(
        &["ballpath", "--surface", "0", "--radius", "1", "--x=0:1", "--y=0:1", "--stepover", "1"]
            .into_iter()
            .chain(["--step", "1", "--format", "no-such-dialect"])
            .collect::<Vec<_>>(),
    );
    let list = run.stderr.split("[possible values: ").nth(1).expect("clap lists the formats");
    let list = &list[..list.find(']').expect("the list ends")];
    let names: Vec<String> = list.split(", ").filter(|n| *n != "csv").map(str::to_string).collect();
    assert!(names.len() >= 4, "{names:?}");
    names
}

/// A straight cutting move of the programmed point, from where the control was to the block's end.
type Move = ([f64; 3], [f64; 3]);

/// The value of an address word such as `X-1.029`, `Y0.`, `Z+0.2849`.
fn number(word: &str) -> f64 {
    let text = word[1..].trim_end_matches('.');
    let text = if text.is_empty() || text == "-" || text == "+" { "0" } else { text };
    text.parse().unwrap_or_else(|_| panic!("'{word}' is not a coordinate word"))
}

/// The cutting moves of a word-address program (ISO, LinuxCNC, Sinumerik): comments in
/// parentheses or after `;` dropped, G0/G1 modal, X Y Z modal and absolute (the writers'
/// G90). A block that moves no axis is no move; an arc would be a failure of this test.
fn word_address_moves(text: &str) -> Vec<Move> {
    let mut at = [None::<f64>; 3];
    let mut feed = false;
    let mut moves = Vec::new();
    for line in text.lines() {
        let mut code = String::new();
        let mut depth = 0;
        for c in line.split(';').next().unwrap_or("").chars() {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ if depth == 0 => code.push(c),
                _ => {}
            }
        }
        if code.trim_start().starts_with('%') {
            continue;
        }
        let before = at;
        let mut moved = false;
        for word in code.split_whitespace() {
            let letter = word.chars().next().unwrap().to_ascii_uppercase();
            match letter {
                'G' => match number(word) as i64 {
                    0 => feed = false,
                    1 => feed = true,
                    2 | 3 => panic!("an arc in a ball path's program: {line}"),
                    _ => {}
                },
                'X' | 'Y' | 'Z' => {
                    at["XYZ".find(letter).unwrap()] = Some(number(word));
                    moved = true;
                }
                _ => {}
            }
        }
        if moved && feed {
            let from = before.map(|v| v.unwrap_or_else(|| panic!("a cut from an unknown position: {line}")));
            moves.push((from, at.map(Option::unwrap)));
        }
    }
    moves
}

/// The cutting moves of a Heidenhain conversational program: `L` blocks, coordinates modal
/// and absolute, `FMAX` a rapid for its block, any other F a cut.
fn heidenhain_moves(text: &str) -> Vec<Move> {
    let mut at = [None::<f64>; 3];
    let mut moves = Vec::new();
    for line in text.lines() {
        let code = line.split(';').next().unwrap_or("");
        let words: Vec<&str> = code.split_whitespace().collect();
        if words.get(1) != Some(&"L") {
            continue;
        }
        let before = at;
        let mut moved = false;
        for word in &words[2..] {
            if let Some(axis) = "XYZ".find(&word[..1]) {
                at[axis] = Some(number(word));
                moved = true;
            }
        }
        if moved && !words.contains(&"FMAX") {
            let from = before.map(|v| v.unwrap_or_else(|| panic!("a cut from an unknown position: {line}")));
            moves.push((from, at.map(Option::unwrap)));
        }
    }
    moves
}

fn cutting_moves(text: &str) -> Vec<Move> {
    if text.starts_with("0 BEGIN PGM") {
        heidenhain_moves(text)
    } else {
        word_address_moves(text)
    }
}

impl Case {
    /// f(u, v) + √(R² − d²) for the ball centred over (cx, cy); −∞ outside its footprint or
    /// the part.
    fn reach(&self, cx: f64, cy: f64, u: f64, v: f64) -> f64 {
        let d2 = (u - cx).powi(2) + (v - cy).powi(2);
        let r2 = self.radius * self.radius;
        if d2 > r2 || u < self.x[0] || u > self.x[1] || v < self.y[0] || v > self.y[1] {
            return f64::NEG_INFINITY;
        }
        (self.f)(u, v) + (r2 - d2).sqrt()
    }

    /// The drop-cutter height of the ball's centre over (cx, cy): the best of a 40 × 40 grid
    /// over the footprint's box inside the part, each of the best six nodes climbed by a
    /// pattern search whose step halves down to 1e-7 mm. Never above the exact height.
    fn drop(&self, cx: f64, cy: f64) -> f64 {
        let r = self.radius;
        let (x0, x1) = ((cx - r).max(self.x[0]), (cx + r).min(self.x[1]));
        let (y0, y1) = ((cy - r).max(self.y[0]), (cy + r).min(self.y[1]));
        if x0 > x1 || y0 > y1 {
            return f64::NEG_INFINITY;
        }
        const N: usize = 40;
        let node = |a: f64, b: f64, k: usize| a + (b - a) * k as f64 / N as f64;
        let mut nodes: Vec<(f64, f64, f64)> = Vec::with_capacity((N + 1) * (N + 1));
        for i in 0..=N {
            for j in 0..=N {
                let (u, v) = (node(x0, x1, i), node(y0, y1, j));
                nodes.push((self.reach(cx, cy, u, v), u, v));
            }
        }
        nodes.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut best = f64::NEG_INFINITY;
        for &(mut top, mut u, mut v) in nodes.iter().take(6).filter(|n| n.0.is_finite()) {
            let mut step = (x1 - x0).max(y1 - y0) / N as f64;
            while step > 1e-7 {
                let around = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.7, 0.7), (-0.7, -0.7), (0.7, -0.7)];
                let climbed = around
                    .iter()
                    .chain(&[(-0.7, 0.7)])
                    .map(|(du, dv)| (self.reach(cx, cy, u + du * step, v + dv * step), u + du * step, v + dv * step))
                    .max_by(|a, b| a.0.total_cmp(&b.0))
                    .filter(|c| c.0 > top);
                match climbed {
                    Some(c) => (top, u, v) = c,
                    None => step *= 0.5,
                }
            }
            best = best.max(top);
        }
        best
    }

    fn command(&self, dialect: &str, out: &str) -> Vec<String> {
        let mut args: Vec<String> = ["ballpath", "--surface", self.formula, "--radius"].map(str::to_string).to_vec();
        args.push(self.radius.to_string());
        args.push(format!("--x={}:{}", self.x[0], self.x[1]));
        args.push(format!("--y={}:{}", self.y[0], self.y[1]));
        args.extend(self.options.split_whitespace().map(str::to_string));
        if self.centre {
            args.extend(["--program".into(), "centre".into()]);
        }
        args.extend(["--format".into(), dialect.into(), "-o".into(), out.into()]);
        args
    }

    /// The deepest the ball gets below the drop-cutter height along `program`'s cutting
    /// moves, sampled at most 0.01 mm apart (and at 16 points at least) on each, and where.
    fn deepest(&self, program: &str, heights: &mut HashMap<(u64, u64), f64>) -> (f64, [f64; 3]) {
        let lift = if self.centre { 0.0 } else { self.radius };
        let mut worst = (f64::NEG_INFINITY, [0.0; 3]);
        let moves = cutting_moves(program);
        assert!(moves.len() > 20, "{} cutting moves:\n{program}", moves.len());
        for (a, b) in moves {
            let along = (b[0] - a[0]).hypot(b[1] - a[1]);
            let n = ((along / 0.01).ceil() as usize).max(16);
            for k in 0..=n {
                let t = k as f64 / n as f64;
                let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]) + lift];
                let key = (c[0].to_bits(), c[1].to_bits());
                let drop = *heights.entry(key).or_insert_with(|| self.drop(c[0], c[1]));
                if drop - c[2] > worst.0 {
                    worst = (drop - c[2], c);
                }
            }
        }
        worst
    }

    /// Every dialect's program of this case keeps the tolerance along every cutting move.
    fn check(&self) {
        let dir = tempfile::tempdir().unwrap();
        let mut heights = HashMap::new();
        let mut failures = Vec::new();
        for dialect in dialects() {
            let out = dir.path().join(format!("p.{dialect}"));
            let args = self.command(&dialect, out.to_str().unwrap());
            let run = ncsheet(&args.iter().map(String::as_str).collect::<Vec<_>>());
            assert_eq!(run.code, 0, "{}: {}", args.join(" "), run.stderr);
            let program = std::fs::read_to_string(&out).unwrap();
            let (depth, at) = self.deepest(&program, &mut heights);
            if depth > self.tol + 1e-9 {
                failures.push(format!("{dialect}: the ball centred at {at:?} is {depth:.6} mm below the drop-cutter"));
            }
        }
        assert!(failures.is_empty(), "{} (tolerance {}):\n{}", self.formula, self.tol, failures.join("\n"));
    }
}

/// A steep sine wall crossed by the raster (lines of constant y run across it), 1 mm ball.
#[test]
fn a_steep_sine_wall_as_written_keeps_the_tolerance() {
    Case {
        formula: "1.5*SIN(1.7*x)+0.05*y",
        f: |x, y| 1.5 * (1.7 * x).sin() + 0.05 * y,
        radius: 1.0,
        x: [-1.2, 1.2],
        y: [0.0, 0.5],
        options: "--lines y --stepover 0.25 --step 0.3 --gouge lift --gouge-tol 0.001",
        tol: 0.001,
        centre: false,
    }
    .check();
}

/// The flank of a cone whose apex lies outside the part (smooth there), a 6 mm ball.
#[test]
fn a_cones_flank_as_written_keeps_the_tolerance() {
    Case {
        formula: "4-0.8*SQRT((x-5)^2+(y+4)^2)",
        f: |x, y| 4.0 - 0.8 * ((x - 5.0).powi(2) + (y + 4.0).powi(2)).sqrt(),
        radius: 6.0,
        x: [-2.0, 2.0],
        y: [-1.0, 1.0],
        options: "--stepover 0.5 --step 0.7 --gouge lift --gouge-tol 0.001",
        tol: 0.001,
        centre: false,
    }
    .check();
}

/// A tilted plane with a curved crest, programmed at the ball's centre, a 10 mm ball.
#[test]
fn a_tilted_curved_plane_as_written_keeps_the_tolerance() {
    Case {
        formula: "0.7*x-0.3*y-0.08*x^2+0.03*x*y",
        f: |x, y| 0.7 * x - 0.3 * y - 0.08 * x * x + 0.03 * x * y,
        radius: 10.0,
        x: [-3.0, 3.0],
        y: [-1.0, 1.0],
        options: "--stepover 1 --step 1.5 --gouge lift --gouge-tol 0.0005",
        tol: 0.0005,
        centre: true,
    }
    .check();
}

/// A ridge across the raster lines, a 2.5 mm ball, the check failing on any gouge (none
/// here: the ridge is wider than the ball) and the tolerance 2 µm.
#[test]
fn a_ridge_as_written_keeps_the_tolerance() {
    Case {
        formula: "1.2/(1+((x-0.3*y)/0.9)^2)",
        f: |x, y| 1.2 / (1.0 + ((x - 0.3 * y) / 0.9).powi(2)),
        radius: 2.5,
        x: [-2.0, 2.0],
        y: [0.0, 1.0],
        options: "--stepover 0.5 --step 0.4 --gouge lift --gouge-tol 0.002",
        tol: 0.002,
        centre: false,
    }
    .check();
}

/// The head's tool axis for angles A, B (degrees): A about X, then B about Y
/// (docs/domain.md §4: A = −asin(a_y), B = atan2(a_x, a_z)).
fn head_axis(a: f64, b: f64) -> [f64; 3] {
    let (a, b) = (a.to_radians(), b.to_radians());
    [a.cos() * b.sin(), -a.sin(), a.cos() * b.cos()]
}

/// `post`'s program of a 5-axis ball path cannot keep a tolerance against a surface it does
/// not know: its help and docs/limits.md state how far the tool as written may lie from the
/// CL file's, √3/2·10^−d + H·π/180·10^−d mm for d decimals and pivot length H (X Y Z and
/// both angles each rounded by half a step). Each cutting block of each dialect's program,
/// read here (pivot and angles), puts the tip and the ball's centre within that of the
/// file's GOTO.
#[test]
fn post_keeps_the_ball_within_its_stated_bound_of_the_cl_file() {
    let help = ncsheet(&["post", "--help"]).stdout;
    assert!(help.contains("H·π/180·10^−d mm"), "{help}");
    let dir = tempfile::tempdir().unwrap();
    let cl = dir.path().join("p.cl");
    let (radius, pivot) = (3.0, 400.0);
    let run = ncsheet(&[
        "ballpath",
        "--surface",
        "0.7*x-0.3*y-0.08*x^2+0.03*x*y",
        "--radius",
        "3",
        "--x=-2:2",
        "--y=-1:1",
        "--stepover",
        "0.5",
        "--step",
        "0.5",
        "--gouge",
        "lift",
        "--cl",
        cl.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    // The file's cutting GOTOs (tip, axis): every GOTO not reached by a RAPID.
    let text = std::fs::read_to_string(&cl).unwrap();
    let mut gotos = Vec::new();
    let mut rapid = false;
    for line in text.lines() {
        if line.starts_with("RAPID") {
            rapid = true;
        } else if let Some(values) = line.strip_prefix("GOTO/") {
            let v: Vec<f64> = values.split(',').map(|s| s.trim().parse().unwrap()).collect();
            if !rapid {
                gotos.push(([v[0], v[1], v[2]], [v[3], v[4], v[5]]));
            }
            rapid = false;
        }
    }
    assert!(gotos.len() > 30, "{}", gotos.len());
    let posted = ["iso", "linuxcnc", "sinumerik"];
    for dialect in dialects() {
        for decimals in [None, Some(5)] {
            let mut args = vec!["post", cl.to_str().unwrap(), "--machine", "ab-head", "--pivot", "400"];
            args.extend(["--dialect", &dialect]);
            let d = decimals.map(|d: u8| d.to_string());
            if let Some(d) = &d {
                args.extend(["--decimals", d]);
            }
            let run = ncsheet(&args);
            if !posted.contains(&dialect.as_str()) {
                // Heidenhain's swivel head wants tool-tip coordinates (TCPM): refused by name.
                assert_eq!(run.code, 1, "{dialect}: {}", run.stdout);
                continue;
            }
            assert_eq!(run.code, 0, "{dialect}: {}", run.stderr);
            let step = 10f64.powi(-(d.as_deref().unwrap_or("3").parse::<i32>().unwrap()));
            let bound = 3f64.sqrt() / 2.0 * step + pivot * std::f64::consts::PI / 180.0 * step;
            let blocks = posted_cuts(&run.stdout);
            assert_eq!(blocks.len(), gotos.len(), "{dialect}");
            let mut worst = 0.0f64;
            for ((p, [a, b]), (tip, axis)) in blocks.iter().zip(&gotos) {
                let w = head_axis(*a, *b);
                let written_tip: Vec<f64> =
                    (0..3).map(|i| p[i] - pivot * w[i] + if i == 2 { pivot } else { 0.0 }).collect();
                let off = |i: usize, r: f64| written_tip[i] + r * w[i] - (tip[i] + r * axis[i]);
                for r in [0.0, radius] {
                    let distance = (0..3).map(|i| off(i, r).powi(2)).sum::<f64>().sqrt();
                    worst = worst.max(distance);
                }
            }
            assert!(worst <= bound, "{dialect} {decimals:?}: the tool is {worst} mm off the file, past {bound}");
        }
    }
}

/// The cutting blocks of a posted program: pivot X Y Z and angles A B, all modal.
fn posted_cuts(text: &str) -> Vec<([f64; 3], [f64; 2])> {
    let mut at = [0.0; 5];
    let mut feed = false;
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split(';').next().unwrap_or("");
        if code.starts_with('(') || code.starts_with('%') {
            continue;
        }
        let mut moved = false;
        for word in code.split_whitespace() {
            let letter = word.chars().next().unwrap();
            if letter == 'G' {
                match number(word) as i64 {
                    0 => feed = false,
                    1 => feed = true,
                    _ => {}
                }
            } else if let Some(i) = "XYZAB".find(letter) {
                at[i] = number(word);
                moved = true;
            }
        }
        if moved && feed {
            out.push(([at[0], at[1], at[2]], [at[3], at[4]]));
        }
    }
    out
}
