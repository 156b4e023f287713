//! Ball-end mill paths over surface formulas (docs/domain.md §3), checked against geometry written
//! by hand here: each surface's height and gradient are typed out below, and the distance
//! from a ball centre to the surface is found by a minimisation of this file's own.

use ncsheet::eval::functions::{formula_ball_path, Registry};
use ncsheet::eval::surface::{FormulaSurface, Home};
use ncsheet::eval::{Ctx, Value, XlError};
use ncsheet::formula::parse::ParseContext;
use ncsheet::formula::Pos;
use ncsheet::geometry::ballpath::{BallPath, BallPathSpec, GougeCheck, GougeKind, Lines, Spacing, GOUGE_TOLERANCE};
use ncsheet::workbook::Workbook;

/// A surface by hand: height and gradient.
struct Hand {
    formula: &'static str,
    f: fn(f64, f64) -> f64,
    grad: fn(f64, f64) -> (f64, f64),
}

fn path(formula: &str, spec: &BallPathSpec) -> Result<BallPath, String> {
    let ctx = ParseContext { at: Pos::new(0, 0), functions: &Registry, sheet: &|_| None };
    let surface = FormulaSurface::parse(formula, &ctx).map_err(|e| e.render(formula))?;
    let wb = Workbook::with_sheet();
    let mut ctx = Ctx::new(&wb, 0, Pos::new(0, 0));
    formula_ball_path(&mut ctx, &surface, Home::Here, spec, &mut |_, _| {}).map_err(|(_, m)| m)
}

fn spec(radius: f64, x: [f64; 2], y: [f64; 2], stepover: f64, step: f64) -> BallPathSpec {
    BallPathSpec {
        radius,
        x,
        y,
        stepover,
        spacing: Spacing::Step(step),
        lines: Lines::ConstantX,
        gouge: GougeCheck::Report,
        gouge_tol: GOUGE_TOLERANCE,
        gouge_samples: ncsheet::geometry::ballpath::GOUGE_SAMPLES,
        check_links: true,
        direction: ncsheet::geometry::ballpath::Direction::Zigzag,
        max_points: 1_000_000,
    }
}

/// The distance from `c` to the surface near (u0, v0): a compass search on the squared
/// distance, steps halved down to 1e-12 mm.
fn distance_to_surface(s: &Hand, c: [f64; 3], u0: f64, v0: f64) -> f64 {
    let d2 = |u: f64, v: f64| (u - c[0]).powi(2) + (v - c[1]).powi(2) + ((s.f)(u, v) - c[2]).powi(2);
    let (mut u, mut v, mut best) = (u0, v0, d2(u0, v0));
    let mut step = 0.5;
    while step > 1e-12 {
        let mut moved = false;
        for (du, dv) in
            [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.6, 0.8), (-0.6, -0.8), (0.8, -0.6), (-0.8, 0.6)]
        {
            let (nu, nv) = (u + du * step, v + dv * step);
            let d = d2(nu, nv);
            if d < best {
                (u, v, best, moved) = (nu, nv, d, true);
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    best.sqrt()
}

/// The smallest distance from `c` to the surface samples on a grid over the disk of radius
/// `r` around it: a grid point closer than R would prove the ball cuts the surface.
fn nearest_on_grid(s: &Hand, c: [f64; 3], r: f64, area: ([f64; 2], [f64; 2])) -> f64 {
    let n = 40;
    let mut best = f64::INFINITY;
    for i in 0..=n {
        for j in 0..=n {
            let u = c[0] - r + 2.0 * r * i as f64 / n as f64;
            let v = c[1] - r + 2.0 * r * j as f64 / n as f64;
            if u < area.0[0] || u > area.0[1] || v < area.1[0] || v > area.1[1] {
                continue;
            }
            let d = ((u - c[0]).powi(2) + (v - c[1]).powi(2) + ((s.f)(u, v) - c[2]).powi(2)).sqrt();
            best = best.min(d);
        }
    }
    best
}

fn surfaces() -> Vec<(Hand, BallPathSpec)> {
    vec![
        (Hand { formula: "5", f: |_, _| 5.0, grad: |_, _| (0.0, 0.0) }, spec(2.0, [0.0, 10.0], [0.0, 10.0], 2.5, 1.0)),
        (
            Hand { formula: "0.5*x-0.25*y+1", f: |x, y| 0.5 * x - 0.25 * y + 1.0, grad: |_, _| (0.5, -0.25) },
            spec(3.0, [-10.0, 10.0], [-5.0, 5.0], 2.0, 0.7),
        ),
        (
            // A sphere of radius 10 around (0, 0, −6): convex, any ball fits.
            Hand {
                formula: "SQRT(100-x^2-y^2)-6",
                f: |x, y| (100.0 - x * x - y * y).sqrt() - 6.0,
                grad: |x, y| {
                    let w = (100.0 - x * x - y * y).sqrt();
                    (-x / w, -y / w)
                },
            },
            spec(3.0, [-6.0, 6.0], [-6.0, 6.0], 1.5, 0.5),
        ),
        (
            // The paper's bump 0.3·e^(−16x²−16y²) on the unit square, scaled 50× (docs/domain.md §3, with
            // the [fix]ed derivative): f = 15·e^(−0.0064(x²+y²)), ∂f/∂x = −0.192·x·e^(…).
            Hand {
                formula: "15*EXP(-16*((x/50)^2+(y/50)^2))",
                f: |x, y| 15.0 * (-0.0064 * (x * x + y * y)).exp(),
                grad: |x, y| {
                    let e = (-0.0064 * (x * x + y * y)).exp();
                    (-0.192 * x * e, -0.192 * y * e)
                },
            },
            spec(3.0, [-25.0, 25.0], [-25.0, 25.0], 2.5, 1.25),
        ),
        (
            Hand { formula: "(x^2-y^2)/40", f: |x, y| (x * x - y * y) / 40.0, grad: |x, y| (x / 20.0, -y / 20.0) },
            spec(3.0, [-10.0, 10.0], [-10.0, 10.0], 1.0, 1.0),
        ),
    ]
}

#[test]
fn every_centre_is_r_from_the_surface_along_the_exact_normal() {
    for (s, spec) in surfaces() {
        let p = path(s.formula, &spec).unwrap_or_else(|e| panic!("{e}"));
        // No ball gouges where it is placed (straight moves across a dome may dip: they are
        // tests/ballpath_gouge.rs's business).
        assert!(p.gouges.iter().all(|g| g.kind == GougeKind::Move), "{}: {:?}", s.formula, p.gouges.first());
        let r = spec.radius;
        for (k, pt) in p.points.iter().enumerate() {
            let (t, c) = (pt.contact, pt.centre);
            // The contact point lies on the surface.
            assert!((t.z - (s.f)(t.x, t.y)).abs() <= 1e-12 * t.z.abs().max(1.0), "{}: contact {t:?}", s.formula);
            // The centre lies along the outward normal (−f_x, −f_y, 1)/|…| written by hand.
            let (fx, fy) = (s.grad)(t.x, t.y);
            let norm = (1.0 + fx * fx + fy * fy).sqrt();
            let want = [t.x - r * fx / norm, t.y - r * fy / norm, t.z + r / norm];
            for (got, want) in [c.x, c.y, c.z].iter().zip(want) {
                assert!((got - want).abs() <= 1e-12 * (1.0 + want.abs()), "{}: centre {c:?}, want {want:?}", s.formula);
            }
            // Its distance to the surface, found independently, is R.
            // Started a quarter of the way from the contact point to above the centre (the
            // point above the centre itself may be off the surface's domain).
            let (u0, v0) = (t.x + 0.25 * (c.x - t.x), t.y + 0.25 * (c.y - t.y));
            let d = distance_to_surface(&s, [c.x, c.y, c.z], u0, v0);
            assert!((d - r).abs() <= 1e-9, "{}: point {k}: distance {d} from R {r}", s.formula);
            if k % 7 == 0 {
                let nearest = nearest_on_grid(&s, [c.x, c.y, c.z], r, (spec.x, spec.y));
                assert!(nearest >= r - 1e-9, "{}: point {k}: a grid point is {nearest} away", s.formula);
            }
        }
    }
}

#[test]
fn the_raster_is_a_zig_zag_with_both_edges() {
    let p = path("0", &spec(1.0, [0.0, 1.0], [0.0, 2.0], 0.3, 0.8)).unwrap();
    let xs: Vec<f64> = p.line_starts.iter().map(|&i| p.points[i].contact.x).collect();
    assert_eq!(xs, [0.0, 0.3, 0.6, 0.8999999999999999, 1.0]);
    let line = |k: usize| -> Vec<f64> {
        let end = p.line_starts.get(k + 1).copied().unwrap_or(p.points.len());
        p.points[p.line_starts[k]..end].iter().map(|q| q.contact.y).collect()
    };
    assert_eq!(line(0), [0.0, 0.8, 1.6, 2.0]);
    assert_eq!(line(1), [2.0, 1.6, 0.8, 0.0]);
    // Lines of constant y instead.
    let q =
        path("0", &BallPathSpec { lines: Lines::ConstantY, ..spec(1.0, [0.0, 1.0], [0.0, 2.0], 1.0, 0.5) }).unwrap();
    let first: Vec<(f64, f64)> = q.points[..3].iter().map(|p| (p.contact.x, p.contact.y)).collect();
    assert_eq!(first, [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0)]);
}

#[test]
fn chord_tolerance_puts_points_where_the_path_bends() {
    // A ridge along y: z = e^(−x²), lines of constant y run across it.
    let tolerance = 0.001;
    let spacing = Spacing::Chord { tolerance, max_step: 1.0 };
    let spec = BallPathSpec { spacing, lines: Lines::ConstantY, ..spec(0.5, [-4.0, 4.0], [0.0, 0.0], 1.0, 1.0) };
    // Excel reads -x^2 as (-x)^2: the parentheses make it -(x^2).
    let p = path("EXP(-(x^2))", &spec).unwrap();
    let xs: Vec<f64> = p.points.iter().map(|q| q.contact.x).collect();
    let near_top = xs.iter().filter(|x| x.abs() < 1.5).count();
    let flanks = xs.iter().filter(|x| x.abs() > 3.0).count();
    assert!(near_top > 4 * flanks, "{xs:?}");
    // Every chord between programmed centres stays within the tolerance of the true centre
    // path, sampled finely between them (by hand: the centre of the ball touching at x).
    let centre = |x: f64| {
        let (f, fx) = ((-x * x).exp(), -2.0 * x * (-x * x).exp());
        let n = (1.0 + fx * fx).sqrt();
        (x - 0.5 * fx / n, f + 0.5 / n)
    };
    for w in p.points.windows(2) {
        let (a, b) = (w[0].centre, w[1].centre);
        for k in 1..20 {
            let t = w[0].contact.x + (w[1].contact.x - w[0].contact.x) * k as f64 / 20.0;
            let (cx, cz) = centre(t);
            let (ex, ez) = (b.x - a.x, b.z - a.z);
            let cross = ((cx - a.x) * ez - (cz - a.z) * ex).abs() / (ex * ex + ez * ez).sqrt();
            assert!(cross <= 1.5 * tolerance, "chord {a:?}–{b:?} is {cross} from the path at x={t}");
        }
    }
}

/// A groove z = −e^(−x²/4) (typed `-EXP(-(x^2)/4)`: Excel's `-x^2` is (−x)²): its bottom has curvature radius 2, tighter than a 3 mm ball.
fn groove(x: f64) -> f64 {
    -(-x * x / 4.0).exp()
}

/// How far the ball centred at `c` must rise to clear the groove: the vertical interference
/// max over u of groove(u) − (c_z − √(R² − (u − c_x)²)), found on a fine grid and refined.
fn groove_interference(c: [f64; 3], r: f64, x_range: [f64; 2]) -> (f64, f64) {
    let depth = |u: f64| groove(u) - (c[2] - (r * r - (u - c[0]).powi(2)).max(0.0).sqrt());
    let (lo, hi) = ((c[0] - r).max(x_range[0]), (c[0] + r).min(x_range[1]));
    let n = 20000;
    let mut best = (f64::NEG_INFINITY, lo);
    for k in 0..=n {
        let u = lo + (hi - lo) * k as f64 / n as f64;
        if depth(u) > best.0 {
            best = (depth(u), u);
        }
    }
    let mut h = (hi - lo) / n as f64;
    while h > 1e-13 {
        for u in [best.1 - h, best.1 + h] {
            if (lo..=hi).contains(&u) && depth(u) > best.0 {
                best = (depth(u), u);
            }
        }
        h *= 0.5;
    }
    best
}

#[test]
fn a_hollow_tighter_than_the_ball_is_reported_where_it_gouges() {
    let formula = "-EXP(-(x^2)/4)";
    let spec = spec(3.0, [-6.0, 6.0], [0.0, 2.0], 0.25, 1.0);
    let p = path(formula, &spec).unwrap();
    assert!(!p.gouges.is_empty());
    for (k, pt) in p.points.iter().enumerate() {
        let c = pt.centre;
        let (depth, _) = groove_interference([c.x, c.y, c.z], 3.0, spec.x);
        let reported = p.gouges.iter().find(|g| g.point == k && g.kind == GougeKind::Position);
        match reported {
            Some(g) => {
                // Within the check's tolerance (1 µm, half of it in the search), never deeper.
                let tol = GOUGE_TOLERANCE;
                assert!(
                    g.depth <= depth + 1e-9 && g.depth >= depth - tol / 2.0,
                    "point {k}: reported {} deep, by hand {depth}",
                    g.depth
                );
                // Where it says, the groove cuts the ball that deep.
                let under = c.z - (9.0 - (g.at.x - c.x).powi(2) - (g.at.y - c.y).powi(2)).sqrt();
                assert!((groove(g.at.x) - under - g.depth).abs() < 1e-9, "point {k}: at {:?}", g.at);
                assert!((g.at.z - groove(g.at.x)).abs() < 1e-12);
            }
            None => {
                assert!(depth <= GOUGE_TOLERANCE, "point {k} at x={} is not reported but cuts {depth}", pt.contact.x)
            }
        }
    }
    // The ball over the bottom gouges; far up the flanks it does not.
    let gouging_x = |x: f64| p.gouges.iter().any(|g| (g.contact.x - x).abs() < 1e-9);
    assert!(gouging_x(0.0));
    assert!(!gouging_x(-6.0) && !gouging_x(6.0));
}

#[test]
fn lifting_clears_the_hollow_and_touches_it() {
    let spec = BallPathSpec { gouge: GougeCheck::Lift, ..spec(3.0, [-6.0, 6.0], [0.0, 0.0], 0.25, 1.0) };
    let p = path("-EXP(-(x^2)/4)", &spec).unwrap();
    assert!(!p.gouges.is_empty());
    for pt in &p.points {
        let c = pt.centre;
        let (depth, _) = groove_interference([c.x, c.y, c.z], 3.0, spec.x);
        // Clear of the surface within the check's tolerance, and still touching it.
        assert!((-1e-9..=GOUGE_TOLERANCE).contains(&depth), "centre {c:?}: interference {depth}");
        assert_eq!(pt.contact.z, groove(pt.contact.x));
    }
}

#[test]
fn where_the_surface_has_no_value_is_said() {
    let err = path("SQRT(1-x^2)", &spec(0.5, [-2.0, 2.0], [0.0, 0.0], 1.0, 1.0)).unwrap_err();
    assert_eq!(err, "the surface's height is #NUM! at x=-2, y=0");
    let err = path("LN(x)", &spec(0.5, [0.0, 2.0], [0.0, 0.0], 1.0, 1.0)).unwrap_err();
    assert_eq!(err, "the surface's height is #NUM! at x=0, y=0");
    // A vertical wall: the height exists, the slope does not.
    let err = path("SQRT(x)", &spec(0.5, [0.0, 2.0], [0.0, 0.0], 1.0, 1.0)).unwrap_err();
    assert_eq!(err, "the surface's slope ∂f/∂x is #DIV/0! at x=0, y=0");
    let err = path("INDEX(A1:A3,x)", &spec(0.5, [0.0, 2.0], [0.0, 0.0], 1.0, 1.0)).unwrap_err();
    assert!(err.contains("cannot differentiate INDEX"), "{err}");
}

#[test]
fn kinks_take_a_documented_slope() {
    // ABS at 0 is SIGN(0)·1 = 0: the ball sits straight above the kink.
    let p = path("ABS(x)", &spec(1.0, [0.0, 0.0], [0.0, 0.0], 1.0, 1.0)).unwrap();
    assert_eq!((p.points[0].centre.x, p.points[0].centre.z), (0.0, 1.0));
    // IF takes the branch its condition picks: at x = 0 that is the else branch (slope −1).
    let p =
        path("IF(x>0,x,-x)", &BallPathSpec { gouge: GougeCheck::Off, ..spec(1.0, [0.0, 0.0], [0.0, 0.0], 1.0, 1.0) })
            .unwrap();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    assert!((p.points[0].centre.x - s).abs() < 1e-15 && (p.points[0].centre.z - s).abs() < 1e-15);
}

// ---- LAMBDA and BALLPATH in a workbook -----------------------------------------------------

fn at(wb: &Workbook, cell: &str) -> Value {
    wb.value(0, ncsheet::formula::address::parse_cell(cell).unwrap())
}

fn set(wb: &mut Workbook, cell: &str, input: &str) {
    wb.set_input(0, ncsheet::formula::address::parse_cell(cell).unwrap(), input).unwrap();
}

#[test]
fn a_named_lambda_is_called_like_a_function() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("bump", "=LAMBDA(x,y,0.3*EXP(-16*(x^2+y^2)))", None).unwrap();
    set(&mut wb, "A1", "=bump(0.1,0.2)");
    set(&mut wb, "A2", "=bump(1)");
    set(&mut wb, "A3", "=LAMBDA(x,x+1)");
    set(&mut wb, "A4", "=bump");
    set(&mut wb, "A5", "=nothing(1)");
    // 0.3·e^(−16·0.05) = 0.3·e^(−0.8) = 0.13479868923...
    match at(&wb, "A1") {
        Value::Number(v) => assert!((v - 0.134_798_689_235_2).abs() < 1e-12, "{v}"),
        v => panic!("{v:?}"),
    }
    assert_eq!(at(&wb, "A2"), Value::Error(XlError::Value));
    assert_eq!(at(&wb, "A3"), Value::Error(XlError::Calc));
    assert_eq!(at(&wb, "A4"), Value::Error(XlError::Calc));
    assert_eq!(at(&wb, "A5"), Value::Error(XlError::Name));
}

#[test]
fn ballpath_spills_the_same_path_for_a_named_lambda_an_inline_one_and_text() {
    let mut wb = Workbook::with_sheet();
    wb.define_name("bump", "=LAMBDA(u,v,0.3*EXP(-16*(u^2+v^2)))", None).unwrap();
    set(&mut wb, "A1", "0.3*EXP(-16*(x^2+y^2))");
    // "lift": straight moves across the dome dip more than 1 µm, the points inserted there
    // are part of the path.
    set(&mut wb, "B1", "=BALLPATH(bump,0.1,-0.5,0.5,-0.5,0.5,0.5,0.5,,\"lift\")");
    set(&mut wb, "F1", "=BALLPATH(LAMBDA(x,y,0.3*EXP(-16*(x^2+y^2))),0.1,-0.5,0.5,-0.5,0.5,0.5,0.5,,\"lift\")");
    set(&mut wb, "J1", "=BALLPATH(A1,0.1,-0.5,0.5,-0.5,0.5,0.5,0.5,,\"lift\")");
    set(&mut wb, "N1", "=BALLPATH(A1,0.1,-0.5,0.5,-0.5,0.5,0.5,0.5,\"centre\",\"lift\")");
    let number = |cell: &str| match at(&wb, cell) {
        Value::Number(v) => v,
        v => panic!("{cell}: {v:?}"),
    };
    let rows = (1..).find(|r| at(&wb, &format!("B{r}")) == Value::Blank).unwrap() - 1;
    assert!(rows >= 9, "{rows}");
    // The top of the bump (0, 0, 0.3) is a programmed point: tip = contact there.
    let top = (1..=rows).find(|r| number(&format!("B{r}")) == 0.0 && number(&format!("C{r}")) == 0.0).unwrap();
    assert!((number(&format!("D{top}")) - 0.3).abs() < 1e-15 && (number(&format!("P{top}")) - 0.4).abs() < 1e-15);
    for row in 1..=rows {
        for (a, b, c) in [("B", "F", "J"), ("C", "G", "K"), ("D", "H", "L")] {
            let (a, b, c) = (number(&format!("{a}{row}")), number(&format!("{b}{row}")), number(&format!("{c}{row}")));
            assert!(a == b && b == c, "row {row}: {a} {b} {c}");
        }
    }
    // The first point by hand: contact (−0.5, −0.5), f = 0.3·e^(−8), ∂f/∂x = ∂f/∂y = 9.6·0.5·e^(−8).
    let (f, g) = (0.3 * (-8f64).exp(), 4.8 * (-8f64).exp());
    let n = (1.0 + 2.0 * g * g).sqrt();
    let want = [-0.5 - 0.1 * g / n, -0.5 - 0.1 * g / n, f + 0.1 / n - 0.1];
    for (col, w) in ["B", "C", "D"].iter().zip(want) {
        assert!((number(&format!("{col}1")) - w).abs() < 1e-15, "{col}1");
    }
}

#[test]
fn ballpath_refuses_a_gouge_unless_asked_to_lift() {
    let mut wb = Workbook::with_sheet();
    set(&mut wb, "A1", "=BALLPATH(\"-EXP(-(x^2)/4)\",3,-1,1,0,0,1,1)");
    set(&mut wb, "E1", "=BALLPATH(\"-EXP(-(x^2)/4)\",3,-1,1,0,0,1,1,,\"lift\")");
    set(&mut wb, "I1", "=BALLPATH(\"VLOOKUP(x,A1:B2,2)\",3,-1,1,0,0,1,1)");
    assert_eq!(at(&wb, "A1"), Value::Error(XlError::Num));
    let notes = wb.notes(0, Pos::new(0, 0)).join("\n");
    assert!(notes.contains("gouges; the first: the ball touching (") && notes.contains("\"lift\""), "{notes}");
    assert!(matches!(at(&wb, "E1"), Value::Number(_)));
    assert_eq!(at(&wb, "I1"), Value::Error(XlError::Value));
}

#[test]
fn a_surface_that_computes_a_ballpath_itself_is_refused_not_recursed() {
    // The named surface calls BALLPATH over itself: without a guard this recurses until the
    // stack gives out. Each workbook's evaluation carries its own guard.
    let mut wb = Workbook::with_sheet();
    wb.define_name("loop", "=LAMBDA(x,y,INDEX(BALLPATH(loop,0.1,0,0.1,0,0.1,0.1,0.1),1,3))", None).unwrap();
    set(&mut wb, "A1", "=BALLPATH(loop,0.1,0,0.1,0,0.1,0.1,0.1)");
    assert!(matches!(at(&wb, "A1"), Value::Error(_)), "{:?}", at(&wb, "A1"));
    // A plain surface on the same thread afterwards is not refused.
    set(&mut wb, "B1", "=BALLPATH(LAMBDA(x,y,0),0.1,0,0.1,0,0.1,0.1,0.1)");
    assert!(matches!(at(&wb, "B1"), Value::Number(_)), "{:?}", at(&wb, "B1"));
}
