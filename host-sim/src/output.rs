//! Output files that never destroy a user's data.
//!
//! Every file a command writes (`--csv FILE`, `--plot DIR`, ...) goes through this
//! module, in four steps:
//!
//! 1. **plan**, before any simulation runs: [`Plan::file`] and [`Plan::dir`] check each
//!    output (its directory exists and is writable, it is not a directory where a file
//!    is expected, an existing file is only replaced with `--force`, no two outputs name
//!    the same file) and [`FileTarget::limit`] refuses an output whose estimated size is
//!    over a limit. Planning touches no file, so a refused option leaves everything as it was.
//! 2. **open**: [`FileTarget::open`] creates a hidden temporary file in the target's own
//!    directory (`.NAME.camsim-HOST-PID-N.tmp`) and returns an [`AtomicFile`], a buffered
//!    [`Write`]r. [`DirTarget::open`] returns an [`AtomicDir`] whose [`AtomicDir::path`]
//!    gives a temporary of the same form inside DIR for each declared file.
//! 3. **write** while the simulation runs.
//! 4. **commit**: [`AtomicFile::commit`] flushes, fsyncs and renames the temporary over
//!    the target, so the target is either its old self or the complete new file.
//!    Dropped without a commit (an error returned with `?`, a panic unwinding) the
//!    temporary is removed and the target is untouched. On SIGINT, SIGTERM, SIGHUP,
//!    SIGQUIT or SIGXCPU the temporaries of every live output are removed and the
//!    process exits with 128 + the signal number; a write over the file size limit
//!    (SIGXFSZ, `ulimit -f`) fails with an error that names the output, and its
//!    temporary is removed. Temporaries of processes that died uncatchably (SIGKILL) are
//!    removed by the next output created in the same directory on the same machine.
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! use std::io::Write;
//! use camsim::output::Plan;
//! # let (force, csv_path, est, limit) = (false, std::path::PathBuf::from("out.csv"), 1u64, 2u64);
//! let mut plan = Plan::new(force);
//! let csv = plan.file("--csv", &csv_path)?.limit(est, limit, "--max-csv-bytes N")?;
//! // ... every other option checked, still nothing touched ...
//! let mut out = csv.open()?;
//! writeln!(out, "t_s,y_in")?; // ... the run ...
//! out.commit()?;
//! # Ok(()) }
//! ```
//!
//! A directory output (`--plot DIR`) declares the names of the files it will write.
//! Each file is written under a temporary name inside DIR and renamed to its own name
//! at commit, so DIR never holds a partial file; a DIR that did not exist is created
//! when the output opens and removed again (only if still empty) when it is dropped
//! without a commit. Temporaries inside DIR rather than a temporary sibling directory:
//! the temporary is always on DIR's file system (rename stays atomic), and DIR's parent
//! need not be writable (`--plot .`, `--plot ~`, `--plot /tmp` all work).
//!
//! A target that is not a regular file (a block or character device, a FIFO, a socket,
//! also behind a symbolic link) is refused: written in place it would overwrite a disk
//! image or hang on a FIFO with no reader. Two are allowed explicitly and written in
//! place, never truncated: `/dev/null`, and the process's own streams (`/dev/stdout`,
//! `/dev/stderr`, `/dev/fd/N`, which may be a shell redirection to a regular file).

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::fmt;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, OnceLock};

use anyhow::{anyhow, bail, Context, Result};

/// The option that allows replacing existing files, as named in the messages.
pub const FORCE_OPTION: &str = "--force";

// ---------------------------------------------------------------------------------------
// Planning
// ---------------------------------------------------------------------------------------

/// What the outputs of one command claim, checked before any of them is opened.
#[derive(Debug)]
pub struct Plan {
    force: bool,
    claims: Vec<Claim>,
    /// The command's input files (option and path): never replaced by an output.
    inputs: Vec<(String, PathBuf)>,
}

/// One path an output will write.
#[derive(Debug)]
struct Claim {
    /// The option and path as the user wrote them, for messages.
    label: String,
    /// The resolved path (existing directories canonical).
    path: PathBuf,
    /// A directory output's directory (several outputs may share one).
    is_dir: bool,
}

impl Plan {
    /// A plan for one command; `force` allows replacing existing files.
    pub fn new(force: bool) -> Self {
        Self {
            force,
            claims: Vec::new(),
            inputs: Vec::new(),
        }
    }

    /// Declares an input file of the command (`--scene FILE`, `--measured FILE`): no
    /// output of this plan may replace it, even with force. Declare the inputs before
    /// the outputs.
    pub fn input(&mut self, option: &str, path: &Path) -> &mut Self {
        self.inputs
            .push((format!("{option} {}", path.display()), path.to_owned()));
        self
    }

    /// Refuses an output target that is one of the declared inputs (the same file by
    /// device and inode, however spelled or linked).
    fn not_an_input(&self, label: &str, target: &Path) -> Result<()> {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            let Ok(t) = fs::metadata(target) else {
                return Ok(());
            };
            for (input, path) in &self.inputs {
                if let Ok(m) = fs::metadata(path) {
                    if (m.dev(), m.ino()) == (t.dev(), t.ino()) {
                        bail!("{label}: is the input {input}: an output never replaces an input, even with {FORCE_OPTION}");
                    }
                }
            }
        }
        Ok(())
    }

    /// Checks a file output (`option` as the command line names it, e.g. `"--csv"`).
    ///
    /// Refuses, with one line naming the option and the path: a path without a file
    /// name, a directory, anything but a regular file (a device, a FIFO, a socket, also
    /// through a symbolic link: writing in place would destroy a disk image or hang on a
    /// FIFO), an existing file without force, one of the command's inputs, a missing or
    /// unwritable parent directory, a dangling symbolic link, a path another output of
    /// this plan already writes. A symbolic link to a file is followed: the file it
    /// points to is replaced and the link kept. Two non-files are allowed explicitly,
    /// written in place: the process's own streams (`/dev/stdout`, `/dev/stderr`,
    /// `/dev/fd/N`) and `/dev/null`.
    pub fn file(&mut self, option: &str, path: &Path) -> Result<FileTarget> {
        let label = format!("{option} {}", path.display());
        if is_direct_path(path) {
            // The process's own streams: written in place, never renamed over.
            return Ok(FileTarget {
                label,
                target: path.to_owned(),
                force: self.force,
                direct: true,
                limit: None,
            });
        }
        let target = resolve(path).map_err(|e| anyhow!("{label}: {e}"))?;
        self.claim(&label, &target, false)?;
        self.not_an_input(&label, &target)?;
        let direct = match fs::metadata(&target) {
            Ok(m) if m.is_dir() => bail!("{label}: is a directory"),
            Ok(m) if !m.is_file() && is_null_device(&target, &m) => true,
            Ok(m) if !m.is_file() => bail!(
                "{label}: is {}, not a regular file: outputs go to a regular file or a new name (/dev/stdout and /dev/null are allowed)",
                file_kind(&m)
            ),
            Ok(_) if !self.force => bail!("{label}: exists (use {FORCE_OPTION} to overwrite)"),
            Ok(_) => false,
            Err(e) if absent(&e) => false,
            Err(e) => bail!("{label}: cannot inspect: {e}"),
        };
        if !direct {
            writable_dir(&label, parent_of(&target))?;
        }
        Ok(FileTarget {
            label,
            target,
            force: self.force,
            direct,
            limit: None,
        })
    }

    /// Checks a directory output that will write the files `names` (plain file names)
    /// into `dir`. DIR may be missing (its parent must then exist and be writable: it
    /// is created when the output opens); an existing DIR must be a writable directory
    /// and each of its files that the output would replace needs force.
    pub fn dir(&mut self, option: &str, dir: &Path, names: &[&str]) -> Result<DirTarget> {
        let label = format!("{option} {}", dir.display());
        for name in names {
            let p = Path::new(name);
            if name.is_empty()
                || p.components().count() != 1
                || !matches!(p.components().next(), Some(Component::Normal(_)))
            {
                bail!("{label}: {name:?} is not a plain file name");
            }
        }
        let resolved = resolve(dir).map_err(|e| anyhow!("{label}: {e}"))?;
        self.claim(&label, &resolved, true)?;
        for name in names {
            self.claim(&label, &resolved.join(name), false)?;
            self.not_an_input(
                &format!("{option} {}", dir.join(name).display()),
                &resolved.join(name),
            )?;
        }
        let exists = match fs::metadata(&resolved) {
            Ok(m) if m.is_dir() => true,
            Ok(_) => bail!("{label}: is not a directory"),
            Err(e) if absent(&e) => false,
            Err(e) => bail!("{label}: cannot inspect: {e}"),
        };
        if exists {
            writable_dir(&label, &resolved)?;
            for name in names {
                let f = resolved.join(name);
                match fs::metadata(&f) {
                    Ok(m) if !m.is_file() => {
                        bail!(
                            "{label}: {} is not a regular file",
                            dir.join(name).display()
                        )
                    }
                    Ok(_) if !self.force => bail!(
                        "{label}: {} exists (use {FORCE_OPTION} to overwrite)",
                        dir.join(name).display()
                    ),
                    Ok(_) => {}
                    Err(e) if absent(&e) => {}
                    Err(e) => bail!("{label}: cannot inspect {}: {e}", dir.join(name).display()),
                }
            }
        } else {
            writable_dir(&label, parent_of(&resolved))?;
        }
        Ok(DirTarget {
            label,
            dir: resolved,
            names: names.iter().map(|s| s.to_string()).collect(),
            force: self.force,
        })
    }

    /// Records a claimed path; two outputs may share a directory, nothing else.
    fn claim(&mut self, label: &str, path: &Path, is_dir: bool) -> Result<()> {
        if let Some(c) = self
            .claims
            .iter()
            .find(|c| c.path == path && !(c.is_dir && is_dir))
        {
            bail!("{label}: {} is also written by {}", path.display(), c.label);
        }
        self.claims.push(Claim {
            label: label.to_owned(),
            path: path.to_owned(),
            is_dir,
        });
        Ok(())
    }
}

/// Paths written in place: the process's own streams (whatever they point to).
fn is_direct_path(path: &Path) -> bool {
    path == Path::new("/dev/stdout")
        || path == Path::new("/dev/stderr")
        || ((path.starts_with("/dev/fd") || path.starts_with("/proc/self/fd"))
            && path.file_name().is_some_and(|n| n != "fd"))
}

/// Whether a resolved output path is `/dev/null` (a character device there).
fn is_null_device(target: &Path, m: &fs::Metadata) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        target == Path::new("/dev/null") && m.file_type().is_char_device()
    }
    #[cfg(not(unix))]
    {
        let _ = (target, m);
        false
    }
}

/// What a file that is not a regular file is, for messages ("a block device").
fn file_kind(m: &fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = m.file_type();
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if m.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

/// The directory part of a resolved path ("." for a bare name).
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Follows a symbolic link to its target (a dangling one is refused) and makes an
/// existing parent directory canonical, so that two spellings of one file compare equal.
fn resolve(path: &Path) -> std::result::Result<PathBuf, String> {
    let is_link = fs::symlink_metadata(path)
        .map(|m| m.file_type().is_symlink())
        .unwrap_or(false);
    if is_link {
        return fs::canonicalize(path)
            .map_err(|e| format!("is a symbolic link to a missing file ({e})"));
    }
    let name = match path.file_name() {
        Some(n) => n.to_owned(),
        // "." or ".." or "/": an existing directory, or nothing usable.
        None => return fs::canonicalize(path).map_err(|e| format!("not a file name ({e})")),
    };
    match fs::canonicalize(parent_of(path)) {
        Ok(p) => Ok(p.join(name)),
        // A missing parent is reported by the writability check, with the path as given.
        Err(_) => Ok(path.to_owned()),
    }
}

/// Whether an error inspecting a path means that nothing is there (a missing file, or a
/// file where a directory of the path should be: the parent check names which).
fn absent(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::NotFound | io::ErrorKind::NotADirectory
    )
}

/// Checks that `dir` exists, is a directory and can be written to.
fn writable_dir(label: &str, dir: &Path) -> Result<()> {
    match fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => bail!("{label}: {} is not a directory", dir.display()),
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            bail!("{label}: directory {} does not exist", dir.display())
        }
        Err(e) => bail!("{label}: cannot inspect {}: {e}", dir.display()),
    }
    #[cfg(unix)]
    {
        use nix::unistd::{access, AccessFlags};
        access(dir, AccessFlags::W_OK | AccessFlags::X_OK)
            .map_err(|e| anyhow!("{label}: directory {} is not writable ({e})", dir.display()))?;
    }
    Ok(())
}

/// Sizes for messages: decimal units (1 GB = 10^9 bytes), three significant digits.
pub fn human_bytes(n: u64) -> String {
    const UNITS: [&str; 6] = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut v = n as f64;
    let mut u = 0;
    while v >= 999.5 && u + 1 < UNITS.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{n} B")
    } else if v < 9.995 {
        format!("{v:.2} {}", UNITS[u])
    } else if v < 99.95 {
        format!("{v:.1} {}", UNITS[u])
    } else {
        format!("{v:.0} {}", UNITS[u])
    }
}

/// A size limit on one file output.
#[derive(Debug, Clone)]
struct SizeLimit {
    bytes: u64,
    /// The option that raises the limit, as the messages name it.
    allow: String,
}

/// A checked file output, not yet opened (nothing on disk has changed).
#[derive(Debug)]
pub struct FileTarget {
    label: String,
    target: PathBuf,
    force: bool,
    direct: bool,
    limit: Option<SizeLimit>,
}

impl FileTarget {
    /// The file that a commit writes (symbolic links resolved).
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// Size guard: refuses the output if `estimate` bytes is over `limit`, with one line
    /// naming the option, both sizes and `allow` (the option that raises the limit, e.g.
    /// `"--max-csv-mb N"`). The written bytes are held to the same limit (an estimate
    /// can be wrong): a write past it fails with the same kind of message.
    pub fn limit(mut self, estimate: u64, limit: u64, allow: &str) -> Result<Self> {
        if estimate > limit {
            bail!(
                "{}: would be about {}, over the {} limit (use {allow} to allow it)",
                self.label,
                human_bytes(estimate),
                human_bytes(limit)
            );
        }
        self.limit = Some(SizeLimit {
            bytes: limit,
            allow: allow.to_owned(),
        });
        Ok(self)
    }

    /// Opens the output: creates its temporary next to the target (or, for a device or
    /// FIFO, opens the target itself). The target is checked again: a file that
    /// appeared since the plan is not replaced without force.
    pub fn open(self) -> Result<AtomicFile> {
        let label = self.label;
        if self.direct {
            let f = open_direct(&self.target).with_context(|| format!("{label}: cannot open"))?;
            return Ok(AtomicFile {
                out: Some(BufWriter::new(f)),
                tmp: None,
                target: self.target,
                label,
                force: self.force,
                limit: self.limit,
                written: 0,
            });
        }
        let old = match fs::metadata(&self.target) {
            Ok(m) if !m.is_file() => bail!("{label}: is not a regular file"),
            Ok(_) if !self.force => bail!("{label}: exists (use {FORCE_OPTION} to overwrite)"),
            Ok(m) => Some(m),
            Err(_) => None,
        };
        let (f, tmp) = create_temp(parent_of(&self.target), &self.target)
            .with_context(|| format!("{label}: cannot create a temporary file"))?;
        let out = AtomicFile {
            out: Some(BufWriter::new(f)),
            tmp: Some(tmp),
            target: self.target,
            label,
            force: self.force,
            limit: self.limit,
            written: 0,
        };
        if let (Some(m), Some(tmp)) = (old, &out.tmp) {
            // The replacement keeps the replaced file's owner and group (where this
            // process may give them: root, or a group it belongs to), then its mode
            // (after the owner: a change of owner clears the set-id bits).
            #[cfg(unix)]
            {
                use std::os::unix::fs::MetadataExt;
                let _ = std::os::unix::fs::chown(tmp, Some(m.uid()), None);
                let _ = std::os::unix::fs::chown(tmp, None, Some(m.gid()));
            }
            fs::set_permissions(tmp, m.permissions())
                .with_context(|| format!("{}: cannot set permissions", out.label))?;
        }
        Ok(out)
    }
}

/// Opens a target written in place. Standard output and error are shared with the
/// process (same offset, as a shell redirection expects); nothing is truncated.
fn open_direct(path: &Path) -> io::Result<File> {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        if path == Path::new("/dev/stdout") {
            return Ok(File::from(io::stdout().as_fd().try_clone_to_owned()?));
        }
        if path == Path::new("/dev/stderr") {
            return Ok(File::from(io::stderr().as_fd().try_clone_to_owned()?));
        }
    }
    OpenOptions::new().write(true).open(path)
}

/// A checked directory output, not yet opened.
#[derive(Debug)]
pub struct DirTarget {
    label: String,
    dir: PathBuf,
    names: Vec<String>,
    force: bool,
}

impl DirTarget {
    /// The directory that a commit writes into.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// Opens the output: creates DIR if it is missing (removed again on an abort if it
    /// is still empty). The files' temporaries are created by [`AtomicDir::path`].
    pub fn open(self) -> Result<AtomicDir> {
        let label = self.label;
        let created = match fs::metadata(&self.dir) {
            Ok(m) if m.is_dir() => false,
            Ok(_) => bail!("{label}: is not a directory"),
            Err(_) => {
                create_dir_registered(&self.dir)
                    .with_context(|| format!("{label}: cannot create the directory"))?;
                true
            }
        };
        Ok(AtomicDir {
            label,
            dir: self.dir,
            names: self.names,
            force: self.force,
            created,
            temps: BTreeMap::new(),
            done: false,
        })
    }
}

// ---------------------------------------------------------------------------------------
// Open outputs
// ---------------------------------------------------------------------------------------

/// A file output being written: a buffered writer on a temporary that [`commit`]
/// renames over the target. Dropped without a commit, the temporary is removed.
///
/// Write errors name the option and the path.
///
/// [`commit`]: AtomicFile::commit
pub struct AtomicFile {
    /// Taken by the commit (so that nothing can be written after the flush).
    out: Option<BufWriter<File>>,
    /// `None` for a target written in place (a device, a FIFO).
    tmp: Option<PathBuf>,
    target: PathBuf,
    label: String,
    force: bool,
    limit: Option<SizeLimit>,
    written: u64,
}

impl fmt::Debug for AtomicFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("AtomicFile")
            .field("tmp", &self.tmp)
            .field("target", &self.target)
            .field("written", &self.written)
            .finish()
    }
}

impl AtomicFile {
    /// The temporary being written (`None` for a target written in place).
    pub fn temp_path(&self) -> Option<&Path> {
        self.tmp.as_deref()
    }

    /// The file that the commit writes.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Bytes accepted so far.
    pub fn written(&self) -> u64 {
        self.written
    }

    /// Flushes, fsyncs and renames the temporary over the target (without force, a
    /// target that appeared meanwhile is not replaced: the commit fails and the
    /// temporary is removed). After an interrupt has started the cleanup, fails.
    pub fn commit(mut self) -> Result<()> {
        let label = self.label.clone();
        // Flushed and closed here: no buffered byte can reach the file after the rename.
        let file = match self.out.take() {
            Some(out) => out
                .into_inner()
                .map_err(|e| e.into_error())
                .with_context(|| format!("{label}: write failed"))?,
            None => bail!("{label}: already closed"),
        };
        let Some(tmp) = self.tmp.clone() else {
            return Ok(());
        };
        file.sync_all()
            .with_context(|| format!("{label}: write failed (fsync)"))?;
        drop(file);
        {
            let mut reg = registry();
            if reg.terminating {
                bail!("{label}: interrupted");
            }
            place(&tmp, &self.target, self.force).map_err(|e| anyhow!("{label}: {e}"))?;
            reg.forget(&tmp);
        }
        self.tmp = None;
        sync_dir(parent_of(&self.target));
        Ok(())
    }

    fn io_err(&self, e: io::Error) -> io::Error {
        // EFBIG: the process's file size limit (`ulimit -f`, SIGXFSZ caught).
        let hint = if e.raw_os_error() == Some(27) {
            " (the process's file size limit, ulimit -f)"
        } else {
            ""
        };
        io::Error::new(e.kind(), format!("{}: write failed: {e}{hint}", self.label))
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if let Some(l) = &self.limit {
            if self.written.saturating_add(buf.len() as u64) > l.bytes {
                return Err(io::Error::other(format!(
                    "{}: over the {} limit (use {} to allow it)",
                    self.label,
                    human_bytes(l.bytes),
                    l.allow
                )));
            }
        }
        let n = match self.out.as_mut() {
            Some(out) => out.write(buf),
            None => Err(io::Error::other("closed")),
        }
        .map_err(|e| self.io_err(e))?;
        self.written += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        match self.out.as_mut() {
            Some(out) => out.flush(),
            None => Err(io::Error::other("closed")),
        }
        .map_err(|e| self.io_err(e))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // The buffer is discarded, not flushed: an abandoned output gets no more bytes.
        if let Some(out) = self.out.take() {
            let _ = out.into_parts();
        }
        if let Some(tmp) = self.tmp.take() {
            let mut reg = registry();
            let _ = fs::remove_file(&tmp);
            reg.forget(&tmp);
        }
    }
}

/// A directory output being written: each declared file is written to the temporary
/// that [`AtomicDir::path`] names and renamed to its own name by [`AtomicDir::commit`].
/// Dropped without a commit, the temporaries are removed (and DIR too if this output
/// created it and it is empty).
#[derive(Debug)]
pub struct AtomicDir {
    label: String,
    dir: PathBuf,
    names: Vec<String>,
    force: bool,
    created: bool,
    /// Declared name -> its temporary, once asked for.
    temps: BTreeMap<String, PathBuf>,
    done: bool,
}

impl AtomicDir {
    /// The directory that the commit writes into.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Where to write the declared file `name`: an (empty, already created) temporary
    /// inside DIR, for writers that want a path (plotters, image encoders). The same
    /// name gives the same path. An undeclared name is an error.
    pub fn path(&mut self, name: &str) -> Result<PathBuf> {
        if let Some(p) = self.temps.get(name) {
            return Ok(p.clone());
        }
        if !self.names.iter().any(|n| n == name) {
            bail!("{}: {name} is not one of the declared files", self.label);
        }
        let (_, tmp) = create_temp(&self.dir, &self.dir.join(name)).with_context(|| {
            format!("{}: cannot create a temporary file for {name}", self.label)
        })?;
        self.temps.insert(name.to_owned(), tmp.clone());
        Ok(tmp)
    }

    /// Writes the whole of the declared file `name`.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.path(name)?;
        fs::write(&p, bytes).with_context(|| format!("{}: cannot write {name}", self.label))
    }

    /// Fsyncs every written file and renames each to its name in DIR. Without force no
    /// file that appeared meanwhile is replaced: all are checked before any is renamed.
    /// Declared files never asked for by [`AtomicDir::path`] are not written.
    pub fn commit(mut self) -> Result<()> {
        let label = self.label.clone();
        for (name, tmp) in &self.temps {
            File::open(tmp)
                .and_then(|f| f.sync_all())
                .with_context(|| format!("{label}: write of {name} failed (fsync)"))?;
        }
        {
            let mut reg = registry();
            if reg.terminating {
                bail!("{label}: interrupted");
            }
            if !self.force {
                for name in self.temps.keys() {
                    if fs::symlink_metadata(self.dir.join(name)).is_ok() {
                        bail!(
                            "{label}: {} exists (use {FORCE_OPTION} to overwrite)",
                            self.dir.join(name).display()
                        );
                    }
                }
            }
            for (name, tmp) in &self.temps {
                place(tmp, &self.dir.join(name), self.force)
                    .map_err(|e| anyhow!("{label}: {name}: {e}"))?;
                reg.forget(tmp);
            }
            if self.created {
                reg.forget(&self.dir);
            }
        }
        self.temps.clear();
        self.done = true;
        sync_dir(&self.dir);
        Ok(())
    }
}

impl Drop for AtomicDir {
    fn drop(&mut self) {
        let mut reg = registry();
        for tmp in self.temps.values() {
            let _ = fs::remove_file(tmp);
            reg.forget(tmp);
        }
        if self.created && !self.done {
            // Only if empty: never anything the user put there meanwhile.
            let _ = fs::remove_dir(&self.dir);
            reg.forget(&self.dir);
        }
    }
}

/// Moves a complete temporary onto `dest`: a rename with force; without, a hard link
/// (which refuses an existing `dest` atomically) then the temporary's removal, or a
/// checked rename where the file system has no hard links.
fn place(tmp: &Path, dest: &Path, force: bool) -> std::result::Result<(), String> {
    if force {
        return fs::rename(tmp, dest).map_err(|e| format!("cannot rename the temporary: {e}"));
    }
    match fs::hard_link(tmp, dest) {
        Ok(()) => {
            let _ = fs::remove_file(tmp);
            Ok(())
        }
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Err(format!(
            "{} appeared during the run (use {FORCE_OPTION} to overwrite)",
            dest.display()
        )),
        Err(_) => {
            if fs::symlink_metadata(dest).is_ok() {
                return Err(format!(
                    "{} appeared during the run (use {FORCE_OPTION} to overwrite)",
                    dest.display()
                ));
            }
            fs::rename(tmp, dest).map_err(|e| format!("cannot rename the temporary: {e}"))
        }
    }
}

/// Makes a rename durable (best effort: some file systems refuse to fsync a directory).
fn sync_dir(dir: &Path) {
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
}

// ---------------------------------------------------------------------------------------
// Live temporaries and the interrupt handler
// ---------------------------------------------------------------------------------------

/// What an interrupt removes.
#[derive(Debug, Clone, PartialEq)]
enum Live {
    /// A temporary file.
    File(PathBuf),
    /// A directory an output created (removed only if empty, after the files).
    Dir(PathBuf),
}

/// Every live temporary of the process; the interrupt handler empties it.
#[derive(Debug, Default)]
struct Registry {
    live: Vec<Live>,
    /// Set by the interrupt handler: no temporary is created or committed afterwards.
    terminating: bool,
}

impl Registry {
    fn forget(&mut self, path: &Path) {
        self.live.retain(|l| match l {
            Live::File(p) | Live::Dir(p) => p != path,
        });
    }

    /// Removes every live temporary, files before directories; returns how many.
    fn clean(&mut self) -> usize {
        let mut n = 0;
        for l in &self.live {
            if let Live::File(p) = l {
                n += usize::from(fs::remove_file(p).is_ok());
            }
        }
        for l in &self.live {
            if let Live::Dir(p) = l {
                n += usize::from(fs::remove_dir(p).is_ok());
            }
        }
        self.live.clear();
        n
    }
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    live: Vec::new(),
    terminating: false,
});

/// Locks the registry (a panic elsewhere while holding it does not disable cleanup).
fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// The temporaries currently registered (files and created directories), for diagnostics.
pub fn live_temporaries() -> Vec<PathBuf> {
    registry()
        .live
        .iter()
        .map(|l| match l {
            Live::File(p) | Live::Dir(p) => p.clone(),
        })
        .collect()
}

/// Distinguishes the temporaries of one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// The hidden temporary name for `target` in `dir`: `.NAME.camsim-HOST-PID-N.tmp`
/// (HOST: this machine's name, so that a run on another machine sharing the directory
/// never takes a live temporary for a stale one).
fn temp_name(dir: &Path, target: &Path, n: u64) -> PathBuf {
    let mut name = OsString::from(".");
    name.push(target.file_name().unwrap_or_else(|| "out".as_ref()));
    name.push(format!(
        ".camsim-{}-{}-{n}.tmp",
        host_tag(),
        std::process::id()
    ));
    dir.join(name)
}

/// This machine's name as the temporaries carry it (letters, digits, `-` and `_`;
/// "host" if it has none).
fn host_tag() -> &'static str {
    static TAG: OnceLock<String> = OnceLock::new();
    TAG.get_or_init(|| {
        let raw = fs::read_to_string("/proc/sys/kernel/hostname")
            .ok()
            .or_else(|| std::env::var("HOSTNAME").ok())
            .unwrap_or_default();
        let tag: String = raw
            .trim()
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .take(64)
            .collect();
        if tag.is_empty() {
            "host".to_owned()
        } else {
            tag
        }
    })
}

/// The host and process id in a temporary's name (`.NAME.camsim-HOST-PID-N.tmp`, or
/// `.NAME.camsim-PID-N.tmp` as earlier versions wrote it: host `None`).
fn temp_owner(name: &str) -> Option<(Option<&str>, u32)> {
    if !is_temp_name(name) {
        return None;
    }
    let rest = name.strip_suffix(".tmp")?;
    let rest = &rest[rest.rfind(".camsim-")? + ".camsim-".len()..];
    let mut parts = rest.rsplitn(3, '-');
    let _n: u64 = parts.next()?.parse().ok()?;
    let pid: u32 = parts.next()?.parse().ok()?;
    Some((parts.next(), pid))
}

/// Whether process `pid` of this machine is alive (a process of another user counts).
fn process_alive(pid: u32) -> bool {
    #[cfg(unix)]
    {
        use nix::errno::Errno;
        let Ok(p) = i32::try_from(pid) else {
            return true;
        };
        if p <= 0 {
            return true;
        }
        !matches!(
            nix::sys::signal::kill(nix::unistd::Pid::from_raw(p), None),
            Err(Errno::ESRCH)
        )
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

/// Removes the stale temporaries in `dir`: regular files named as this module's
/// temporaries, made on this machine by a process that no longer runs (killed by
/// SIGKILL, a power cut). Best effort, returns how many were removed; a file of a live
/// process, of another machine, or that this user may not remove is left alone.
pub fn remove_stale_temporaries(dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let me = std::process::id();
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some((host, pid)) = temp_owner(name) else {
            continue;
        };
        if host.is_some_and(|h| h != host_tag()) || pid == me || process_alive(pid) {
            continue;
        }
        if e.file_type().is_ok_and(|t| t.is_file()) && fs::remove_file(e.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Whether a file name is one of this module's temporaries (any process).
pub fn is_temp_name(name: &str) -> bool {
    name.starts_with('.') && name.ends_with(".tmp") && name.contains(".camsim-")
}

/// Creates and registers a new temporary for `target` in `dir`, under the registry lock
/// so that the interrupt handler sees every temporary that exists.
fn create_temp(dir: &Path, target: &Path) -> io::Result<(File, PathBuf)> {
    install_interrupt_handler()?;
    remove_stale_temporaries(dir);
    let mut reg = registry();
    if reg.terminating {
        return Err(io::Error::new(io::ErrorKind::Interrupted, "interrupted"));
    }
    for _ in 0..100 {
        let p = temp_name(dir, target, COUNTER.fetch_add(1, Ordering::Relaxed));
        match OpenOptions::new().write(true).create_new(true).open(&p) {
            Ok(f) => {
                reg.live.push(Live::File(p.clone()));
                return Ok((f, p));
            }
            // A stale temporary of an earlier process with the same id.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        "no free temporary name",
    ))
}

/// Creates and registers a directory an output writes into.
fn create_dir_registered(dir: &Path) -> io::Result<()> {
    install_interrupt_handler()?;
    let mut reg = registry();
    if reg.terminating {
        return Err(io::Error::new(io::ErrorKind::Interrupted, "interrupted"));
    }
    fs::create_dir(dir)?;
    reg.live.push(Live::Dir(dir.to_owned()));
    Ok(())
}

/// Installs, once per process and before the first temporary exists, the handler that
/// on SIGINT, SIGTERM, SIGHUP, SIGQUIT or SIGXCPU removes every live temporary and exits
/// with 128 + the signal (130, 143, 129, 131, 152), and catches SIGXFSZ (the write over
/// the file size limit then fails with an error). Commands that write no file keep the
/// default signal behaviour.
pub fn install_interrupt_handler() -> io::Result<()> {
    static INSTALLED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    INSTALLED
        .get_or_init(|| imp::install().map_err(|e| e.to_string()))
        .clone()
        .map_err(|e| io::Error::other(format!("cannot install the interrupt handler: {e}")))
}

/// Starts the interrupt cleanup: marks the process as terminating (no new temporary,
/// no commit) and removes every live temporary; returns how many paths were removed.
fn clean_for_exit() -> usize {
    let mut reg = registry();
    reg.terminating = true;
    reg.clean()
}

#[cfg(unix)]
mod imp {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGXCPU, SIGXFSZ};
    use signal_hook::iterator::Signals;

    /// A thread waits for the signals (signal-hook's handler only writes to a pipe, so
    /// the cleanup runs as ordinary code, free to lock and remove files). SIGXFSZ
    /// (over `ulimit -f`) is only caught, not acted on: with a handler the write fails
    /// with EFBIG instead of killing the process, the error names the output and the
    /// limit, and the temporary goes with the error like any other.
    pub(super) fn install() -> std::io::Result<()> {
        let mut signals = Signals::new(super::CLEANUP_SIGNALS.iter().map(|(s, _)| *s))?;
        signals.add_signal(SIGXFSZ)?;
        std::thread::Builder::new()
            .name("camsim-signals".into())
            .spawn(move || {
                for sig in signals.forever() {
                    if sig == SIGXFSZ {
                        continue;
                    }
                    super::clean_for_exit();
                    std::process::exit(128 + sig);
                }
            })?;
        Ok(())
    }

    /// The signals that remove the temporaries and end the process with 128 + the
    /// signal, and their names.
    pub(super) const SIGNALS: [(i32, &str); 5] = [
        (SIGINT, "SIGINT"),
        (SIGTERM, "SIGTERM"),
        (SIGHUP, "SIGHUP"),
        (SIGQUIT, "SIGQUIT"),
        (SIGXCPU, "SIGXCPU"),
    ];
}

/// The catchable signals that end a run (interrupt, termination, a dropped terminal or
/// ssh session, quit, the CPU time limit): each removes every live temporary and exits
/// with 128 + the signal. SIGKILL cannot be caught: its temporaries are removed by the
/// next run in the directory ([`remove_stale_temporaries`]).
#[cfg(unix)]
pub const CLEANUP_SIGNALS: [(i32, &str); 5] = imp::SIGNALS;

#[cfg(not(unix))]
mod imp {
    /// No signal handling off Unix: temporaries are still removed on errors and panics.
    pub(super) fn install() -> std::io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use std::os::unix::fs::PermissionsExt;

    /// A fresh empty directory for one test.
    fn scratch(name: &str) -> PathBuf {
        static N: AtomicU64 = AtomicU64::new(0);
        let d = std::env::temp_dir().join(format!(
            "camsim-output-{}-{name}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    /// The module's temporaries left in `dir`.
    fn temps_in(dir: &Path) -> Vec<String> {
        fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| is_temp_name(n))
            .collect()
    }

    fn msg(e: anyhow::Error) -> String {
        format!("{e:#}")
    }

    #[test]
    fn an_existing_file_is_refused_without_force_and_left_byte_identical() {
        let d = scratch("refuse");
        let f = d.join("out.csv");
        let old: Vec<u8> = (0..=255u8).cycle().take(10_000).collect();
        fs::write(&f, &old).unwrap();
        let before = fs::metadata(&f).unwrap();
        let e = Plan::new(false).file("--csv", &f).unwrap_err();
        assert_eq!(
            msg(e),
            format!("--csv {}: exists (use --force to overwrite)", f.display())
        );
        assert_eq!(fs::read(&f).unwrap(), old);
        let after = fs::metadata(&f).unwrap();
        assert_eq!(before.modified().unwrap(), after.modified().unwrap());
        assert_eq!(before.len(), after.len());
        // The refusal made no temporary either.
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn with_force_the_old_content_is_replaced_only_at_commit() {
        let d = scratch("force");
        let f = d.join("out.csv");
        fs::write(&f, b"old\n").unwrap();
        let mut out = Plan::new(true).file("--csv", &f).unwrap().open().unwrap();
        let tmp = out.temp_path().unwrap().to_owned();
        assert_eq!(
            tmp.parent(),
            Some(d.as_path()),
            "temporary beside the target"
        );
        assert!(is_temp_name(&tmp.file_name().unwrap().to_string_lossy()));
        assert!(live_temporaries().contains(&tmp));
        out.write_all(&[b'n'; 20_000]).unwrap();
        out.flush().unwrap();
        assert_eq!(
            fs::read(&f).unwrap(),
            b"old\n",
            "target untouched before commit"
        );
        assert_eq!(fs::metadata(&tmp).unwrap().len(), 20_000);
        out.commit().unwrap();
        assert_eq!(fs::read(&f).unwrap(), vec![b'n'; 20_000]);
        assert!(temps_in(&d).is_empty());
        assert!(!live_temporaries().contains(&tmp));
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn an_error_or_a_panic_before_commit_leaves_the_old_file_and_no_temporary() {
        let d = scratch("abort");
        let f = d.join("out.csv");
        fs::write(&f, b"precious").unwrap();
        // An error returned with `?` half-way through the rows.
        let run = |rows: usize| -> Result<()> {
            let mut out = Plan::new(true).file("--csv", &f)?.open()?;
            for i in 0..rows {
                writeln!(out, "{i},{}", i * i)?;
                if i == rows / 2 {
                    bail!("the solver failed at row {i}");
                }
            }
            out.commit()
        };
        assert!(msg(run(10_000).unwrap_err()).contains("solver failed at row 5000"));
        assert_eq!(fs::read(&f).unwrap(), b"precious");
        assert!(temps_in(&d).is_empty());
        // A panic unwinding through the writer.
        let g = f.clone();
        let r = std::panic::catch_unwind(move || {
            let mut out = Plan::new(true).file("--csv", &g).unwrap().open().unwrap();
            out.write_all(&[b'x'; 100_000]).unwrap();
            panic!("bug in the observer");
        });
        assert!(r.is_err());
        assert_eq!(fs::read(&f).unwrap(), b"precious");
        assert!(temps_in(&d).is_empty());
        // A new target stays absent.
        let n = d.join("new.csv");
        let mut out = Plan::new(false).file("--csv", &n).unwrap().open().unwrap();
        out.write_all(b"partial").unwrap();
        drop(out);
        assert!(!n.exists());
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_committed_file_has_exactly_the_content_written() {
        let d = scratch("exact");
        let f = d.join("out.bin");
        let mut out = Plan::new(false).file("--csv", &f).unwrap().open().unwrap();
        // Writes of many sizes, straddling the buffer's 8 KiB.
        let mut expect = Vec::new();
        let mut x: u32 = 12345;
        for len in (0..300).map(|i| (i * 97) % 20_000) {
            let chunk: Vec<u8> = (0..len)
                .map(|_| {
                    x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    (x >> 16) as u8
                })
                .collect();
            out.write_all(&chunk).unwrap();
            expect.extend_from_slice(&chunk);
        }
        assert_eq!(out.written(), expect.len() as u64);
        out.commit().unwrap();
        assert_eq!(fs::read(&f).unwrap(), expect);
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_size_guard_refuses_and_names_the_option() {
        let d = scratch("size");
        let f = d.join("big.csv");
        let e = Plan::new(false)
            .file("--csv", &f)
            .unwrap()
            .limit(3_400_000_000, 1_000_000_000, "--max-csv-mb N")
            .unwrap_err();
        assert_eq!(
            msg(e),
            format!(
                "--csv {}: would be about 3.40 GB, over the 1.00 GB limit (use --max-csv-mb N to allow it)",
                f.display()
            )
        );
        assert!(!f.exists());
        // An estimate at the limit passes; writing past it fails, naming the option.
        let mut out = Plan::new(false)
            .file("--csv", &f)
            .unwrap()
            .limit(1000, 1000, "--max-csv-mb N")
            .unwrap()
            .open()
            .unwrap();
        out.write_all(&[b'a'; 1000]).unwrap();
        let e = out.write_all(b"b").unwrap_err();
        assert!(e.to_string().contains("--csv"), "{e}");
        assert!(e.to_string().contains("1.00 kB limit"), "{e}");
        assert!(e.to_string().contains("--max-csv-mb N"), "{e}");
        drop(out);
        assert!(!f.exists());
        assert!(temps_in(&d).is_empty());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_plan_refuses_bad_paths_by_option_and_touches_nothing() {
        let d = scratch("plan");
        let sub = d.join("sub");
        fs::create_dir(&sub).unwrap();
        let file = d.join("file");
        fs::write(&file, b"f").unwrap();
        let mut p = Plan::new(true);
        let cases = [
            (sub.clone(), "is a directory".to_owned()),
            (
                d.join("missing/out.csv"),
                format!("directory {} does not exist", d.join("missing").display()),
            ),
            (
                file.join("out.csv"),
                format!("{} is not a directory", file.display()),
            ),
        ];
        for (path, why) in cases {
            let e = msg(p.file("--csv", &path).unwrap_err());
            assert_eq!(e, format!("--csv {}: {why}", path.display()));
        }
        // A dangling symbolic link.
        let link = d.join("dangling");
        std::os::unix::fs::symlink(d.join("nowhere"), &link).unwrap();
        let e = msg(p.file("--csv", &link).unwrap_err());
        assert!(e.contains("symbolic link to a missing file"), "{e}");
        // Two outputs naming one file, spelled differently.
        p.file("--csv", &d.join("a.csv")).unwrap();
        let e = msg(p.file("--json", &sub.join("../a.csv")).unwrap_err());
        assert!(
            e.starts_with("--json ") && e.contains("also written by --csv"),
            "{e}"
        );
        // A file output inside a directory output's files.
        p.dir("--plot", &d.join("plots"), &["velocity.png"])
            .unwrap();
        let e = msg(p.file("--csv", &d.join("plots/velocity.png")).unwrap_err());
        assert!(e.contains("also written by --plot"), "{e}");
        // Two directory outputs may share a directory, not a file.
        p.dir("--plot-extra", &d.join("plots"), &["other.png"])
            .unwrap();
        assert!(p
            .dir("--plot2", &d.join("plots"), &["velocity.png"])
            .is_err());
        // Nothing was created by any of it.
        let mut names: Vec<_> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["dangling", "file", "sub"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_file_that_appears_during_the_run_is_not_replaced_without_force() {
        let d = scratch("race");
        let f = d.join("out.csv");
        let mut out = Plan::new(false).file("--csv", &f).unwrap().open().unwrap();
        out.write_all(b"new").unwrap();
        fs::write(&f, b"someone else's").unwrap();
        let e = msg(out.commit().unwrap_err());
        assert!(e.contains("appeared during the run"), "{e}");
        assert_eq!(fs::read(&f).unwrap(), b"someone else's");
        assert!(temps_in(&d).is_empty());
        // And one that appears between plan and open is refused at open.
        let g = d.join("g.csv");
        let t = Plan::new(false).file("--csv", &g).unwrap();
        fs::write(&g, b"mine").unwrap();
        assert!(msg(t.open().unwrap_err()).contains("exists (use --force"));
        assert_eq!(fs::read(&g).unwrap(), b"mine");
        assert!(temps_in(&d).is_empty());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_symbolic_link_is_kept_and_its_file_replaced_with_its_permissions() {
        let d = scratch("link");
        let real = d.join("real.csv");
        fs::write(&real, b"old").unwrap();
        fs::set_permissions(&real, fs::Permissions::from_mode(0o640)).unwrap();
        let link = d.join("link.csv");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        assert!(Plan::new(false).file("--csv", &link).is_err());
        let mut out = Plan::new(true)
            .file("--csv", &link)
            .unwrap()
            .open()
            .unwrap();
        out.write_all(b"new").unwrap();
        out.commit().unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(&real).unwrap(), b"new");
        assert_eq!(
            fs::metadata(&real).unwrap().permissions().mode() & 0o777,
            0o640
        );
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn only_dev_null_and_the_own_streams_are_written_in_place() {
        let mut out = Plan::new(false)
            .file("--csv", Path::new("/dev/null"))
            .unwrap()
            .open()
            .unwrap();
        assert!(out.temp_path().is_none());
        out.write_all(b"discarded").unwrap();
        out.commit().unwrap();
        use std::os::unix::fs::FileTypeExt;
        assert!(fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device());
        // Any other device, with or without force, directly or through a symbolic link,
        // is refused before anything is opened; so is a FIFO (no hang without a reader).
        let d = scratch("fifo");
        let fifo = d.join("pipe");
        assert!(std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success());
        let link = d.join("zero-link");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        for (p, kind) in [
            (Path::new("/dev/zero"), "a character device"),
            (fifo.as_path(), "a FIFO"),
            (link.as_path(), "a character device"),
        ] {
            for force in [false, true] {
                let e = msg(Plan::new(force).file("--csv", p).unwrap_err());
                assert_eq!(
                    e,
                    format!("--csv {}: is {kind}, not a regular file: outputs go to a regular file or a new name (/dev/stdout and /dev/null are allowed)", p.display())
                );
            }
        }
        assert!(fs::metadata(&fifo).unwrap().file_type().is_fifo());
        fs::remove_dir_all(&d).unwrap();
        // The process's own streams are direct; a regular file elsewhere under /dev
        // (a tmpfs such as /dev/shm) is not.
        for p in ["/dev/stdout", "/dev/stderr", "/dev/fd/3", "/proc/self/fd/1"] {
            assert!(is_direct_path(Path::new(p)), "{p}");
        }
        for p in ["/dev/shm/out.csv", "/dev/fd", "/dev", "out.csv"] {
            assert!(!is_direct_path(Path::new(p)), "{p}");
        }
        // Standard error opens as a shared descriptor (nothing written to it here).
        let out = Plan::new(false)
            .file("--csv", Path::new("/dev/stderr"))
            .unwrap()
            .open()
            .unwrap();
        assert!(out.temp_path().is_none());
        out.commit().unwrap();
    }

    #[test]
    fn an_input_is_never_replaced_even_with_force() {
        let d = scratch("input");
        let scene = d.join("scene.toml");
        fs::write(&scene, b"[run]\n").unwrap();
        let link = d.join("alias.toml");
        std::os::unix::fs::symlink(&scene, &link).unwrap();
        for p in [&scene, &link, &d.join("./scene.toml")] {
            let mut plan = Plan::new(true);
            plan.input("--scene", &scene);
            let e = msg(plan.file("--csv", p).unwrap_err());
            assert!(
                e.contains(&format!("is the input --scene {}", scene.display())),
                "{e}"
            );
        }
        assert_eq!(fs::read(&scene).unwrap(), b"[run]\n");
        let mut plan = Plan::new(true);
        plan.input("--scene", &scene);
        assert!(plan.file("--csv", &d.join("other.csv")).is_ok());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_replaced_file_keeps_its_owner_and_mode() {
        use std::os::unix::fs::MetadataExt;
        let d = scratch("owner");
        let f = d.join("theirs.csv");
        fs::write(&f, b"old").unwrap();
        fs::set_permissions(&f, fs::Permissions::from_mode(0o600)).unwrap();
        // Given to another user where this process may (root); else it stays ours and
        // the check is the same: the replacement has the old owner and mode.
        let _ = std::os::unix::fs::chown(&f, Some(65534), Some(65534));
        let before = fs::metadata(&f).unwrap();
        let mut out = Plan::new(true).file("--csv", &f).unwrap().open().unwrap();
        out.write_all(b"new").unwrap();
        out.commit().unwrap();
        let after = fs::metadata(&f).unwrap();
        assert_eq!(fs::read(&f).unwrap(), b"new");
        assert_eq!((after.uid(), after.gid()), (before.uid(), before.gid()));
        assert_eq!(after.mode() & 0o7777, 0o600);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed_at_the_next_open() {
        let d = scratch("stale");
        // A process that has exited: its id is free (until reused, when the file stays).
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let host = host_tag();
        let stale = [
            format!(".out.csv.camsim-{host}-{dead}-0.tmp"),
            format!(".other.png.camsim-{dead}-3.tmp"),
        ];
        let kept = [
            // A live process (this one's parent), another machine, not a temporary.
            format!(
                ".out.csv.camsim-{host}-{}-0.tmp",
                std::os::unix::process::parent_id()
            ),
            format!(".out.csv.camsim-elsewhere-{dead}-0.tmp"),
            "notes.camsim-1-0.tmp".to_owned(),
        ];
        for n in stale.iter().chain(&kept) {
            fs::write(d.join(n), b"partial").unwrap();
        }
        assert_eq!(temp_owner(&stale[0]), Some((Some(host), dead)));
        assert_eq!(temp_owner(&stale[1]), Some((None, dead)));
        let out = Plan::new(false)
            .file("--csv", &d.join("new.csv"))
            .unwrap()
            .open()
            .unwrap();
        drop(out);
        let mut left: Vec<String> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        let mut expect = kept.to_vec();
        expect.sort();
        assert_eq!(left, expect);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_new_directory_output_appears_only_at_commit_and_vanishes_on_abort() {
        let d = scratch("dir-new");
        let plots = d.join("plots");
        let names = ["a.png", "b.png"];
        // Aborted: the directory it created is removed again.
        let mut out = Plan::new(false)
            .dir("--plot", &plots, &names)
            .unwrap()
            .open()
            .unwrap();
        assert!(plots.is_dir());
        let pa = out.path("a.png").unwrap();
        assert_eq!(pa.parent(), Some(plots.as_path()));
        assert_eq!(out.path("a.png").unwrap(), pa, "same name, same temporary");
        fs::write(&pa, b"half a png").unwrap();
        assert!(!plots.join("a.png").exists());
        let e = msg(out.path("c.png").unwrap_err());
        assert!(e.contains("c.png is not one of the declared files"), "{e}");
        drop(out);
        assert!(!plots.exists());
        // Committed: exactly the files written, no temporary.
        let mut out = Plan::new(false)
            .dir("--plot", &plots, &names)
            .unwrap()
            .open()
            .unwrap();
        fs::write(out.path("a.png").unwrap(), b"AAA").unwrap();
        out.write("b.png", b"BBBB").unwrap();
        out.commit().unwrap();
        assert_eq!(fs::read(plots.join("a.png")).unwrap(), b"AAA");
        assert_eq!(fs::read(plots.join("b.png")).unwrap(), b"BBBB");
        assert_eq!(fs::read_dir(&plots).unwrap().count(), 2);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn an_existing_directory_output_needs_force_per_file_and_replaces_at_commit() {
        let d = scratch("dir-old");
        fs::write(d.join("a.png"), b"old a").unwrap();
        fs::write(d.join("notes.txt"), b"the user's").unwrap();
        let e = msg(Plan::new(false)
            .dir("--plot", &d, &["a.png", "b.png"])
            .unwrap_err());
        assert_eq!(
            e,
            format!(
                "--plot {}: {} exists (use --force to overwrite)",
                d.display(),
                d.join("a.png").display()
            )
        );
        assert!(Plan::new(false).dir("--plot", &d, &["../x.png"]).is_err());
        assert!(Plan::new(false)
            .dir("--plot", &d.join("notes.txt"), &["a.png"])
            .is_err());
        let mut out = Plan::new(true)
            .dir("--plot", &d, &["a.png", "b.png"])
            .unwrap()
            .open()
            .unwrap();
        out.write("a.png", b"new a").unwrap();
        out.write("b.png", b"new b").unwrap();
        assert_eq!(fs::read(d.join("a.png")).unwrap(), b"old a");
        assert!(!d.join("b.png").exists());
        out.commit().unwrap();
        assert_eq!(fs::read(d.join("a.png")).unwrap(), b"new a");
        assert_eq!(fs::read(d.join("b.png")).unwrap(), b"new b");
        assert_eq!(fs::read(d.join("notes.txt")).unwrap(), b"the user's");
        assert!(temps_in(&d).is_empty());
        // An aborted output into an existing directory leaves it and its files.
        let mut out = Plan::new(true)
            .dir("--plot", &d, &["a.png"])
            .unwrap()
            .open()
            .unwrap();
        out.write("a.png", b"newer a").unwrap();
        drop(out);
        assert_eq!(fs::read(d.join("a.png")).unwrap(), b"new a");
        assert!(temps_in(&d).is_empty());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn sizes_read_in_decimal_units() {
        assert_eq!(human_bytes(0), "0 B");
        assert_eq!(human_bytes(999), "999 B");
        assert_eq!(human_bytes(1000), "1.00 kB");
        assert_eq!(human_bytes(1_234_567), "1.23 MB");
        assert_eq!(human_bytes(56_700_000), "56.7 MB");
        assert_eq!(human_bytes(999_400_000), "999 MB");
        assert_eq!(human_bytes(999_600_000), "1.00 GB");
        assert_eq!(human_bytes(u64::MAX), "18447 PB");
    }
}
