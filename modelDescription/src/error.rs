//! Errors of reading and writing a model description. Each variant that comes from a file
//! says where (line, element, attribute) so a user can fix the file from the message alone.
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    #[error("cannot read {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// The text is not well-formed XML (truncated, mismatched tags, bad characters).
    #[error(
        "line {line}, column {column}: not well-formed XML{}: {message}",
        inside_clause(.inside)
    )]
    Malformed {
        line: u64,
        column: u64,
        /// The innermost open element, described as in [`Error::Invalid`].
        inside: Option<String>,
        message: String,
    },

    /// A document type or entity declaration, refused before the file is parsed: FMI and
    /// SSP descriptions have none, and its entities could expand without bound.
    #[error(
        "line {line}: <!{keyword} ...>: a document type or entity declaration; FMI and SSP \
         descriptions have none, and entity expansion could exhaust memory, so the file is \
         refused unparsed"
    )]
    Declaration { line: u64, keyword: String },

    #[error("root element is <{found}>, expected <fmiModelDescription>")]
    WrongRoot { found: String },

    /// Well-formed XML that breaks the FMI 2.0 schema at a known place.
    #[error("line {line}: {element}{}: {problem}", attribute_clause(.attribute))]
    Invalid {
        line: u64,
        /// E.g. `ScalarVariable 'x' (index 3) > Real`.
        element: String,
        attribute: Option<String>,
        problem: String,
    },

    /// The schema mapping failed where the diagnosis pass found nothing to point at.
    #[error("cannot map the file onto the FMI 2.0 model description: {0}")]
    Unmapped(String),

    #[error("cannot write the model description: {0}")]
    Write(String),
}

impl Error {
    /// The event reader's error, with its place and the innermost open element of `stack`.
    pub(crate) fn malformed(error: &xml::reader::Error, stack: &[String]) -> Self {
        let position = xml::common::Position::position(error);
        Error::Malformed {
            line: position.row + 1,
            column: position.column + 1,
            inside: stack.last().cloned(),
            message: error.to_string(),
        }
    }
}

fn inside_clause(inside: &Option<String>) -> String {
    inside
        .as_ref()
        .map(|element| format!(" (inside {element})"))
        .unwrap_or_default()
}

fn attribute_clause(attribute: &Option<String>) -> String {
    attribute
        .as_ref()
        .map(|name| format!(": attribute {name}"))
        .unwrap_or_default()
}
