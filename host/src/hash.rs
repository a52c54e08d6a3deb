//! The content hash that names what a cache entry or a part file was made from (a scene's
//! files, the kernels module): FNV-1a, 64 bits, as 16 hex digits (`builder/src/fnv.rs`, the
//! one definition, shared with the kernels' builder).

#[path = "../../builder/src/fnv.rs"]
mod fnv;

/// FNV-1a (64 bit) of `bytes`, as hex.
pub fn content_hash(bytes: &[u8]) -> String {
    fnv::fnv1a(bytes)
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
