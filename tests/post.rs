//! `ncsheet post`: APT cutter-location files posted for an (A,B) head (docs/domain.md §4), checked
//! against the paper's table T8.1.4, against tool paths OpenCAMLib computes, and read back by
//! LinuxCNC's rs274.

mod common;

use std::path::Path;
use std::process::Command;

use common::cli::{ncsheet, Run};
use common::rs274;

/// Table T8.1.4 (docs/domain.md §4): sphere R = 100 at the origin, parallel z_T = 95, H = 400.
/// (φ, x_T, y_T, a_x, a_y, a_z, X, Y, Z, A, B) as printed there.
const T8_1_4: [[f64; 11]; 3] = [
    [0.0, 31.224989992, 0.0, 0.31224989992, 0.0, 0.95, 156.125, 0.0, 75.0, 0.0, 18.195],
    [45.0, 22.0794021658, 22.0794021658, 0.22079402166, 0.22079402166, 0.95, 110.397, 110.397, 75.0, -12.756, 13.084],
    [90.0, 0.0, 31.224989992, 0.0, 0.31224989992, 0.95, 0.0, 156.125, 75.0, -18.195, 0.0],
];

/// The whole parallel at 45° steps: the table's three rows, the others by the sphere's
/// symmetry (docs/domain.md: "the other angles follow from these three"): mirroring y negates y,
/// a_y and A; mirroring x negates x, a_x and B.
fn parallel() -> Vec<[f64; 11]> {
    let [r0, r45, r90] = T8_1_4;
    let mirror_x = |r: [f64; 11], phi: f64| [phi, -r[1], r[2], -r[3], r[4], r[5], -r[6], r[7], r[8], r[9], -r[10]];
    let mirror_y = |r: [f64; 11], phi: f64| [phi, r[1], -r[2], r[3], -r[4], r[5], r[6], -r[7], r[8], -r[9], r[10]];
    let r135 = mirror_x(r45, 135.0);
    let r180 = mirror_x(r0, 180.0);
    vec![
        r0,
        r45,
        r90,
        r135,
        r180,
        mirror_y(r135, 225.0),
        mirror_y(r90, 270.0),
        mirror_y(r45, 315.0),
        [360.0, r0[1], r0[2], r0[3], r0[4], r0[5], r0[6], r0[7], r0[8], r0[9], r0[10]],
    ]
}

fn sphere_cl() -> String {
    let mut cl =
        String::from("PARTNO SPHERE PARALLEL\n$$ docs/domain.md table T8.1.4\nLOADTL/1\nSPINDL/RPM,2000,CLW\n");
    cl.push_str("FEDRAT/300,MMPM\n");
    for r in parallel() {
        cl.push_str(&format!("GOTO/{},{},95.0,$\n     {},{},{}\n", r[1], r[2], r[3], r[4], r[5]));
    }
    cl.push_str("FINI\n");
    cl
}

fn post(dir: &Path, cl: &str, extra: &[&str]) -> Run {
    let file = dir.join("path.cl");
    std::fs::write(&file, cl).unwrap();
    let mut args = vec!["post", file.to_str().unwrap(), "--machine", "ab-head"];
    args.extend_from_slice(extra);
    ncsheet(&args)
}

/// The `G1` blocks' X Y Z A B words, as written.
fn g1_words(program: &str) -> Vec<[f64; 5]> {
    program
        .lines()
        .filter(|l| l.split_whitespace().nth(1) == Some("G1"))
        .map(|l| {
            let word = |a: char| {
                l.split_whitespace()
                    .find_map(|w| w.strip_prefix(a))
                    .and_then(|v| v.parse::<f64>().ok())
                    .unwrap_or_else(|| panic!("no {a} in {l}"))
            };
            [word('X'), word('Y'), word('Z'), word('A'), word('B')]
        })
        .collect()
}

#[test]
fn the_sphere_parallel_reproduces_table_t8_1_4() {
    let dir = tempfile::tempdir().unwrap();
    let run = post(dir.path(), &sphere_cl(), &["--pivot", "400", "--dialect", "iso"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let blocks = g1_words(&run.stdout);
    let rows = parallel();
    assert_eq!(blocks.len(), rows.len(), "{}", run.stdout);
    for (b, r) in blocks.iter().zip(&rows) {
        let expected = [r[6], r[7], r[8], r[9], r[10]];
        for (k, (got, want)) in b.iter().zip(expected).enumerate() {
            // The table prints 3 decimals (1 µm, 0.001°), as the iso dialect writes them.
            assert!((got - want).abs() < 0.0015, "φ = {}: word {k} is {got}, the table says {want}", r[0]);
        }
    }
    assert!(run.stdout.contains("T1 M6") && run.stdout.contains("S2000 M3") && run.stdout.contains("G94"));
}

/// rs274's STRAIGHT_FEED and STRAIGHT_TRAVERSE as (feed?, [x, y, z, a, b]).
fn canonical_moves(program: &Path) -> Vec<(bool, [f64; 5])> {
    let text = rs274::canon(program).unwrap_or_else(|e| panic!("rs274 rejected the program:\n{e}"));
    text.lines()
        .filter_map(|l| {
            let feed = l.contains("STRAIGHT_FEED(");
            if !feed && !l.contains("STRAIGHT_TRAVERSE(") {
                return None;
            }
            let args = l.split_once('(')?.1.trim_end_matches(')');
            let v: Vec<f64> = args.split(',').map(|a| a.trim().parse().unwrap()).collect();
            Some((feed, [v[0], v[1], v[2], v[3], v[4]]))
        })
        .collect()
}

#[test]
fn rs274_reads_the_posted_parallel() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sphere.ngc");
    let run = post(dir.path(), &sphere_cl(), &["--pivot", "400", "--dialect", "linuxcnc", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let moves = canonical_moves(&out);
    let feeds: Vec<[f64; 5]> = moves.iter().filter(|m| m.0).map(|m| m.1).collect();
    let rows = parallel();
    assert_eq!(feeds.len(), rows.len(), "{moves:?}");
    for (m, r) in feeds.iter().zip(&rows) {
        for (got, want) in m.iter().zip(&r[6..]) {
            assert!((got - want).abs() < 0.0015, "φ = {}: {m:?} against the table's {:?}", r[0], &r[6..]);
        }
    }
    // The approach: up to the clearance (tip 95 + 5), then over the first point, turned.
    let rapids: Vec<[f64; 5]> = moves.iter().take_while(|m| !m.0).map(|m| m.1).collect();
    assert_eq!(rapids.last().map(|r| (r[2], r[4])), Some((100.0, 18.195)), "{moves:?}");
}

#[test]
fn the_singular_position_is_refused_naming_the_record() {
    let dir = tempfile::tempdir().unwrap();
    for axis in ["0,1,0", "0,-1,0", "0,0.99999,0.0044721"] {
        let cl = format!("LOADTL/1\nSPINDL/1000\nFEDRAT/100\nGOTO/0,0,0\nGOTO/0,0,0,$\n {axis}\n");
        let run = post(dir.path(), &cl, &["--pivot", "100", "--dialect", "iso"]);
        assert_eq!(run.code, 1, "{axis}: {}", run.stdout);
        assert!(run.stderr.contains("path.cl: line 5 (GOTO)"), "{axis}: {}", run.stderr);
        assert!(run.stderr.contains("singular position") && run.stderr.contains("A = ±90°"), "{}", run.stderr);
        assert!(run.stdout.is_empty());
    }
    // 2° from the singular position passes with the default margin of 1°, not with 3°.
    let axis = "0,0.999390827,0.034899497";
    let cl = format!("LOADTL/1\nSPINDL/1000\nFEDRAT/100\nGOTO/0,0,0\nGOTO/0,0,0,{axis}\n");
    let run = post(dir.path(), &cl, &["--pivot", "100", "--dialect", "iso", "--max-swing", "90"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("A-88."), "{}", run.stdout);
    let run = post(dir.path(), &cl, &["--pivot", "100", "--dialect", "iso", "--singular", "3"]);
    assert!(run.code == 1 && run.stderr.contains("line 5 (GOTO)"), "{}", run.stderr);
}

#[test]
fn axis_limits_and_unknown_records_are_refused_with_their_place() {
    let dir = tempfile::tempdir().unwrap();
    let cl = "LOADTL/1\nSPINDL/1000\nFEDRAT/100\nGOTO/0,0,0,0.5,0,0.8660254\n";
    let run = post(dir.path(), cl, &["--pivot", "100", "--dialect", "iso", "--b-limits", "-20:20"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("line 4 (GOTO)") && run.stderr.contains("B = 30.000°"), "{}", run.stderr);
    let run = post(dir.path(), "LOADTL/1\nTLAXIS/0,0,1\n", &["--pivot", "100", "--dialect", "iso"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("path.cl: line 2, column 1: unknown record TLAXIS"), "{}", run.stderr);
    let run = post(dir.path(), &sphere_cl(), &["--pivot", "400", "--dialect", "nc31"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("no A and B axes"), "{}", run.stderr);
}

#[test]
fn the_input_file_is_never_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("path.cl");
    std::fs::write(&file, sphere_cl()).unwrap();
    let f = file.to_str().unwrap();
    let run = ncsheet(&["post", f, "--machine", "ab-head", "--pivot", "400", "--dialect", "iso", "-o", f]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("refusing to overwrite the input file"), "{}", run.stderr);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), sphere_cl());
}

// ---- a tool path computed by OpenCAMLib ---------------------------------------------------

/// Whether OpenCAMLib's Python module can be imported; on CI (`CI` set) it must be:
/// `.ci/run` installs it.
fn opencamlib_available() -> bool {
    let found = Command::new("python3").args(["-c", "import opencamlib"]).output().is_ok_and(|o| o.status.success());
    assert!(found || std::env::var_os("CI").is_none(), "OpenCAMLib (pip opencamlib) is missing on CI");
    found
}

/// OpenCAMLib drops a 6 mm ball cutter onto a triangulated dome (a sphere of radius 50
/// centred 40 below the XY plane) along two zig-zag lines; the CL file gives each contact
/// point as the tool tip with the tool axis along the surface normal there (from the ball's
/// centre to the contact), as a 5-axis CAM writes it.
const OCL_SCRIPT: &str = r#"
import math, sys, opencamlib as ocl
R, zc, r = 50.0, -40.0, 3.0
surface = ocl.STLSurf()
def P(x, y):
    return ocl.Point(x, y, zc + math.sqrt(R * R - x * x - y * y))
h = 2.5
for i in range(-12, 12):
    for j in range(-12, 12):
        a, b, c, d = P(i*h, j*h), P((i+1)*h, j*h), P((i+1)*h, (j+1)*h), P(i*h, (j+1)*h)
        surface.addTriangle(ocl.Triangle(a, b, c))
        surface.addTriangle(ocl.Triangle(a, c, d))
dropper = ocl.PathDropCutter()
dropper.setSTL(surface)
dropper.setCutter(ocl.BallCutter(2 * r, 50.0))
dropper.minimumZ = -20.0
dropper.setSampling(2.0)
path = ocl.Path()
path.append(ocl.Line(ocl.Point(-20, -8, 0), ocl.Point(20, -8, 0)))
path.append(ocl.Line(ocl.Point(20, -8, 0), ocl.Point(20, 8, 0)))
path.append(ocl.Line(ocl.Point(20, 8, 0), ocl.Point(-20, 8, 0)))
dropper.setPath(path)
dropper.run()
out = ["PARTNO OPENCAMLIB DOME", "$$ opencamlib " + str(ocl.version()), "UNITS/MM", "LOADTL/2",
       "SPINDL/RPM,4000,CLW", "FEDRAT/600,MMPM", "MULTAX"]
for k, p in enumerate(dropper.getCLPoints()):
    cc = p.getCC()
    n = (p.x - cc.x, p.y - cc.y, p.z + r - cc.z)
    length = math.sqrt(sum(c * c for c in n))
    if abs(length - r) > 1e-6:
        sys.exit("no contact at CL point %d" % k)
    n = tuple(c / length for c in n)
    if k == 0:
        out.append("RAPID")
    out.append("GOTO/%.9f,%.9f,%.9f,%.9f,%.9f,%.9f" % (cc.x, cc.y, cc.z, n[0], n[1], n[2]))
out.append("FINI")
print("\n".join(out))
"#;

/// The (tip, axis) of each GOTO, read here with a plain split.
fn gotos(cl: &str) -> Vec<([f64; 3], [f64; 3])> {
    cl.lines()
        .filter_map(|l| l.strip_prefix("GOTO/"))
        .map(|args| {
            let v: Vec<f64> = args.split(',').map(|a| a.parse().unwrap()).collect();
            ([v[0], v[1], v[2]], [v[3], v[4], v[5]])
        })
        .collect()
}

#[test]
fn an_opencamlib_tool_path_posts_onto_its_normals() {
    if !opencamlib_available() {
        eprintln!("skipped: OpenCAMLib is not installed (bash .ci/run installs it with pip)");
        return;
    }
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let made = Command::new("python3").args(["-c", OCL_SCRIPT]).output().unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let cl = String::from_utf8(made.stdout).unwrap();
    let points = gotos(&cl);
    assert!(points.len() > 20, "{cl}");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("dome.ngc");
    let h = 250.0;
    let run = post(dir.path(), &cl, &["--pivot", "250", "--dialect", "linuxcnc", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let moves = canonical_moves(&out);
    // Two rapids of the approach, one move per GOTO (the first after RAPID a traverse, the
    // others cuts), the retract.
    assert_eq!(moves.len(), points.len() + 3, "{moves:?}");
    assert_eq!(moves.iter().filter(|m| m.0).count(), points.len() - 1, "{moves:?}");
    let posted: Vec<[f64; 5]> = moves[2..moves.len() - 1].iter().map(|m| m.1).collect();
    for (m, (tip, n)) in posted.iter().zip(&points) {
        // The head's axis at these angles, R_Y(B)·R_X(A)·k, is OpenCAMLib's normal …
        let (a, b) = (m[3].to_radians(), m[4].to_radians());
        let axis = [a.cos() * b.sin(), -a.sin(), a.cos() * b.cos()];
        for k in 0..3 {
            assert!((axis[k] - n[k]).abs() < 2e-5, "{m:?}: axis {axis:?}, normal {n:?}");
        }
        // … and the pivot is H along it from the contact point, less H along Z.
        let pivot = [tip[0] + h * n[0], tip[1] + h * n[1], tip[2] + h * (n[2] - 1.0)];
        for k in 0..3 {
            assert!((m[k] - pivot[k]).abs() < 0.0006, "{m:?}: pivot {pivot:?}");
        }
    }
}

// ---- a ball-end path of ncsheet's own, through its CL file ---------------------------------

/// The bowl z = (x² + y²)/100 and its outward unit normal, here by hand: (−z_x, −z_y, 1)
/// normalised, z_x = x/50, z_y = y/50.
fn bowl(x: f64, y: f64) -> (f64, [f64; 3]) {
    let (zx, zy) = (x / 50.0, y / 50.0);
    let length = (zx * zx + zy * zy + 1.0).sqrt();
    ((x * x + y * y) / 100.0, [-zx / length, -zy / length, 1.0 / length])
}

#[test]
fn ballpath_cl_posts_with_the_tool_along_the_surface_normal() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cl = dir.path().join("bowl.cl");
    let run = ncsheet(&[
        "ballpath",
        "--surface",
        "(x^2+y^2)/100",
        "--radius",
        "3",
        "--x",
        "-20:20",
        "--y",
        "-15:15",
        "--stepover",
        "5",
        "--step",
        "4",
        "--cl",
        cl.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.is_empty(), "with --cl and no -o only the CL file is written");
    let text = std::fs::read_to_string(&cl).unwrap();
    // The contact points, where the tip stands on the surface; the others are the rapids above.
    let contacts: Vec<([f64; 3], [f64; 3])> =
        gotos(&text).into_iter().filter(|(t, _)| (t[2] - bowl(t[0], t[1]).0).abs() < 1e-9).collect();
    // 9 lines of constant x, 5 apart; along each y = −15, −11, … 13 and the edge 15.
    assert_eq!(contacts.len(), 9 * 9, "{text}");
    let out = dir.path().join("bowl.ngc");
    let h = 320.0;
    let run = ncsheet(&[
        "post",
        cl.to_str().unwrap(),
        "--machine",
        "ab-head",
        "--pivot",
        "320",
        "--dialect",
        "linuxcnc",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let feeds: Vec<[f64; 5]> = canonical_moves(&out).into_iter().filter(|m| m.0).map(|m| m.1).collect();
    assert_eq!(feeds.len(), contacts.len());
    let mut steepest: f64 = 0.0;
    for (m, (tip, _)) in feeds.iter().zip(&contacts) {
        let (_, n) = bowl(tip[0], tip[1]);
        let (a, b) = (m[3].to_radians(), m[4].to_radians());
        let axis = [a.cos() * b.sin(), -a.sin(), a.cos() * b.cos()];
        for k in 0..3 {
            assert!((axis[k] - n[k]).abs() < 2e-5, "at {tip:?}: head axis {axis:?}, normal {n:?}");
        }
        let pivot = [tip[0] + h * n[0], tip[1] + h * n[1], tip[2] + h * (n[2] - 1.0)];
        for k in 0..3 {
            assert!((m[k] - pivot[k]).abs() < 0.0006, "at {tip:?}: {m:?}, pivot {pivot:?}");
        }
        steepest = steepest.max(m[3].abs()).max(m[4].abs());
    }
    assert!(steepest > 15.0, "the path tilts the head: {steepest}");
}

#[test]
fn a_circle_with_the_tool_tilted_is_the_pivot_s_arc() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    // A quarter circle of radius 10 about (0, 0), clockwise seen from +Z (axis −Z), the tool
    // tilted 30° towards +X all the way: the pivot runs the same circle about
    // (0 + H·sin 30°, 0) = (50, 0), at z = −H·(1 − cos 30°).
    let (s, c) = (0.5, 0.75f64.sqrt());
    let cl = format!(
        "LOADTL/1\nSPINDL/1000\nFEDRAT/200\nGOTO/10,0,0,{s},0,{c}\nCIRCLE/0,0,0,0,0,-1,10\nGOTO/0,-10,0,{s},0,{c}\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("arc.ngc");
    let run = post(dir.path(), &cl, &["--pivot", "100", "--dialect", "linuxcnc", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let moves = rs274::moves(&out).unwrap();
    let z = -100.0 * (1.0 - c);
    let arc = moves.iter().find_map(|m| match m {
        rs274::Move::Arc { first_end, second_end, first_centre, second_centre, rotation, axis_end } => {
            Some((*first_end, *second_end, *first_centre, *second_centre, *rotation, *axis_end))
        }
        _ => None,
    });
    let (x, y, cx, cy, rotation, arc_z) = arc.unwrap_or_else(|| panic!("no arc: {moves:?}"));
    for (got, want) in [(x, 50.0), (y, -10.0), (cx, 50.0), (cy, 0.0), (arc_z, z)] {
        assert!((got - want).abs() < 0.0006, "{moves:?}");
    }
    assert_eq!(rotation, -1, "clockwise");
    // A CIRCLE whose end is off the circle is refused with the GOTO's line.
    let bad = cl.replace("GOTO/0,-10,0", "GOTO/0,-10.5,0");
    let run = post(dir.path(), &bad, &["--pivot", "100", "--dialect", "iso"]);
    assert!(run.code == 1 && run.stderr.contains("line 6 (GOTO)"), "{}", run.stderr);
}

// ---- the tool length in the control's table (the pivot is compensated already) ------------

/// The spindle's point (programmed + the tool length offset in force) of each cut, when
/// `program` runs under rs274 with tool 1 of length 50 mm in its table.
fn cuts_with_a_50_mm_tool(dir: &Path, program: &Path) -> Vec<([f64; 3], f64)> {
    let table = rs274::tool_table(dir, 1, 50.0);
    let canon = rs274::canon_with_tools(program, Some(&table)).unwrap_or_else(|e| panic!("rs274:\n{e}"));
    assert!(canon.contains("USE_TOOL_LENGTH_OFFSET"), "{canon}");
    let feeds: Vec<&str> = canon.lines().filter(|l| l.contains("STRAIGHT_")).collect();
    let moves = rs274::moves_with_length_offset(&canon);
    assert_eq!(feeds.len(), moves.len());
    moves.into_iter().zip(feeds).filter(|(_, l)| l.contains("STRAIGHT_FEED")).map(|(m, _)| m).collect()
}

#[test]
fn a_tool_length_in_the_table_does_not_move_the_posted_pivot() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let h = 400.0;
    for dialect in ["linuxcnc", "iso"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("sphere.ngc");
        let run =
            post(dir.path(), &sphere_cl(), &["--pivot", "400", "--dialect", dialect, "-o", out.to_str().unwrap()]);
        assert_eq!(run.code, 0, "{}", run.stderr);
        let cuts = cuts_with_a_50_mm_tool(dir.path(), &out);
        let rows = parallel();
        assert_eq!(cuts.len(), rows.len(), "{dialect}: {cuts:?}");
        for (([x, y, z], offset), r) in cuts.iter().zip(&rows) {
            // docs/domain.md §4: the pivot X = x_T + H·a_x, Y = y_T + H·a_y, Z = z_T + H·(a_z − 1).
            let pivot = [r[1] + h * r[3], r[2] + h * r[4], 95.0 + h * (r[5] - 1.0)];
            let spindle = [*x, *y, z + offset];
            assert_eq!(*offset, 0.0, "{dialect}: the table's 50 mm is applied at φ = {}", r[0]);
            for k in 0..3 {
                assert!(
                    (spindle[k] - pivot[k]).abs() < 0.0015,
                    "{dialect} φ = {}: {spindle:?} against {pivot:?}",
                    r[0]
                );
            }
        }
    }
}

#[test]
fn a_tool_tip_program_keeps_the_table_length() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    for dialect in ["linuxcnc", "iso"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("ball.ngc");
        let mut args = common::cli::bump_ballpath("5", "5", "off");
        args.extend(["--format", dialect, "-o", out.to_str().unwrap()].map(String::from));
        let run = ncsheet(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(run.code, 0, "{}", run.stderr);
        let cuts = cuts_with_a_50_mm_tool(dir.path(), &out);
        assert!(cuts.len() > 10, "{cuts:?}");
        // The ball path's coordinates are the tool tip's: the spindle runs 50 mm above them.
        assert!(cuts.iter().all(|(_, offset)| (offset - 50.0).abs() < 1e-4), "{dialect}: {cuts:?}");
    }
}

#[test]
fn each_control_cancels_the_length_or_refuses_the_post() {
    let dir = tempfile::tempdir().unwrap();
    // Siemens, Function Manual Basic Functions, Tool offset (W1): "D0 ; Compensation
    // deselection" (the tool's length and radius are not applied).
    let run = post(dir.path(), &sphere_cl(), &["--pivot", "400", "--dialect", "sinumerik"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let tool_line = run.stdout.lines().find(|l| l.contains(" T1")).unwrap();
    assert!(tool_line.ends_with("T1 M6 D0"), "{}", run.stdout);
    // Heidenhain's TOOL CALL always applies the table's length (TNC user's manual, "Tool length
    // compensation": cancelled only by TOOL CALL 0): the post is refused, naming the CL line
    // of the tool change (issue 30: a block's place in an unwritten program helps nobody).
    let run = post(dir.path(), &sphere_cl(), &["--pivot", "400", "--dialect", "heidenhain"]);
    assert_eq!(run.code, 1, "{}", run.stdout);
    assert!(run.stderr.contains("(LOADTL)") && run.stderr.contains("TCPM"), "{}", run.stderr);
    assert!(run.stdout.is_empty());
}

/// A CL file written as a CAM system's APT output writes it (the records and their syntax of
/// aamorim1913/AptPostProcessor, parts-tools/boss.apt: `PARTNO/1`, `UNIT/MM`, the
/// 7-parameter `CUTTER`, `LOAD/TOOL,1`, `SELECT/TOOL,5`, `SPINDL/12000,RPM,CLW`, `RAPID/`,
/// `FEDRAT/…,MMPM`, and a pocket corner `CIRCLE/95.,44.249705,-3.,0,0,-1.` given by centre
/// and axis only). The corner is the circle through the arc's start about that centre, run
/// counter-clockwise about the axis −Z (APT): clockwise seen from above.
#[test]
fn a_cam_systems_cl_file_posts() {
    if !rs274::available() {
        eprintln!("skipped: LinuxCNC's rs274 is not installed (bash .ci/run installs linuxcnc-uspace)");
        return;
    }
    let cl = "PARTNO/1\nUNIT/MM\nCUTTER/6.,0,3.,0,0,0,51.\nLOAD/TOOL,1\nSELECT/TOOL,5\nCOOLNT/FLOOD\n\
              SPINDL/12000,RPM,CLW\nRAPID/\nGOTO/96.4375,-1.4375,2.5\nFEDRAT/411.48,MMPM\n\
              GOTO/96.4375,-1.4375,-3.\nFEDRAT/1645.92,MMPM\nGOTO/96.4375,41.334899,-3.\n\
              CIRCLE/95.,44.249705,-3.,0,0,-1.\nGOTO/95.,40.999705,-3.\nGOTO/78.25,40.999705,-3.\nFINI\n";
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("boss.ngc");
    let run = post(dir.path(), cl, &["--pivot", "0", "--dialect", "linuxcnc", "-o", out.to_str().unwrap()]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("T1 M6 G49") && text.contains("S12000 M3") && text.contains("(next tool 5"), "{text}");
    // The radius the record leaves out: the start's distance from the centre, as the end's.
    let radius = (96.4375f64 - 95.0).hypot(41.334899 - 44.249705);
    assert!((radius - (44.249705 - 40.999705)).abs() < 1e-5, "{radius}");
    let moves = rs274::moves(&out).unwrap();
    let arc = moves.iter().find_map(|m| match m {
        rs274::Move::Arc { first_end, second_end, first_centre, second_centre, rotation, axis_end } => {
            Some((*first_end, *second_end, *first_centre, *second_centre, *rotation, *axis_end))
        }
        _ => None,
    });
    let (x, y, cx, cy, rotation, z) = arc.unwrap_or_else(|| panic!("no arc: {moves:?}"));
    for (got, want) in [(x, 95.0), (y, 40.999705), (cx, 95.0), (cy, 44.249705), (z, -3.0)] {
        assert!((got - want).abs() < 0.0006, "{moves:?}");
    }
    assert_eq!(rotation, -1, "clockwise seen from +Z");
    // An inch file is refused, not converted.
    let run = post(dir.path(), &cl.replace("UNIT/MM", "UNIT/INCHES"), &["--pivot", "0", "--dialect", "iso"]);
    assert!(run.code == 1 && run.stderr.contains("line 2, column 6"), "{}", run.stderr);
}
