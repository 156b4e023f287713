//! Issue 33, scope 4: 5-axis finishing with the tool inclined to the surface normal (a lead
//! along the feed, a tilt across it), from `ballpath --cl` through `post` for the (A,B) head of
//! docs/domain.md §4, checked by forward kinematics written here: a = R_Y(B)·R_X(A)·k =
//! (cosA·sinB, −sinA, cosA·cosB), tip = pivot − H·a + H·k, ball centre = tip + R·a.

use std::process::Command;

const BUMP: &str = "15*EXP(-16*((x/50)^2+(y/50)^2))";
const R: f64 = 3.0;
const H: f64 = 400.0;

fn ncsheet(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// The bump's height and outward unit normal, from its closed form.
fn surface(x: f64, y: f64) -> (f64, [f64; 3]) {
    let z = 15.0 * (-16.0 * ((x / 50.0).powi(2) + (y / 50.0).powi(2))).exp();
    let (fx, fy) = (-32.0 * x / 2500.0 * z, -32.0 * y / 2500.0 * z);
    let norm = (1.0 + fx * fx + fy * fy).sqrt();
    (z, [-fx / norm, -fy / norm, 1.0 / norm])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// The cutting blocks (G1) of the posted program: X Y Z A B.
fn cutting_blocks(text: &str) -> Vec<[f64; 5]> {
    let mut at = [f64::NAN; 5];
    let mut blocks = Vec::new();
    for line in text.lines().filter(|l| l.starts_with('N')) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let value = |letter: char| words.iter().find_map(|w| w.strip_prefix(letter)?.parse::<f64>().ok());
        for (i, letter) in ['X', 'Y', 'Z', 'A', 'B'].into_iter().enumerate() {
            if let Some(v) = value(letter) {
                at[i] = v;
            }
        }
        if words.contains(&"G1") {
            blocks.push(at);
        }
    }
    blocks
}

fn check(lead_deg: f64, tilt_deg: f64, direction: &str) {
    let dir = tempfile::tempdir().unwrap();
    let (cl, csv, nc) = (dir.path().join("b.cl"), dir.path().join("b.csv"), dir.path().join("b.nc"));
    let (lead, tilt) = (lead_deg.to_string(), tilt_deg.to_string());
    ncsheet(&[
        "ballpath",
        "--surface",
        BUMP,
        "--radius",
        "3",
        "--x=-25:25",
        "--y=-25:25",
        "--stepover",
        "10",
        "--step",
        "2.5",
        "--gouge",
        "off",
        "--direction",
        direction,
        "--lead",
        &lead,
        "--tilt",
        &tilt,
        "--cl",
        cl.to_str().unwrap(),
        "--format",
        "csv",
        "-o",
        csv.to_str().unwrap(),
    ]);
    let post = ["post", cl.to_str().unwrap(), "--machine", "ab-head", "--pivot", "400", "--dialect", "iso"];
    ncsheet(&[&post[..], &["--decimals", "5", "-o", nc.to_str().unwrap()]].concat());
    // The contact points, in cutting order, and each ball centre on the outward normal.
    let rows: Vec<Vec<f64>> = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let contacts: Vec<([f64; 3], [f64; 3])> = rows
        .iter()
        .map(|r| {
            let (z, n) = surface(r[3], r[4]);
            assert!((r[5] - z).abs() < 1e-9, "contact {r:?} off the bump");
            let contact = [r[3], r[4], z];
            (contact, [contact[0] + R * n[0], contact[1] + R * n[1], contact[2] + R * n[2]])
        })
        .collect();
    let blocks = cutting_blocks(&std::fs::read_to_string(&nc).unwrap());
    assert_eq!(blocks.len(), contacts.len());
    assert!(blocks.len() > 20, "{} blocks", blocks.len());
    let same_line = |i: usize, j: usize| rows[i][3] == rows[j][3];
    for (i, b) in blocks.iter().enumerate() {
        let (a_deg, b_deg) = (b[3].to_radians(), b[4].to_radians());
        let axis = [a_deg.cos() * b_deg.sin(), -a_deg.sin(), a_deg.cos() * b_deg.cos()];
        let tip = [b[0] - H * axis[0], b[1] - H * axis[1], b[2] - H * (axis[2] - 1.0)];
        let centre = [tip[0] + R * axis[0], tip[1] + R * axis[1], tip[2] + R * axis[2]];
        let (contact, expected) = contacts[i];
        let miss = dot(
            [centre[0] - expected[0], centre[1] - expected[1], centre[2] - expected[2]],
            [centre[0] - expected[0], centre[1] - expected[1], centre[2] - expected[2]],
        )
        .sqrt();
        assert!(miss <= 1e-3, "block {i}: the ball centre is {miss} mm off contact {contact:?} + R·n");
        // The feed: towards the next ball centre on the line (from the one before at its end),
        // taken into the tangent plane.
        let (from, to) = if i + 1 < blocks.len() && same_line(i, i + 1) { (i, i + 1) } else { (i - 1, i) };
        let step = [0, 1, 2].map(|k| contacts[to].1[k] - contacts[from].1[k]);
        let n = surface(contact[0], contact[1]).1;
        let along = dot(step, n);
        let f = unit([step[0] - along * n[0], step[1] - along * n[1], step[2] - along * n[2]]);
        let c = cross(n, f);
        let lead = dot(axis, f).atan2(dot(axis, n)).to_degrees();
        let tilt = dot(axis, c).asin().to_degrees();
        assert!((lead - lead_deg).abs() <= 1e-3, "block {i}: lead {lead}° for {lead_deg}°");
        assert!((tilt - tilt_deg).abs() <= 1e-3, "block {i}: tilt {tilt}° for {tilt_deg}°");
    }
}

#[test]
fn every_block_puts_the_ball_on_its_contact_point_with_the_asked_lead_and_tilt() {
    check(10.0, 5.0, "climb");
    check(15.0, -8.0, "conventional");
    check(12.0, 0.0, "zigzag");
    // No inclination: the axis is the normal.
    check(0.0, 0.0, "climb");
}
