//! Refuses `.geo` files that could make gmsh run shell commands, before gmsh reads them.
//!
//! gmsh runs `SystemCall`, `System`, `NonBlockingSystemCall` and `OnelabRun` while it reads a
//! file, through the API too. The check lexes each file as gmsh does (strings in `"` or `'`,
//! comments `//` and `/* */`, identifiers, numbers) and refuses:
//! - those four commands, and `Exit`, which would end the calling process;
//! - the commands that write files (`Save`, `Print`, `Printf(...) >`): a file written while
//!   reading could then be included with a content this check never saw;
//! - `Include` and `Merge` of a computed file name, which cannot be followed.
//!
//! `Include` and `Merge` of a quoted name are checked recursively (relative to the including
//! file), as is the option file `<file>.opt` that gmsh merges after every opened or merged file.
//!
//! Comments and strings are ignored, except in files containing `If`, `For`, `Function` or
//! `Macro`: gmsh skips inactive blocks with raw scanners that do not follow its lexer (the
//! `If` one ignores strings), so it can resume inside what its lexer would read as a string or
//! a comment and run that text. In such files the words above are refused anywhere.

use super::GmshError;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Commands that run programs.
const RUNS: [&str; 4] = ["SystemCall", "System", "NonBlockingSystemCall", "OnelabRun"];
/// Commands that read another file as gmsh input.
const READS: [&str; 3] = ["Include", "Merge", "MergeWithBoundingBox"];
/// Commands that write files.
const WRITES: [&str; 3] = ["Save", "Print", "Printf"];
/// Statements whose blocks gmsh may skip with its raw scanners.
const SKIPPERS: [&str; 6] = ["If", "ElseIf", "Else", "For", "Function", "Macro"];

/// How gmsh reads a file: `Include` parses it; opening it or `Merge` also merges `<file>.opt`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum How {
    Include,
    Merge,
}

/// Checks the file gmsh is about to open and every file it would read along.
pub(super) fn check(path: &Path) -> Result<(), GmshError> {
    check_tree(path.to_path_buf())
}

/// Checks the option files gmsh merges after opening the mesh file `path`.
pub(super) fn check_options(path: &Path) -> Result<(), GmshError> {
    check_tree(with_opt(path))
}

fn with_opt(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".opt");
    name.into()
}

/// Checks `start`, merged, and what it reads; missing files are skipped (gmsh reports them).
fn check_tree(start: PathBuf) -> Result<(), GmshError> {
    check_file(start, How::Merge, &mut Vec::new(), &mut HashSet::new())
}

/// Checks `path`, read as `how`, then the files it reads, depth first; `chain` holds the files
/// being read (canonical), which a file must not read again: gmsh would recurse without end.
/// A path that is not a regular file (a FIFO would block the read) is refused.
fn check_file(
    path: PathBuf,
    how: How,
    chain: &mut Vec<PathBuf>,
    seen: &mut HashSet<(PathBuf, How)>,
) -> Result<(), GmshError> {
    let canonical = match path.canonicalize() {
        Ok(canonical) => canonical,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(source) => return Err(GmshError::Io { path, source }),
    };
    if !seen.insert((canonical.clone(), how)) {
        return Ok(());
    }
    if let Err(e) = crate::io::input::check_regular(&path) {
        return Err(GmshError::NotAFile { path, reason: e.to_string() });
    }
    let src = std::fs::read(&path).map_err(|source| GmshError::Io { path: path.clone(), source })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let line = |at: usize| 1 + src[..at].iter().filter(|&&c| c == b'\n').count();
    chain.push(canonical);
    for finding in scan(&src) {
        match finding.what {
            What::Read(target, how) => {
                let read = dir.join(&target);
                if read.canonicalize().is_ok_and(|c| chain.contains(&c)) {
                    return Err(GmshError::Recursion { path, line: line(finding.at), target });
                }
                check_file(read, how, chain, seen)?;
            }
            What::Refuse(reason) => return Err(GmshError::SystemCall { line: line(finding.at), path, reason }),
        }
    }
    chain.pop();
    if how == How::Merge {
        check_file(with_opt(&path), How::Merge, chain, seen)?;
    }
    Ok(())
}

/// Something found at byte `at` of a file.
#[derive(Debug, PartialEq)]
struct Finding {
    at: usize,
    what: What,
}

#[derive(Debug, PartialEq)]
enum What {
    /// The file must be refused; the reason completes "line N ...".
    Refuse(String),
    /// gmsh will read this file, relative to the directory of the current one.
    Read(String, How),
}

/// What one file holds, in file order.
fn scan(src: &[u8]) -> Vec<Finding> {
    let tokens = lex(src);
    let code: Vec<Token> = tokens.iter().copied().filter(|t| t.kind != Kind::Comment).collect();
    let mut findings: Vec<Finding> = (0..code.len()).filter_map(|k| code_finding(src, &code[k..])).collect();
    if code.iter().any(|t| t.kind == Kind::Word && one_of(t.text(src), &SKIPPERS)) {
        let text = tokens.iter().filter(|t| matches!(t.kind, Kind::Str | Kind::Comment));
        findings.extend(text.flat_map(|t| text_findings(src, t)));
    }
    findings.sort_by_key(|f| f.at);
    findings
}

/// The finding of the first token of `code`, if it is a command word.
fn code_finding(src: &[u8], code: &[Token]) -> Option<Finding> {
    let token = code[0];
    if token.kind != Kind::Word {
        return None;
    }
    let word = token.text(src);
    let name = String::from_utf8_lossy(word);
    let what = if one_of(word, &RUNS) {
        What::Refuse(format!("uses {name}, which runs shell commands"))
    } else if word == b"Exit" {
        What::Refuse("uses Exit, which would end this program".into())
    } else if one_of(word, &READS) {
        read_target(src, &name, code.get(1))
    } else if writes(src, word, &code[1..]) {
        What::Refuse(format!("uses {name} to write a file, which could then be read unchecked"))
    } else {
        return None;
    };
    Some(Finding { at: token.start, what })
}

/// `Include`/`Merge` followed by `next`: the quoted file to check, or a refusal.
fn read_target(src: &[u8], name: &str, next: Option<&Token>) -> What {
    let how = if name == "Include" { How::Include } else { How::Merge };
    match next.filter(|t| t.kind == Kind::Str).map(|t| t.text(src)) {
        Some(target) => match std::str::from_utf8(target) {
            Ok(target) => What::Read(target.into(), how),
            Err(_) => What::Refuse(format!("uses {name} with a file name that is not UTF-8")),
        },
        None => What::Refuse(format!("uses {name} with a computed file name, which cannot be checked")),
    }
}

/// Whether `word`, followed by the code tokens `rest`, writes a file: `Save` or `Print` (not
/// the option categories `Print.`), or `Printf(...)` redirected with `>` or `>>`.
fn writes(src: &[u8], word: &[u8], rest: &[Token]) -> bool {
    let is = |k: usize, s: &[u8]| rest.get(k).is_some_and(|t| t.kind == Kind::Other && t.text(src) == s);
    match word {
        b"Save" | b"Print" => !is(0, b"."),
        b"Printf" if is(0, b"(") => {
            let mut depth = 0;
            for (k, t) in rest.iter().enumerate().filter(|(_, t)| t.kind == Kind::Other) {
                match t.text(src) {
                    b"(" => depth += 1,
                    b")" if depth == 1 => return is(k + 1, b">"),
                    b")" => depth -= 1,
                    _ => {}
                }
            }
            false
        }
        _ => false,
    }
}

/// Dangerous words in the string or comment `token`, seen as gmsh could after a skip.
fn text_findings(src: &[u8], token: &Token) -> Vec<Finding> {
    let text = &src[..token.end];
    (token.start..token.end)
        .filter(|&p| is_word_start(text[p]) && (p == 0 || !is_word_start(text[p - 1])))
        .filter_map(|p| {
            let word = &text[p..p + span(&text[p..], is_word_char)];
            let dangerous = [&RUNS[..], &READS, &WRITES, &["Exit"]];
            dangerous.iter().any(|list| one_of(word, list)).then(|| Finding {
                at: p,
                what: What::Refuse(format!(
                    "mentions {} in a comment or string, which gmsh can still run after \
                     skipping an If, For or Function block",
                    String::from_utf8_lossy(word)
                )),
            })
        })
        .collect()
}

fn one_of(word: &[u8], list: &[&str]) -> bool {
    list.iter().any(|w| w.as_bytes() == word)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Word,
    /// A string; the token spans its content, without quotes.
    Str,
    /// A comment; the token spans its content, without delimiters.
    Comment,
    /// A number or a punctuation character.
    Other,
}

#[derive(Clone, Copy, Debug)]
struct Token {
    kind: Kind,
    start: usize,
    end: usize,
}

impl Token {
    fn text<'a>(&self, src: &'a [u8]) -> &'a [u8] {
        &src[self.start..self.end]
    }
}

/// Splits `src` like gmsh's lexer (`Parser/Gmsh.l`); unterminated strings and comments run
/// to the end.
fn lex(src: &[u8]) -> Vec<Token> {
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < src.len() {
        let rest = &src[i..];
        let (kind, start, end, next) = if rest.starts_with(b"//") {
            let end = find(src, i + 2, b"\n");
            (Kind::Comment, i + 2, end, end)
        } else if rest.starts_with(b"/*") {
            let end = find(src, i + 2, b"*/");
            (Kind::Comment, i + 2, end, end + 2)
        } else if rest[0] == b'"' || rest[0] == b'\'' {
            let end = find(src, i + 1, &rest[..1]);
            (Kind::Str, i + 1, end, end + 1)
        } else if is_word_start(rest[0]) {
            let end = i + span(rest, is_word_char);
            (Kind::Word, i, end, end)
        } else if rest[0].is_ascii_digit() {
            let end = i + number_len(rest);
            (Kind::Other, i, end, end)
        } else if rest[0].is_ascii_whitespace() {
            i += 1;
            continue;
        } else {
            (Kind::Other, i, i + 1, i + 1)
        };
        tokens.push(Token { kind, start, end });
        i = next;
    }
    tokens
}

/// Position of `pattern` at or after `from`, or the length of `src`.
fn find(src: &[u8], from: usize, pattern: &[u8]) -> usize {
    src[from..].windows(pattern.len()).position(|w| w == pattern).map_or(src.len(), |p| from + p)
}

/// Length of the leading run of `s` whose bytes satisfy `f`.
fn span(s: &[u8], f: impl Fn(u8) -> bool) -> usize {
    s.iter().take_while(|&&c| f(c)).count()
}

/// Length of the number starting `s`: digits, optional `.` and digits, optional exponent.
fn number_len(s: &[u8]) -> usize {
    let digits = |from: usize| span(s.get(from..).unwrap_or_default(), |c| c.is_ascii_digit());
    let mut n = digits(0);
    if s.get(n) == Some(&b'.') {
        n += 1 + digits(n + 1);
    }
    if matches!(s.get(n), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(s.get(n + 1), Some(b'+' | b'-')));
        let exponent = digits(n + 1 + sign);
        if exponent > 0 {
            n += 1 + sign + exponent;
        }
    }
    n
}

fn is_word_start(c: u8) -> bool {
    c.is_ascii_alphabetic() || c == b'_'
}

fn is_word_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reasons of the refusals in `src`, with their lines.
    fn refusals(src: &str) -> Vec<(usize, String)> {
        scan(src.as_bytes())
            .into_iter()
            .filter_map(|f| match f.what {
                What::Refuse(reason) => {
                    let line = 1 + src[..f.at].matches('\n').count();
                    Some((line, reason))
                }
                What::Read(..) => None,
            })
            .collect()
    }

    fn refused_lines(src: &str) -> Vec<usize> {
        refusals(src).into_iter().map(|(line, _)| line).collect()
    }

    #[test]
    fn plain_geometry_passes() {
        let src = "lc = 0.1; // System of units: m\nPoint(1) = {0, 0, 0, lc};\n\
                   /* SystemCall \"x\"; */ Physical Surface(\"System\") = {1};\n\
                   Print.Format = 1; Printf(\"a = %g\", lc > 1 ? 1 : 0);";
        assert!(scan(src.as_bytes()).is_empty());
    }

    #[test]
    fn commands_are_refused_with_their_line() {
        let src = "x = 1;\nSystemCall \"touch p\";\ny = 2; System 'ls';\n\
                   NonBlockingSystemCall \"a\";\nOnelabRun(\"a\", \"b\");\nExit;";
        assert_eq!(refused_lines(src), [2, 3, 4, 5, 6]);
        assert_eq!(refusals(src)[0].1, "uses SystemCall, which runs shell commands");
    }

    #[test]
    fn words_follow_gmsh_lexer() {
        assert!(refusals("SystemCalls = 1; my_System = 2; xSystem = 3; System2 = 4;").is_empty());
        // gmsh reads `1` then `SystemCall`, `1e5` then `System`
        assert_eq!(refused_lines("a = 1SystemCall \"x\";\nb = 1e5System \"y\";"), [1, 2]);
        assert_eq!(refused_lines("a = \"//\"; SystemCall \"x\";"), [1]);
        assert_eq!(refused_lines("/* \" */ SystemCall \"x\"; // \""), [1]);
    }

    #[test]
    fn file_writes_are_refused() {
        assert_eq!(refused_lines("Save \"a.geo\";\nPrint \"a.png\";"), [1, 2]);
        assert_eq!(refused_lines("Printf(\"%g\", (1)) > \"a.geo\";\nPrintf(\"b\") >> s;"), [1, 2]);
        assert!(refusals("Print.Width = 10; Printf(\"%g\", 1 > 2);").is_empty());
    }

    #[test]
    fn reads_are_followed_or_refused() {
        let found = scan(b"Include \"a.geo\";\nMerge 'b/c.msh';\nInclude StrCat(\"d\", \".geo\");");
        let whats: Vec<_> = found.into_iter().map(|f| f.what).collect();
        assert_eq!(whats[0], What::Read("a.geo".into(), How::Include));
        assert_eq!(whats[1], What::Read("b/c.msh".into(), How::Merge));
        assert!(matches!(&whats[2], What::Refuse(r) if r.contains("computed file name")));
    }

    #[test]
    fn text_is_checked_in_files_with_skipped_blocks() {
        // gmsh 4.8 runs this SystemCall: its `If` skipper stops at the "EndIf" in the string
        let src = "If (0)\n  a = \"EndIf\"; // \"; SystemCall 'touch p';\nEndIf\n";
        assert_eq!(refused_lines(src), [2]);
        assert!(refusals(src)[0].1.starts_with("mentions SystemCall in a comment or string"));
        assert_eq!(refused_lines("For i In {1:2}\nEndFor\nn = \"System\";"), [3]);
        assert_eq!(refused_lines("// Include\nFunction f\nReturn"), [1]);
    }

    #[test]
    fn unterminated_text_is_safe() {
        assert!(refusals("a = \"abc").is_empty());
        assert!(refusals("/* abc").is_empty());
        assert_eq!(refused_lines("If(1) a = \"SystemCall"), [1]);
        assert_eq!(number_len(b"1e+"), 1);
        assert_eq!(number_len(b"12.5e-3x"), 7);
    }

    /// A fresh directory for one test.
    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("damfem-guard-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        dir
    }

    #[test]
    fn included_files_are_checked_recursively() {
        let dir = temp_dir("include");
        let write = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
        write("main.geo", "Include \"sub/a.geo\";\nInclude \"sub/a.geo\";\n");
        write("sub/a.geo", "Merge \"b.geo\"; // relative to sub/\n");
        write("sub/b.geo", "Point(1) = {0, 0, 0};\n");
        assert!(check(&dir.join("main.geo")).is_ok());
        write("sub/b.geo", "Include \"../main.geo\";\n");
        let err = check(&dir.join("main.geo")).unwrap_err();
        assert!(matches!(&err, GmshError::Recursion { path, line: 1, .. } if path.ends_with("sub/b.geo")), "{err}");
        write("sub/b.geo", "Point(1) = {0, 0, 0};\n");
        write("sub/b.geo.opt", "\n\nSystem \"ls\";\n");
        let err = check(&dir.join("main.geo")).unwrap_err();
        assert!(
            matches!(&err, GmshError::SystemCall { path, line: 3, .. } if path.ends_with("sub/b.geo.opt")),
            "{err}"
        );
        std::fs::remove_file(dir.join("sub/b.geo.opt")).unwrap();
        write("main.geo.opt", "Exit;");
        assert!(matches!(check(&dir.join("main.geo")), Err(GmshError::SystemCall { line: 1, .. })));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn option_files_of_meshes_are_checked() {
        let dir = temp_dir("options");
        let mesh = dir.join("a.msh");
        assert!(check_options(&mesh).is_ok());
        std::fs::write(dir.join("a.msh.opt"), "SystemCall \"ls\";").unwrap();
        assert!(matches!(check_options(&mesh), Err(GmshError::SystemCall { .. })));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
