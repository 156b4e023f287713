//! The gouge check against an exact drop-cutter written here, apart from the code: the
//! surface is a plain f64 closure of the same formula, the drop-cutter height of a ball is
//! found by sampling the surface densely under its footprint and refining the best samples by
//! a local search, and a move's depth by the same at many points along it.
//!
//! Cases: the two of issue #13 (the 50 mm bump under a 20 mm ball, and a parabola tighter
//! than a 3 mm ball), and surfaces nobody tuned the check for: a saddle, a sine ridge, a bowl.

mod common;

use common::cli::ncsheet;
use ncsheet::eval::functions::{formula_ball_path, Registry};
use ncsheet::eval::surface::{FormulaSurface, Home};
use ncsheet::eval::Ctx;
use ncsheet::formula::parse::ParseContext;
use ncsheet::formula::Pos;
use ncsheet::geometry::ballpath::{BallPath, BallPathSpec, GougeCheck, GougeKind, Lines, Spacing, GOUGE_TOLERANCE};
use ncsheet::workbook::Workbook;

/// 1 µm: the depth the acceptance counts from.
const UM: f64 = 1e-3;

struct Case {
    formula: &'static str,
    f: fn(f64, f64) -> f64,
    radius: f64,
    x: [f64; 2],
    y: [f64; 2],
    stepover: f64,
    step: f64,
}

impl Case {
    fn spec(&self, gouge: GougeCheck) -> BallPathSpec {
        BallPathSpec {
            radius: self.radius,
            x: self.x,
            y: self.y,
            stepover: self.stepover,
            spacing: Spacing::Step(self.step),
            lines: Lines::ConstantX,
            gouge,
            gouge_tol: GOUGE_TOLERANCE,
            gouge_samples: ncsheet::geometry::ballpath::GOUGE_SAMPLES,
            check_links: true,
            direction: ncsheet::geometry::ballpath::Direction::Zigzag,
            max_points: 1_000_000,
        }
    }

    fn path(&self, gouge: GougeCheck) -> BallPath {
        let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
        let surface = FormulaSurface::parse(self.formula, &ctx).unwrap();
        let wb = Workbook::with_sheet();
        let mut ctx = Ctx::new(&wb, 0, Pos::new(0, 0));
        formula_ball_path(&mut ctx, &surface, Home::Here, &self.spec(gouge), &mut |_, _| {})
            .unwrap_or_else(|(_, m)| panic!("{}: {m}", self.formula))
    }

    /// The exact drop-cutter: the lowest centre height at which the ball over (cx, cy)
    /// clears the surface inside the rectangle, max of f(u, v) + √(R² − d²) over its
    /// footprint, and where that maximum is.
    fn drop(&self, cx: f64, cy: f64) -> (f64, [f64; 2]) {
        let r = self.radius;
        let g = |u: f64, v: f64| {
            let d2 = (u - cx).powi(2) + (v - cy).powi(2);
            let inside = d2 <= r * r && (self.x[0]..=self.x[1]).contains(&u) && (self.y[0]..=self.y[1]).contains(&v);
            if inside {
                (self.f)(u, v) + (r * r - d2).sqrt()
            } else {
                f64::NEG_INFINITY
            }
        };
        let (x0, x1) = ((cx - r).max(self.x[0]), (cx + r).min(self.x[1]));
        let (y0, y1) = ((cy - r).max(self.y[0]), (cy + r).min(self.y[1]));
        let n = 48;
        let grid = |a: f64, b: f64, k: usize| if b > a { a + (b - a) * k as f64 / n as f64 } else { a };
        let mut samples = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (grid(x0, x1, i), grid(y0, y1, j));
                let value = g(u, v);
                if value.is_finite() {
                    samples.push((value, u, v));
                }
            }
        }
        samples.sort_by(|a, b| b.0.total_cmp(&a.0));
        let cell = ((x1 - x0).max(y1 - y0) / n as f64).max(1e-3);
        let mut best = (f64::NEG_INFINITY, [cx, cy]);
        for &(mut value, mut u, mut v) in samples.iter().take(8) {
            // A compass search uphill, steps halved down to 1e-10 mm.
            let mut step = cell;
            while step > 1e-10 {
                let mut moved = false;
                for (du, dv) in [
                    (1.0, 0.0),
                    (-1.0, 0.0),
                    (0.0, 1.0),
                    (0.0, -1.0),
                    (0.6, 0.8),
                    (-0.6, -0.8),
                    (0.8, -0.6),
                    (-0.8, 0.6),
                ] {
                    let w = g(u + du * step, v + dv * step);
                    if w > value {
                        (value, u, v, moved) = (w, u + du * step, v + dv * step, true);
                    }
                }
                if !moved {
                    step *= 0.5;
                }
            }
            if value > best.0 {
                best = (value, [u, v]);
            }
        }
        best
    }

    /// How far the ball centred at `c` is below the drop-cutter height (negative: above).
    fn depth(&self, c: [f64; 3]) -> f64 {
        self.drop(c[0], c[1]).0 - c[2]
    }

    /// The deepest a ball moving straight from centre `a` to `b` gets below the drop-cutter
    /// height: at 17 points along the move, refined by a golden-section search around the
    /// deepest.
    fn move_depth(&self, a: [f64; 3], b: [f64; 3]) -> f64 {
        let at = |t: f64| self.depth([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])]);
        let n = 16;
        let (mut best, mut tb) = (f64::NEG_INFINITY, 0.0);
        for k in 0..=n {
            let t = k as f64 / n as f64;
            let d = at(t);
            if d > best {
                (best, tb) = (d, t);
            }
        }
        let (mut lo, mut hi) = ((tb - 1.0 / n as f64).max(0.0), (tb + 1.0 / n as f64).min(1.0));
        let phi = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..30 {
            let (m1, m2) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
            if at(m1) > at(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        best.max(at(0.5 * (lo + hi)))
    }
}

fn centre(p: &ncsheet::geometry::ballpath::PathPoint) -> [f64; 3] {
    [p.centre.x, p.centre.y, p.centre.z]
}

/// Every position and move the exact drop-cutter finds gouging by more than 1 µm is
/// reported, with its depth; returns the number of positions gouging by more than 1 µm and
/// by anything beyond rounding (10 nm), and the worst depth.
fn every_gouge_is_reported(case: &Case) -> (usize, usize, f64) {
    let path = case.path(GougeCheck::Report);
    let (mut gouging, mut any, mut worst) = (0, 0, 0.0f64);
    for (k, p) in path.points.iter().enumerate() {
        let exact = case.depth(centre(p));
        let reported = path.gouges.iter().find(|g| g.kind == GougeKind::Position && g.point == k);
        worst = worst.max(exact);
        any += usize::from(exact > 1e-5);
        if exact > UM {
            gouging += 1;
            let g = reported.unwrap_or_else(|| {
                panic!("{}: position {k} at {:?} cuts {exact} mm, not reported", case.formula, p.contact)
            });
            assert!(
                g.depth <= exact + 1e-9 && g.depth >= exact - UM / 2.0 - 1e-9,
                "{}: position {k}: reported {} mm, exact {exact}",
                case.formula,
                g.depth
            );
        }
        if let Some(g) = reported {
            // Nothing is reported that cuts no deeper than the tolerance (issue 32, scope 10).
            assert!(exact > UM - 1e-9, "{}: position {k} reported {} mm, exact {exact}", case.formula, g.depth);
        }
    }
    for (k, w) in path.points.windows(2).enumerate() {
        let exact = case.move_depth(centre(&w[0]), centre(&w[1]));
        let reported = path.gouges.iter().find(|g| g.kind == GougeKind::Move && g.point == k);
        if exact > UM {
            let g = reported.unwrap_or_else(|| {
                panic!(
                    "{}: the move from {:?} to {:?} cuts {exact} mm, not reported",
                    case.formula, w[0].contact, w[1].contact
                )
            });
            assert!(g.depth <= exact + 1e-6, "{}: move {k}: reported {} mm, exact {exact}", case.formula, g.depth);
        }
    }
    (gouging, any, worst)
}

/// After `--gouge lift`, every centre is at the exact drop-cutter height within 1 µm, and
/// so is every point a quarter, half and three quarters along every move (never below it by
/// more than 1 µm).
fn lifting_clears_every_position_and_move(case: &Case) {
    let path = case.path(GougeCheck::Lift);
    for p in &path.points {
        let depth = case.depth(centre(p));
        assert!(
            (-1e-6..=UM).contains(&depth),
            "{}: centre {:?} is {depth} mm below the drop-cutter height",
            case.formula,
            p.centre
        );
    }
    for w in path.points.windows(2) {
        let (a, b) = (centre(&w[0]), centre(&w[1]));
        for t in [0.25, 0.5, 0.75] {
            let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])];
            let depth = case.depth(c);
            assert!(depth <= UM, "{}: {t} of the way from {a:?} to {b:?} the ball is {depth} mm too low", case.formula);
        }
    }
}

fn bump() -> Case {
    Case {
        formula: "15*EXP(-16*((x/50)^2+(y/50)^2))",
        f: |x, y| 15.0 * (-16.0 * ((x / 50.0).powi(2) + (y / 50.0).powi(2))).exp(),
        radius: 20.0,
        x: [-25.0, 25.0],
        y: [-25.0, 25.0],
        stepover: 2.0,
        step: 2.0,
    }
}

fn parabola() -> Case {
    Case {
        formula: "0.17*x^2",
        f: |x, _| 0.17 * x * x,
        radius: 3.0,
        x: [-2.0, 2.0],
        y: [0.0, 1.0],
        stepover: 0.25,
        step: 1.0,
    }
}

#[test]
fn the_bump_under_a_20_mm_ball() {
    let case = bump();
    let (gouging, _, worst) = every_gouge_is_reported(&case);
    // The figures, from its own exact drop-cutter: 284 positions gouge; the worst of
    // those the old check missed is 0.223 mm deep, touching (17, −13).
    assert!((280..=284).contains(&gouging), "{gouging} positions gouge by more than 1 µm");
    assert!(worst > 0.223, "the worst gouge is {worst} mm");
    let path = case.path(GougeCheck::Report);
    let k = path.points.iter().position(|p| p.contact.x == 17.0 && p.contact.y == -13.0).unwrap();
    let exact = case.depth(centre(&path.points[k]));
    assert!((exact - 0.223).abs() < 0.0005, "touching (17, −13) the ball cuts {exact} mm");
    let g = path.gouges.iter().find(|g| g.kind == GougeKind::Position && g.point == k).unwrap();
    assert!((g.depth - exact).abs() <= UM / 2.0, "reported {} mm", g.depth);
    lifting_clears_every_position_and_move(&case);
}

#[test]
fn a_parabola_tighter_than_the_ball() {
    let case = parabola();
    // The count: 10 positions cut at all (8 of them by more than 1 µm).
    let (gouging, any, _) = every_gouge_is_reported(&case);
    assert_eq!((gouging, any), (8, 10));
    lifting_clears_every_position_and_move(&case);
}

#[test]
fn a_saddle() {
    // Curvature 1/5 up along x, −1/5 along y: a 6 mm ball is too big for the hollow direction.
    let case = Case {
        formula: "(x^2-y^2)/10",
        f: |x, y| (x * x - y * y) / 10.0,
        radius: 6.0,
        x: [-6.0, 6.0],
        y: [-6.0, 6.0],
        stepover: 1.5,
        step: 1.0,
    };
    let (gouging, _, _) = every_gouge_is_reported(&case);
    assert!(gouging > 0);
    lifting_clears_every_position_and_move(&case);
}

#[test]
fn a_sine_ridge_across_the_lines() {
    let case = Case {
        formula: "2*SIN(y/3)+0.5*COS(x/2)",
        f: |x, y| 2.0 * (y / 3.0).sin() + 0.5 * (x / 2.0).cos(),
        radius: 5.0,
        x: [-8.0, 8.0],
        y: [-10.0, 10.0],
        stepover: 2.0,
        step: 1.5,
    };
    every_gouge_is_reported(&case);
    lifting_clears_every_position_and_move(&case);
}

#[test]
fn a_bowl_tighter_than_the_ball() {
    // Curvature radius 12 at the bottom, ball radius 15: every position near the bottom gouges.
    let case = Case {
        formula: "SQRT(x^2+y^2+144)-12",
        f: |x, y| (x * x + y * y + 144.0).sqrt() - 12.0,
        radius: 15.0,
        x: [-10.0, 10.0],
        y: [-10.0, 10.0],
        stepover: 2.5,
        step: 2.0,
    };
    let (gouging, _, _) = every_gouge_is_reported(&case);
    assert!(gouging > 0);
    lifting_clears_every_position_and_move(&case);
}

// ---- issue 32, scopes 5, 7 and 10 --------------------------------------------------------

/// A command line's words (none with spaces of its own).
fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// A path over a case with the spec changed by `change`, through the library.
fn path_with(case: &Case, change: impl Fn(&mut BallPathSpec)) -> Result<BallPath, String> {
    let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
    let surface = FormulaSurface::parse(case.formula, &ctx).unwrap();
    let wb = Workbook::with_sheet();
    let mut ctx = Ctx::new(&wb, 0, Pos::new(0, 0));
    let mut spec = case.spec(GougeCheck::Report);
    change(&mut spec);
    formula_ball_path(&mut ctx, &surface, Home::Here, &spec, &mut |_, _| {}).map_err(|(_, m)| m)
}

/// The drop-cutter height of a ball of radius r over x = cx, by hand, onto the crease
/// z = max(0, x − a) for x in [−1, 1] (a profile in x; the part is the line y = 0): the
/// highest of the ball resting on each facet where its tangent point lies on the facet, and on
/// each facet's end points (a circle on a point: z + √(r² − d²)).
fn crease_drop(a: f64, r: f64, cx: f64) -> f64 {
    let mut h = f64::NEG_INFINITY;
    // The flat from (−1, 0) to (a, 0): tangent right under the centre.
    if (-1.0..=a).contains(&cx) {
        h = h.max(r);
    }
    // The slope 1 from (a, 0) to (1, 1 − a): normal (−1, 1)/√2, tangent point cx + r/√2.
    let t = cx + r / 2f64.sqrt();
    if (a..=1.0).contains(&t) {
        h = h.max((cx - a) + r * 2f64.sqrt());
    }
    for (vx, vz) in [(-1.0, 0.0), (a, 0.0), (1.0, 1.0 - a)] {
        let d = cx - vx;
        if d.abs() <= r {
            h = h.max(vz + (r * r - d * d).sqrt());
        }
    }
    h
}

/// `--gouge-tol` means what it says (issue 32, scope 10): a ball cutting deeper than it is a
/// gouge, one cutting no deeper is not — not "from half the tolerance". The crease
/// max(0, x − a) with a = √2 − 1 − 0.03 puts the 1 mm ball touching the flat at x = 0 exactly
/// 0.03 mm into the slope (by hand: (0 − a) + √2 − 1), and the ball touching the slope at
/// x = 0.5 a − 0.2071 mm into the flat; the links are not checked (each line is one point).
#[test]
fn the_gouge_tolerance_separates_gouges_from_cuts_shallower_than_it() {
    let a = 2f64.sqrt() - 1.0 - 0.03;
    let formula: &'static str = Box::leak(format!("MAX(0,x-{a:.15})").into_boxed_str());
    let case = Case { formula, f: |_, _| 0.0, radius: 1.0, x: [-1.0, 1.0], y: [0.0, 0.0], stepover: 0.5, step: 1.0 };
    for tol in [0.05, 0.02, 0.2] {
        let path = path_with(&case, |s| {
            s.gouge_tol = tol;
            s.check_links = false;
        })
        .unwrap();
        for (k, p) in path.points.iter().enumerate() {
            let exact = crease_drop(a, 1.0, p.centre.x) - p.centre.z;
            let reported = path.gouges.iter().find(|g| g.point == k);
            match reported {
                Some(g) => {
                    assert!(exact > tol, "tol {tol}: x = {} reported {} mm, exact {exact}", p.contact.x, g.depth);
                    assert!(
                        g.depth <= exact + 1e-9 && g.depth >= exact - tol / 2.0,
                        "tol {tol}: {} vs {exact}",
                        g.depth
                    );
                }
                None => assert!(exact <= tol, "tol {tol}: x = {} cuts {exact} mm, not reported", p.contact.x),
            }
        }
        let reported: Vec<f64> = path.gouges.iter().map(|g| path.points[g.point].contact.x).collect();
        let expected: &[f64] = match tol {
            0.05 => &[0.5],
            0.02 => &[0.0, 0.5],
            _ => &[],
        };
        assert_eq!(reported, expected, "tol {tol}");
    }
}

/// A bump narrower than the path's spacing (issue 32, scope 7): EXP(−((x − 0.33)/0.1)²) under
/// a 3 mm ball at stepover and step 1 lies between the path's points; the balls placed beside
/// it cut it up to 0.98 mm deep. Every one is reported (against the drop-cutter written here),
/// and `lift` clears them all.
#[test]
fn a_bump_narrower_than_the_stepover_is_found() {
    let case = Case {
        formula: "EXP(-(((x-0.33)/0.1)^2))",
        f: |x, _| (-((x - 0.33) / 0.1).powi(2)).exp(),
        radius: 3.0,
        x: [-3.0, 3.0],
        y: [-1.0, 1.0],
        stepover: 1.0,
        step: 1.0,
    };
    let (gouging, _, worst) = every_gouge_is_reported(&case);
    // By hand: the ball resting on the flat at x = 0 meets the bump's top 0.33 mm off its
    // axis, where its underside is 3 − √(9 − 0.33²) = 0.0182 mm up: 0.98 mm into it.
    assert!(gouging >= 3 && (worst - (1.0 - (3.0 - (9.0f64 - 0.33 * 0.33).sqrt()))).abs() < 0.01, "{gouging} {worst}");
    lifting_clears_every_position_and_move(&case);
}

/// A step (IF) cannot be checked by slopes that are 0 on both sides: the check refuses it by
/// name, at the step, rather than pass a ball cutting 0.995 mm into it (issue 32, scope 10).
#[test]
fn a_step_in_the_surface_is_refused_where_it_is() {
    let run = ncsheet(&words("ballpath --surface IF(x>0.1,1,0) --radius 1 --x=-1:1 --y=0:0 --stepover 0.5 --step 0.5"));
    assert_eq!(run.code, 1, "{}{}", run.stdout, run.stderr);
    assert!(run.stderr.contains("jumps or bends more sharply"), "{}", run.stderr);
    let near = run.stderr.split("near (").nth(1).unwrap();
    let x: f64 = near.split(',').next().unwrap().parse().unwrap();
    assert!((x - 0.1).abs() < 1e-3, "{}", run.stderr);
}

/// The check's time is bounded (issue 32, scopes 7 and 10): past its sample budget it stops
/// with a message naming the ball and the options, never runs on.
#[test]
fn the_gouge_search_stops_at_its_sample_budget_with_a_message() {
    let run = ncsheet(&words(
        "ballpath --surface (x^2-y^2)/5+0.05*x*y --radius 1 --x=-6:6 --y=-6:6 --stepover 1 --step 1 --gouge-samples 2000",
    ));
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(run.stderr.contains("took its 2000 surface samples"), "{}", run.stderr);
    assert!(run.stderr.contains("--gouge-samples"), "{}", run.stderr);
}

/// The program as written keeps the tolerance (issue 32, scope 5): a steep tanh wall under a
/// 1 mm ball, lifted with --gouge-tol 0.001, written for LinuxCNC (3 decimals), read by
/// rs274: every feed point the control makes, and the middle of every feed move, is within
/// 1 µm of the drop-cutter height computed here, or above it.
#[test]
fn the_written_program_keeps_the_gouge_tolerance() {
    if !common::rs274::available() {
        eprintln!("rs274 not installed: skipped");
        return;
    }
    let case = Case {
        formula: "2*TANH(3*x)",
        f: |x, _| 2.0 * (3.0 * x).tanh(),
        radius: 1.0,
        x: [-1.5, 1.5],
        y: [0.0, 0.6],
        stepover: 0.3,
        step: 0.05,
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("wall.ngc");
    let mut args = words("ballpath --radius 1 --x=-1.5:1.5 --y=0:0.6 --stepover 0.3 --step 0.05 --gouge lift");
    args.extend(["--surface", case.formula, "--format", "linuxcnc", "-o", out.to_str().unwrap()]);
    let run = ncsheet(&args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let moves = common::rs274::moves(&out).unwrap();
    let feeds: Vec<[f64; 3]> = moves
        .iter()
        .filter_map(|m| match m {
            common::rs274::Move::Feed { x, y, z } => Some([*x, *y, *z + case.radius]),
            _ => None,
        })
        .collect();
    assert!(feeds.len() > 100, "{}", feeds.len());
    let mut worst = f64::NEG_INFINITY;
    // The first feed is the plunge from the clearance height.
    for w in feeds[1..].windows(2) {
        let mid = [0.5 * (w[0][0] + w[1][0]), 0.5 * (w[0][1] + w[1][1]), 0.5 * (w[0][2] + w[1][2])];
        worst = worst.max(case.depth(w[1])).max(case.depth(mid));
    }
    assert!(worst <= UM, "the program as written goes {worst} mm below the drop-cutter height");
}
