//! Files written atomically: into a temporary file in the destination's directory, flushed to
//! disk, then renamed over the destination. A failure part-way leaves no partial file, and a
//! previous file of that name survives intact.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Distinguishes the temporary files of one process.
static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// The temporary file beside `path` that [`write_atomically`] writes first.
fn temporary_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tag = format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    );
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(tag),
        _ => PathBuf::from(tag),
    }
}

/// Writes `path` atomically with `write`, which gets a buffered writer on the temporary file.
///
/// Errors: any failure to create, write, flush or rename; the temporary file is then removed
/// and `path` is left as it was.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let temporary = temporary_beside(path);
    let result = (|| {
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(&temporary)?;
        let mut writer = BufWriter::with_capacity(1 << 20, file);
        write(&mut writer)?;
        writer.flush()?;
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Writes the bytes `data` to `path` atomically ([`write_atomically`]).
pub fn write_bytes_atomically(path: &Path, data: &[u8]) -> std::io::Result<()> {
    write_atomically(path, |w| w.write_all(data))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!("demkit-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_file_is_replaced_whole_and_no_temporary_stays() {
        let d = dir().join("whole");
        std::fs::create_dir_all(&d).unwrap();
        let path = d.join("out.txt");
        std::fs::write(&path, "old").unwrap();
        write_bytes_atomically(&path, b"new contents").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new contents");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    }

    #[test]
    fn a_failed_write_leaves_the_previous_file_and_no_temporary() {
        let d = dir().join("failed");
        std::fs::create_dir_all(&d).unwrap();
        let path = d.join("out.txt");
        std::fs::write(&path, "old").unwrap();
        let err = write_atomically(&path, |w| {
            w.write_all(b"partial")?;
            Err(std::io::Error::other("the computation failed"))
        });
        assert!(err.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
    }

    #[test]
    fn a_missing_directory_is_an_error_that_creates_nothing() {
        let path = dir().join("no-such-dir").join("out.txt");
        assert!(write_bytes_atomically(&path, b"x").is_err());
        assert!(!path.exists());
    }
}
