//! A deck's lines with its includes expanded in place: an Abaqus/CalculiX deck's
//! `*INCLUDE, INPUT=file`, or an LS-DYNA keyword file's `*INCLUDE` with the file's name on
//! the card after it (a name ending in ` +` goes on on the next card). A keyword file and
//! each file it includes end at their `*END`: the lines after it are not read.
//!
//! An included file is found relative to the folder of the file that includes it, may
//! include others in turn (at most [`MAX_DEPTH`] deep, which also stops a file that includes
//! itself), and may hold any part of the deck, data lines of an open keyword included. The
//! reader works on the expanded text; [`Deck::origin`] maps its line numbers back to the file
//! and line each came from, for messages.

use std::path::{Path, PathBuf};

use super::parse_error::ParseError;

/// Includes nest at most this deep.
pub(crate) const MAX_DEPTH: usize = 16;

/// How a deck names an included file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Dialect {
    /// `*INCLUDE, INPUT=file` (Abaqus, CalculiX).
    Abaqus,
    /// `*INCLUDE`, then the file's name on the next card (LS-DYNA; `$` starts a comment).
    Keyword,
}

/// A deck's text with its includes expanded.
pub(crate) struct Deck {
    /// The expanded text, one line per line of the files.
    pub text: String,
    /// Each expanded line's file (an index into `files`) and 1-based line there.
    lines: Vec<(usize, usize)>,
    /// The deck's own file first (an empty path for text without a file), then each included
    /// file.
    files: Vec<PathBuf>,
}

impl Deck {
    /// The deck in `text`, read from `path` (`None`: text with no file, where an `*INCLUDE`
    /// is refused).
    pub fn expand(text: &str, path: Option<&Path>) -> Result<Deck, ParseError> {
        Self::expand_as(Dialect::Abaqus, text, path)
    }

    /// [`Self::expand`] for a deck of `dialect`.
    pub fn expand_as(
        dialect: Dialect,
        text: &str,
        path: Option<&Path>,
    ) -> Result<Deck, ParseError> {
        let mut deck = Deck {
            text: String::with_capacity(text.len()),
            lines: Vec::new(),
            files: vec![path.map(Path::to_path_buf).unwrap_or_default()],
        };
        deck.add(dialect, text, 0, 0)?;
        Ok(deck)
    }

    /// The deck's own file, then each file it includes, as they were named.
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// The file and line of expanded line `line` (1-based); the file is `None` for the
    /// deck's own.
    pub fn origin(&self, line: usize) -> (Option<&Path>, usize) {
        match line.checked_sub(1).and_then(|i| self.lines.get(i)) {
            Some(&(0, l)) => (None, l),
            Some(&(f, l)) => (Some(self.files[f].as_path()), l),
            None => (None, line),
        }
    }

    /// A reader's error at an expanded line, moved to its file and line.
    pub fn locate(&self, mut e: ParseError) -> ParseError {
        if let Some(line) = e.line {
            let (file, l) = self.origin(line);
            e.line = Some(l);
            e.file = file.map(Path::to_path_buf);
        }
        e
    }

    /// Appends the lines of `text`, file `file` at include depth `depth`.
    fn add(
        &mut self,
        dialect: Dialect,
        text: &str,
        file: usize,
        depth: usize,
    ) -> Result<(), ParseError> {
        // a byte-order mark some editors write is no part of the deck
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text.lines().enumerate();
        while let Some((i, raw)) = lines.next() {
            let line = i + 1;
            // a keyword file ends at *END, an included one too (its *END ends it alone)
            if dialect == Dialect::Keyword
                && raw.starts_with('*')
                && super::lsdyna::keyword(raw) == "END"
            {
                if file == 0 {
                    self.text.push_str("*END\n");
                    self.lines.push((file, line));
                }
                break;
            }
            let include = match dialect {
                Dialect::Abaqus => include_target(raw),
                Dialect::Keyword => keyword_include(raw, &mut lines),
            };
            match include {
                None => {
                    self.text.push_str(raw);
                    self.text.push('\n');
                    self.lines.push((file, line));
                }
                Some(target) => {
                    let at = |m: String| ParseError {
                        line: Some(line),
                        file: (file > 0).then(|| self.files[file].clone()),
                        message: m,
                    };
                    let target = target.map_err(at)?;
                    let Some(folder) = (file > 0 || !self.files[0].as_os_str().is_empty())
                        .then(|| self.files[file].parent().unwrap_or(Path::new("")))
                    else {
                        return Err(at(
                            "*INCLUDE needs the deck to be read from a file (its folder finds the included file)".into(),
                        ));
                    };
                    let path = folder.join(&target);
                    if depth + 1 > MAX_DEPTH {
                        return Err(at(format!(
                            "*INCLUDE of {} is nested more than {MAX_DEPTH} deep (does a file include itself?)",
                            path.display()
                        )));
                    }
                    let text = crate::limits::read_input_text(&path).map_err(|e| {
                        at(format!("*INCLUDE: cannot read {}: {e}", path.display()))
                    })?;
                    if let Some((limit, why)) = crate::limits::input_limit()
                        .filter(|(l, _)| (self.text.len() + text.len()) as u64 > *l)
                    {
                        return Err(at(format!(
                            "*INCLUDE of {}: the deck with its includes grows past the {} an input may take ({why})",
                            path.display(),
                            crate::error::bytes(limit)
                        )));
                    }
                    self.files.push(path);
                    let index = self.files.len() - 1;
                    self.add(dialect, &text, index, depth + 1)?;
                }
            }
        }
        Ok(())
    }
}

/// For an LS-DYNA `*INCLUDE` keyword line, the file its next card names (taken from
/// `lines`, with any comment cards before it, and the cards a name ending in ` +` goes on
/// on), or what is wrong with it; `None` for any other line (`*INCLUDE_PATH` and the other
/// options are keywords of their own, which the reader refuses).
fn keyword_include<'a>(
    raw: &str,
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Option<Result<String, String>> {
    let rest = raw.trim_end().strip_prefix('*')?;
    if !rest.trim().eq_ignore_ascii_case("INCLUDE") {
        return None;
    }
    let mut name = String::new();
    for (_, card) in lines.by_ref() {
        if card.starts_with('$') || card.trim().is_empty() {
            continue;
        }
        if card.starts_with('*') {
            return Some(Err(format!(
                "*INCLUDE needs the file's name on the card after it, not the keyword `{}`",
                card.trim()
            )));
        }
        let card = card.trim();
        match card.strip_suffix(" +") {
            Some(head) => name.push_str(head.trim_end()),
            None => {
                name.push_str(card);
                return Some(Ok(name));
            }
        }
    }
    Some(Err(
        "*INCLUDE needs the file's name on the card after it".into()
    ))
}

/// For an `*INCLUDE` keyword line, the file it names (or what is wrong with it); `None` for
/// any other line.
fn include_target(raw: &str) -> Option<Result<String, String>> {
    let line = raw.trim();
    let rest = line.strip_prefix('*')?;
    if rest.starts_with('*') {
        return None;
    }
    let mut parts = rest.splitn(2, ',');
    if !parts.next()?.trim().eq_ignore_ascii_case("INCLUDE") {
        return None;
    }
    let params = parts.next().unwrap_or("");
    let input = params.split(',').find_map(|p| {
        let (k, v) = p.split_once('=')?;
        k.trim().eq_ignore_ascii_case("INPUT").then(|| v.trim())
    });
    Some(match input.map(|v| v.trim_matches('"')) {
        Some(v) if !v.is_empty() => Ok(v.to_string()),
        _ => Err("*INCLUDE needs INPUT=<file>".into()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn include_lines_are_recognised() {
        assert_eq!(
            include_target("*Include, input=\"nodes.inp\""),
            Some(Ok("nodes.inp".into()))
        );
        assert_eq!(
            include_target(" *INCLUDE,INPUT=a/b.inp "),
            Some(Ok("a/b.inp".into()))
        );
        assert!(matches!(include_target("*INCLUDE"), Some(Err(_))));
        assert_eq!(include_target("** *INCLUDE, INPUT=x"), None);
        assert_eq!(include_target("*NODE"), None);
    }

    #[test]
    fn keyword_includes_take_the_next_card() {
        let take = |text: &str| {
            let mut lines = text.lines().enumerate();
            let (_, first) = lines.next().unwrap();
            keyword_include(first, &mut lines)
        };
        assert_eq!(take("*INCLUDE\nmesh.k\n"), Some(Ok("mesh.k".into())));
        assert_eq!(
            take("*include\n$ the mesh\n  parts/a +\n/b.k\n"),
            Some(Ok("parts/a/b.k".into()))
        );
        assert_eq!(take("*INCLUDE_PATH\nparts\n"), None);
        assert!(matches!(take("*INCLUDE\n*NODE\n"), Some(Err(_))));
        assert!(matches!(take("*INCLUDE\n"), Some(Err(_))));
        assert_eq!(take("*NODE\n"), None);
    }

    #[test]
    fn an_include_without_a_file_is_refused() {
        let e = Deck::expand("*NODE\n*INCLUDE, INPUT=x.inp\n", None)
            .err()
            .unwrap();
        assert_eq!(e.line, Some(2));
        assert!(e.message.contains("from a file"), "{}", e.message);
    }
}
