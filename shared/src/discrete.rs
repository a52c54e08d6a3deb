//! Drawing an index in proportion to non-negative weights by inverting their running sum.
//! Used to draw a speculative tree's next state from its leaf probabilities (the paper's Eq. 2) and a
//! reject chain's next state from its outcome probabilities.

/// Returns the first index `i < n` whose running sum of `weights[..=i]` exceeds
/// `xi · Σ weights[..n]`, for `xi` ∈ [0, 1). Rounding can leave no such index when `xi` is
/// close to 1; the last index with a positive weight is returned then. Entries that are zero
/// are never returned while any entry is positive; if all are zero, 0 is returned.
#[inline]
pub fn sample_discrete<const N: usize>(weights: &[f32; N], n: u32, xi: f32) -> u32 {
    let n = if (n as usize) < N { n } else { N as u32 };
    let mut total = 0.0f32;
    let mut last_positive = 0u32;
    let mut i = 0u32;
    while i < n {
        let w = weights[i as usize];
        if w > 0.0 {
            total += w;
            last_positive = i;
        }
        i += 1;
    }
    let target = xi * total;
    let mut running = 0.0f32;
    i = 0;
    while i < n {
        let w = weights[i as usize];
        if w > 0.0 {
            running += w;
            if running > target {
                return i;
            }
        }
        i += 1;
    }
    last_positive
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    #[test]
    fn inverts_the_running_sum() {
        let w = [0.25f32, 0.0, 0.5, 0.25];
        assert_eq!(sample_discrete(&w, 4, 0.0), 0);
        assert_eq!(sample_discrete(&w, 4, 0.2499), 0);
        assert_eq!(sample_discrete(&w, 4, 0.25), 2);
        assert_eq!(sample_discrete(&w, 4, 0.7499), 2);
        assert_eq!(sample_discrete(&w, 4, 0.75), 3);
        assert_eq!(sample_discrete(&w, 4, 1.0 - f32::EPSILON), 3);
    }

    #[test]
    fn never_returns_a_zero_weight_or_an_index_past_n() {
        let w = [0.0f32, 1e-30, 0.0, 0.0, 7.0];
        for i in 0..1000 {
            let xi = i as f32 / 1000.0;
            let k = sample_discrete(&w, 2, xi);
            assert_eq!(k, 1);
        }
        assert_eq!(sample_discrete(&[0.0f32; 4], 4, 0.5), 0);
        assert_eq!(sample_discrete(&[1.0f32; 4], 9, 0.99), 3, "n is clamped to N");
    }

    #[test]
    fn frequencies_follow_the_weights() {
        let w = [1.0f32, 2.0, 3.0, 4.0];
        let mut counts = [0u32; 4];
        let n = 100_000;
        for i in 0..n {
            counts[sample_discrete(&w, 4, (i as f32 + 0.5) / n as f32) as usize] += 1;
        }
        for (k, c) in counts.iter().enumerate() {
            let expected = n as f32 * w[k] / 10.0;
            assert!((*c as f32 - expected).abs() <= 2.0, "{counts:?}");
        }
    }
}
