//! Opening input files safely: regular files only, never blocking, bounded.
//!
//! `open` on a FIFO blocks until a writer appears, and a symbolic link to
//! `/dev/zero` reads forever: an archive folder is user data, so every input
//! the analyzer reads goes through here. The type is checked before opening
//! (so a FIFO is never opened for reading), the open itself is non-blocking
//! (so a file swapped for a FIFO in between cannot hang us either) and checked
//! again on the open handle. Whole-file reads are capped, with a message that
//! names the file.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};

/// Cap for small structured inputs (manifest, legend): far above any real one.
pub const SMALL_INPUT_LIMIT: u64 = 256 << 20;
/// Cap for one PNG tile or texture read into memory.
pub const IMAGE_LIMIT: u64 = 2 << 30;

/// What a path is, for messages.
pub(crate) fn kind(metadata: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let file_type = metadata.file_type();
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_socket() {
            return "a socket";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
    }
    if metadata.is_dir() { "a folder" } else { "not a regular file" }
}

/// Opens `path` for reading if it is a regular file (symbolic links followed).
#[allow(clippy::disallowed_methods, clippy::disallowed_types)] // the layer: type checked before and after a non-blocking open
pub fn open_regular(path: &Path) -> Result<File> {
    let metadata = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !metadata.is_file() {
        return Err(Error::bad_file(path, format!("is {}, not a regular file", kind(&metadata))));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Never wait for a writer, should the path have become a FIFO.
        options.custom_flags(libc_o_nonblock());
    }
    let file = options.open(path).map_err(|e| Error::io(path, e))?;
    let metadata = file.metadata().map_err(|e| Error::io(path, e))?;
    if !metadata.is_file() {
        return Err(Error::bad_file(path, format!("is {}, not a regular file", kind(&metadata))));
    }
    Ok(file)
}

/// `O_NONBLOCK` (the same value on Linux and the BSDs we build for is not
/// guaranteed, so it is spelled per target).
#[cfg(unix)]
const fn libc_o_nonblock() -> i32 {
    if cfg!(any(target_os = "macos", target_os = "ios", target_os = "freebsd", target_os = "openbsd")) {
        0x0004
    } else {
        0o4000
    }
}

/// Reads a whole regular file of at most `limit` bytes.
pub fn read_limited(path: &Path, limit: u64) -> Result<Vec<u8>> {
    let file = open_regular(path)?;
    let length = file.metadata().map_err(|e| Error::io(path, e))?.len();
    if length > limit {
        return Err(Error::bad_file(
            path,
            format!("is {length} bytes, more than the {limit} this input may have"),
        ));
    }
    let mut bytes = Vec::with_capacity(length as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(Error::bad_file(path, format!("grew past {limit} bytes while being read")));
    }
    Ok(bytes)
}

/// [`read_limited`] as UTF-8 text (an error names the file otherwise).
pub fn read_limited_text(path: &Path, limit: u64) -> Result<String> {
    String::from_utf8(read_limited(path, limit)?)
        .map_err(|e| Error::bad_file(path, format!("is not UTF-8 text ({})", e.utf8_error())))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_and_devices_are_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let error = open_regular(dir.path()).unwrap_err().to_string();
        assert!(error.contains("a folder") && error.contains(&dir.path().display().to_string()), "{error}");
        #[cfg(unix)]
        {
            let error = read_limited(Path::new("/dev/zero"), 10).unwrap_err().to_string();
            assert!(error.contains("a device"), "{error}");
        }
        let file = dir.path().join("big");
        std::fs::write(&file, [0u8; 100]).unwrap();
        assert!(read_limited(&file, 99).unwrap_err().to_string().contains("more than"));
        assert_eq!(read_limited(&file, 100).unwrap().len(), 100);
    }
}
