//! The `$PhysicalNames` section of a `.msh` file, read before gmsh reads the file: gmsh keeps
//! one name of a physical group given two and drops the other without a word.

use super::GmshError;
use std::collections::BTreeMap;
use std::path::Path;

/// Refuses a `.msh` file whose `$PhysicalNames` give one physical group (dimension and tag)
/// two different names.
pub(super) fn check_physical_names(path: &Path) -> Result<(), GmshError> {
    let bytes = std::fs::read(path).map_err(|source| GmshError::Io { path: path.into(), source })?;
    let text = String::from_utf8_lossy(section(&bytes));
    let mut names = BTreeMap::new();
    for (dim, tag, name) in text.lines().filter_map(entry) {
        match names.insert((dim, tag), name) {
            Some(first) if first != name => {
                let (first, second) = (first.into(), name.into());
                return Err(GmshError::TwoNames { path: path.into(), dim, tag, first, second });
            }
            _ => {}
        }
    }
    Ok(())
}

/// The text between `$PhysicalNames` and `$EndPhysicalNames` (none without the section).
fn section(bytes: &[u8]) -> &[u8] {
    let find = |what: &[u8], from: usize| bytes[from..].windows(what.len()).position(|w| w == what).map(|i| from + i);
    let Some(start) = find(b"$PhysicalNames", 0).map(|i| i + b"$PhysicalNames".len()) else { return &[] };
    &bytes[start..find(b"$EndPhysicalNames", start).unwrap_or(bytes.len())]
}

/// The dimension, tag and name of a line `dim tag "name"` of the section (None for its first
/// line, the count).
fn entry(line: &str) -> Option<(i32, i32, &str)> {
    let (dim, rest) = line.trim_start().split_once(char::is_whitespace)?;
    let (tag, name) = rest.trim_start().split_once(char::is_whitespace)?;
    Some((dim.parse().ok()?, tag.parse().ok()?, name.trim().trim_matches('"')))
}
