//! How much memory this machine has left for what a command would hold: refusals before a
//! run that could not fit, instead of growing until the allocator aborts.

/// `MemAvailable` of /proc/meminfo (Linux); `None` where there is no such file.
pub fn available_bytes() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// The share of the available memory a command may plan to hold.
pub const USABLE_FRACTION: f64 = 0.8;
