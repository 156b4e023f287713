//! `ncsheet repl` driven as a person drives it: in a real terminal (tmux, 80 columns), typing
//! names, `show`, recalling lines with the arrow keys, and reading a table that fits.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// A tmux server of this test's own (its socket in the test's folder).
struct Tmux {
    socket: String,
}

impl Tmux {
    fn run(&self, args: &[&str]) -> String {
        let out = Command::new("tmux").arg("-S").arg(&self.socket).args(args).output().expect("tmux runs");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", "repl"];
        args.extend_from_slice(keys);
        self.run(&args);
    }

    /// The screen, wrapped lines joined, once `ready` holds (or after 20 s).
    fn screen_when(&self, ready: impl Fn(&str) -> bool) -> String {
        let start = Instant::now();
        loop {
            let screen = self.run(&["capture-pane", "-p", "-J", "-t", "repl", "-S", "-200"]);
            if ready(&screen) || start.elapsed() > Duration::from_secs(20) {
                return screen;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux").arg("-S").arg(&self.socket).arg("kill-server").output();
    }
}

fn tmux_available() -> bool {
    let found = Command::new("tmux").arg("-V").output().is_ok();
    assert!(found || std::env::var_os("CI").is_none(), "tmux is missing on CI (.ci/run installs it)");
    found
}

#[test]
fn a_person_uses_names_show_history_and_tables_in_an_80_column_terminal() {
    if !tmux_available() {
        eprintln!("skipped: tmux is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let tmux = Tmux { socket: dir.path().join("tmux.sock").to_str().unwrap().to_string() };
    let book = Path::new(env!("CARGO_MANIFEST_DIR")).join("sheets/chamfer.xlsx");
    let command = format!("{} repl {} --sheet Outer", env!("CARGO_BIN_EXE_ncsheet"), book.display());
    tmux.run(&["new-session", "-d", "-s", "repl", "-x", "80", "-y", "50", &command]);
    let prompts = |n: usize| move |s: &str| s.matches("chamfer.xlsx> ").count() >= n;
    tmux.screen_when(prompts(1));

    // A name where a cell goes: alpha is Outer!B8, 45° on the shipped sheet.
    tmux.keys(&["alpha", "Enter"]);
    let screen = tmux.screen_when(prompts(2));
    assert!(screen.lines().any(|l| l.trim() == "45"), "{screen}");
    tmux.keys(&["alpha=30", "Enter"]);
    tmux.screen_when(prompts(3));
    // XA's cell: its formula and what it reads.
    tmux.keys(&["show G6", "Enter"]);
    let screen = tmux.screen_when(prompts(4));
    assert!(screen.contains("formula  =C21"), "{screen}");
    assert!(screen.contains("reads    C21"), "{screen}");
    // Up three times recalls `alpha`; it now shows 30.
    tmux.keys(&["Up", "Up", "Up"]);
    let screen = tmux.screen_when(|s| s.trim_end().ends_with("> alpha"));
    assert!(screen.trim_end().ends_with("chamfer.xlsx> alpha"), "{screen}");
    tmux.keys(&["Enter"]);
    let screen = tmux.screen_when(prompts(5));
    let after: Vec<&str> = screen.lines().skip_while(|l| !l.ends_with("show G6")).collect();
    let recalled = after.iter().position(|l| l.ends_with("> alpha")).expect("the recalled line");
    assert_eq!(after[recalled + 1].trim(), "30", "{screen}");
    // A wide range as a table that fits the 80 columns (lines joined: none wrapped).
    tmux.keys(&["A1:H12", "Enter"]);
    let screen = tmux.screen_when(prompts(6));
    let table: Vec<&str> = screen.lines().skip_while(|l| !l.ends_with("> A1:H12")).skip(1).collect();
    assert!(table.len() > 12, "{screen}");
    assert!(table.iter().all(|l| l.chars().count() <= 80), "{screen}");
    assert!(table[0].contains('H'), "{screen}");
    tmux.keys(&["quit", "Enter"]);
}
