//! `llvm-size -A` of an ELF, run as a child with a time limit and its output read through
//! the firmware log's limit (firmware-check's sizes of the images).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};

/// Default of `--llvm-size-timeout`: 60 s. `llvm-size -A` of a firmware ELF (about 1 MB)
/// takes milliseconds; a minute leaves room for a loaded CI machine and still ends a tool
/// that never answers (a wrong `--llvm-size`, a FIFO given as the ELF) instead of hanging
/// camsim and the firmware CI with it.
pub const LLVM_SIZE_TIMEOUT_S: u64 = 60;

/// Most bytes of `llvm-size`'s standard error kept for a failure's message.
const MAX_STDERR_BYTES: u64 = 64 * 1024;

/// A child's output read on a thread: at most `max` bytes, and whether there was more
/// (`over`, set as soon as the limit is passed).
struct CappedRead {
    thread: std::thread::JoinHandle<Vec<u8>>,
    over: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

/// Starts reading at most `max` bytes of `from` on a thread.
fn capped_reader(from: Option<impl std::io::Read + Send + 'static>, max: u64) -> CappedRead {
    let over = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = over.clone();
    let thread = std::thread::spawn(move || {
        use std::io::Read;
        let mut bytes = Vec::new();
        if let Some(from) = from {
            let _ = from.take(max.saturating_add(1)).read_to_end(&mut bytes);
        }
        if bytes.len() as u64 > max {
            flag.store(true, std::sync::atomic::Ordering::SeqCst);
            bytes.truncate(usize::try_from(max).unwrap_or(usize::MAX));
        }
        bytes
    });
    CappedRead { thread, over }
}

impl CappedRead {
    fn over(&self) -> bool {
        self.over.load(std::sync::atomic::Ordering::SeqCst)
    }

    /// The bytes read and whether there was more, once the thread ends, waiting until
    /// `deadline` at most (a child's child may hold the pipe open after the child exits).
    fn join_by(self, deadline: Instant) -> Option<(Vec<u8>, bool)> {
        while !self.thread.is_finished() {
            if Instant::now() >= deadline {
                return None;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let bytes = self.thread.join().ok()?;
        Some((bytes, self.over.load(std::sync::atomic::Ordering::SeqCst)))
    }
}

/// Runs `tool -A elf` within `timeout`, its standard output read through the log limit;
/// its output, or why not (cannot run, over the limit, no answer in time: killed, failed
/// with its exit status and standard error).
pub fn run_llvm_size(tool: &str, elf: &Path, timeout: Duration) -> Result<String> {
    let what = format!("--llvm-size {tool} -A {}", elf.display());
    let mut child = Command::new(tool)
        .arg("-A")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("--llvm-size {tool}: cannot run it"))?;
    let max = crate::cmd::predict::MAX_LOG_BYTES;
    let out = capped_reader(child.stdout.take(), max);
    let err = capped_reader(child.stderr.take(), MAX_STDERR_BYTES);
    let deadline = Instant::now() + timeout;
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break status;
        }
        let over = out.over();
        if over || Instant::now() >= deadline {
            let _ = child.kill();
            let _ = child.wait();
            if over {
                bail!("{what}: its output is larger than the limit of {max} bytes (killed, read no further)");
            }
            bail!(
                "{what}: no answer in {} s (--llvm-size-timeout): killed",
                timeout.as_secs()
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let (stdout, over) = out.join_by(deadline).unwrap_or_default();
    // Over the limit first: the child may have died of the pipe closed at the limit.
    if over {
        bail!("{what}: its output is larger than the limit of {max} bytes (read no further)");
    }
    if !status.success() {
        let (stderr, _) = err.join_by(deadline).unwrap_or_default();
        let stderr = String::from_utf8_lossy(&stderr);
        let said = match stderr.trim() {
            "" => "nothing on standard error".to_string(),
            s => s.lines().next().unwrap_or(s).chars().take(200).collect(),
        };
        bail!("{what}: it failed ({status}): {said}");
    }
    Ok(String::from_utf8_lossy(&stdout).into_owned())
}
