//! Counter-based random numbers: a pure function of (seed, chain, iteration, dimension), so the
//! CPU and every GPU thread reproduce the same number without carrying generator state, and a
//! render is reproducible from its seed whatever order the threads run in.
//!
//! The generator is the `pcg4d` hash of Jarzynski and Olano, "Hash Functions for GPU
//! Rendering" (JCGT 2020): a 4×32-bit input is mapped to four 32-bit outputs with two rounds
//! of an LCG step and cross-multiplication, which passes TestU01's BigCrush as a hash of
//! consecutive counters and costs a handful of integer multiplies.

/// The four words that name one random draw. `dimension` is split into a stream (high 8 bits,
/// what the number is used for) and an index within it (low 24 bits), see [`dimension`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RngKey {
    /// The user's `--seed`.
    pub seed: u32,
    /// The Markov chain (or bootstrap sample) the number belongs to.
    pub chain: u32,
    /// The iteration of that chain.
    pub iteration: u32,
    /// What the number is for, from [`dimension`].
    pub dimension: u32,
}

/// Stream of the level-`j` perturbations of a speculative tree (`j` in 1..=8 is added to it).
pub const STREAM_PERTURBATION: u32 = 0;
/// Stream of fresh uniforms used by a large step.
pub const STREAM_LARGE_STEP: u32 = 16;
/// Stream of the per-iteration decisions: large step or not, and the draw of the next state.
pub const STREAM_CONTROL: u32 = 17;
/// Streams of the perturbations of reject-chain proposal i (0-based; i < 64 is added).
pub const STREAM_REJECT_PERTURBATION: u32 = 32;
/// Streams of the large-step uniforms of reject-chain proposal i (i < 64 is added).
pub const STREAM_REJECT_LARGE_STEP: u32 = 96;
/// Stream of the path tracer (index: 2 · vertex + group).
pub const STREAM_PATH_TRACER: u32 = 200;
/// Stream used by the device self-test.
pub const STREAM_SELFTEST: u32 = 255;

/// Index within [`STREAM_CONTROL`]: the uniform that decides a large step.
pub const CONTROL_LARGE_STEP: u32 = 0;
/// Index within [`STREAM_CONTROL`]: the uniform that selects the next state.
pub const CONTROL_SELECT: u32 = 1;
/// Index within [`STREAM_CONTROL`]: the uniform that picks a chain's bootstrap sample.
pub const CONTROL_BOOTSTRAP_PICK: u32 = 2;
/// Index within [`STREAM_CONTROL`]: the uniform that picks the path depth of a tree's level-1
/// large step.
pub const CONTROL_DEPTH: u32 = 3;
/// Index within [`STREAM_CONTROL`] of the large-step decision of reject-chain proposal i
/// (i < 64 is added).
pub const CONTROL_REJECT_LARGE_STEP: u32 = 16;
/// Index within [`STREAM_CONTROL`] of the uniform picking the path depth of reject-chain
/// proposal i's large step (i < 64 is added).
pub const CONTROL_REJECT_DEPTH: u32 = 128;

/// Packs a stream (high 8 bits) and an index within it (low 24 bits) into a dimension word.
#[inline]
pub fn dimension(stream: u32, index: u32) -> u32 {
    (stream << 24) | (index & 0x00ff_ffff)
}

/// The `pcg4d` hash: four 32-bit words in, four well-mixed 32-bit words out. Written on four
/// scalars, not a loop over an array, so that a device keeps them in registers (lavapipe keeps
/// a private array with a computed index in memory).
#[inline]
pub fn pcg4d(v: [u32; 4]) -> [u32; 4] {
    let lcg = |x: u32| x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
    let (mut a, mut b, mut c, mut d) = (lcg(v[0]), lcg(v[1]), lcg(v[2]), lcg(v[3]));
    a = a.wrapping_add(b.wrapping_mul(d));
    b = b.wrapping_add(c.wrapping_mul(a));
    c = c.wrapping_add(a.wrapping_mul(b));
    d = d.wrapping_add(b.wrapping_mul(c));
    a ^= a >> 16;
    b ^= b >> 16;
    c ^= c >> 16;
    d ^= d >> 16;
    a = a.wrapping_add(b.wrapping_mul(d));
    b = b.wrapping_add(c.wrapping_mul(a));
    c = c.wrapping_add(a.wrapping_mul(b));
    d = d.wrapping_add(b.wrapping_mul(c));
    [a, b, c, d]
}

/// Four random 32-bit words for `key`.
#[inline]
pub fn random_u32x4(key: RngKey) -> [u32; 4] {
    pcg4d([key.seed, key.chain, key.iteration, key.dimension])
}

/// Maps 32 random bits to a float in [0, 1): the top 24 bits times 2^-24, so every value is
/// exactly representable and 1.0 is never returned.
#[inline]
pub fn unit_f32(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// One uniform number in [0, 1) for `key` (the first output word of [`random_u32x4`]).
#[inline]
pub fn uniform(key: RngKey) -> f32 {
    unit_f32(random_u32x4(key)[0])
}

/// Four uniforms for the four consecutive primary-sample dimensions `4·group .. 4·group + 4`
/// of `stream`: one hash serves four dimensions.
#[inline]
pub fn uniform4(key: RngKey, stream: u32, group: u32) -> [f32; 4] {
    let w = random_u32x4(RngKey { dimension: dimension(stream, group), ..key });
    [unit_f32(w[0]), unit_f32(w[1]), unit_f32(w[2]), unit_f32(w[3])]
}

/// The uniform of primary-sample dimension `dim` of `stream` (lane `dim mod 4` of
/// [`uniform4`] for group `dim / 4`).
#[inline]
pub fn uniform_dim(key: RngKey, stream: u32, dim: u32) -> f32 {
    uniform4(key, stream, dim >> 2)[(dim & 3) as usize]
}

#[cfg(all(test, not(target_arch = "spirv")))]
mod tests {
    use super::*;

    fn key(seed: u32, chain: u32, iteration: u32, dimension: u32) -> RngKey {
        RngKey { seed, chain, iteration, dimension }
    }

    #[test]
    fn same_key_same_number_and_any_word_changes_it() {
        let k = key(7, 11, 13, dimension(STREAM_CONTROL, 3));
        assert_eq!(random_u32x4(k), random_u32x4(k));
        let base = random_u32x4(k);
        for w in 0..4 {
            let mut words = [k.seed, k.chain, k.iteration, k.dimension];
            words[w] ^= 1;
            let other = pcg4d(words);
            assert_ne!(base, other, "flipping one bit of word {w} left the output unchanged");
            // Avalanche: about half of the 128 output bits change.
            let flipped: u32 = (0..4).map(|i| (base[i] ^ other[i]).count_ones()).sum();
            assert!((32..=96).contains(&flipped), "word {w}: {flipped} of 128 bits changed");
        }
    }

    /// The scalar form is Jarzynski and Olano's `pcg4d` as their paper writes it, over a
    /// vector (here an array and loops), word for word.
    #[test]
    fn pcg4d_is_the_papers_vector_form() {
        fn vector_form(mut v: [u32; 4]) -> [u32; 4] {
            for x in &mut v {
                *x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            }
            let mix = |v: &mut [u32; 4]| {
                v[0] = v[0].wrapping_add(v[1].wrapping_mul(v[3]));
                v[1] = v[1].wrapping_add(v[2].wrapping_mul(v[0]));
                v[2] = v[2].wrapping_add(v[0].wrapping_mul(v[1]));
                v[3] = v[3].wrapping_add(v[1].wrapping_mul(v[2]));
            };
            mix(&mut v);
            for x in &mut v {
                *x ^= *x >> 16;
            }
            mix(&mut v);
            v
        }
        for i in 0..10_000u32 {
            let words = [i, i.wrapping_mul(2_654_435_761), 7 ^ (i << 3), u32::MAX - i];
            assert_eq!(pcg4d(words), vector_form(words), "{words:?}");
        }
    }

    #[test]
    fn unit_f32_stays_in_the_half_open_interval() {
        assert_eq!(unit_f32(0), 0.0);
        assert!(unit_f32(u32::MAX) < 1.0);
        assert_eq!(unit_f32(u32::MAX), 1.0 - 1.0 / 16_777_216.0);
    }

    #[test]
    fn dimension_packs_stream_and_index() {
        assert_eq!(dimension(STREAM_CONTROL, 5), (17 << 24) | 5);
        assert_eq!(dimension(1, 0x0100_0002), (1 << 24) | 2, "index is masked to 24 bits");
    }

    /// Chi-squared over 64 bins for consecutive counters along each of the four words: the
    /// hash of a counter must look uniform whichever word the counter runs in.
    #[test]
    fn consecutive_counters_are_uniform() {
        const BINS: usize = 64;
        const N: u32 = 64 * 2000;
        for w in 0..4 {
            let mut counts = [0u32; BINS];
            for i in 0..N {
                let mut words = [12345, 6789, 42, 3];
                words[w] = i;
                let u = unit_f32(pcg4d(words)[0]);
                counts[(u * BINS as f32) as usize] += 1;
            }
            let expected = N as f64 / BINS as f64;
            let chi2: f64 = counts.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
            // 63 degrees of freedom: the 99.9 % quantile is 103.4.
            assert!(chi2 < 103.4, "word {w}: chi2 = {chi2}");
        }
    }

    /// Neighbouring chains must not be correlated: the sample correlation of the uniforms of
    /// chain p and chain p + 1 at the same iteration is within noise of zero.
    #[test]
    fn neighbouring_chains_are_uncorrelated() {
        let n = 100_000u32;
        let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
        for p in 0..n {
            let x = uniform(key(1, p, 9, 0)) as f64;
            let y = uniform(key(1, p + 1, 9, 0)) as f64;
            sxy += x * y;
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
        }
        let nf = n as f64;
        let cov = sxy / nf - sx / nf * sy / nf;
        let r = cov / ((sxx / nf - (sx / nf).powi(2)) * (syy / nf - (sy / nf).powi(2))).sqrt();
        // Standard error of r is 1/sqrt(n) ≈ 0.0032; allow 5 sigma.
        assert!(r.abs() < 0.016, "correlation {r}");
    }
}
