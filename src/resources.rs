//! Resource accounting for reports and benchmarks: memory of this process and wall-clock time
//! per phase.
//!
//! Memory comes from Linux's `/proc/self/status` (proc(5)): `VmRSS` is the resident set size
//! now, `VmHWM` its high-water mark since the process started. Both are given in kB (KiB) there;
//! we return bytes. On other systems, or if the file cannot be read, the functions return `None`.
//!
//! Phase times are wall-clock seconds from [`std::time::Instant`] (monotonic), kept in the order
//! the phases first ran:
//!
//! ```text
//!   timings.time("mesh", || ...)      phases: [("mesh", 0.12), ("assemble", 0.40)]
//!   timings.time("assemble", || ...)  JSON:   {"mesh": 0.12, "assemble": 0.40, "total": 0.52}
//! ```
use std::time::Instant;

/// Peak resident memory of this process (`VmHWM`), in bytes.
pub fn peak_memory_bytes() -> Option<u64> {
    status_field_bytes("VmHWM")
}

/// Reset the peak (VmHWM) to the current resident size (Linux: `5` into
/// `/proc/self/clear_refs`); returns false where that is not possible.
pub fn reset_peak_memory() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Current resident memory of this process (`VmRSS`), in bytes.
pub fn current_memory_bytes() -> Option<u64> {
    status_field_bytes("VmRSS")
}

/// The memory the system can give new work without swapping (`MemAvailable` in
/// `/proc/meminfo`), in bytes.
pub fn available_memory_bytes() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_status_field(&info, "MemAvailable")
}

/// Reads a line such as `VmHWM:    12345 kB` from `/proc/self/status`.
fn status_field_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_status_field(&status, field)
}

fn parse_status_field(status: &str, field: &str) -> Option<u64> {
    status.lines().find_map(|line| {
        let rest = line.strip_prefix(field)?.strip_prefix(':')?;
        let mut words = rest.split_whitespace();
        let value: u64 = words.next()?.parse().ok()?;
        match words.next() {
            Some("kB") => value.checked_mul(1024),
            _ => None,
        }
    })
}

/// Wall-clock seconds per named phase, in the order the phases were first recorded.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Timings {
    phases: Vec<(String, f64)>,
}

impl Timings {
    /// No phase timed yet.
    pub fn new() -> Self {
        Timings::default()
    }

    /// Run `f`, add its wall-clock time to `phase`, and return its result.
    pub fn time<T>(&mut self, phase: &str, f: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let result = f();
        self.add(phase, start.elapsed().as_secs_f64());
        result
    }

    /// Add `seconds` to `phase` (a repeated phase accumulates; a new one goes last).
    pub fn add(&mut self, phase: &str, seconds: f64) {
        match self.phases.iter_mut().find(|(name, _)| name == phase) {
            Some((_, total)) => *total += seconds,
            None => self.phases.push((phase.to_string(), seconds)),
        }
    }

    /// Seconds recorded for `phase`, if it ran.
    pub fn get(&self, phase: &str) -> Option<f64> {
        self.phases.iter().find(|(name, _)| name == phase).map(|&(_, s)| s)
    }

    /// Sum over all phases.
    pub fn total(&self) -> f64 {
        // A fold from +0.0: `sum` of no floats is -0.0.
        self.phases.iter().fold(0.0, |acc, &(_, s)| acc + s)
    }

    /// `(phase, seconds)` in the order the phases were first recorded.
    pub fn phases(&self) -> &[(String, f64)] {
        &self.phases
    }
}

/// A JSON object `{phase: seconds, ..., "total": sum}` in recording order. A phase itself named
/// `total` would clash with the sum: then only the phase is written.
impl serde::Serialize for Timings {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let has_total_phase = self.get("total").is_some();
        let mut map = serializer.serialize_map(Some(self.phases.len() + usize::from(!has_total_phase)))?;
        for (name, seconds) in &self.phases {
            map.serialize_entry(name, seconds)?;
        }
        if !has_total_phase {
            map.serialize_entry("total", &self.total())?;
        }
        map.end()
    }
}

#[cfg(test)]
mod tests {
    use super::parse_status_field;

    #[test]
    fn parses_kilobyte_fields_only() {
        let status = "Name:\tx\nVmHWM:\t    2048 kB\nVmRSS:\t 1 kB\nVmBad:\t12\nThreads:\t1\n";
        assert_eq!(parse_status_field(status, "VmHWM"), Some(2048 * 1024));
        assert_eq!(parse_status_field(status, "VmRSS"), Some(1024));
        assert_eq!(parse_status_field(status, "VmBad"), None);
        assert_eq!(parse_status_field(status, "VmSwap"), None);
        assert_eq!(parse_status_field(status, "Vm"), None);
    }
}
