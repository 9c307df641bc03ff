//! [`ParseError`]: what a mesh or deck reader reports.

/// A reader's error: the 1-based line it concerns (where there is one) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct ParseError {
    pub line: Option<usize>,
    /// The file the line is in, when it is not the one being read (a deck's `*INCLUDE`).
    pub file: Option<std::path::PathBuf>,
    pub message: String,
}

impl ParseError {
    pub fn at(line: usize, message: impl Into<String>) -> ParseError {
        ParseError {
            line: Some(line),
            file: None,
            message: message.into(),
        }
    }

    pub fn whole(message: impl Into<String>) -> ParseError {
        ParseError {
            line: None,
            file: None,
            message: message.into(),
        }
    }
}
