//! openpyxl, the outside reader and writer of xlsx packages the tests compare with (`.ci/run`
//! installs it).

use std::path::Path;
use std::process::Command;

/// Whether openpyxl can be imported; on CI (`CI` set) it must be: `.ci/run` installs it.
pub fn openpyxl_available() -> bool {
    let found = Command::new("python3").args(["-c", "import openpyxl"]).output().is_ok_and(|o| o.status.success());
    assert!(found || std::env::var_os("CI").is_none(), "openpyxl (pip openpyxl) is missing on CI");
    found
}

/// Runs a Python script with `args`; its standard output.
pub fn python(script: &str, args: &[&Path]) -> String {
    let out = Command::new("python3").arg("-c").arg(script).args(args).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}
