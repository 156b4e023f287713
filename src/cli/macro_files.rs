//! The files a macro of `ncsheet run` reads and writes: `--out-dir DIR` (the one folder it
//! may write, and read) and `--in-file PATH` (files it may read, by their file names). The
//! library's sandbox (`ncsheet::vba::FileAccess`) never touches a file: this module reads the
//! listed inputs, answers the library's reads of the folder, and turns what the macro wrote
//! into outputs that are written with the others, all or none, only when the macro ran to its
//! end.

use std::path::{Path, PathBuf};
use std::rc::Rc;

use ncsheet::io::Encoded;
use ncsheet::vba::{checked_name, FileAccess, RunOutput};

use super::report::{Error, Result};

/// The sandbox of a run: `None` when neither `--out-dir` nor `--in-file` was given (file
/// statements are then refused by name). `max_bytes` bounds one file read (the macro's
/// memory limit).
pub(super) fn access(out_dir: Option<&Path>, in_files: &[PathBuf], max_bytes: u64) -> Result<Option<FileAccess>> {
    if out_dir.is_none() && in_files.is_empty() {
        return Ok(None);
    }
    if let Some(dir) = out_dir {
        match std::fs::metadata(dir) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => return Err(Error::Usage(format!("--out-dir {}: not a folder", dir.display()))),
            Err(e) => return Err(Error::Usage(format!("--out-dir {}: {e} (the folder must exist)", dir.display()))),
        }
    }
    let mut inputs: Vec<(String, Rc<[u8]>)> = Vec::new();
    for path in in_files {
        let name = input_name(path)?;
        if inputs.iter().any(|(n, _)| n.eq_ignore_ascii_case(&name)) {
            return Err(Error::Usage(format!(
                "--in-file {}: another --in-file is named {name} too (a macro opens each by its file name)",
                path.display()
            )));
        }
        inputs.push((name, read_limited(path, max_bytes).map_err(|m| Error::User(format!("--in-file {m}")))?.into()));
    }
    let folder = out_dir.map(Path::to_path_buf);
    let read_out_dir = move |name: &str| match &folder {
        Some(dir) => read_in_folder(&dir.join(name), max_bytes),
        None => Ok(None),
    };
    let folder = out_dir.map(Path::to_path_buf);
    let list_out_dir = move || match &folder {
        Some(dir) => plain_files(dir),
        None => Ok(Vec::new()),
    };
    let folder = out_dir.map(Path::to_path_buf);
    let modified_out_dir = move |name: &str| match &folder {
        Some(dir) => modified_in_folder(&dir.join(name)),
        None => Ok(None),
    };
    Ok(Some(FileAccess {
        out_dir: out_dir.map(|d| d.display().to_string()),
        inputs,
        read_out_dir: Rc::new(read_out_dir),
        list_out_dir: Rc::new(list_out_dir),
        modified_out_dir: Rc::new(modified_out_dir),
    }))
}

/// When a file of the output folder was last modified (`FileDateTime`): `None` when there is
/// none; a symbolic link or anything but a plain file is refused, as for reading.
fn modified_in_folder(path: &Path) -> std::result::Result<Option<std::time::SystemTime>, String> {
    match folder_entry(path)? {
        None => Ok(None),
        Some(m) if !m.is_file() => Err(format!("{}: not a plain file", path.display())),
        Some(m) => m.modified().map(Some).map_err(|e| format!("{}: {e}", path.display())),
    }
}

/// What the output folder holds at `path`, not following a link: `None` when nothing; a
/// symbolic link (which could point anywhere) is refused.
fn folder_entry(path: &Path) -> std::result::Result<Option<std::fs::Metadata>, String> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
        Ok(m) if m.file_type().is_symlink() => Err(format!(
            "{} is a symbolic link, which could lead out of --out-dir: a macro reads only the folder's own files",
            path.display()
        )),
        Ok(m) => Ok(Some(m)),
    }
}

/// The name a macro opens a listed input by: its file name, a plain name of the sandbox.
fn input_name(path: &Path) -> Result<String> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    match checked_name(name) {
        None => Ok(name.to_string()),
        Some(why) => Err(Error::Usage(format!(
            "--in-file {}: a macro opens a listed file by its file name, and this one cannot be one ({why})",
            path.display()
        ))),
    }
}

/// A file's bytes, refused past `max_bytes` before anything is read.
fn read_limited(path: &Path, max_bytes: u64) -> std::result::Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if !meta.is_file() {
        return Err(format!("{}: not a plain file", path.display()));
    }
    if meta.len() > max_bytes {
        return Err(format!(
            "{}: {} bytes, more than the macro's memory limit of {max_bytes} bytes (--max-memory)",
            path.display(),
            meta.len()
        ));
    }
    std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// A file of the output folder: `None` when there is none; a symbolic link (which could
/// point anywhere) or anything but a plain file is refused.
fn read_in_folder(path: &Path, max_bytes: u64) -> std::result::Result<Option<Vec<u8>>, String> {
    folder_entry(path)?.map(|_| read_limited(path, max_bytes)).transpose()
}

/// The names of a folder's plain files that a macro could name (for `Dir` and `Kill` with
/// wildcards): no folder, no symbolic link, no name the sandbox refuses.
fn plain_files(dir: &Path) -> std::result::Result<Vec<String>, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut names = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| format!("{}: {e}", dir.display()))?;
        let plain = entry.file_type().is_ok_and(|t| t.is_file());
        if let (true, Some(name)) = (plain, entry.file_name().to_str()) {
            if checked_name(name).is_none() {
                names.push(name.to_string());
            }
        }
    }
    Ok(names)
}

/// Removes the files of `out_dir` the macro deleted (`Kill`), once its outputs are written;
/// returns what a run says of each. A symbolic link there is removed itself, never what it
/// points to.
pub(super) fn remove_killed(out_dir: Option<&Path>, out: &RunOutput) -> Result<Vec<String>> {
    let mut said = Vec::new();
    for name in &out.removed {
        let (Some(dir), None) = (out_dir, checked_name(name)) else {
            return Err(Error::User(format!("the macro deleted {name:?}, which is no file of --out-dir")));
        };
        let path = dir.join(name);
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.is_dir() => {
                return Err(Error::User(format!("{}: a folder, which a macro's Kill does not remove", path.display())))
            }
            Ok(_) => std::fs::remove_file(&path).map_err(|e| Error::User(format!("{}: {e}", path.display())))?,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
            Err(e) => return Err(Error::User(format!("{}: {e}", path.display()))),
        }
        said.push(format!("removed {}, by the macro's Kill", path.display()));
    }
    Ok(said)
}

/// What the macro wrote, as outputs to write with the program and the saved workbook: each
/// a plain file of `out_dir`, never a symbolic link there (which would write elsewhere).
pub(super) fn outputs(out_dir: Option<&Path>, out: &RunOutput) -> Result<Vec<Encoded>> {
    let mut files = Vec::new();
    for (name, bytes) in &out.files {
        let (Some(dir), None) = (out_dir, checked_name(name)) else {
            return Err(Error::User(format!("the macro wrote {name:?}, which is no file of --out-dir")));
        };
        let path = dir.join(name);
        if std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(Error::User(format!(
                "{}: a symbolic link, which would write the macro's file outside --out-dir; nothing was written",
                path.display()
            )));
        }
        files.push(Encoded::new(&path, bytes.clone()));
    }
    Ok(files)
}

/// What a run says about the macro's files once written.
pub(super) fn written(files: &[Encoded]) -> Vec<String> {
    files.iter().map(|f| format!("wrote {}: {} bytes, from the macro", f.path.display(), f.bytes().len())).collect()
}

/// Said when the macro stopped: the files it had written stay unwritten.
pub(super) fn not_written(out: &RunOutput) -> Option<String> {
    if out.files.is_empty() {
        return None;
    }
    // A macro may write 200,000 files: the note names the first few and counts the rest.
    const NAMED: usize = 10;
    let names: Vec<&str> = out.files.iter().take(NAMED).map(|(n, _)| n.as_str()).collect();
    let more = match out.files.len().saturating_sub(NAMED) {
        0 => String::new(),
        n => format!(" and {n} more"),
    };
    Some(format!("note: the macro did not run to its end, so its files were not written: {}{more}", names.join(", ")))
}
