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

/// Rewrites the archive at `path` with `entries` added, replacing those of the same paths,
/// all in path order as [`archive`] writes them. The other entries are copied as they are
/// compressed: deflating the libraries again would cost seconds per FMU.
pub fn add(path: &Path, entries: Vec<Entry>) -> Result<()> {
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    let mut old =
        zip::ZipArchive::new(file).with_context(|| format!("cannot read {}", path.display()))?;
    // (path, the old entry's index or the new entry's)
    let mut order: Vec<(String, Result<usize, usize>)> = Vec::new();
    for i in 0..old.len() {
        let name = old.name_for_index(i).unwrap_or_default().to_owned();
        if !entries.iter().any(|e| e.path == name) {
            order.push((name, Ok(i)));
        }
    }
    order.extend(
        entries
            .iter()
            .enumerate()
            .map(|(j, e)| (e.path.clone(), Err(j))),
    );
    order.sort_by(|a, b| a.0.cmp(&b.0));
    let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for (name, source) in order {
        match source {
            Ok(i) => zip
                .raw_copy_file(old.by_index_raw(i)?)
                .with_context(|| format!("cannot copy {name} of {}", path.display()))?,
            Err(j) => {
                let entry = &entries[j];
                let options = SimpleFileOptions::default()
                    .compression_method(CompressionMethod::Deflated)
                    .last_modified_time(DateTime::default())
                    .unix_permissions(entry.unix_mode);
                zip.start_file(entry.path.as_str(), options)
                    .with_context(|| format!("cannot add {}", entry.path))?;
                zip.write_all(&entry.bytes)?;
            }
        }
    }
    let bytes = zip.finish()?.into_inner();
    let partial = path.with_extension("fmu.partial");
    std::fs::write(&partial, bytes)
        .with_context(|| format!("cannot write {}", partial.display()))?;
    std::fs::rename(&partial, path).with_context(|| format!("cannot write {}", path.display()))
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
    fn added_entries_join_the_archive_and_replace_those_of_their_path() {
        let dir = std::env::temp_dir().join(format!("fmu_zip_add_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("M.fmu");
        write(&path, sample()).unwrap();
        add(
            &path,
            vec![
                Entry::file("extra/a/x.csv", b"time\n".to_vec()),
                Entry::file("modelDescription.xml", b"<new/>".to_vec()),
            ],
        )
        .unwrap();
        let mut expected = sample();
        expected[0].bytes = b"<new/>".to_vec();
        expected.push(Entry::file("extra/a/x.csv", b"time\n".to_vec()));
        assert_eq!(std::fs::read(&path).unwrap(), archive(expected).unwrap());
        std::fs::remove_dir_all(&dir).unwrap();
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
