//! Where an FMU's files are: a `.fmu` zip unpacked into a temporary directory, or a directory
//! that already holds the unpacked layout (`modelDescription.xml`, `binaries/`, `resources/`).
//! The one unpacker of the workspace, for the harness loader and the test crates.
use std::fmt;
use std::fs::File;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// Why an FMU could not be opened; every variant names the file.
#[derive(Debug)]
pub enum UnpackError {
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    Zip {
        path: PathBuf,
        source: zip::result::ZipError,
    },
    MissingModelDescription {
        path: PathBuf,
    },
}

impl fmt::Display for UnpackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnpackError::Io { path, .. } => write!(f, "cannot read FMU {}", path.display()),
            UnpackError::Zip { path, .. } => {
                write!(f, "FMU {} is not a readable zip archive", path.display())
            }
            UnpackError::MissingModelDescription { path } => write!(
                f,
                "FMU {} has no modelDescription.xml at its top level",
                path.display()
            ),
        }
    }
}

impl std::error::Error for UnpackError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            UnpackError::Io { source, .. } => Some(source),
            UnpackError::Zip { source, .. } => Some(source),
            UnpackError::MissingModelDescription { .. } => None,
        }
    }
}

/// Platform folder and shared-library extension of the FMI 2.0 binary layout on this host.
#[cfg(target_os = "linux")]
pub const FMI2_PLATFORM: (&str, &str) = ("linux64", "so");
#[cfg(target_os = "macos")]
pub const FMI2_PLATFORM: (&str, &str) = ("darwin64", "dylib");
#[cfg(target_os = "windows")]
pub const FMI2_PLATFORM: (&str, &str) = ("win64", "dll");

/// An FMU's files on disk; a temporary copy is deleted on drop, so keep this as long as a
/// library loaded from it.
#[derive(Debug)]
pub struct Unpacked {
    root: PathBuf,
    /// Deleted on drop, so it lives as long as the loaded library that was read from it.
    _temp_dir: Option<TempDir>,
}

impl Unpacked {
    pub fn open(path: &Path) -> Result<Self, UnpackError> {
        let unpacked = if path.is_dir() {
            Self {
                root: path.to_path_buf(),
                _temp_dir: None,
            }
        } else {
            unzip(path)?
        };
        if !unpacked.model_description_path().is_file() {
            return Err(UnpackError::MissingModelDescription {
                path: path.to_path_buf(),
            });
        }
        Ok(unpacked)
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    pub fn model_description_path(&self) -> PathBuf {
        self.root.join("modelDescription.xml")
    }

    pub fn binary_path(&self, model_identifier: &str) -> PathBuf {
        let (platform, extension) = FMI2_PLATFORM;
        self.root
            .join("binaries")
            .join(platform)
            .join(format!("{model_identifier}.{extension}"))
    }

    /// The `fmi2Instantiate` resource location: a `file:` URI of the `resources` folder.
    pub fn resource_uri(&self) -> String {
        file_uri(&self.root.join("resources"))
    }
}

fn unzip(path: &Path) -> Result<Unpacked, UnpackError> {
    let io_error = |source| UnpackError::Io {
        path: path.to_path_buf(),
        source,
    };
    let zip_error = |source| UnpackError::Zip {
        path: path.to_path_buf(),
        source,
    };
    let file = File::open(path).map_err(io_error)?;
    let mut archive = zip::ZipArchive::new(file).map_err(zip_error)?;
    let temp_dir = tempfile::Builder::new()
        .prefix("fmu-")
        .tempdir()
        .map_err(io_error)?;
    // `extract` refuses entries whose names escape the target directory (zip slip).
    archive.extract(temp_dir.path()).map_err(zip_error)?;
    Ok(Unpacked {
        root: temp_dir.path().to_path_buf(),
        _temp_dir: Some(temp_dir),
    })
}

/// `file://` + the absolute path, percent-encoding every byte outside RFC 3986's unreserved
/// set and `/`, so paths with spaces or non-ASCII names survive the FMU's URI parser.
pub fn file_uri(path: &Path) -> String {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut uri = String::from("file://");
    let text = absolute.to_string_lossy().replace('\\', "/");
    if !text.starts_with('/') {
        uri.push('/');
    }
    for byte in text.bytes() {
        match byte {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' => {
                uri.push(byte as char)
            }
            // A Windows drive letter's colon stays literal in file URIs.
            b':' => uri.push(':'),
            _ => uri.push_str(&format!("%{byte:02X}")),
        }
    }
    uri
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resource_uri_percent_encodes_spaces_and_non_ascii() {
        let uri = file_uri(Path::new("/tmp/my fmu/été/resources"));
        assert_eq!(uri, "file:///tmp/my%20fmu/%C3%A9t%C3%A9/resources");
    }

    #[test]
    fn resource_uri_of_a_plain_path_is_unchanged() {
        assert_eq!(
            file_uri(Path::new("/a/b_c-d.e~f/resources")),
            "file:///a/b_c-d.e~f/resources"
        );
    }
}
