//! The first difftest: the device evaluates the shared tree, reject-chain, acceptance,
//! mutation, rng and packing functions exactly as the CPU does (within a few ulps for floats,
//! bit for bit for integers).

mod common;

use kernels::selftest::{CASE_TREE, U32_OUTPUTS_PER_CASE};
use smlt::selftest::{compare, standard_batch, TOLERANCE_ULPS};

#[test]
fn device_math_equals_the_shared_functions_on_the_cpu() {
    let Some(gpu) = common::gpu_or_skip("device_math_equals_the_shared_functions_on_the_cpu") else {
        return;
    };
    for seed in [1, 2, 3] {
        let batch = standard_batch(seed);
        let cpu = batch.run_cpu();
        let device = batch.run_gpu(&gpu).expect("device run");
        let cmp = compare(&batch, &cpu, &device);
        assert!(
            cmp.mismatches.is_empty(),
            "{} mismatches, first: {}",
            cmp.mismatches.len(),
            cmp.mismatches[0]
        );
        println!(
            "seed {seed}: {} floats (max {:.2} ulps of {TOLERANCE_ULPS}), {} words exact, {} boundary selections",
            cmp.floats, cmp.max_ulps, cmp.words, cmp.boundary_selections
        );
        assert!(cmp.floats > 10_000 && cmp.words > 1_000);
    }
}

/// The comparison itself must catch a wrong device result: corrupt one weight and one random
/// word of the CPU outputs and check both are reported.
#[test]
fn the_comparison_catches_a_wrong_value() {
    let batch = standard_batch(1);
    let cpu = batch.run_cpu();
    let mut wrong = cpu.clone();
    const DEPTH: u32 = 3;
    let tree = batch.cases.iter().position(|c| c.kind == CASE_TREE && c.size == DEPTH).unwrap();
    // A tree case's floats: the 2^d − 1 edge acceptances, the 2^d leaf probabilities, then the
    // 2^d weights (kernels::selftest).
    let (acceptances, leaves) = ((1usize << DEPTH) - 1, 1usize << DEPTH);
    let weights = batch.cases[tree].output as usize + acceptances + leaves;
    wrong.floats[weights + 2] += 1e-4;
    let last = batch.cases.len() - 1;
    wrong.words[last * U32_OUTPUTS_PER_CASE + 1] ^= 1;
    let cmp = compare(&batch, &cpu, &wrong);
    assert_eq!(cmp.mismatches.len(), 2, "{:?}", cmp.mismatches);
    assert!(compare(&batch, &cpu, &cpu).mismatches.is_empty());
}
