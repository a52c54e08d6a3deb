//! FNV-1a, 64 bits, as 16 hex digits: the content hash of the project (scenes' files, the
//! kernels module, part files, the kernels' inputs). Stable across machines and versions; not
//! cryptographic. One definition, compiled into the builder, `host/build.rs` and the host
//! (`smlt::hash`) by `#[path]`.

/// FNV-1a (64 bit) of `bytes`, as hex.
pub fn fnv1a(bytes: &[u8]) -> String {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}
