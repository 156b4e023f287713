//! NC programs as a control runs them (issue 15): the DDA interpolator against the paper's
//! table T8.1.1 (DOMAIN.md §4).

use std::process::Command;

use ncsheet::nc::dda;

/// Table T8.1.1 of Glavonjić (`../shared/seeds/003_01afb1c580101bdc.txt`), typed from the
/// paper: n = 4, δx = 16, δy = 8; per clock (X p, X q after, X pulse, Y p, Y q after, Y pulse).
const T8_1_1: [(u64, u64, u64, u64, u64, u64, u64); 16] = [
    (1, 16, 0, 1, 8, 8, 0),
    (2, 16, 0, 1, 8, 0, 1),
    (3, 16, 0, 1, 8, 8, 0),
    (4, 16, 0, 1, 8, 0, 1),
    (5, 16, 0, 1, 8, 8, 0),
    (6, 16, 0, 1, 8, 0, 1),
    (7, 16, 0, 1, 8, 8, 0),
    (8, 16, 0, 1, 8, 0, 1),
    (9, 16, 0, 1, 8, 8, 0),
    (10, 16, 0, 1, 8, 0, 1),
    (11, 16, 0, 1, 8, 8, 0),
    (12, 16, 0, 1, 8, 0, 1),
    (13, 16, 0, 1, 8, 8, 0),
    (14, 16, 0, 1, 8, 0, 1),
    (15, 16, 0, 1, 8, 8, 0),
    (16, 16, 0, 1, 8, 0, 1),
];

#[test]
fn dda_reproduces_table_t8_1_1_every_clock() {
    let run = dda::linear(4, &[16, 8]).unwrap();
    assert_eq!(run.clocks.len(), 16);
    for (clock, row) in run.clocks.iter().zip(T8_1_1) {
        let (x, y) = (clock.axes[0], clock.axes[1]);
        let got = (clock.number, x.p, x.q, u64::from(x.pulse), y.p, y.q, u64::from(y.pulse));
        assert_eq!(got, row, "clock {}", row.0);
    }
    // The paper's sums: 16 pulses on X, 8 on Y, both arriving at K after the 16th clock.
    assert_eq!(run.pulses(), vec![16, 8]);
}

#[test]
fn nc_dda_prints_table_t8_1_1() {
    let out = Command::new(env!("CARGO_BIN_EXE_ncsheet"))
        .args(["nc", "dda", "--bits", "4", "--dx", "16", "--dy", "8"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split_whitespace().collect()).collect();
    // The paper writes an overflow as `16-16=0` and a sum below 2ⁿ as the sum kept in q.
    let q = |q_after: u64, pulse: u64, p: u64| {
        if pulse == 1 {
            format!("{}-16={q_after}", q_after + 16)
        } else {
            assert!(q_after < 16 && q_after >= p);
            q_after.to_string()
        }
    };
    for (clock, xp, xq, xd, yp, yq, yd) in T8_1_1 {
        let row = rows.iter().find(|r| r.first() == Some(&clock.to_string().as_str())).expect("clock row");
        let want = [
            clock.to_string(),
            xp.to_string(),
            q(xq, xd, xp),
            xd.to_string(),
            yp.to_string(),
            q(yq, yd, yp),
            yd.to_string(),
        ];
        assert_eq!(row.iter().map(|s| s.to_string()).collect::<Vec<_>>(), want, "clock {clock}");
    }
    assert_eq!(rows.last().unwrap(), &vec!["pulses", "16", "8"]);
}

#[test]
fn nc_dda_takes_millimetres_at_the_machine_increment() {
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_ncsheet")).args(args).output().unwrap();
    let mm = run(&["nc", "dda", "--increment", "0.001", "--dx", "0.016", "--dy", "0.008"]);
    let counts = run(&["nc", "dda", "--dx", "16", "--dy", "8"]);
    assert!(mm.status.success(), "{}", String::from_utf8_lossy(&mm.stderr));
    assert_eq!(mm.stdout, counts.stdout);
    let off_grid = run(&["nc", "dda", "--increment", "0.001", "--dx", "0.0165"]);
    assert_eq!(off_grid.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&off_grid.stderr).contains("--dx"));
}
