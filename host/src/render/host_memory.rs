//! Whether a render's per-pixel buffers fit the host's memory, checked before the CPU backend
//! allocates them. Beyond it an allocation aborted the process with a backtrace (16384×16384
//! under a 4 GB limit: "memory allocation of 6442450944 bytes failed"), or, where Linux
//! overcommits, its OOM killer would end the render midway; now it is one line.

use super::RenderError;

/// Host bytes a pixel of a render on the CPU backend takes at its peak, with a margin: measured
/// 94 for `pt` and 113 for `naive` (the peak resident memory of 4096×2048 renders less that of
/// 64×64 ones, `/usr/bin/time -f %M`): the backend's f64 image, the renderer's sums, the pixel
/// importance, the EXR and PNG being written.
pub const BYTES_PER_PIXEL: u64 = 128;

/// `MemAvailable` of a `/proc/meminfo` text, in bytes.
pub fn parse_mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// The host's available memory in bytes (Linux's `MemAvailable`), or `None` where it cannot be
/// read, which leaves renders unchecked.
pub fn available() -> Option<u64> {
    parse_mem_available(&std::fs::read_to_string("/proc/meminfo").ok()?)
}

/// Refuses a `width`×`height` render on the CPU backend whose pixels need more than `available`
/// bytes (unchecked when `None`), naming both and the way out.
pub fn check(width: u32, height: u32, available: Option<u64>) -> Result<(), RenderError> {
    let needed = width as u64 * height as u64 * BYTES_PER_PIXEL;
    match available {
        Some(free) if needed > free => Err(RenderError::TooLarge(format!(
            "a {width}×{height} image needs about {:.1} GiB of host memory on the CPU backend \
             ({BYTES_PER_PIXEL} bytes a pixel) and {:.1} GiB are available: lower --width and --height",
            needed as f64 / GIB,
            free as f64 / GIB
        ))),
        _ => Ok(()),
    }
}

const GIB: f64 = (1u64 << 30) as f64;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mem_available_from_meminfo() {
        let text = "MemTotal:       24000000 kB\nMemFree:        19000000 kB\nMemAvailable:   23000000 kB\n";
        assert_eq!(parse_mem_available(text), Some(23_000_000 * 1024));
        assert_eq!(parse_mem_available("MemTotal: 1 kB\n"), None);
        assert_eq!(parse_mem_available("MemAvailable: lots kB\n"), None);
    }

    /// 4096×2048 (1 GiB at 128 bytes a pixel) fits 23 GB; 16384×16384 (32 GiB) does not, in one
    /// line that names the need, what is available and the remedy; an unknown amount is not
    /// checked.
    #[test]
    fn refuses_an_image_beyond_the_available_memory_in_one_line() {
        let available = Some(23_000_000 * 1024);
        assert!(check(4096, 2048, available).is_ok());
        let e = check(16384, 16384, available).unwrap_err().to_string();
        assert!(e.contains("16384×16384") && e.contains("32.0 GiB") && e.contains("21.9 GiB"), "{e}");
        assert!(e.contains("--width") && !e.contains('\n'), "{e}");
        assert!(check(16384, 16384, None).is_ok());
    }
}
