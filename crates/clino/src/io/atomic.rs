//! Output files that appear whole or not at all.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::{Error, ErrorKind, Result};

/// A file written under a temporary name beside its destination and renamed
/// over it by [`AtomicFile::commit`]: a run that fails (or is interrupted)
/// leaves what was there before untouched, never a half-written file. The
/// temporary file is removed when the value is dropped without a commit.
///
/// ```
/// use std::io::Write;
/// let dir = std::env::temp_dir().join(format!("clino-atomic-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("out.csv");
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
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub struct AtomicFile {
    dest: PathBuf,
    tmp: PathBuf,
    out: Option<BufWriter<File>>,
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
        let tmp = dest.with_file_name(format!(".{name}.clino-tmp-{}", std::process::id()));
        let f = File::create(&tmp).map_err(|e| Error::from(e).in_file(dest))?;
        Ok(Self {
            dest: dest.to_path_buf(),
            tmp,
            out: Some(BufWriter::with_capacity(1 << 16, f)),
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
            let f = out.into_inner().map_err(|e| io(e.into_error()))?;
            f.sync_all().map_err(io)?;
        }
        std::fs::rename(&self.tmp, &self.dest).map_err(io)
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
        if self.out.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}
