//! `smlt selftest`: runs the device self-test (the speculative-tree, reject-chain, acceptance,
//! mutation, random-number and packing math of `shared`) on the chosen adapter and on the CPU,
//! and compares them. The integration tests use the same batch and comparison.

use kernels::selftest::{SelfTestCase, CASE_REJECT_CHAIN, CASE_SCALAR, CASE_TREE, U32_OUTPUTS_PER_CASE};
use shared::layout::NO_PIXEL;
use shared::reject_chain::MAX_REJECT_CHAIN;
use shared::rng::{uniform, RngKey};
use shared::tree::MAX_TREE_DEPTH;

use crate::passes::selftest::{SelfTestBatch, SelfTestOutputs};

/// Relative tolerance, in units of f32::EPSILON, between device and CPU floats. Vulkan allows
/// 2.5 ulp for a division and 3 + 2|x| ulp for exp, and lets the driver fuse a multiply and an
/// add; the tree's products compound that over up to 8 levels.
pub const TOLERANCE_ULPS: f32 = 32.0;

/// The standard batch: every tree depth 1..=8 and reject-chain lengths up to 64 with random
/// targets (zeros, NaN and ±Inf among them) and the scalar functions at their edge cases.
pub fn standard_batch(seed: u32) -> SelfTestBatch {
    let mut batch = SelfTestBatch::default();
    let mut n = 0u32;
    let mut rand = || {
        n += 1;
        uniform(RngKey { seed, chain: n, iteration: 0, dimension: 0 })
    };
    let special = [0.0f32, 1e-30, f32::NAN, f32::INFINITY, -1.0, 1.0, 1.0 - 1e-7];
    let target = |rand: &mut dyn FnMut() -> f32, style: u32| -> f32 {
        let r = rand();
        match style {
            0 => r * 10.0,
            1 if r < 0.3 => special[((rand() * special.len() as f32) as usize).min(special.len() - 1)],
            1 => r,
            2 => 1.0 + r * 1e-4,
            _ => (r * 60.0 - 30.0).exp(),
        }
    };
    for depth in 1..=MAX_TREE_DEPTH {
        for style in 0..4 {
            let c: Vec<f32> = (0..1usize << depth).map(|_| target(&mut rand, style)).collect();
            let case = SelfTestCase { kind: CASE_TREE, size: depth, xi: rand(), ..Default::default() };
            batch.push(case, &c);
        }
    }
    for length in [1, 2, 3, 4, 8, 16, 32, 63, MAX_REJECT_CHAIN] {
        for style in 0..4 {
            let c: Vec<f32> = (0..=length).map(|_| target(&mut rand, style)).collect();
            let case =
                SelfTestCase { kind: CASE_REJECT_CHAIN, size: length, xi: rand(), ..Default::default() };
            batch.push(case, &c);
        }
    }
    let pairs = [
        (0.0, 0.0),
        (0.0, 1.0),
        (1.0, 0.0),
        (2.0, 1.0),
        (1.0, f32::NAN),
        (f32::NAN, 1.0),
        (f32::INFINITY, 1.0),
        (1.0, f32::INFINITY),
        (1e-30, 1e30),
        (f32::MAX, f32::MIN_POSITIVE),
        (3.0, 1.5),
    ];
    let pixels = [0u32, 1, (1 << 23) - 1, 1 << 23, 1920 * 1080 - 1, NO_PIXEL, 0x7fc0_0000];
    for i in 0..256u32 {
        let (cx, cy) = pairs[i as usize % pairs.len()];
        let u = if i % 16 == 0 { 0.999_999_9 } else { rand() };
        let inputs = [cx, cy, u, rand() * 4.0, rand(), rand() * 1e-3];
        let case = SelfTestCase {
            kind: CASE_SCALAR,
            xi: rand(),
            seed: pixels[i as usize % pixels.len()].wrapping_add(i / 64),
            chain: i,
            iteration: i * 7,
            ..Default::default()
        };
        batch.push(case, &inputs);
    }
    batch
}

/// The outcome of comparing device and CPU outputs.
#[derive(Clone, Debug, Default)]
pub struct Comparison {
    /// Floats compared.
    pub floats: usize,
    /// Integer words compared (random bits, pixel bits, selected states).
    pub words: usize,
    /// Largest float difference seen, in ulps of the CPU value.
    pub max_ulps: f32,
    /// Selections that differ only because ξ fell within rounding of a probability boundary.
    pub boundary_selections: usize,
    /// Every disagreement beyond tolerance, described.
    pub mismatches: Vec<String>,
}

fn ulps(a: f32, b: f32) -> f32 {
    if a == b || (a.is_nan() && b.is_nan()) {
        return 0.0;
    }
    let scale = a.abs().max(b.abs()).max(f32::MIN_POSITIVE);
    (a - b).abs() / (scale * f32::EPSILON)
}

/// Compares device outputs with the CPU's. Floats must agree within [`TOLERANCE_ULPS`]
/// relative to the quantity's scale (1 for probabilities, the depth or length for weights);
/// random and pixel bits exactly; selected states exactly unless ξ lies within rounding of a
/// boundary of the cumulative probabilities.
pub fn compare(batch: &SelfTestBatch, cpu: &SelfTestOutputs, gpu: &SelfTestOutputs) -> Comparison {
    let mut cmp = Comparison::default();
    for (i, case) in batch.cases.iter().enumerate() {
        let o = case.output as usize;
        let len = case.float_outputs();
        let scale_floor = match case.kind {
            CASE_TREE => case.size as f32,
            CASE_REJECT_CHAIN => case.size as f32,
            _ => 0.0,
        };
        for j in o..o + len {
            let (c, g) = (cpu.floats[j], gpu.floats[j]);
            cmp.floats += 1;
            if case.kind != CASE_SCALAR && (c.is_nan() || g.is_nan()) {
                cmp.mismatches
                    .push(format!("case {i} ({case:?}) output {}: NaN (cpu {c}, device {g})", j - o));
                continue;
            }
            let scale = c.abs().max(g.abs()).max(scale_floor).max(f32::MIN_POSITIVE);
            let diff = if c == g || (c.is_nan() && g.is_nan()) {
                0.0
            } else {
                (c - g).abs() / (scale * f32::EPSILON)
            };
            cmp.max_ulps = cmp.max_ulps.max(diff.min(ulps(c, g)));
            if diff.is_nan() || diff > TOLERANCE_ULPS {
                cmp.mismatches.push(format!("case {i} ({case:?}) output {}: cpu {c:e}, device {g:e}", j - o));
            }
        }
        let w = i * U32_OUTPUTS_PER_CASE;
        if case.kind == CASE_SCALAR {
            for k in 0..5 {
                cmp.words += 1;
                if cpu.words[w + k] != gpu.words[w + k] {
                    cmp.mismatches.push(format!(
                        "case {i} word {k}: cpu {:#010x}, device {:#010x}",
                        cpu.words[w + k],
                        gpu.words[w + k]
                    ));
                }
            }
        } else {
            cmp.words += 1;
            if cpu.words[w] != gpu.words[w] {
                // Next-state probabilities start after the acceptances.
                let (start, count) = if case.kind == CASE_TREE {
                    (o + (1usize << case.size) - 1, 1usize << case.size)
                } else {
                    (o + case.size as usize, case.size as usize + 1)
                };
                let probs = &cpu.floats[start..start + count];
                let total: f32 = probs.iter().filter(|p| **p > 0.0).sum();
                let target = case.xi * total;
                let mut running = 0.0f32;
                let near = probs.iter().any(|p| {
                    running += p.max(0.0);
                    (running - target).abs() <= 1e-5 * total.max(1.0)
                });
                if near {
                    cmp.boundary_selections += 1;
                } else {
                    cmp.mismatches.push(format!(
                        "case {i} ({case:?}): next state cpu {}, device {}",
                        cpu.words[w], gpu.words[w]
                    ));
                }
            }
        }
    }
    cmp
}
