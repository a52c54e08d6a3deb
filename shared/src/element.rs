//! Reading a buffer element without a panic path. Indexing a slice carries a bounds check that
//! panics; rust-gpu inlines every function with a panic path at each of its calls, `inline(never)`
//! or not, so a function called from many places that indexes (the texture lookup) grows the
//! kernels' module by a copy per call. [`element_or`] checks the bound itself and reads with
//! `spirv_std`'s `index_unchecked` (`get_unchecked` and `Option<&T>` do not compile for SPIR-V).

use spirv_std::arch::IndexUnchecked;

/// `slice[i]`, or `default` when `i` is not below its length.
#[inline]
pub fn element_or<T: Copy>(slice: &[T], i: usize, default: T) -> T {
    if i < slice.len() {
        // SAFETY: `i` is below the slice's length.
        unsafe { *slice.index_unchecked(i) }
    } else {
        default
    }
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn reads_inside_and_defaults_outside() {
        let s = [3u32, 5, 7];
        assert_eq!((element_or(&s, 0, 0), element_or(&s, 2, 0), element_or(&s, 3, 9)), (3, 7, 9));
        assert_eq!(element_or(&[] as &[u32], 0, 1), 1);
    }
}
