//! A reproducible FMU archive: entries sorted by path, fixed timestamps and permissions,
//! so the same inputs give the same bytes.
use anyhow::{Context, Result};
use std::io::Write;
use std::path::Path;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

pub struct Entry {
    pub path: String,
    pub bytes: Vec<u8>,
    pub unix_mode: u32,
}

impl Entry {
    pub fn file(path: impl Into<String>, bytes: Vec<u8>) -> Self {
        Self {
            path: path.into(),
            bytes,
            unix_mode: 0o644,
        }
    }

    pub fn executable(path: impl Into<String>, bytes: Vec<u8>) -> Self {
        Self {
            path: path.into(),
            bytes,
            unix_mode: 0o755,
        }
    }
}

/// Archive bytes for `entries`, in path order, dated 1980-01-01 (the zip epoch).
pub fn archive(mut entries: Vec<Entry>) -> Result<Vec<u8>> {
    entries.sort_by(|a, b| a.path.cmp(&b.path));
    let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for entry in &entries {
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Deflated)
            .last_modified_time(DateTime::default())
            .unix_permissions(entry.unix_mode);
        zip.start_file(entry.path.as_str(), options)
            .with_context(|| format!("cannot add {}", entry.path))?;
        zip.write_all(&entry.bytes)?;
    }
    Ok(zip.finish()?.into_inner())
}

/// Write the archive to `path` through a temporary file, so a reader never sees half an FMU.
pub fn write(path: &Path, entries: Vec<Entry>) -> Result<()> {
    let bytes = archive(entries)?;
    let partial = path.with_extension("fmu.partial");
    std::fs::write(&partial, bytes)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    std::fs::rename(&partial, path).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    fn sample() -> Vec<Entry> {
        vec![
            Entry::file("modelDescription.xml", b"<xml/>".to_vec()),
            Entry::executable("binaries/linux64/M.so", vec![0x7f, b'E', b'L', b'F']),
            Entry::file("documentation/index.html", b"<html/>".to_vec()),
        ]
    }

    #[test]
    fn same_entries_in_any_order_give_identical_bytes() {
        let forward = archive(sample()).unwrap();
        let mut reversed = sample();
        reversed.reverse();
        assert_eq!(forward, archive(reversed).unwrap());
    }

    #[test]
    fn archive_reads_back_sorted_with_contents_modes_and_fixed_time() {
        let bytes = archive(sample()).unwrap();
        let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        assert_eq!(zip.len(), 3);
        for expected in sample() {
            let mut file = zip.by_name(&expected.path).unwrap();
            let mut contents = Vec::new();
            file.read_to_end(&mut contents).unwrap();
            assert_eq!(contents, expected.bytes, "{}", expected.path);
            assert_eq!(file.unix_mode().unwrap() & 0o777, expected.unix_mode);
            assert_eq!(file.last_modified(), Some(DateTime::default()));
        }
        let order: Vec<_> = (0..zip.len())
            .map(|i| zip.by_index(i).unwrap().name().to_owned())
            .collect();
        let mut sorted = order.clone();
        sorted.sort();
        assert_eq!(order, sorted);
    }
}
