//! ParaView collection files (`.pvd`): a time series of data files.
//!
//! `vtkio` has no support for this format, so the short XML text is written by hand. File paths
//! are stored relative to the directory of the `.pvd` file, with `/` separators, so that the
//! output directory can be moved as a whole. Files are written atomically.

use super::atomic::{write_output, OutputError};
use std::io;
use std::path::{Component, Path, PathBuf};

/// Writes the collection `path` listing `(time, file)` entries in the given order.
///
/// Each `file` is a path as seen from the current directory (or absolute); it is written relative
/// to the directory of `path`.
pub fn write_pvd(path: &Path, entries: &[(f64, PathBuf)]) -> Result<(), OutputError> {
    let base = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let mut xml = String::from(concat!(
        "<?xml version=\"1.0\"?>\n",
        "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n",
        "  <Collection>\n",
    ));
    for (time, file) in entries {
        xml += &data_set(path, base, *time, file)?;
    }
    xml += "  </Collection>\n</VTKFile>\n";
    write_output(path, xml.as_bytes())
}

/// The `DataSet` element of one entry of the collection `path` stored in directory `base`.
fn data_set(path: &Path, base: &Path, time: f64, file: &Path) -> Result<String, OutputError> {
    let invalid = |reason: String| OutputError::Invalid { path: path.to_path_buf(), reason };
    if !time.is_finite() {
        return Err(OutputError::NonFinite {
            path: path.to_path_buf(),
            location: format!("the time of {}", file.display()),
            value: time,
        });
    }
    let relative = relative_to(file, base).map_err(|e| invalid(format!("cannot locate {}: {e}", file.display())))?;
    let relative =
        slash_separated(&relative).ok_or_else(|| invalid(format!("{} is not valid UTF-8", file.display())))?;
    Ok(format!("    <DataSet timestep=\"{time}\" file=\"{}\"/>\n", escape(&relative)))
}

/// `target` as seen from directory `base`, both resolved lexically from the current directory.
fn relative_to(target: &Path, base: &Path) -> io::Result<PathBuf> {
    let target = normalize(&std::path::absolute(target)?);
    let base = normalize(&std::path::absolute(base)?);
    let common = target.components().zip(base.components()).take_while(|(a, b)| a == b).count();
    let ups = base.components().count() - common;
    let mut relative: PathBuf = std::iter::repeat_n(Component::ParentDir, ups).collect();
    relative.extend(target.components().skip(common));
    Ok(relative)
}

/// Removes `.` and resolves `..` without touching the file system.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The components of a relative path joined by `/`, or `None` if one is not UTF-8.
fn slash_separated(path: &Path) -> Option<String> {
    let parts: Option<Vec<&str>> = path.components().map(|c| c.as_os_str().to_str()).collect();
    Some(parts?.join("/"))
}

/// Escapes the characters that cannot appear verbatim in an XML attribute value.
pub(super) fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths() {
        let rel = |t: &str, b: &str| relative_to(Path::new(t), Path::new(b)).unwrap();
        assert_eq!(rel("out/a.vtu", "out"), Path::new("a.vtu"));
        assert_eq!(rel("out/./sub/a.vtu", "out/"), Path::new("sub/a.vtu"));
        assert_eq!(rel("/x/y/a.vtu", "/x/z"), Path::new("../y/a.vtu"));
        assert_eq!(rel("/x/z/../y/a.vtu", "/x/y"), Path::new("a.vtu"));
        assert_eq!(rel("a.vtu", "."), Path::new("a.vtu"));
    }

    #[test]
    fn escaping() {
        assert_eq!(escape(r#"a&b<c>"d"#), "a&amp;b&lt;c&gt;&quot;d");
    }
}
