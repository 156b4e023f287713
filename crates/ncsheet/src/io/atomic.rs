//! The one way ncsheet writes a file: a temporary file in the target's folder, filled, flushed
//! to disk, then renamed over the target (atomic on one file system). A reader, or a crash,
//! sees either the old file or the whole new one.
//!
//! The target is respected:
//! - a symbolic link is followed to its file, which is replaced (the link stays a link); a
//!   link to nothing is refused;
//! - anything but a regular file (a directory, a FIFO, a device) is refused;
//! - the new file keeps the old one's mode, and its owner and group where the system lets
//!   us (root can; anyone can keep their own group);
//! - a read-only file is refused unless [`Options::force`];
//! - a file with several hard links is refused unless [`Options::force`]: the rename gives
//!   this name a new file, and the other names would keep the old content.
//!
//! Temporary files are named `.NAME.ncsheet-PID-N.tmp`. A save that is killed leaves its
//! temporary file behind; the next save into that folder removes every such file whose PID
//! is no longer a running process.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// What a save may replace besides an ordinary writable file.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options {
    /// Replace a read-only file, or one with several hard links (breaking the link).
    pub force: bool,
}

/// Writes `path` through `write`: either the whole new content replaces the file, or the old
/// file is left as it was (and no temporary file stays behind).
pub fn write_file(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    write_file_with(path, Options::default(), write)
}

/// [`write_file`] with bytes already computed.
pub fn write_bytes(path: &Path, options: Options, bytes: &[u8]) -> io::Result<()> {
    write_file_with(path, options, |w: &mut dyn Write| w.write_all(bytes))
}

/// [`write_file`] with [`Options`].
pub fn write_file_with(
    path: &Path,
    options: Options,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let target = resolve(path)?;
    let old = existing(&target, options)?;
    let dir = folder_of(&target);
    remove_stale_temporaries(&dir);
    let (tmp_path, file) = create_temp_in(&dir, &target)?;
    let res = fill(file, old.as_ref(), write).and_then(|()| fs::rename(&tmp_path, &target));
    if res.is_err() {
        let _ = fs::remove_file(&tmp_path);
        return res;
    }
    // The rename is durable only once the folder is on disk too.
    if let Ok(d) = File::open(&dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// Whether a save to `path` would be refused (see the module's list), without writing.
pub fn check(path: &Path, options: Options) -> io::Result<()> {
    existing(&resolve(path)?, options).map(|_| ())
}

/// The file a save to `path` replaces: `path` itself, or the file its symbolic link names.
pub fn resolve(path: &Path) -> io::Result<PathBuf> {
    match fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => path.canonicalize().map_err(|e| {
            let to = fs::read_link(path).map(|t| t.display().to_string()).unwrap_or_default();
            refused(format!("is a symbolic link to {to}, which cannot be reached ({e}); nothing was written"))
        }),
        _ => Ok(path.to_path_buf()),
    }
}

/// The metadata of the file being replaced (None for a new file), after the checks.
fn existing(target: &Path, options: Options) -> io::Result<Option<fs::Metadata>> {
    use std::os::unix::fs::{FileTypeExt, MetadataExt};
    let meta = match fs::metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e),
    };
    let t = meta.file_type();
    let special = if t.is_dir() {
        Some("a directory")
    } else if t.is_fifo() {
        Some("a FIFO (named pipe)")
    } else if t.is_char_device() || t.is_block_device() {
        Some("a device")
    } else if t.is_socket() {
        Some("a socket")
    } else if !t.is_file() {
        Some("not a regular file")
    } else {
        None
    };
    if let Some(what) = special {
        return Err(refused(format!("is {what}; ncsheet only replaces regular files")));
    }
    if !options.force && meta.permissions().readonly() {
        return Err(io::Error::new(
            io::ErrorKind::PermissionDenied,
            "is read-only; nothing was written (--force replaces it, keeping it read-only)",
        ));
    }
    if !options.force && meta.nlink() > 1 {
        return Err(refused(format!(
            "has {} hard links; replacing it would leave the other names with the old content, so nothing \
             was written (--force replaces this name only)",
            meta.nlink()
        )));
    }
    Ok(Some(meta))
}

fn refused(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

fn fill(
    file: File,
    old: Option<&fs::Metadata>,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    if let Some(meta) = old {
        keep_owner_and_mode(&file, meta)?;
    }
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    let file = out.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()
}

/// Gives the new file the old one's owner, group and mode. Changing the owner needs root
/// and changing the group needs membership: each is tried alone and kept if refused.
fn keep_owner_and_mode(file: &File, meta: &fs::Metadata) -> io::Result<()> {
    use std::os::unix::fs::{fchown, MetadataExt};
    let _ = fchown(file, Some(meta.uid()), Some(meta.gid())).or_else(|_| fchown(file, None, Some(meta.gid())));
    file.set_permissions(meta.permissions())
}

fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

const TEMP_MARK: &str = ".ncsheet-";

/// The PID in a temporary file's name `.NAME.ncsheet-PID-N.tmp`, if it is one.
fn temp_owner(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (_, tail) = rest.rsplit_once(TEMP_MARK)?;
    let (pid, n) = tail.split_once('-')?;
    n.parse::<u32>().ok()?;
    pid.parse().ok()
}

/// Removes the temporary files of saves whose process is gone (killed mid-save).
fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(temp_owner) else { continue };
        let alive = pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists();
        if !alive && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// A new file `.NAME.ncsheet-PID-N.tmp` in `dir`.
fn create_temp_in(dir: &Path, target: &Path) -> io::Result<(PathBuf, File)> {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let name = target.file_name().map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    loop {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(".{name}{TEMP_MARK}{}-{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// An in-place edit's hold on its file, from before it is read until its save is renamed
/// over it: an exclusive advisory lock (`flock`) that other ncsheet edits of the file wait
/// for, and the file's identity, size, modification time and content hash as read, so that a
/// program that does not lock (an editor, a sync tool) changing it meanwhile is noticed before
/// the save replaces its work. Without it, concurrent edits each report "saved" and all but
/// the last rename are lost. Dropping it releases the lock.
pub struct EditLock {
    _file: File,
    /// The name the edit saves to: a symbolic link is followed again at the save, so the
    /// check reads the file the name leads to then, not only the one locked.
    path: PathBuf,
    stamp: Stamp,
}

/// What identifies one state of a file: which file (device, inode) and its content.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    dev: u64,
    ino: u64,
    len: u64,
    modified_ns: i128,
    hash: u64,
}

impl EditLock {
    /// Locks the file `path` names (a symbolic link's file), waiting for another edit of it
    /// to finish. A save renames a new file over the old one, so a lock won on a file the
    /// name no longer points to is dropped and taken again on the current one.
    pub fn acquire(path: &Path) -> io::Result<EditLock> {
        use std::os::unix::fs::MetadataExt;
        use std::os::unix::io::AsRawFd;
        let target = resolve(path)?;
        loop {
            let file = File::open(&target)?;
            // SAFETY: flock on a descriptor this function owns; it blocks until granted.
            while unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) } != 0 {
                let e = io::Error::last_os_error();
                if e.kind() != io::ErrorKind::Interrupted {
                    return Err(e);
                }
            }
            let held = file.metadata()?;
            let named = fs::metadata(&target)?;
            if held.dev() == named.dev() && held.ino() == named.ino() {
                let stamp = stamp_of(&target)?;
                return Ok(EditLock { _file: file, path: path.to_path_buf(), stamp });
            }
        }
    }

    /// Whether the file is still as it was when the lock was taken; an error saying so if not.
    pub fn unchanged(&self) -> io::Result<()> {
        self.still(&self.stamp, ": run the edit again")
    }

    /// Whether the file is still as it was in `read`, taken when a program that cannot hold
    /// the lock that long (the workbench, open for hours) read it; an error saying so if not.
    pub fn unchanged_since(&self, read: &ReadState) -> io::Result<()> {
        self.still(&read.0, "")
    }

    /// Whether the file the name leads to now is still in the state `then`; an error ending
    /// in `advice` if not. A link pointed at another file meanwhile is a change: the save would
    /// replace that other file, a workbook this edit never read.
    fn still(&self, then: &Stamp, advice: &str) -> io::Result<()> {
        match resolve(&self.path).and_then(|target| stamp_of(&target)) {
            Ok(now) if now == *then => Ok(()),
            _ => Err(io::Error::other(format!(
                "changed since ncsheet read it (another program saved it, or pointed its link elsewhere, meanwhile); nothing was written, \
                 so that program's work is kept{advice}"
            ))),
        }
    }
}

/// A file's state as a program read it (which file, its size, modification time and a hash of
/// its bytes), to check under an [`EditLock`] at a later save over it that no other program
/// saved it meanwhile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadState(Stamp);

impl ReadState {
    /// The state of the file `path` names (a symbolic link's file) now.
    pub fn of(path: &Path) -> io::Result<ReadState> {
        stamp_of(&resolve(path)?).map(ReadState)
    }
}

/// The file's identity and a hash of its bytes, read in blocks.
fn stamp_of(path: &Path) -> io::Result<Stamp> {
    use std::hash::Hasher;
    use std::io::Read;
    use std::os::unix::fs::MetadataExt;
    let mut file = File::open(path)?;
    let meta = file.metadata()?;
    let mut hasher = std::hash::DefaultHasher::new();
    let mut block = vec![0u8; 1 << 16];
    loop {
        let n = match file.read(&mut block) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        hasher.write(&block[..n]);
    }
    Ok(Stamp {
        dev: meta.dev(),
        ino: meta.ino(),
        len: meta.len(),
        modified_ns: i128::from(meta.mtime()) * 1_000_000_000 + i128::from(meta.mtime_nsec()),
        hash: hasher.finish(),
    })
}

/// A scratch file for a library that only reads from a path (rust_xlsxwriter's VBA
/// project), named and cleaned up like the save's own temporary files; removed on drop.
pub struct Scratch(PathBuf);

impl Scratch {
    /// Writes `bytes` to a new temporary file beside `target`.
    pub fn beside(target: &Path, bytes: &[u8]) -> io::Result<Scratch> {
        let dir = folder_of(target);
        remove_stale_temporaries(&dir);
        let (path, mut file) = create_temp_in(&dir, target)?;
        let scratch = Scratch(path);
        file.write_all(bytes)?;
        Ok(scratch)
    }

    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::{symlink, PermissionsExt};

    fn leftovers(dir: &Path) -> Vec<String> {
        fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".tmp"))
            .collect()
    }

    fn put(path: &Path, text: &str) -> io::Result<()> {
        write_file(path, |w: &mut dyn Write| w.write_all(text.as_bytes()))
    }

    #[test]
    fn replaces_the_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        fs::write(&path, "old").unwrap();
        put(&path, "new").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_failed_write_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.csv");
        fs::write(&path, "old").unwrap();
        let res = write_file(&path, |w: &mut dyn Write| {
            w.write_all(b"half")?;
            Err(io::Error::other("disk full"))
        });
        assert!(res.is_err());
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_symlink_is_followed_and_stays_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        let link = dir.path().join("link.csv");
        fs::write(&real, "old").unwrap();
        symlink(&real, &link).unwrap();
        put(&link, "new").unwrap();
        assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(fs::read_to_string(&real).unwrap(), "new");
        let dangling = dir.path().join("dangling.csv");
        symlink(dir.path().join("nowhere/x.csv"), &dangling).unwrap();
        let err = put(&dangling, "x").unwrap_err();
        assert!(err.to_string().contains("symbolic link"), "{err}");
    }

    #[test]
    fn special_files_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let err = put(dir.path(), "x").unwrap_err();
        assert!(err.to_string().contains("directory"), "{err}");
        let err = put(Path::new("/dev/null"), "x").unwrap_err();
        assert!(err.to_string().contains("device"), "{err}");
        let fifo = dir.path().join("fifo");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let err = put(&fifo, "x").unwrap_err();
        assert!(err.to_string().contains("FIFO"), "{err}");
        assert!(!fs::metadata(&fifo).unwrap().file_type().is_file());
    }

    #[test]
    fn read_only_and_hard_linked_files_need_force_and_keep_their_mode() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ro.csv");
        fs::write(&path, "old").unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o444)).unwrap();
        assert!(put(&path, "new").unwrap_err().to_string().contains("read-only"));
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
        write_bytes(&path, Options { force: true }, b"new").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(fs::metadata(&path).unwrap().permissions().mode() & 0o777, 0o444);

        let a = dir.path().join("a.csv");
        let b = dir.path().join("b.csv");
        fs::write(&a, "old").unwrap();
        fs::hard_link(&a, &b).unwrap();
        assert!(put(&a, "new").unwrap_err().to_string().contains("hard links"));
        assert_eq!(fs::read_to_string(&b).unwrap(), "old");
    }

    #[test]
    fn an_edit_lock_notices_a_file_changed_since_it_was_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("book.csv");
        put(&path, "1,2\n").unwrap();
        let lock = EditLock::acquire(&path).unwrap();
        assert!(lock.unchanged().is_ok());
        // Another program rewrites it in place, same size: the content hash tells.
        fs::write(&path, "3,4\n").unwrap();
        let e = lock.unchanged().unwrap_err();
        assert!(e.to_string().contains("changed since ncsheet read it"), "{e}");
        drop(lock);
        // Or renames a new file over it (an editor's save): another file now.
        let lock = EditLock::acquire(&path).unwrap();
        write_bytes(&path, Options::default(), b"3,4\n").unwrap();
        assert!(lock.unchanged().is_err());
    }

    #[test]
    fn an_edit_lock_notices_a_link_pointed_at_another_file_since_it_was_read() {
        // `ln -sfn other.csv link.csv` while `set link.csv --in-place` computes: the save
        // follows the link again and would replace other.csv, unread, with book.csv's cells.
        let dir = tempfile::tempdir().unwrap();
        let (book, other, link) =
            (dir.path().join("book.csv"), dir.path().join("other.csv"), dir.path().join("link.csv"));
        put(&book, "1,2\n").unwrap();
        put(&other, "3,4\n").unwrap();
        symlink(&book, &link).unwrap();
        let lock = EditLock::acquire(&link).unwrap();
        assert!(lock.unchanged().is_ok());
        fs::remove_file(&link).unwrap();
        symlink(&other, &link).unwrap();
        let e = lock.unchanged().unwrap_err();
        assert!(e.to_string().contains("changed since ncsheet read it"), "{e}");
        drop(lock);
        // A plain file replaced by a link to another file is the same change.
        let lock = EditLock::acquire(&book).unwrap();
        fs::remove_file(&book).unwrap();
        symlink(&other, &book).unwrap();
        assert!(lock.unchanged().is_err());
    }

    #[test]
    fn temporaries_of_dead_processes_are_removed_by_the_next_save() {
        let dir = tempfile::tempdir().unwrap();
        // A process that has exited: its PID is free (until reused, which a test cannot see).
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let stale = dir.path().join(format!(".a.csv.ncsheet-{dead}-0.tmp"));
        let live = dir.path().join(format!(".a.csv.ncsheet-{}-99.tmp", std::process::id()));
        let other = dir.path().join(".notes.tmp");
        for p in [&stale, &live, &other] {
            fs::write(p, "x").unwrap();
        }
        put(&dir.path().join("a.csv"), "new").unwrap();
        assert!(!stale.exists());
        assert!(live.exists() && other.exists());
    }
}
