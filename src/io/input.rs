//! Input paths checked before they are opened, so that a FIFO does not block a read and a
//! device does not feed one without end.

use std::fs::FileType;
use std::os::unix::fs::FileTypeExt;
use std::path::Path;

/// Why a path named as an input file is not a regular file (or a link to one); its
/// `Display` ends the sentence "cannot open PATH: …".
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NotAFile {
    #[error("file not found")]
    Missing,
    #[error("it is a directory, not a file")]
    Directory,
    /// Anything else: a symbolic link loop, a FIFO, a device, a socket, an unreadable path.
    #[error("{0}")]
    Other(String),
}

/// Checks, without opening it, that `path` is a regular file or a symbolic link to one.
pub fn check_regular(path: &Path) -> Result<(), NotAFile> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => Ok(()),
        Ok(meta) if meta.is_dir() => Err(NotAFile::Directory),
        Ok(meta) => Err(NotAFile::Other(format!("it is {}, not a regular file", kind(meta.file_type())))),
        Err(e) if e.raw_os_error() == Some(libc::ELOOP) => {
            Err(NotAFile::Other("it is a loop of symbolic links, which leads to no file".into()))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => match std::fs::symlink_metadata(path) {
            Ok(_) => Err(NotAFile::Other("it is a symbolic link to a file that does not exist".into())),
            Err(_) => Err(NotAFile::Missing),
        },
        Err(e) => Err(NotAFile::Other(e.to_string())),
    }
}

/// What a file type other than a regular file or a directory is, with its article.
fn kind(file_type: FileType) -> &'static str {
    if file_type.is_fifo() {
        "a named pipe (FIFO)"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}
