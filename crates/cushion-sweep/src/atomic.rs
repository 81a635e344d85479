//! Crash-safe files: write to a temporary file in the same folder, flush it to disk (fsync),
//! rename it over the target, then fsync the folder. A reader (or a resumed sweep) sees the old
//! file or the whole new one, never half of one.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written; becomes `target` on [`AtomicFile::commit`], vanishes if dropped.
pub struct AtomicFile {
    target: PathBuf,
    temp: PathBuf,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
        let name = target
            .file_name()
            .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "no file name"))?;
        let temp = target.with_file_name(format!(
            ".{}.tmp-{}",
            name.to_string_lossy(),
            std::process::id()
        ));
        let file = File::create(&temp)?;
        Ok(AtomicFile {
            target: target.to_path_buf(),
            temp,
            writer: Some(BufWriter::with_capacity(1 << 16, file)),
        })
    }

    /// The temporary file's path (for writers that want a `File`).
    pub fn temp_path(&self) -> &Path {
        &self.temp
    }

    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("open until commit")
    }

    /// Take the underlying buffered file (e.g. for a Parquet writer); give it back with
    /// [`AtomicFile::commit_with`].
    pub fn take(&mut self) -> BufWriter<File> {
        self.writer.take().expect("open until commit")
    }

    /// Flush, fsync, rename over the target, fsync the folder.
    pub fn commit(mut self) -> io::Result<()> {
        let w = self.writer.take().expect("open until commit");
        Self::finish(w, &self.temp, &self.target)
    }

    /// Commit a writer previously taken with [`AtomicFile::take`].
    pub fn commit_with(self, w: BufWriter<File>) -> io::Result<()> {
        Self::finish(w, &self.temp, &self.target)
    }

    fn finish(w: BufWriter<File>, temp: &Path, target: &Path) -> io::Result<()> {
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        fs::rename(temp, target)?;
        sync_dir(target.parent().unwrap_or(Path::new(".")))
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Not committed (an error on the way): leave no temporary behind.
        if self.temp.exists() {
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// Write `bytes` to `target` atomically.
pub fn write_atomic(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(target)?;
    f.writer().write_all(bytes)?;
    f.commit()
}

/// Remove the temporary files that a process killed while writing left for the files `names`
/// in `dir` (their `.<name>.tmp-<pid>` siblings); other files stay. Errors are ignored: a
/// leftover temporary is only clutter.
pub fn remove_stale_temps(dir: &Path, names: &[&str]) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        if names
            .iter()
            .any(|n| file.starts_with(&format!(".{n}.tmp-")))
        {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// fsync a folder so a rename in it survives power loss (a no-op where folders can't be opened).
pub fn sync_dir(dir: &Path) -> io::Result<()> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    match File::open(dir) {
        Ok(d) => {
            let _ = d.sync_all();
            Ok(())
        }
        Err(_) => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commit_replaces_and_drop_discards() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        {
            let mut f = AtomicFile::create(&p).unwrap();
            f.writer().write_all(b"three").unwrap();
        }
        assert_eq!(fs::read(&p).unwrap(), b"two");
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temporary left"
        );
    }

    #[test]
    fn stale_temps_of_the_named_files_go_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        for f in [
            ".a.txt.tmp-12",
            ".b.txt.tmp-7",
            "a.txt",
            ".a.txt.keep",
            "x.tmp-1",
        ] {
            fs::write(dir.path().join(f), b"").unwrap();
        }
        remove_stale_temps(dir.path(), &["a.txt", "b.txt"]);
        let mut left: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, [".a.txt.keep", "a.txt", "x.tmp-1"]);
    }
}
