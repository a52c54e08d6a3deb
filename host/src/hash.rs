//! The content hash that names what a cache entry or a part file was made from (a scene's
//! files, the kernels module): FNV-1a, 64 bits, as 16 hex digits. Stable across machines and
//! versions; not cryptographic.

/// FNV-1a (64 bit) of `bytes`, as hex.
pub fn content_hash(bytes: &[u8]) -> String {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

#[cfg(test)]
mod tests {
    /// The published FNV-1a test vectors.
    #[test]
    fn fnv1a_test_vectors() {
        assert_eq!(super::content_hash(b""), "cbf29ce484222325");
        assert_eq!(super::content_hash(b"a"), "af63dc4c8601ec8c");
        assert_eq!(super::content_hash(b"foobar"), "85944171f73967e8");
    }
}
