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
//!    directory (`.NAME.camsim-TOKEN.tmp`, TOKEN random, NAME cut so that the whole
//!    name fits NAME_MAX) holding an exclusive lock on it, and returns an [`AtomicFile`], a buffered
//!    [`Write`]r. [`DirTarget::open`] returns an [`AtomicDir`] whose [`AtomicDir::path`]
//!    gives a temporary of the same form inside DIR for each declared file.
//! 3. **write** while the simulation runs.
//! 4. **commit**: [`AtomicFile::commit`] flushes, fsyncs and renames the temporary over
//!    the target, so the target is either its old self or the complete new file.
//!    Dropped without a commit (an error returned with `?`, a panic unwinding) the
//!    temporary is removed and the target is untouched. On every catchable signal
//!    that ends a process ([`CLEANUP_SIGNALS`]: SIGINT, SIGTERM, SIGHUP, SIGQUIT,
//!    SIGXCPU, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF) the temporaries of every
//!    live output are removed and the process exits with 128 + the signal number; a write over the file size limit
//!    (SIGXFSZ, `ulimit -f`) fails with an error that names the output, and its
//!    temporary is removed. Temporaries of processes that died uncatchably (SIGKILL) are
//!    removed by the next output created in the same directory: a temporary whose lock
//!    nobody holds is dead (the kernel drops a lock with its process, in any PID
//!    namespace or container); files named as earlier versions named theirs are never
//!    removed.
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
//! need not be writable (`--plot .`, `--plot ~`, `--plot /tmp` all work). The set of
//! files is replaced as a whole: with `--force` the commit removes every file of the
//! command's known outputs (the declared names, and [`Plan::dir_replacing`]'s others,
//! such as the cutter path of `profile --cutter-radius`) that this run did not write,
//! so that no file of an earlier run stays beside the new ones; [`AtomicDir::commit`]
//! returns what it wrote and removed.
//!
//! A target that is not a regular file (a block or character device, a FIFO, a socket,
//! also behind a symbolic link) is refused: written in place it would overwrite a disk
//! image or hang on a FIFO with no reader. Two are allowed explicitly and written in
//! place, never truncated: `/dev/null`, and the process's own descriptors (`/dev/stdout`,
//! `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N`), written through the descriptor when it
//! is open for writing and is none of the command's inputs; a regular file behind one
//! must be open for writing only (a shell's `>`): a descriptor open for reading
//! (`--csv /dev/fd/0 < scene.toml`) is refused.

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
        if let Some(fd) = descriptor_of(path) {
            // The process's own descriptors: written in place, never renamed over.
            let fd = fd.ok_or_else(|| {
                anyhow!("{label}: names no descriptor: outputs go to a file, /dev/stdout or /dev/fd/N with N a number")
            })?;
            self.writable_descriptor(&label, fd)?;
            return Ok(FileTarget {
                label,
                target: path.to_owned(),
                force: self.force,
                direct: true,
                fd: Some(fd),
                limit: None,
            });
        }
        name_fits(&label, path)?;
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
            fd: None,
            limit: None,
        })
    }

    /// Checks a directory output that will write the files `names` (plain file names)
    /// into `dir`. DIR may be missing (its parent must then exist and be writable: it
    /// is created when the output opens); an existing DIR must be a writable directory
    /// and each of its files that the output would replace needs force.
    pub fn dir(&mut self, option: &str, dir: &Path, names: &[&str]) -> Result<DirTarget> {
        self.dir_replacing(option, dir, names, &[])
    }

    /// [`Plan::dir`] for a command whose other variants write more files into DIR
    /// (`others`: e.g. the cutter path that only `--cutter-radius` writes). The set is
    /// replaced as a whole: with force the commit removes an existing file of `others`
    /// (as it removes a declared file not written), so that none of an earlier run's
    /// stays; without force an existing one refuses the output like a declared one.
    pub fn dir_replacing(
        &mut self,
        option: &str,
        dir: &Path,
        names: &[&str],
        others: &[&str],
    ) -> Result<DirTarget> {
        let label = format!("{option} {}", dir.display());
        for name in names.iter().chain(others) {
            let p = Path::new(name);
            if name.is_empty()
                || p.components().count() != 1
                || !matches!(p.components().next(), Some(Component::Normal(_)))
            {
                bail!("{label}: {name:?} is not a plain file name");
            }
        }
        name_fits(&label, dir)?;
        let resolved = resolve(dir).map_err(|e| anyhow!("{label}: {e}"))?;
        self.claim(&label, &resolved, true)?;
        for name in names {
            self.claim(&label, &resolved.join(name), false)?;
        }
        for name in names.iter().chain(others) {
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
            for name in names.iter().chain(others) {
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
            others: others.iter().map(|s| s.to_string()).collect(),
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

impl Plan {
    /// Checks a descriptor output (`/dev/stdout`, `/dev/fd/N`): it must be open, open
    /// for writing, and not a directory; a regular file behind it must be open for
    /// writing only (a shell's `>` or `>>`: a file also open for reading, such as
    /// `< scene.toml` or `<> file`, is refused) and be none of the command's inputs.
    /// Pipes, terminals and other devices open for writing are the streams they
    /// usually are.
    fn writable_descriptor(&self, label: &str, fd: i32) -> Result<()> {
        #[cfg(unix)]
        {
            use nix::fcntl::{fcntl, FcntlArg, OFlag};
            use nix::sys::stat::{fstat, SFlag};
            use std::os::unix::fs::MetadataExt;
            const RULE: &str = "outputs go to a file, or to a descriptor open for writing only";
            let flags = fcntl(fd, FcntlArg::F_GETFL)
                .map_err(|_| anyhow!("{label}: descriptor {fd} is not open: {RULE}"))?;
            let st = fstat(fd).map_err(|e| anyhow!("{label}: descriptor {fd}: {e}"))?;
            let kind = SFlag::from_bits_truncate(st.st_mode) & SFlag::S_IFMT;
            let mode = OFlag::from_bits_truncate(flags) & OFlag::O_ACCMODE;
            if kind == SFlag::S_IFDIR {
                bail!("{label}: descriptor {fd} is a directory: {RULE}");
            }
            if mode == OFlag::O_RDONLY {
                bail!("{label}: descriptor {fd} is open for reading only: an output never writes into a file open for reading");
            }
            for (input, path) in &self.inputs {
                if let Ok(m) = fs::metadata(path) {
                    if (m.dev(), m.ino()) == (st.st_dev, st.st_ino) {
                        bail!("{label}: is the input {input}: an output never replaces an input, even with {FORCE_OPTION}");
                    }
                }
            }
            if kind == SFlag::S_IFREG && mode != OFlag::O_WRONLY {
                bail!("{label}: descriptor {fd} is a file open for reading and writing: an output never writes into a file open for reading");
            }
        }
        #[cfg(not(unix))]
        let _ = (label, fd);
        Ok(())
    }
}

/// The descriptor a path names if it is one of the process's own (`/dev/stdin`,
/// `/dev/stdout`, `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N`,
/// `/proc/thread-self/fd/N`, `/proc/PID/fd/N` with this process's PID): `Some(Some(N))`,
/// or `Some(None)` for a name in a descriptor directory that is not a number. These are
/// written in place through the descriptor itself, under [`Plan::writable_descriptor`]'s
/// rules, never by a rename.
fn descriptor_of(path: &Path) -> Option<Option<i32>> {
    for (name, fd) in [("/dev/stdin", 0), ("/dev/stdout", 1), ("/dev/stderr", 2)] {
        if path == Path::new(name) {
            return Some(Some(fd));
        }
    }
    let own = format!("/proc/{}/fd", std::process::id());
    let parent = path.parent()?;
    let dirs = [
        "/dev/fd",
        "/proc/self/fd",
        "/proc/thread-self/fd",
        own.as_str(),
    ];
    if !dirs.iter().any(|d| parent == Path::new(d)) {
        return None;
    }
    let n = path.file_name()?.to_str();
    Some(
        n.filter(|n| n.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|n| n.parse().ok()),
    )
}

/// Refuses a path whose last name is longer than a file system allows (NAME_MAX, 255
/// bytes), before anything runs: it could never be created.
fn name_fits(label: &str, path: &Path) -> Result<()> {
    let len = path.file_name().map_or(0, |n| n.as_encoded_bytes().len());
    if len > NAME_MAX {
        bail!("{label}: the file name is {len} bytes, over the {NAME_MAX} a file system allows");
    }
    Ok(())
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
    /// The process's descriptor that a direct target names (`/dev/stdout`: 1).
    fd: Option<i32>,
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
            let f = open_direct(&self.target, self.fd)
                .with_context(|| format!("{label}: cannot open"))?;
            return Ok(AtomicFile {
                out: Some(BufWriter::new(f)),
                tmp: None,
                lock: None,
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
        let (f, tmp, lock) = create_temp(parent_of(&self.target), &self.target)
            .with_context(|| format!("{label}: cannot create a temporary file"))?;
        let out = AtomicFile {
            out: Some(BufWriter::new(f)),
            tmp: Some(tmp),
            lock: Some(lock),
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
/// process (same offset, as a shell redirection expects); another descriptor is opened
/// again through `/proc/self/fd/N` (appending if it appends, else at its offset); `/dev/null`
/// is opened. Nothing is truncated.
fn open_direct(path: &Path, fd: Option<i32>) -> io::Result<File> {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        match fd {
            Some(1) => return Ok(File::from(io::stdout().as_fd().try_clone_to_owned()?)),
            Some(2) => return Ok(File::from(io::stderr().as_fd().try_clone_to_owned()?)),
            Some(n) => return reopen_descriptor(n),
            None => {}
        }
    }
    let _ = fd;
    OpenOptions::new().write(true).open(path)
}

/// Opens descriptor `n` again for writing, in the mode it was opened with.
#[cfg(unix)]
fn reopen_descriptor(n: i32) -> io::Result<File> {
    use nix::fcntl::{fcntl, FcntlArg, OFlag};
    use nix::unistd::{lseek, Whence};
    use std::io::{Seek, SeekFrom};
    let flags = OFlag::from_bits_truncate(fcntl(n, FcntlArg::F_GETFL)?);
    let append = flags.contains(OFlag::O_APPEND);
    let mut f = OpenOptions::new()
        .write(true)
        .append(append)
        .open(format!("/proc/self/fd/{n}"))?;
    if !append && f.metadata()?.is_file() {
        let at = lseek(n, 0, Whence::SeekCur)?;
        f.seek(SeekFrom::Start(u64::try_from(at).unwrap_or(0)))?;
    }
    Ok(f)
}

/// A checked directory output, not yet opened.
#[derive(Debug)]
pub struct DirTarget {
    label: String,
    dir: PathBuf,
    names: Vec<String>,
    /// Files of the command's other variants, removed under force ([`Plan::dir_replacing`]).
    others: Vec<String>,
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
            others: self.others,
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
    /// Held until the temporary is renamed or removed: marks it as live.
    lock: Option<TempLock>,
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
        self.lock = None;
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
        // Released only once the temporary is gone.
        self.lock = None;
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
    others: Vec<String>,
    force: bool,
    created: bool,
    /// Declared name -> its temporary and the lock that marks it live, once asked for.
    temps: BTreeMap<String, (PathBuf, TempLock)>,
    done: bool,
}

impl AtomicDir {
    /// The directory that the commit writes into.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Where to write the declared file `name`: an (empty, already created) temporary
    /// inside DIR, for writers that want a path (the PNG encoder). The same
    /// name gives the same path. An undeclared name is an error.
    pub fn path(&mut self, name: &str) -> Result<PathBuf> {
        if let Some((p, _)) = self.temps.get(name) {
            return Ok(p.clone());
        }
        if !self.names.iter().any(|n| n == name) {
            bail!("{}: {name} is not one of the declared files", self.label);
        }
        let (_, tmp, lock) = create_temp(&self.dir, &self.dir.join(name)).with_context(|| {
            format!("{}: cannot create a temporary file for {name}", self.label)
        })?;
        self.temps.insert(name.to_owned(), (tmp.clone(), lock));
        Ok(tmp)
    }

    /// Writes the whole of the declared file `name`.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.path(name)?;
        fs::write(&p, bytes).with_context(|| format!("{}: cannot write {name}", self.label))
    }

    /// Fsyncs every written file and renames each to its name in DIR. Without force no
    /// file that appeared meanwhile is replaced: all are checked before any is renamed.
    /// Declared files never asked for by [`AtomicDir::path`] are not written; with force
    /// those of them and of the others ([`Plan::dir_replacing`]) that exist in DIR (an
    /// earlier run's) are removed, so DIR holds this run's set of files and no other.
    /// Returns what was written and removed.
    pub fn commit(mut self) -> Result<DirCommit> {
        let label = self.label.clone();
        for (name, (tmp, _)) in &self.temps {
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
            for (name, (tmp, _)) in &self.temps {
                place(tmp, &self.dir.join(name), self.force)
                    .map_err(|e| anyhow!("{label}: {name}: {e}"))?;
                reg.forget(tmp);
            }
            if self.created {
                reg.forget(&self.dir);
            }
        }
        let written: Vec<PathBuf> = (self.names.iter())
            .filter(|n| self.temps.contains_key(*n))
            .map(|n| self.dir.join(n))
            .collect();
        let removed = if self.force {
            self.remove_unwritten()
        } else {
            Vec::new()
        };
        removed_note(&label, &removed);
        self.temps.clear();
        self.done = true;
        sync_dir(&self.dir);
        Ok(DirCommit { written, removed })
    }

    /// Removes the regular files of the command's known outputs that this run did not
    /// write (never a directory, a link or anything of another name).
    fn remove_unwritten(&self) -> Vec<PathBuf> {
        let mut removed = Vec::new();
        for name in self.names.iter().chain(&self.others) {
            let f = self.dir.join(name);
            let stale = fs::symlink_metadata(&f).is_ok_and(|m| m.is_file());
            if !self.temps.contains_key(name) && stale && fs::remove_file(&f).is_ok() {
                removed.push(f);
            }
        }
        removed
    }
}

/// What a directory output's commit did: the files it wrote, and the files of an
/// earlier run it removed (under force: the known outputs this run did not write).
#[derive(Debug, Default, Clone, PartialEq)]
pub struct DirCommit {
    /// The files written, in DIR, in the order of the declared names.
    pub written: Vec<PathBuf>,
    /// The earlier run's files removed, in DIR.
    pub removed: Vec<PathBuf>,
}

/// The note printed to standard error when a commit removed an earlier run's files.
fn removed_note(label: &str, removed: &[PathBuf]) {
    if removed.is_empty() {
        return;
    }
    let names: Vec<String> = removed.iter().map(|p| p.display().to_string()).collect();
    let _ = writeln!(
        io::stderr().lock(),
        "camsim: note: {label}: removed {} (an earlier run's output that this run does not write)",
        names.join(", ")
    );
}

impl Drop for AtomicDir {
    fn drop(&mut self) {
        let mut reg = registry();
        for (tmp, _) in self.temps.values() {
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

/// The marker between a temporary's target name and its token.
const TEMP_MARK: &str = ".camsim-";
/// The end of every temporary's name.
const TEMP_END: &str = ".tmp";
/// Hexadecimal digits of a temporary's token.
const TOKEN_DIGITS: usize = 16;
/// The longest file name (bytes) Linux and the BSDs allow in a directory (NAME_MAX).
const NAME_MAX: usize = 255;

/// A random 64-bit token: the standard library's per-process random hash keys over this
/// process's id, the time and a counter (no two temporaries of any processes, in any
/// PID namespace, share one in practice; the lock, not the name, proves ownership).
fn temp_token() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
    h.write_u32(std::process::id());
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    h.write_u128(now);
    h.finish()
}

/// The hidden temporary name for `target` in `dir`: `.NAME.camsim-TOKEN.tmp`, TOKEN 16
/// hexadecimal digits ([`temp_token`]). NAME is the target's name cut (at a character
/// boundary) so that the whole name stays within NAME_MAX: any legal target name works.
fn temp_name(dir: &Path, target: &Path) -> PathBuf {
    let base = target.file_name().unwrap_or_else(|| "out".as_ref());
    let room = NAME_MAX - 1 - TEMP_MARK.len() - TOKEN_DIGITS - TEMP_END.len();
    let mut name = OsString::from(".");
    name.push(cut_name(base, room));
    name.push(format!("{TEMP_MARK}{:016x}{TEMP_END}", temp_token()));
    dir.join(name)
}

/// The first at most `room` bytes of a file name (whole characters if it is UTF-8).
fn cut_name(name: &std::ffi::OsStr, room: usize) -> OsString {
    if let Some(s) = name.to_str() {
        let mut end = s.len().min(room);
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        return OsString::from(s.get(..end).unwrap_or_default());
    }
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        let b = name.as_bytes();
        std::ffi::OsStr::from_bytes(b.get(..b.len().min(room)).unwrap_or_default()).to_owned()
    }
    #[cfg(not(unix))]
    {
        name.to_owned()
    }
}

/// Whether a file name is a temporary of this version's form (`.NAME.camsim-TOKEN.tmp`):
/// the only names the stale clean-up considers. Names of earlier versions' form
/// (`.NAME.camsim-PID-N.tmp`, `.NAME.camsim-HOST-PID-N.tmp`) are never removed: their
/// owner cannot be proven, and a user's file may look like one.
fn is_owned_form(name: &str) -> bool {
    let Some(rest) = name.strip_suffix(TEMP_END) else {
        return false;
    };
    let Some(at) = rest.rfind(TEMP_MARK) else {
        return false;
    };
    let token = rest.get(at + TEMP_MARK.len()..).unwrap_or_default();
    name.starts_with('.')
        && token.len() == TOKEN_DIGITS
        && token
            .bytes()
            .all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}

/// The lock that marks a temporary as live: an exclusive `flock` on it, held by the
/// process writing it until the temporary is renamed or removed. The kernel releases it
/// when the process dies, however it dies, so a temporary that can be locked is dead,
/// in any PID namespace or container sharing the file system. `None` where the file
/// system has no locks (such a temporary is never removed by another process).
#[derive(Debug)]
struct TempLock(#[allow(dead_code)] Option<LockHandle>);

#[cfg(unix)]
type LockHandle = nix::fcntl::Flock<File>;
#[cfg(not(unix))]
type LockHandle = File;

/// What trying to lock a temporary found.
enum Locked {
    /// Locked by this process now.
    Held(TempLock),
    /// Another process holds it.
    Busy,
}

/// Takes the exclusive lock on `f` without waiting.
fn try_lock(f: &File) -> io::Result<Locked> {
    #[cfg(unix)]
    {
        use nix::errno::Errno;
        use nix::fcntl::{Flock, FlockArg};
        match Flock::lock(f.try_clone()?, FlockArg::LockExclusiveNonblock) {
            Ok(l) => Ok(Locked::Held(TempLock(Some(l)))),
            Err((_, Errno::EWOULDBLOCK)) => Ok(Locked::Busy),
            // No locks on this file system: nothing can be proven either way.
            Err((_, Errno::ENOLCK | Errno::EOPNOTSUPP | Errno::ENOSYS)) => {
                Ok(Locked::Held(TempLock(None)))
            }
            Err((_, e)) => Err(e.into()),
        }
    }
    #[cfg(not(unix))]
    {
        let _ = f;
        Ok(Locked::Held(TempLock(None)))
    }
}

/// Whether the open file `f` is still the file at `path` (not removed or replaced).
fn same_file(f: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (f.metadata(), fs::symlink_metadata(path)) {
            (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (f, path);
        true
    }
}

/// Removes the stale temporaries in `dir`: regular files named in this version's form
/// (`.NAME.camsim-TOKEN.tmp`, TOKEN 16 hexadecimal digits) whose lock (the exclusive
/// `flock` their writer holds while they live) nobody holds, that is whose writer
/// died uncatchably (SIGKILL, a power cut). Best effort, returns how many were removed;
/// a locked temporary (a live run, in any container), a file of another form, and one
/// where locks do not work are left alone.
pub fn remove_stale_temporaries(dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name();
        if !name.to_str().is_some_and(is_owned_form) || !e.file_type().is_ok_and(|t| t.is_file()) {
            continue;
        }
        let path = e.path();
        let Ok(f) = File::open(&path) else { continue };
        // Held: the lock proves no process writes it; the identity check that the
        // name still names the file locked (not a new temporary under the same name).
        if let Ok(Locked::Held(TempLock(Some(_lock)))) = try_lock(&f) {
            if same_file(&f, &path) && fs::remove_file(&path).is_ok() {
                removed += 1;
            }
        }
    }
    removed
}

/// Whether a file name is one of this module's temporaries (any process, any version).
pub fn is_temp_name(name: &str) -> bool {
    name.starts_with('.') && name.ends_with(TEMP_END) && name.contains(TEMP_MARK)
}

/// Creates, locks and registers a new temporary for `target` in `dir`, under the
/// registry lock so that the interrupt handler sees every temporary that exists. A
/// temporary that another process's clean-up took between its creation and its lock is
/// given up for a new name.
fn create_temp(dir: &Path, target: &Path) -> io::Result<(File, PathBuf, TempLock)> {
    install_interrupt_handler()?;
    remove_stale_temporaries(dir);
    let mut reg = registry();
    if reg.terminating {
        return Err(io::Error::new(io::ErrorKind::Interrupted, "interrupted"));
    }
    for _ in 0..100 {
        let p = temp_name(dir, target);
        let f = match OpenOptions::new().write(true).create_new(true).open(&p) {
            Ok(f) => f,
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        };
        match try_lock(&f)? {
            Locked::Held(lock) if same_file(&f, &p) => {
                reg.live.push(Live::File(p.clone()));
                return Ok((f, p, lock));
            }
            // Taken by a clean-up (which removes it): try another name.
            _ => continue,
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
/// on each of [`CLEANUP_SIGNALS`] (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGXCPU, SIGUSR1,
/// SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF) removes every live temporary and exits with
/// 128 + the signal (130, 143, 129, 131, 152, ...), and catches SIGXFSZ (the write over
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
    use signal_hook::consts::{
        SIGALRM, SIGHUP, SIGINT, SIGPROF, SIGQUIT, SIGTERM, SIGUSR1, SIGUSR2, SIGVTALRM, SIGXCPU,
        SIGXFSZ,
    };
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
    pub(super) const SIGNALS: [(i32, &str); 10] = [
        (SIGINT, "SIGINT"),
        (SIGTERM, "SIGTERM"),
        (SIGHUP, "SIGHUP"),
        (SIGQUIT, "SIGQUIT"),
        (SIGXCPU, "SIGXCPU"),
        (SIGUSR1, "SIGUSR1"),
        (SIGUSR2, "SIGUSR2"),
        (SIGALRM, "SIGALRM"),
        (SIGVTALRM, "SIGVTALRM"),
        (SIGPROF, "SIGPROF"),
    ];
}

/// Every catchable signal whose default action ends the process (interrupt,
/// termination, a dropped terminal or ssh session, quit, the CPU time limit, the user
/// signals, the three interval timers): each removes every live temporary and exits
/// with 128 + the signal. SIGKILL cannot be caught: its temporaries are removed by the
/// next run in the directory ([`remove_stale_temporaries`]). The signals of faults
/// (SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT) are left to their default: the process is
/// then in no state to run code, and its temporaries are removed like SIGKILL's; SIGPIPE
/// is ignored by the Rust runtime (a write to a closed pipe fails instead).
#[cfg(unix)]
pub const CLEANUP_SIGNALS: [(i32, &str); 10] = imp::SIGNALS;

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
        let own = format!("/proc/{}/fd/7", std::process::id());
        for (p, fd) in [
            ("/dev/stdin", 0),
            ("/dev/stdout", 1),
            ("/dev/stderr", 2),
            ("/dev/fd/3", 3),
            ("/proc/self/fd/1", 1),
            ("/proc/thread-self/fd/12", 12),
            (own.as_str(), 7),
        ] {
            assert_eq!(descriptor_of(Path::new(p)), Some(Some(fd)), "{p}");
        }
        assert_eq!(descriptor_of(Path::new("/dev/fd/x")), Some(None));
        assert_eq!(descriptor_of(Path::new("/dev/fd/-1")), Some(None));
        for p in [
            "/dev/shm/out.csv",
            "/dev/fd",
            "/dev",
            "out.csv",
            "/proc/1/fd/1",
        ] {
            assert_eq!(descriptor_of(Path::new(p)), None, "{p}");
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
    fn only_unlocked_temporaries_of_this_form_are_removed_at_the_next_open() {
        let d = scratch("stale");
        // A dead writer's temporary: this version's form, nobody holds its lock.
        let dead = temp_name(&d, Path::new("out.csv"));
        fs::write(&dead, b"partial").unwrap();
        // A live writer's (in any PID namespace: only its lock counts), locked here
        // through a descriptor of its own.
        let live = temp_name(&d, Path::new("live.csv"));
        fs::write(&live, b"partial").unwrap();
        let held = match try_lock(&File::open(&live).unwrap()).unwrap() {
            Locked::Held(l) => l,
            Locked::Busy => panic!("nobody else holds it"),
        };
        assert!(held.0.is_some(), "this file system has locks");
        // Earlier versions' forms (never provably ours, even of a dead process id: a
        // user's file may look like one), and other names.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let kept = [
            format!(".out.csv.camsim-{pid}-0.tmp"),
            format!(".out.csv.camsim-somehost-{pid}-0.tmp"),
            ".out.csv.camsim-0123456789ABCDEF.tmp".to_owned(),
            ".out.csv.camsim-0123456789abcde.tmp".to_owned(),
            "notes.camsim-1-0.tmp".to_owned(),
        ];
        for n in &kept {
            fs::write(d.join(n), b"the user's").unwrap();
        }
        let out = Plan::new(false)
            .file("--csv", &d.join("new.csv"))
            .unwrap()
            .open()
            .unwrap();
        drop(out);
        let mut expect: Vec<String> = kept.to_vec();
        expect.push(live.file_name().unwrap().to_string_lossy().into_owned());
        expect.sort();
        let mut left: Vec<String> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, expect);
        assert!(!dead.exists());
        // Released, the live one is dead too.
        drop(held);
        assert_eq!(remove_stale_temporaries(&d), 1);
        assert!(!live.exists());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_temporary_name_fits_name_max_for_any_legal_target_name() {
        let d = scratch("long");
        for (len, ch) in [(255, "a"), (254, "a"), (226, "a"), (120, "é"), (85, "€")] {
            let name = ch.repeat(len / ch.len());
            assert!(name.len() <= 255);
            let t = temp_name(&d, Path::new(&name));
            let tn = t.file_name().unwrap().to_str().unwrap();
            assert!(tn.len() <= 255, "{} bytes", tn.len());
            assert!(is_owned_form(tn) && is_temp_name(tn), "{tn}");
            // The legal name is written, through its temporary.
            let mut out = Plan::new(false)
                .file("--csv", &d.join(&name))
                .unwrap()
                .open()
                .unwrap();
            out.write_all(b"x").unwrap();
            out.commit().unwrap();
            assert_eq!(fs::read(d.join(&name)).unwrap(), b"x");
            fs::remove_file(d.join(&name)).unwrap();
        }
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_forced_directory_output_replaces_the_whole_set_of_known_files() {
        let d = scratch("dir-set");
        for n in ["a.png", "b.png", "c.png", "notes.txt"] {
            fs::write(d.join(n), b"earlier").unwrap();
        }
        // Without force an earlier run's file of the set refuses, even one this run
        // would not write.
        assert!(Plan::new(false)
            .dir_replacing("--plot", &d.join("sub"), &["a.png"], &["c.png"])
            .is_ok());
        fs::create_dir(d.join("sub")).unwrap();
        fs::write(d.join("sub/c.png"), b"earlier").unwrap();
        let e = msg(Plan::new(false)
            .dir_replacing("--plot", &d.join("sub"), &["a.png"], &["c.png"])
            .unwrap_err());
        assert!(
            e.ends_with("sub/c.png exists (use --force to overwrite)"),
            "{e}"
        );
        let mut out = Plan::new(true)
            .dir_replacing("--plot", &d, &["a.png", "b.png"], &["c.png"])
            .unwrap()
            .open()
            .unwrap();
        out.write("a.png", b"new a").unwrap();
        let done = out.commit().unwrap();
        assert_eq!(done.written, [d.join("a.png")]);
        assert_eq!(done.removed, [d.join("b.png"), d.join("c.png")]);
        assert_eq!(fs::read(d.join("a.png")).unwrap(), b"new a");
        let mut left = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect::<Vec<_>>();
        left.sort();
        assert_eq!(left, ["a.png", "notes.txt", "sub"]);
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
