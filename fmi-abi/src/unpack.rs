//! Where an FMU's files are: a `.fmu` zip unpacked into a temporary directory, or a directory
//! that already holds the unpacked layout (`modelDescription.xml`, `binaries/`, `resources/`).
//! The one unpacker of the workspace, for FMUs and SSP packages, the harness loader and the
//! test crates.
//!
//! Archives come from third parties, so unpacking refuses what could reach past the
//! extraction directory or exhaust the host: symbolic links, names outside the directory,
//! a name given twice (one copy would silently replace the other), more than [`MAX_ENTRIES`]
//! entries, and more than [`max_unpacked_bytes`] bytes in all, counted as they are written
//! (a zip header may declare fewer bytes than its data inflates to). A refused archive leaves
//! no directory behind.
use std::collections::HashSet;
use std::fmt;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use tempfile::TempDir;

/// The environment variable that sets the bound on the bytes one archive may unpack to,
/// unless [`set_max_unpacked_bytes`] was called.
pub const MAX_UNPACKED_BYTES_ENV: &str = "HARNESS_MAX_UNPACKED_BYTES";

/// 4 GiB: large FMUs carry tables, trained networks or binaries for several platforms in the
/// hundreds of megabytes; a bound well above them still stops a zip bomb before the disk
/// fills.
pub const DEFAULT_MAX_UNPACKED_BYTES: u64 = 4 << 30;

/// Source-code FMUs of large models hold some thousands of files; a hundred thousand empty
/// entries cost an attacker under 10 MB of archive and us as many inodes.
pub const MAX_ENTRIES: usize = 100_000;

static MAX_UNPACKED_BYTES: Mutex<Option<u64>> = Mutex::new(None);

/// Sets the bound on the bytes one archive may unpack to, for every archive unpacked after
/// the call; it takes precedence over [`MAX_UNPACKED_BYTES_ENV`].
pub fn set_max_unpacked_bytes(bytes: u64) {
    *MAX_UNPACKED_BYTES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner()) = Some(bytes);
}

/// The bound in force: [`set_max_unpacked_bytes`]'s, else [`MAX_UNPACKED_BYTES_ENV`]'s
/// (refused if it is not a size), else [`DEFAULT_MAX_UNPACKED_BYTES`].
pub fn max_unpacked_bytes() -> Result<u64, UnpackError> {
    let set = *MAX_UNPACKED_BYTES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(bytes) = set {
        return Ok(bytes);
    }
    match std::env::var(MAX_UNPACKED_BYTES_ENV) {
        Ok(text) => parse_byte_size(&text).map_err(|problem| UnpackError::Setting {
            variable: MAX_UNPACKED_BYTES_ENV,
            value: text,
            problem,
        }),
        Err(std::env::VarError::NotPresent) => Ok(DEFAULT_MAX_UNPACKED_BYTES),
        Err(std::env::VarError::NotUnicode(text)) => Err(UnpackError::Setting {
            variable: MAX_UNPACKED_BYTES_ENV,
            value: text.to_string_lossy().into_owned(),
            problem: "not text".to_owned(),
        }),
    }
}

/// A byte count as a user writes it: `1000000`, `500M`, `4GiB`, `2 G`. Decimal suffixes
/// (k, M, G, T) are powers of 1000, binary ones (Ki, Mi, Gi, Ti) of 1024; a trailing `B` is
/// optional.
pub fn parse_byte_size(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let digits = trimmed
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(trimmed.len());
    let (number, suffix) = trimmed.split_at(digits);
    let number: u64 = number
        .parse()
        .map_err(|_| format!("'{text}' is not a byte count (e.g. 4GiB, 500M, 1000000)"))?;
    let suffix = suffix.trim();
    let suffix = suffix.strip_suffix(['B', 'b']).unwrap_or(suffix);
    let factor: u64 = match suffix {
        "" => 1,
        "k" | "K" => 1000,
        "M" => 1000_u64.pow(2),
        "G" => 1000_u64.pow(3),
        "T" => 1000_u64.pow(4),
        "Ki" => 1 << 10,
        "Mi" => 1 << 20,
        "Gi" => 1 << 30,
        "Ti" => 1 << 40,
        _ => {
            return Err(format!(
                "'{text}': unknown unit '{suffix}' (k, M, G, T, Ki, Mi, Gi, Ti)"
            ))
        }
    };
    number
        .checked_mul(factor)
        .ok_or_else(|| format!("'{text}' is more bytes than 64 bits count"))
}

/// Why an FMU or SSP package could not be opened; every variant names the file.
#[derive(Debug)]
#[non_exhaustive]
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
    /// An entry that cannot be unpacked safely; nothing of the archive is left on disk.
    Entry {
        archive: PathBuf,
        entry: String,
        problem: EntryProblem,
    },
    /// A bound given in the environment that is not a byte count.
    Setting {
        variable: &'static str,
        value: String,
        problem: String,
    },
}

/// What is wrong with one entry of an archive.
#[derive(Debug)]
#[non_exhaustive]
pub enum EntryProblem {
    /// On unpacking it would become a link, e.g. to `/etc/passwd`, that the FMU then reads.
    Symlink { target: String },
    /// An absolute name or one with `..` reaching above the archive's root.
    OutsideDirectory,
    /// The name (after resolving `.` and repeated `/`) of an entry met before.
    Duplicate,
    /// The archive holds more than [`MAX_ENTRIES`] entries; this is the first one past.
    TooManyEntries { limit: usize },
    /// With this entry the archive unpacks past the bound in force.
    TooLarge { limit: u64, declared: bool },
    /// The data inflates to more bytes than the entry's header declares.
    LongerThanDeclared { declared: u64 },
    /// The data is corrupt (bad compression stream or checksum) or uses what we cannot read.
    Read(std::io::Error),
    /// Writing the file into the extraction directory failed.
    Write(std::io::Error),
}

impl fmt::Display for EntryProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EntryProblem::Symlink { target } => write!(
                f,
                "is a symbolic link (to '{target}'); links are refused, an archive must hold \
                 the files themselves"
            ),
            EntryProblem::OutsideDirectory => f.write_str(
                "would be written outside the extraction directory (an absolute name or one \
                 climbing out with '..')",
            ),
            EntryProblem::Duplicate => f.write_str(
                "is named twice in the archive; refused rather than letting one copy silently \
                 replace the other",
            ),
            EntryProblem::TooManyEntries { limit } => {
                write!(f, "is past the limit of {limit} entries in one archive")
            }
            EntryProblem::TooLarge { limit, declared } => write!(
                f,
                "{} the archive past the limit of {limit} bytes unpacked (set {} or the \
                 command's option to raise it)",
                if *declared {
                    "by its declared size takes"
                } else {
                    "takes"
                },
                MAX_UNPACKED_BYTES_ENV
            ),
            EntryProblem::LongerThanDeclared { declared } => write!(
                f,
                "unpacks to more than the {declared} bytes its header declares"
            ),
            EntryProblem::Read(_) => f.write_str("cannot be read (corrupt or unsupported data)"),
            EntryProblem::Write(_) => f.write_str("cannot be written to the extraction directory"),
        }
    }
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
            UnpackError::Entry {
                archive,
                entry,
                problem,
            } => write!(
                f,
                "archive {}: entry '{entry}' {problem}",
                archive.display()
            ),
            UnpackError::Setting {
                variable,
                value,
                problem,
            } => write!(f, "{variable}={value}: {problem}"),
        }
    }
}

impl std::error::Error for UnpackError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            UnpackError::Io { source, .. } => Some(source),
            UnpackError::Zip { source, .. } => Some(source),
            UnpackError::Entry {
                problem: EntryProblem::Read(source) | EntryProblem::Write(source),
                ..
            } => Some(source),
            UnpackError::MissingModelDescription { .. }
            | UnpackError::Entry { .. }
            | UnpackError::Setting { .. } => None,
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
    archive: Option<PathBuf>,
    /// Deleted on drop, so it lives as long as the loaded library that was read from it.
    _temp_dir: Option<TempDir>,
}

impl Unpacked {
    pub fn open(path: &Path) -> Result<Self, UnpackError> {
        Self::open_with(path, None)
    }

    /// [`Unpacked::open`] of the model description alone, for a reader that loads no
    /// binary: the archive's directory is checked as `open` checks it (names, links,
    /// duplicates, declared sizes), but only the one file is inflated and written.
    pub fn open_description(path: &Path) -> Result<Self, UnpackError> {
        Self::open_with(path, Some(Path::new("modelDescription.xml")))
    }

    fn open_with(path: &Path, only: Option<&Path>) -> Result<Self, UnpackError> {
        let unpacked = if path.is_dir() {
            Self {
                root: path.to_path_buf(),
                archive: None,
                _temp_dir: None,
            }
        } else {
            let temp_dir = unpack_bounded(path, "fmu-", max_unpacked_bytes()?, MAX_ENTRIES, only)?;
            Self {
                root: temp_dir.path().to_path_buf(),
                archive: Some(path.to_path_buf()),
                _temp_dir: Some(temp_dir),
            }
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

    /// The `.fmu` these files were unpacked from; `None` for a directory opened in place.
    pub fn archive(&self) -> Option<&Path> {
        self.archive.as_deref()
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

/// Unpacks the zip `archive` (an FMU or SSP package) into a new temporary directory whose name
/// starts with `prefix`, within [`max_unpacked_bytes`] and [`MAX_ENTRIES`]. The directory is
/// deleted when the returned value drops; on any error it is already gone.
pub fn unpack_archive(archive: &Path, prefix: &str) -> Result<TempDir, UnpackError> {
    unpack_archive_within(archive, prefix, max_unpacked_bytes()?)
}

/// [`unpack_archive`] with `max_bytes` instead of the bound in force.
pub fn unpack_archive_within(
    archive: &Path,
    prefix: &str,
    max_bytes: u64,
) -> Result<TempDir, UnpackError> {
    unpack_bounded(archive, prefix, max_bytes, MAX_ENTRIES, None)
}

/// Unpacks `archive` (only the entry at `only`, if given) after checking all of it.
fn unpack_bounded(
    archive: &Path,
    prefix: &str,
    max_bytes: u64,
    max_entries: usize,
    only: Option<&Path>,
) -> Result<TempDir, UnpackError> {
    let io_error = |source| UnpackError::Io {
        path: archive.to_path_buf(),
        source,
    };
    let zip_error = |source| UnpackError::Zip {
        path: archive.to_path_buf(),
        source,
    };
    let refuse = |entry: &str, problem| UnpackError::Entry {
        archive: archive.to_path_buf(),
        entry: entry.to_owned(),
        problem,
    };
    let file = File::open(archive).map_err(io_error)?;
    let mut zip = zip::ZipArchive::new(file).map_err(zip_error)?;
    // The zip crate keeps one entry per name, the last; only the central directory itself
    // still shows the other.
    let repeated =
        repeated_name(archive, zip.central_directory_start(), max_entries).map_err(io_error)?;
    if let Some(name) = repeated {
        return Err(refuse(&name, EntryProblem::Duplicate));
    }
    if zip.len() > max_entries {
        let name = zip
            .name_for_index(max_entries)
            .unwrap_or_default()
            .to_owned();
        return Err(refuse(
            &name,
            EntryProblem::TooManyEntries { limit: max_entries },
        ));
    }
    // The declared sizes refuse an honest large archive before a byte is written; the bytes
    // actually written are counted below all the same.
    let mut declared_total: u64 = 0;
    for index in 0..zip.len() {
        let entry = zip.by_index_raw(index).map_err(zip_error)?;
        declared_total = declared_total.saturating_add(entry.size());
        if declared_total > max_bytes {
            return Err(refuse(
                entry.name(),
                EntryProblem::TooLarge {
                    limit: max_bytes,
                    declared: true,
                },
            ));
        }
    }

    let temp_dir = tempfile::Builder::new()
        .prefix(prefix)
        .tempdir()
        .map_err(io_error)?;
    let root = temp_dir.path();
    let mut seen = HashSet::new();
    let mut written: u64 = 0;
    let mut buffer = vec![0; 64 * 1024];
    for index in 0..zip.len() {
        let name = zip.name_for_index(index).unwrap_or_default().to_owned();
        let mut entry = zip.by_index(index).map_err(|source| {
            refuse(
                &name,
                EntryProblem::Read(std::io::Error::new(std::io::ErrorKind::InvalidData, source)),
            )
        })?;
        if entry.is_symlink() {
            let mut target = Vec::new();
            // A link's data is its target; only the start of it matters for the message.
            let _ = (&mut entry).take(1024).read_to_end(&mut target);
            return Err(refuse(
                &name,
                EntryProblem::Symlink {
                    target: String::from_utf8_lossy(&target).into_owned(),
                },
            ));
        }
        let Some(relative) = contained_path(&name) else {
            return Err(refuse(&name, EntryProblem::OutsideDirectory));
        };
        if relative.as_os_str().is_empty() {
            continue;
        }
        if !seen.insert(relative.clone()) {
            return Err(refuse(&name, EntryProblem::Duplicate));
        }
        if only.is_some_and(|only| relative != only) {
            continue;
        }
        let target = root.join(&relative);
        let write_error = |source| refuse(&name, EntryProblem::Write(source));
        if entry.is_dir() {
            std::fs::create_dir_all(&target).map_err(write_error)?;
            continue;
        }
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(write_error)?;
        }
        // `create_new`: a name that reaches an existing file another way (a case-insensitive
        // file system) is a duplicate too, never an overwrite.
        let mut out = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&target)
            .map_err(|source| match source.kind() {
                std::io::ErrorKind::AlreadyExists => refuse(&name, EntryProblem::Duplicate),
                _ => refuse(&name, EntryProblem::Write(source)),
            })?;
        let declared = entry.size();
        let mut length: u64 = 0;
        loop {
            let count = entry
                .read(&mut buffer)
                .map_err(|source| refuse(&name, EntryProblem::Read(source)))?;
            if count == 0 {
                break;
            }
            length += count as u64;
            written += count as u64;
            if written > max_bytes {
                return Err(refuse(
                    &name,
                    EntryProblem::TooLarge {
                        limit: max_bytes,
                        declared: false,
                    },
                ));
            }
            if length > declared {
                return Err(refuse(&name, EntryProblem::LongerThanDeclared { declared }));
            }
            out.write_all(&buffer[..count]).map_err(write_error)?;
        }
        #[cfg(unix)]
        if entry.unix_mode().is_some_and(|mode| mode & 0o111 != 0) {
            // Executable bits only: setuid, setgid and world-writable modes are not carried
            // over from a stranger's archive.
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o755))
                .map_err(write_error)?;
        }
    }
    Ok(temp_dir)
}

/// `name` as a path inside the extraction directory, `..` resolved by name alone (no link is
/// ever created, so a name means what it says); `None` if it would leave the directory.
fn contained_path(name: &str) -> Option<PathBuf> {
    if name.contains('\0') {
        return None;
    }
    let mut path = PathBuf::new();
    for component in Path::new(name).components() {
        match component {
            std::path::Component::Normal(part) => path.push(part),
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                if !path.pop() {
                    return None;
                }
            }
            std::path::Component::RootDir | std::path::Component::Prefix(_) => return None,
        }
    }
    Some(path)
}

/// The first name that two central directory records share, read from the records
/// themselves (as many as `max_entries` and one).
fn repeated_name(
    archive: &Path,
    directory_start: u64,
    max_entries: usize,
) -> std::io::Result<Option<String>> {
    const SIGNATURE: [u8; 4] = [0x50, 0x4b, 0x01, 0x02];
    const FIXED: usize = 46;
    let mut reader = BufReader::new(File::open(archive)?);
    reader.seek(SeekFrom::Start(directory_start))?;
    let mut names = HashSet::new();
    let mut record = [0u8; FIXED];
    for _ in 0..=max_entries {
        if reader.read_exact(&mut record).is_err() || record[..4] != SIGNATURE {
            break;
        }
        let field = |at: usize| u64::from(u16::from_le_bytes([record[at], record[at + 1]]));
        let (name_length, extra_length, comment_length) = (field(28), field(30), field(32));
        let mut name = vec![0u8; name_length as usize];
        reader.read_exact(&mut name)?;
        reader.seek_relative((extra_length + comment_length) as i64)?;
        if !names.insert(name.clone()) {
            return Ok(Some(String::from_utf8_lossy(&name).into_owned()));
        }
    }
    Ok(None)
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
    use zip::write::SimpleFileOptions;

    fn archive_of(dir: &Path, entries: &[(&str, &[u8])]) -> PathBuf {
        let path = dir.join("test.zip");
        let mut zip = zip::ZipWriter::new(File::create(&path).unwrap());
        let options =
            SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        for (name, data) in entries {
            zip.start_file(*name, options).unwrap();
            zip.write_all(data).unwrap();
        }
        zip.finish().unwrap();
        path
    }

    fn refusal(result: Result<TempDir, UnpackError>) -> (String, EntryProblem) {
        match result {
            Err(UnpackError::Entry { entry, problem, .. }) => (entry, problem),
            other => panic!("expected a refused entry, got {other:?}"),
        }
    }

    #[test]
    fn byte_sizes_are_read_with_decimal_and_binary_units() {
        assert_eq!(parse_byte_size("1000"), Ok(1000));
        assert_eq!(parse_byte_size("4GiB"), Ok(4 << 30));
        assert_eq!(parse_byte_size(" 500 M "), Ok(500_000_000));
        assert_eq!(parse_byte_size("2k"), Ok(2000));
        assert_eq!(parse_byte_size("3Mi"), Ok(3 << 20));
        assert!(parse_byte_size("4 parsecs").is_err());
        assert!(parse_byte_size("-1").is_err());
        assert!(parse_byte_size("99999999999T").is_err());
    }

    #[test]
    fn names_resolve_inside_the_directory_or_not_at_all() {
        assert_eq!(contained_path("a/./b//c"), Some(PathBuf::from("a/b/c")));
        assert_eq!(contained_path("a/../b"), Some(PathBuf::from("b")));
        assert_eq!(contained_path("a/../../b"), None);
        assert_eq!(contained_path("/etc/passwd"), None);
        assert_eq!(contained_path("a\0b"), None);
    }

    #[test]
    fn one_name_reached_two_ways_is_a_duplicate() {
        let dir = TempDir::new().unwrap();
        let path = archive_of(dir.path(), &[("a/b.txt", b"1"), ("a/./b.txt", b"2")]);
        let (entry, problem) = refusal(unpack_archive_within(&path, "test-", 1 << 20));
        assert_eq!(entry, "a/./b.txt");
        assert!(matches!(problem, EntryProblem::Duplicate), "{problem:?}");
    }

    #[test]
    fn the_bound_counts_what_is_written_and_a_header_that_lies_is_caught() {
        let dir = TempDir::new().unwrap();
        let zeros = vec![0u8; 1 << 20];
        let path = archive_of(dir.path(), &[("small", b"x"), ("zeros", &zeros)]);
        let (entry, problem) = refusal(unpack_archive_within(&path, "test-", 1000));
        assert_eq!(entry, "zeros");
        assert!(
            matches!(
                problem,
                EntryProblem::TooLarge {
                    limit: 1000,
                    declared: true
                }
            ),
            "{problem:?}"
        );
        assert!(unpack_archive_within(&path, "test-", (1 << 20) + 1).is_ok());

        // The same archive with both headers of `zeros` declaring 10 bytes (CRC unchanged).
        let mut bytes = std::fs::read(&path).unwrap();
        let declared = (1u32 << 20).to_le_bytes();
        let mut patched = 0;
        for at in 0..bytes.len() - 4 {
            if bytes[at..at + 4] == declared {
                bytes[at..at + 4].copy_from_slice(&10u32.to_le_bytes());
                patched += 1;
            }
        }
        assert_eq!(patched, 2, "local and central header");
        std::fs::write(&path, bytes).unwrap();
        // The declared total passes any bound above 11 bytes; the bytes written do not.
        let (entry, problem) = refusal(unpack_archive_within(&path, "test-", 1000));
        assert_eq!(entry, "zeros");
        assert!(
            matches!(
                problem,
                EntryProblem::TooLarge {
                    limit: 1000,
                    declared: false
                }
            ),
            "{problem:?}"
        );
        // Within the bound, the lie itself is refused.
        let (entry, problem) = refusal(unpack_archive_within(&path, "test-", 2 << 20));
        assert_eq!(entry, "zeros");
        assert!(
            matches!(problem, EntryProblem::LongerThanDeclared { declared: 10 }),
            "{problem:?}"
        );
    }

    #[test]
    fn more_entries_than_the_bound_are_refused() {
        let dir = TempDir::new().unwrap();
        let names: Vec<String> = (0..=10).map(|i| format!("e{i}")).collect();
        let entries: Vec<(&str, &[u8])> = names.iter().map(|n| (n.as_str(), &b""[..])).collect();
        let path = archive_of(dir.path(), &entries);
        assert!(unpack_bounded(&path, "test-", 1 << 20, 11, None).is_ok());
        let (entry, problem) = refusal(unpack_bounded(&path, "test-", 1 << 20, 10, None));
        assert_eq!(entry, "e10");
        assert!(
            matches!(problem, EntryProblem::TooManyEntries { .. }),
            "{problem:?}"
        );
    }

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
