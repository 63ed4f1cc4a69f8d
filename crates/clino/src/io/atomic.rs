//! Output files that appear whole or not at all.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::{Error, ErrorKind, Result};

/// A file written under a temporary name beside its destination and renamed
/// over it by [`AtomicFile::commit`]: a run that fails (or is interrupted)
/// leaves what was there before untouched, never a half-written file. The
/// temporary file is removed when the value is dropped without a commit.
/// A destination that is a stream rather than a file (`/dev/stdout`, a named
/// pipe, a terminal) is written in place: there is nothing to rename.
///
/// The bytes are written to the file by a thread of its own, so the copy
/// into the kernel runs beside the computation.
///
/// ```
/// use std::io::Write;
/// let dir = tempfile::tempdir().unwrap(); // removed when dropped
/// let path = dir.path().join("out.csv");
/// std::fs::write(&path, "old\n").unwrap();
/// {
///     let mut f = clino::io::AtomicFile::create(&path, &[]).unwrap();
///     f.write_all(b"half").unwrap();
///     // dropped without commit: the old content stays
/// }
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n");
/// let mut f = clino::io::AtomicFile::create(&path, &[]).unwrap();
/// f.write_all(b"new\n").unwrap();
/// f.commit().unwrap();
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "new\n");
/// ```
pub struct AtomicFile {
    dest: PathBuf,
    /// the temporary name, or `None` when the destination is a stream
    tmp: Option<PathBuf>,
    out: Option<BufWriter<Background>>,
}

/// Bytes at which a buffer is handed to the writing thread.
const CHUNK: usize = 1 << 20;

enum Msg {
    Data(Vec<u8>),
    Flush(std::sync::mpsc::SyncSender<std::io::Result<()>>),
}

/// A file written by a thread of its own: the copy into the kernel (a fifth
/// of `clino fuse`'s time for a large output) runs beside the computation on
/// a second core. At most two chunks wait, so memory stays bounded; a write
/// error is returned by the next write, flush or commit.
struct Background {
    tx: Option<std::sync::mpsc::SyncSender<Msg>>,
    thread: Option<std::thread::JoinHandle<std::io::Result<File>>>,
}

impl Background {
    fn new(mut f: File) -> std::io::Result<Self> {
        let (tx, rx) = std::sync::mpsc::sync_channel::<Msg>(2);
        let thread = std::thread::Builder::new()
            .name("clino-writer".into())
            .spawn(move || {
                for m in rx {
                    match m {
                        Msg::Data(b) => f.write_all(&b)?,
                        Msg::Flush(ack) => {
                            let _ = ack.send(f.flush());
                        }
                    }
                }
                Ok(f)
            })?;
        Ok(Self {
            tx: Some(tx),
            thread: Some(thread),
        })
    }

    /// The thread's error once it has stopped (it stops only on an error or
    /// when the sender is dropped).
    fn failure(&mut self) -> std::io::Error {
        self.tx = None;
        match self.thread.take().map(|t| t.join()) {
            Some(Ok(Err(e))) => e,
            Some(Err(_)) => std::io::Error::other("the writing thread panicked"),
            _ => std::io::Error::other("the writing thread stopped"),
        }
    }

    fn send(&mut self, m: Msg) -> std::io::Result<()> {
        match &self.tx {
            Some(tx) => match tx.send(m) {
                Ok(()) => Ok(()),
                Err(_) => Err(self.failure()),
            },
            None => Err(std::io::Error::other("file already closed")),
        }
    }

    /// Wait for every byte to be written; give back the file.
    fn finish(mut self) -> std::io::Result<File> {
        self.tx = None;
        match self.thread.take().map(|t| t.join()) {
            Some(Ok(r)) => r,
            Some(Err(_)) => Err(std::io::Error::other("the writing thread panicked")),
            None => Err(std::io::Error::other("file already closed")),
        }
    }
}

impl Drop for Background {
    fn drop(&mut self) {
        // the file is removed after this: let the thread end first
        self.tx = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Write for Background {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.send(Msg::Data(buf.to_vec()))?;
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        let (ack, done) = std::sync::mpsc::sync_channel(1);
        self.send(Msg::Flush(ack))?;
        match done.recv() {
            Ok(r) => r,
            Err(_) => Err(self.failure()),
        }
    }
}

impl AtomicFile {
    /// Start writing `dest`. `inputs` are the files the run reads: writing
    /// over one of them is refused before anything is touched.
    pub fn create(dest: &Path, inputs: &[&Path]) -> Result<Self> {
        if let Ok(d) = dest.canonicalize() {
            for i in inputs {
                if i.canonicalize().is_ok_and(|c| c == d) {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        "the output file is also the input: choose another output name",
                    )
                    .in_file(dest));
                }
            }
            if d.is_dir() {
                return Err(
                    Error::new(ErrorKind::InvalidInput, "the output is a directory").in_file(dest),
                );
            }
        }
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "out".into());
        // `/dev/stdout`, a named pipe, a terminal: written in place (a rename
        // would replace the device node with a regular file). Anything under
        // /dev or /proc names an open descriptor or a device even when it
        // resolves to a regular file (`-o /dev/stdout > out.csv`); it is
        // appended to, as the shell's `>>` expects and `>` already truncated.
        let special = dest.starts_with("/dev") || dest.starts_with("/proc");
        let stream = special || std::fs::metadata(dest).is_ok_and(|m| !m.is_file() && !m.is_dir());
        let (f, tmp) = if stream {
            let f = std::fs::OpenOptions::new()
                .append(true)
                .open(dest)
                .map_err(|e| Error::from(e).in_file(dest))?;
            (f, None)
        } else {
            let tmp = dest.with_file_name(format!(".{name}.clino-tmp-{}", std::process::id()));
            let f = File::create(&tmp).map_err(|e| Error::from(e).in_file(dest))?;
            (f, Some(tmp))
        };
        let bg = match Background::new(f) {
            Ok(bg) => bg,
            Err(e) => {
                if let Some(t) = &tmp {
                    let _ = std::fs::remove_file(t);
                }
                return Err(Error::from(e).in_file(dest));
            }
        };
        Ok(Self {
            dest: dest.to_path_buf(),
            tmp,
            out: Some(BufWriter::with_capacity(CHUNK, bg)),
        })
    }

    /// The destination path.
    pub fn path(&self) -> &Path {
        &self.dest
    }

    /// Flush, sync and rename over the destination.
    pub fn commit(mut self) -> Result<()> {
        let dest = self.dest.clone();
        let io = |e: std::io::Error| Error::from(e).in_file(&dest);
        if let Some(out) = self.out.take() {
            let bg = out.into_inner().map_err(|e| io(e.into_error()))?;
            let f = bg.finish().map_err(io)?;
            if self.tmp.is_none() {
                return Ok(());
            }
            f.sync_all().map_err(io)?;
        }
        match &self.tmp {
            Some(t) => std::fs::rename(t, &self.dest).map_err(io),
            None => Ok(()),
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.out {
            Some(o) => o.write(buf),
            None => Err(std::io::Error::other("file already committed")),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.out {
            Some(o) => o.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.out.take().is_some()
            && let Some(t) = &self.tmp
        {
            let _ = std::fs::remove_file(t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh scratch directory, removed when the value is dropped (at the
    /// end of the test, passed or failed).
    fn scratch(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("clino-atomic-{name}-"))
            .tempdir()
            .unwrap()
    }

    #[test]
    fn many_chunks_arrive_whole_and_in_order() {
        let tmp = scratch("chunks");
        let d = tmp.path();
        let p = d.join("big.bin");
        let data: Vec<u8> = (0..3 * CHUNK + 12345)
            .map(|i| (i * 7 % 251) as u8)
            .collect();
        let mut f = AtomicFile::create(&p, &[]).unwrap();
        for part in data.chunks(1000) {
            f.write_all(part).unwrap();
        }
        f.flush().unwrap();
        f.commit().unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), data);
        assert_eq!(
            std::fs::read_dir(d).unwrap().count(),
            1,
            "no temporary file left"
        );
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_named_pipe_is_written_in_place_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let tmp = scratch("fifo");
        let d = tmp.path();
        let p = d.join("pipe");
        let ok = std::process::Command::new("mkfifo").arg(&p).status();
        if !ok.is_ok_and(|s| s.success()) {
            eprintln!("SKIPPED: no mkfifo");
            return;
        }
        let reader = {
            let p = p.clone();
            std::thread::spawn(move || std::fs::read(p).unwrap())
        };
        let mut f = AtomicFile::create(&p, &[]).unwrap();
        f.write_all(b"through the pipe\n").unwrap();
        f.commit().unwrap();
        assert_eq!(reader.join().unwrap(), b"through the pipe\n");
        let kind = std::fs::symlink_metadata(&p).unwrap().file_type();
        assert!(kind.is_fifo(), "the pipe was replaced by {kind:?}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_write_error_of_the_thread_reaches_the_caller() {
        // /dev/full: every write fails with ENOSPC
        let p = Path::new("/dev/full");
        if !p.exists() {
            return;
        }
        let mut f = AtomicFile::create(p, &[]).unwrap();
        let big = vec![1u8; 3 * CHUNK];
        let wrote = f.write_all(&big).and_then(|_| f.flush());
        let e = match wrote {
            Err(e) => e.to_string(),
            Ok(()) => f.commit().unwrap_err().to_string(),
        };
        assert!(e.contains("space") || e.contains("28"), "{e}");
    }
}
