//! Where an output's bytes go. A regular file (or a name not yet taken) is written under a
//! temporary name beside it and renamed over it, so an interrupted run never leaves half a file;
//! anything else (a device, a named pipe, a socket) is written in place, because renaming over
//! it would replace the node itself; symlinks are followed to the file they name; `-` is
//! standard output. Every failed write is an error naming the path.

use crate::error::{Error, Result};
use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Symlink hops followed before giving up (Linux's own limit, MAXSYMLINKS, is 40).
const MAX_SYMLINK_HOPS: u32 = 40;

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// `-`.
    Stdout,
    /// A regular file, existing or to be created: written beside it, then renamed over it.
    Replace(PathBuf),
    /// An existing node that is not a regular file: opened and written where it is.
    InPlace(PathBuf),
}

/// True for the name that means standard output.
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

impl Target {
    /// Classifies `path`, following symlinks (relative ones from their own folder).
    pub fn of(path: &Path) -> Result<Target> {
        if is_stdout(path) {
            return Ok(Target::Stdout);
        }
        let mut current = path.to_owned();
        for _ in 0..MAX_SYMLINK_HOPS {
            current = with_real_parent(current);
            match fs::symlink_metadata(&current) {
                // /dev/stdout, /dev/fd/N: a link to an open file, pipe or terminal that only the
                // kernel can follow (its text reads "pipe:[...]"); open it where it is.
                Ok(meta) if meta.file_type().is_symlink() && current.starts_with("/proc") => {
                    return Ok(Target::InPlace(path.to_owned()));
                }
                Ok(meta) if meta.file_type().is_symlink() => {
                    let link = fs::read_link(&current).map_err(|e| Error::io(&current, e))?;
                    current = match current.parent() {
                        Some(parent) if link.is_relative() => parent.join(link),
                        _ => link,
                    };
                }
                Ok(meta) if meta.is_file() => return Ok(Target::Replace(current)),
                Ok(meta) if meta.is_dir() => return Err(Error::io(path, "is a directory, not a file")),
                Ok(_) => return Ok(Target::InPlace(current)),
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Target::Replace(current)),
                Err(e) => return Err(Error::io(&current, e)),
            }
        }
        Err(Error::io(path, format!("more than {MAX_SYMLINK_HOPS} symbolic links to follow")))
    }
}

/// The path with its folder's symlinks resolved (/dev/fd/1 is /proc/PID/fd/1), so that each hop
/// is read from where the link really is; unchanged where the folder does not exist.
fn with_real_parent(path: PathBuf) -> PathBuf {
    let real = match (path.parent(), path.file_name()) {
        (Some(parent), Some(name)) if !parent.as_os_str().is_empty() => {
            fs::canonicalize(parent).ok().map(|p| p.join(name))
        }
        _ => None,
    };
    real.unwrap_or(path)
}

/// True for `-`, and for any path that names what standard output is open on (/dev/stdout, or
/// the file the shell redirected it to): status lines must then keep off it.
pub fn names_stdout(path: &Path) -> bool {
    if is_stdout(path) {
        return true;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(ours), Ok(theirs)) = (fs::metadata("/dev/stdout"), fs::metadata(path)) {
            return (ours.dev(), ours.ino()) == (theirs.dev(), theirs.ino());
        }
    }
    false
}

/// Fails, naming the path, where `write` would fail for want of a folder or permission: checked
/// before long work whose result would otherwise be lost.
pub fn check_writable(path: &Path) -> Result<()> {
    match Target::of(path)? {
        Target::Stdout => Ok(()),
        Target::InPlace(node) => OpenOptions::new().append(true).open(&node).map(drop).map_err(|e| Error::io(path, e)),
        Target::Replace(file) => {
            if file.is_file() {
                return OpenOptions::new().append(true).open(&file).map(drop).map_err(|e| Error::io(path, e));
            }
            let mut probe_name = std::ffi::OsString::from(".");
            probe_name.push(file.file_name().ok_or_else(|| Error::io(path, "names no file"))?);
            probe_name.push(format!(".{}.probe", std::process::id()));
            let probe = file.with_file_name(probe_name);
            OpenOptions::new().write(true).create_new(true).open(&probe).map_err(|e| Error::io(path, e))?;
            fs::remove_file(&probe).map_err(|e| Error::io(&probe, e))
        }
    }
}

/// Writes `bytes` to `path` as `Target::of` classifies it.
pub fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    match Target::of(path)? {
        Target::Stdout => {
            let mut out = std::io::stdout().lock();
            out.write_all(bytes).and_then(|()| out.flush()).map_err(|e| Error::io(Path::new("standard output"), e))
        }
        Target::InPlace(node) => in_place(&node, bytes).map_err(|e| Error::io(path, e)),
        Target::Replace(file) => replace(path, &file, bytes),
    }
}

/// Opens an existing node for writing, without creating or truncating it, and writes.
fn in_place(node: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut out = OpenOptions::new().write(true).open(node)?;
    out.write_all(bytes)?;
    out.flush()
}

/// Writes `.NAME.PID.partial` beside `file`, flushes it to disk, keeps the old file's
/// permissions, and renames it over `file`; on failure the partial file is removed. Where the
/// folder does not let us create the partial file but the file itself is writable, the file is
/// rewritten in place (not atomic, but what was asked).
fn replace(asked: &Path, file: &Path, bytes: &[u8]) -> Result<()> {
    let name = file.file_name().ok_or_else(|| Error::io(asked, "names no file"))?;
    let mut partial_name = std::ffi::OsString::from(".");
    partial_name.push(name);
    partial_name.push(format!(".{}.partial", std::process::id()));
    let partial = file.with_file_name(partial_name);
    let mut out = match OpenOptions::new().write(true).create(true).truncate(true).open(&partial) {
        Ok(out) => out,
        // A writable file in a folder we may not add to: it can only be rewritten where it is.
        Err(e) if e.kind() == std::io::ErrorKind::PermissionDenied && file.is_file() => {
            return OpenOptions::new()
                .write(true)
                .truncate(true)
                .open(file)
                .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
                .map_err(|e| Error::io(asked, e));
        }
        Err(e) => return Err(Error::io(asked, e)),
    };
    let result = (|| {
        out.write_all(bytes)?;
        out.sync_all()?;
        if let Ok(old) = fs::metadata(file) {
            fs::set_permissions(&partial, old.permissions())?;
        }
        fs::rename(&partial, file)
    })();
    result.map_err(|e| {
        let _ = fs::remove_file(&partial);
        Error::io(asked, e)
    })
}

/// Which option took standard output, if any; status lines then go to standard error.
static STDOUT_OWNER: Mutex<Option<String>> = Mutex::new(None);

/// Reserves standard output for the output of `option` when its path names it (`-`,
/// /dev/stdout, ...). A second option asking for it is refused, and so is binary data for a
/// terminal.
pub fn claim_stdout(option: &str, path: &Path, binary: bool) -> Result<()> {
    if !names_stdout(path) {
        return Ok(());
    }
    let mut owner = stdout_owner();
    if let Some(first) = owner.as_deref() {
        return Err(Error::Argument(format!(
            "{first} and {option} both ask for standard output; only one output can go there"
        )));
    }
    if binary && std::io::IsTerminal::is_terminal(&std::io::stdout()) {
        return Err(Error::Argument(format!(
            "{option} - would write binary data to the terminal; redirect standard output or name a file"
        )));
    }
    *owner = Some(option.to_owned());
    Ok(())
}

fn stdout_owner() -> std::sync::MutexGuard<'static, Option<String>> {
    // A panic elsewhere cannot leave the Option half-written: take it as it is.
    STDOUT_OWNER.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// True once an output owns standard output (status lines then go to standard error: `say!`).
pub fn stdout_taken() -> bool {
    stdout_owner().is_some()
}
