//! The built `ncsheet` binary run as a user runs it: arguments, a folder, standard input,
//! and what it answered (exit code, stdout, stderr).

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

/// What one run of `ncsheet` gave back.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// How to run it: where, with what on stdin, and under which memory cap.
#[derive(Clone, Copy, Default)]
pub struct Invocation<'a> {
    /// The working folder (default: the test's).
    pub dir: Option<&'a Path>,
    pub stdin: &'a str,
    /// An address-space cap in KiB (`ulimit -v`), for input built to exhaust memory.
    pub memory_kib: Option<u64>,
}

/// `ncsheet ARGS` in the test's folder with nothing on stdin.
pub fn ncsheet(args: &[&str]) -> Run {
    Invocation::default().run(args)
}

impl Invocation<'_> {
    /// Runs `ncsheet ARGS`; a run killed by a signal (a crash) fails the test.
    pub fn run(&self, args: &[&str]) -> Run {
        let binary = env!("CARGO_BIN_EXE_ncsheet");
        let mut command = match self.memory_kib {
            Some(kib) => {
                // `sh -c 'ulimit -v N; exec "$0" "$@"' ncsheet ARGS`: the arguments pass untouched.
                let mut sh = Command::new("sh");
                sh.arg("-c").arg(format!("ulimit -v {kib}; exec \"$0\" \"$@\"")).arg(binary);
                sh
            }
            None => Command::new(binary),
        };
        command.args(args).stdin(Stdio::piped()).stdout(Stdio::piped()).stderr(Stdio::piped());
        if let Some(dir) = self.dir {
            command.current_dir(dir);
        }
        let mut child = command.spawn().expect("the ncsheet binary runs");
        // A command that exits before reading its input closes the pipe: not a failure here.
        let _ = child.stdin.take().expect("piped stdin").write_all(self.stdin.as_bytes());
        let out = child.wait_with_output().expect("ncsheet finishes");
        Run {
            code: out.status.code().unwrap_or_else(|| panic!("ncsheet was killed by a signal: {:?}", out.status)),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        }
    }
}

/// `ncsheet ballpath` over the bump of docs/ballpath.md (`sheets/eqcam-bump.h`): the
/// surface, ball and area the tests share, with the sampling and gouge handling each needs.
pub fn bump_ballpath(stepover: &str, step: &str, gouge: &str) -> Vec<String> {
    [
        "ballpath",
        "--surface",
        "15*EXP(-16*((x/50)^2+(y/50)^2))",
        "--radius",
        "3",
        "--x=-25:25",
        "--y=-25:25",
        "--stepover",
        stepover,
        "--step",
        step,
        "--gouge",
        gouge,
    ]
    .map(String::from)
    .to_vec()
}

/// `ncsheet run` of the paper's macro on the paper's workbook (`sheets/chamfer.bas` on
/// `sheets/chamfer.xlsx`, sheet Outer: docs/domain.md §1's outer chamfer) in `dialect` to `out`.
pub fn outer_chamfer(dialect: &str, out: &str) -> Vec<String> {
    let sheet = |name: &str| format!("{}/sheets/{name}", env!("CARGO_MANIFEST_DIR"));
    let words = ["--sheet", "Outer", "--dialect", dialect, "-o", out].map(String::from);
    ["run".to_string(), sheet("chamfer.xlsx"), sheet("chamfer.bas")].into_iter().chain(words).collect()
}
