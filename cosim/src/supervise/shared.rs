//! Files both processes map: the worker's black box of its last FMI call, and the ring its
//! recorded rows pass through. A row or a call written there is readable by the parent even
//! after the worker died in the middle of the next one.
#![allow(unsafe_code)]

use std::fs::{File, OpenOptions};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// A file mapped shared and writable; unmapped on drop. memmap2 maps it the platform's
/// way (mmap, or a Windows file mapping), so both processes see one memory on either.
pub(super) struct Mapping {
    // Kept for its drop, which unmaps; every access goes through `pointer`.
    _map: memmap2::MmapMut,
    pointer: *mut u8,
}

// The mapping is plain memory; its users synchronise through atomics and the pipe.
unsafe impl Send for Mapping {}

impl Mapping {
    /// Creates (or truncates) `path` to `len` bytes of zeros and maps it.
    pub(super) fn create(path: &Path, len: usize) -> std::io::Result<Self> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(path)?;
        file.set_len(len.max(1) as u64)?;
        Self::map(&file, len)
    }

    /// Maps an existing file of at least `len` bytes.
    pub(super) fn open(path: &Path, len: usize) -> std::io::Result<Self> {
        let file = OpenOptions::new().read(true).write(true).open(path)?;
        if file.metadata()?.len() < len as u64 {
            return Err(std::io::Error::new(
                std::io::ErrorKind::UnexpectedEof,
                format!("{} is shorter than {len} bytes", path.display()),
            ));
        }
        Self::map(&file, len)
    }

    fn map(file: &File, len: usize) -> std::io::Result<Self> {
        // SAFETY: the file is the supervisor's own, in a directory only it and its worker
        // use; the two processes coordinate every access through atomics and the pipe, so
        // no one truncates it while it is mapped.
        let mut map = unsafe { memmap2::MmapOptions::new().len(len.max(1)).map_mut(file)? };
        let pointer = map.as_mut_ptr();
        Ok(Self { _map: map, pointer })
    }

    pub(super) fn as_ptr(&self) -> *mut u8 {
        self.pointer
    }
}

/// The black box: [`fmi_import::blackbox::Record`] in a mapped file.
pub(super) struct BlackBox(Mapping);

impl BlackBox {
    pub(super) const LEN: usize = 4096;

    pub(super) fn create(path: &Path) -> std::io::Result<Self> {
        const { assert!(std::mem::size_of::<fmi_import::blackbox::Record>() <= Self::LEN) };
        Ok(Self(Mapping::create(path, Self::LEN)?))
    }

    pub(super) fn open(path: &Path) -> std::io::Result<Self> {
        Ok(Self(Mapping::open(path, Self::LEN)?))
    }

    pub(super) fn record(&self) -> &fmi_import::blackbox::Record {
        // SAFETY: page-aligned, long enough (checked at compile time above), and a record
        // of atomics is valid for any bytes.
        unsafe { &*self.0.as_ptr().cast() }
    }

    /// Makes this process's FMI calls write here (the worker, once).
    pub(super) fn install(self) {
        let pointer = self.0.as_ptr().cast();
        // The mapping must outlive every later call: it is never unmapped.
        std::mem::forget(self);
        // SAFETY: mapped for the rest of the process, aligned and long enough.
        unsafe { fmi_import::blackbox::install(pointer) };
    }

    pub(super) fn last_call(&self) -> Option<fmi_import::blackbox::LastCall> {
        fmi_import::blackbox::read(self.record())
    }
}

/// The rows of a run on their way to the parent: a ring of two halves of `capacity` rows of
/// `1 + width` values (time first). Row `k` of a run sits in slot `k % (2 capacity)`; the
/// worker writes row `k` only once the parent has taken every row before `k - 2 capacity + 1`,
/// so the rows the parent has not taken are all still there, whenever the worker stops.
pub(super) struct Ring {
    mapping: Mapping,
    pub(super) width: usize,
    pub(super) capacity: usize,
}

/// Bytes of the ring's header: the row count written so far, then padding.
const HEADER: usize = 64;
/// Bytes a half of the ring aims at: every hand-over wakes both processes, so a wide paper
/// flight (91 columns, 12.5 MB) takes six, a campaign flight one.
const HALF_BYTES: usize = 2 << 20;

impl Ring {
    pub(super) fn capacity_for(width: usize) -> usize {
        (HALF_BYTES / (8 * (1 + width))).max(1)
    }

    fn len(width: usize, capacity: usize) -> usize {
        HEADER + 2 * capacity * (1 + width) * 8
    }

    pub(super) fn create(path: &Path, width: usize) -> std::io::Result<Self> {
        let capacity = Self::capacity_for(width);
        Ok(Self {
            mapping: Mapping::create(path, Self::len(width, capacity))?,
            width,
            capacity,
        })
    }

    pub(super) fn open(path: &Path, width: usize, capacity: usize) -> std::io::Result<Self> {
        Ok(Self {
            mapping: Mapping::open(path, Self::len(width, capacity))?,
            width,
            capacity,
        })
    }

    fn written_counter(&self) -> &AtomicU64 {
        // SAFETY: the header starts the page-aligned mapping.
        unsafe { &*self.mapping.as_ptr().cast::<AtomicU64>() }
    }

    /// Rows written in the current run.
    pub(super) fn written(&self) -> u64 {
        self.written_counter().load(Ordering::Acquire)
    }

    pub(super) fn set_written(&self, rows: u64) {
        self.written_counter().store(rows, Ordering::Release);
    }

    fn slot(&self, row: u64) -> *mut f64 {
        let index = (row % (2 * self.capacity as u64)) as usize;
        // SAFETY: inside the mapping: index < 2 capacity, and the data follows the header.
        unsafe {
            self.mapping
                .as_ptr()
                .add(HEADER)
                .cast::<f64>()
                .add(index * (1 + self.width))
        }
    }

    /// Writes row `row` (the worker; the caller respects the parent's credit).
    pub(super) fn write(&self, row: u64, time: f64, values: &[f64]) {
        debug_assert_eq!(values.len(), self.width);
        let slot = self.slot(row);
        // SAFETY: the slot holds 1 + width values, and the parent does not read it now.
        unsafe {
            slot.write(time);
            std::ptr::copy_nonoverlapping(values.as_ptr(), slot.add(1), self.width);
        }
        self.set_written(row + 1);
    }

    /// Row `row` as (time, values) (the parent, for a row the worker has written).
    pub(super) fn read(&self, row: u64) -> (f64, &[f64]) {
        let slot = self.slot(row);
        // SAFETY: the slot holds 1 + width values the worker wrote before it said so.
        unsafe {
            (
                slot.read(),
                std::slice::from_raw_parts(slot.add(1), self.width),
            )
        }
    }
}
