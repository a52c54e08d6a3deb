use super::*;

/// Normal deviates (xorshift and Box–Muller): the tests' noise.
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// A synthetic candidate: two halves of `truth − missing` with independent normal noise of
/// standard deviation `sigma` (each half's), rendered in `seconds`.
fn run(
    method: Method,
    truth: &[f64],
    missing: &[f64],
    sigma: f64,
    seconds: f64,
    noise: &mut Noise,
) -> PilotRun {
    let mut half =
        || truth.iter().zip(missing).map(|(r, m)| (r - m + sigma * noise.normal()) as f32).collect();
    PilotRun { method, halves: [half(), half()], seconds, candidates: [1, 1] }
}

/// The relMSE of a candidate's mean as `run` makes it against relMSE's denominator from
/// `average` (the pilot's reference): its bias² plus half a half's variance.
fn exact_against(truth: &[f64], missing: &[f64], sigma: f64, average: &[f64]) -> f64 {
    truth
        .iter()
        .zip(missing)
        .zip(average)
        .map(|((_, m), a)| (m * m + sigma * sigma / 2.0) / (a * a + RELMSE_FLOOR))
        .sum::<f64>()
        / truth.len() as f64
}

/// A synthetic image of `n` values, WIDTH pixels a row: a random value in [0.05, 1.05] for each
/// 4 × 4 block of pixels and channel (an image is smooth over a few pixels; its edges are not
/// what the tests are about).
fn truth(n: usize, noise: &mut Noise) -> Vec<f64> {
    let blocks: Vec<f64> = (0..n).map(|_| 0.05 + noise.uniform()).collect();
    (0..n)
        .map(|j| {
            let (x, y, c) = ((j / 3) % WIDTH as usize, (j / 3) / WIDTH as usize, j % 3);
            blocks[3 * ((y / 4) * WIDTH as usize + x / 4) + c]
        })
        .collect()
}

/// The synthetic images' width (60 000 values: 200 × 100 pixels of rgb).
const WIDTH: u32 = 200;

const PT: Method = CANDIDATES[0];
const NAIVE: Method = CANDIDATES[1];
/// A third method, as [`assess`] weighs any number (the chains over the path tracer's estimate,
/// once a candidate).
const PATH_NAIVE: Method = Method::Metropolis {
    schedule: crate::render::Schedule::NAIVE,
    estimator: crate::render::Estimator::Path,
};

/// Unbiased candidates: the halves recover each one's relMSE (within 5 %), hardly any light is found
/// missing (under 2 % of the noisiest candidate's variance), and the one predicted best after a second is chosen — here the
/// noisier one that runs eight times faster.
#[test]
fn unbiased_candidates_are_weighed_by_their_noise_and_time() {
    let mut noise = Noise(0x5eed);
    let n = 60_000;
    let r = truth(n, &mut noise);
    let none = vec![0.0; n];
    let runs = [
        run(PT, &r, &none, 0.10, 1.0, &mut noise),
        run(NAIVE, &r, &none, 0.05, 8.0, &mut noise),
        run(PATH_NAIVE, &r, &none, 0.30, 1.0, &mut noise),
    ];
    let assessed = assess(&runs, WIDTH);
    let average = reference(&runs);
    let noisiest = assessed.iter().map(|a| a.halves_relmse).fold(0.0, f64::max);
    for (a, sigma) in assessed.iter().zip([0.10, 0.05, 0.30]) {
        let want = exact_against(&r, &none, sigma, &average);
        assert!(
            (a.halves_relmse / want - 1.0).abs() < 0.05,
            "{}: halves {} vs {want}",
            a.method,
            a.halves_relmse
        );
        assert!(a.missing_relmse < 0.02 * noisiest, "{}: missing {}", a.method, a.missing_relmse);
    }
    // Predicted relMSE after 1 s ∝ σ² t: pt 0.01, naive 0.02, path-naive 0.09.
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), PT);
}

/// The heavy-tail guard: a candidate that misses some light (a path tracer's short pilot that
/// has met no caustic path: its halves agree, both missing it) looks best by its own halves; the
/// light it misses against the others recovers its squared bias (within 10 %), the unbiased
/// candidates are not blamed for it, and an unbiased one is chosen. Also where two of the three
/// miss it (a point lamp's caustic through glass, which neither the path tracer nor the path
/// estimator renders): the one that holds the light is chosen.
#[test]
fn a_candidate_missing_light_is_caught_by_the_others() {
    let mut noise = Noise(0xca05);
    let n = 60_000;
    let r = truth(n, &mut noise);
    let none = vec![0.0; n];
    // A caustic: a fifth of the values hold 2 more light that the first candidate misses
    // (whole blocks of 4 × 4 pixels: a fifth of them). Against the true image its squared bias
    // is about 0.13 in relMSE, the naive candidate's variance 0.05.
    let caustic: Vec<f64> = (0..n)
        .map(|j| {
            let (x, y) = ((j / 3) % WIDTH as usize, (j / 3) / WIDTH as usize);
            if (x / 4 + y / 4) % 5 == 0 {
                2.0
            } else {
                0.0
            }
        })
        .collect();
    let r_lit: Vec<f64> = r.iter().zip(&caustic).map(|(a, c)| a + c).collect();
    for missed_by in [1, 2] {
        let missing = |k: usize| if k < missed_by { &caustic } else { &none };
        let sigmas = [0.02, 0.10, 0.15];
        let runs: Vec<PilotRun> = (0..3)
            .map(|k| run([PT, NAIVE, PATH_NAIVE][k], &r_lit, missing(k), sigmas[k], 1.0, &mut noise))
            .collect();
        let assessed = assess(&runs, WIDTH);
        let average = reference(&runs);
        for (k, a) in assessed.iter().enumerate() {
            if k < missed_by {
                assert!(a.halves_relmse < assessed[2].halves_relmse, "by its halves alone it would win");
                let bias = exact_against(&r_lit, missing(k), 0.0, &average);
                assert!(
                    (a.missing_relmse / bias - 1.0).abs() < 0.1,
                    "{}: missing {} vs {bias}",
                    a.method,
                    a.missing_relmse
                );
            } else {
                let noisiest = assessed.iter().map(|a| a.halves_relmse).fold(0.0, f64::max);
                assert!(a.missing_relmse < 0.02 * noisiest, "{}: missing {}", a.method, a.missing_relmse);
            }
        }
        let chosen = most_efficient(&assessed, 1.0, 1.0);
        assert_eq!(chosen, if missed_by == 1 { NAIVE } else { PATH_NAIVE }, "{assessed:?}");
        let line = Choice {
            method: chosen,
            assessments: assessed,
            seconds: 3.0,
            width: 4,
            height: 4,
            render_seconds: 1.0,
            pixels: 1.0,
            kept: None,
        }
        .describe();
        assert!(line.starts_with(&format!("{chosen} (pilot 3.00 s at 4×4")), "{line}");
        assert_eq!(line.matches("missing light").count(), missed_by, "{line}");
    }
}

/// A skewed candidate — a short Metropolis pilot's image, unbiased but clumped: each value the
/// truth times a lognormal factor of mean 1 (σ = 1 in its logarithm) — is brighter than an
/// unbiased, symmetric one by chance in more blocks than it is darker; neither is read as
/// missing light (under 2 % of the noisiest variance), and the symmetric one, predicted best
/// by its noise, is chosen. (Without the significance threshold the path tracer's missing light
/// came out near the skewed one's whole variance.)
#[test]
fn a_skewed_candidate_does_not_make_another_look_dark() {
    let mut noise = Noise(0x5c3d);
    let n = 60_000;
    let r = truth(n, &mut noise);
    let none = vec![0.0; n];
    let mut clumped =
        || -> Vec<f32> { r.iter().map(|v| (v * (noise.normal() - 0.5).exp()) as f32).collect() };
    let skewed = PilotRun { method: NAIVE, halves: [clumped(), clumped()], seconds: 1.0, candidates: [1, 1] };
    let runs =
        [run(PT, &r, &none, 0.15, 1.0, &mut noise), skewed, run(PATH_NAIVE, &r, &none, 0.3, 1.0, &mut noise)];
    let assessed = assess(&runs, WIDTH);
    let noisiest = assessed.iter().map(|a| a.halves_relmse).fold(0.0, f64::max);
    for a in &assessed {
        assert!(
            a.missing_relmse < 0.02 * noisiest,
            "{}: missing {} of {noisiest}",
            a.method,
            a.missing_relmse
        );
    }
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), PT, "{assessed:?}");
}

/// A firefly met by one half of the least noisy candidate — a path tracer's short pilot that
/// found a caustic path — counts whole in its error: the reference is not raised by it, the
/// halves' estimate is the error against it (within 10 %), and the candidate is not chosen. (The
/// first pilot's reference, the runs weighted by their precision, was the firefly's own run
/// and read its error as a tenth of this.)
#[test]
fn a_firefly_counts_against_the_candidate_that_met_it() {
    let mut noise = Noise(0xf1ef);
    let n = 60_000;
    let r = truth(n, &mut noise);
    let none = vec![0.0; n];
    let mut pt = run(PT, &r, &none, 0.02, 1.0, &mut noise);
    // One value in two thousand of one half: 20 more.
    let fireflies: Vec<usize> = (0..n).filter(|j| j % 2000 == 7).collect();
    for &j in &fireflies {
        pt.halves[0][j] += 20.0;
    }
    let runs =
        [pt, run(NAIVE, &r, &none, 0.10, 1.0, &mut noise), run(PATH_NAIVE, &r, &none, 0.15, 1.0, &mut noise)];
    let reference = reference(&runs);
    for &j in &fireflies {
        assert!(reference[j] < r[j] + 0.5, "the reference holds the firefly at {j}: {}", reference[j]);
    }
    // The mean's error at a firefly is 10: 100 of squared error, each against the reference.
    let exact = (0..n)
        .map(|j| {
            let e = if j % 2000 == 7 { 100.0 } else { 0.02 * 0.02 / 2.0 };
            e / (reference[j] * reference[j] + RELMSE_FLOOR)
        })
        .sum::<f64>()
        / n as f64;
    let assessed = assess(&runs, WIDTH);
    assert!(
        (assessed[0].halves_relmse / exact - 1.0).abs() < 0.1,
        "pt: {} vs {exact}",
        assessed[0].halves_relmse
    );
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), NAIVE, "{assessed:?}");
    // Its error is the fireflies': it met fireflies, the others not.
    assert!(assessed[0].met_fireflies() && assessed[0].firefly_share > 0.99, "{assessed:?}");
    assert!(assessed[1..].iter().all(|a| !a.met_fireflies() && a.firefly_share < 0.2), "{assessed:?}");
}

/// A path tracer whose pilot met fireflies is not chosen while a candidate without them has a
/// prediction, however good its own — the pilot cannot measure how rare or large the next ones
/// are — and chains are never said to have met them (their clumped images concentrate their
/// error by nature, and their halves measure it).
#[test]
fn a_path_tracer_that_met_fireflies_is_not_measured() {
    let a = |method, halves_relmse, firefly_share| Assessment {
        method,
        seconds: 1.0,
        halves_relmse,
        missing_relmse: 0.0,
        firefly_share,
    };
    let assessed = [a(PT, 0.01, 0.95), a(NAIVE, 0.04, 0.95)];
    assert!(assessed[0].met_fireflies() && !assessed[1].met_fireflies());
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), NAIVE);
    assert_eq!(most_efficient(&[a(PT, 0.01, 0.89), a(NAIVE, 0.04, 0.0)], 1.0, 1.0), PT);
    // With no other measured candidate, the path tracer all the same.
    assert_eq!(most_efficient(&[a(PT, 0.01, 0.95), a(NAIVE, 0.0, 0.0)], 1.0, 1.0), PT);
    let line = Choice {
        method: NAIVE,
        assessments: assessed.to_vec(),
        seconds: 1.0,
        width: 4,
        height: 4,
        render_seconds: 1.0,
        pixels: 1.0,
        kept: None,
    }
    .describe();
    assert!(line.contains("pt 1.00e-2, fireflies, naive 4.00e-2)"), "{line}");
}

/// The share of a sum in its largest 0.1 % of terms (at least one).
#[test]
fn firefly_share_is_the_largest_terms_share() {
    let mut terms = vec![1.0; 1999];
    terms.push(1999.0);
    assert_eq!(firefly_share(&mut terms), (1999.0 + 1.0) / 3998.0);
    assert_eq!(firefly_share(&mut [2.0, 6.0]), 0.75);
    assert_eq!(firefly_share(&mut [0.0; 4]), 0.0);
    assert_eq!(firefly_share(&mut []), 0.0);
}

/// The median of an odd count is its middle value; of an even count, the middle two's mean.
#[test]
fn median_of_odd_and_even_counts() {
    assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(&mut [4.0, 1.0, 100.0, 2.0]), 3.0);
    assert_eq!(median(&mut []), 0.0);
}

/// A block's deficit counts whole where it is significant, and not at all where it is not.
#[test]
fn a_block_counts_missing_light_beyond_its_noise() {
    assert_eq!(missing_in_block(0.5, 0.0), 0.25);
    assert!((missing_in_block(0.6, 0.01) - 0.355).abs() < 1e-12);
    assert_eq!(missing_in_block(0.49, 0.01), 0.0);
    assert_eq!(missing_in_block(-1.0, 0.0), 0.0);
    assert_eq!(missing_in_block(0.0, 0.0), 0.0);
}

/// A candidate with no estimate (black pilot images everywhere) never wins; with none at all,
/// the paper's naive chains.
#[test]
fn black_pilots_fall_back_to_naive() {
    let black = |method| PilotRun {
        method,
        halves: [vec![0.0; 12], vec![0.0; 12]],
        seconds: 1.0,
        candidates: [1, 1],
    };
    let assessed = assess(&[black(PT), black(NAIVE), black(PATH_NAIVE)], 2);
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), Method::NAIVE);
    let mut lit = black(PATH_NAIVE);
    lit.halves = [vec![0.5; 12], vec![0.6; 12]];
    let assessed = assess(&[black(PT), black(NAIVE), lit], 2);
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), PATH_NAIVE, "{assessed:?}");
}

/// The pilot's settings: at most PILOT_WIDTH wide with the aspect kept, its own seeds (two a
/// candidate, none the render's), the whole chains, the budget given; the budgets' shares.
#[test]
fn pilot_settings_and_budgets() {
    let s = Settings {
        width: 1920,
        height: 1080,
        seed: 7,
        shard: Shard { index: 2, count: 4 },
        ..Settings::default()
    };
    let mut seeds = std::collections::HashSet::from([s.seed]);
    for m in CANDIDATES {
        for half in 0..2 {
            let p = pilot_settings(&s, m, half, Budget::Seconds(1.0));
            assert_eq!((p.width, p.height, p.shard, p.method()), (128, 72, Shard::WHOLE, m));
            if let Some(chains) = p.metropolis().map(|m| m.chains) {
                assert_eq!(chains.bootstrap_samples, PILOT_BOOTSTRAP);
                // As many chains to a bootstrap sample as the render: an eighth of its chains.
                assert_eq!(p.chains(), s.chains() / 8);
            } else {
                assert_eq!(p.candidates, s.candidates);
            }
            assert!(seeds.insert(p.seed), "seed {} repeats", p.seed);
        }
    }
    // A smaller bootstrap than the pilot's is kept.
    let mut few = s.clone();
    few.metropolis_mut().unwrap().chains.bootstrap_samples = 1000;
    let p = pilot_settings(&few, NAIVE, 0, Budget::Seconds(1.0));
    assert_eq!(p.metropolis().unwrap().chains.bootstrap_samples, 1000);
    assert_eq!(p.candidates, few.candidates);
    let small = Settings { width: 64, height: 48, ..s.clone() };
    assert_eq!(pilot_settings(&small, PT, 0, Budget::Seconds(1.0)).width, 64);
    let seconds = |b: Budget| match b {
        Budget::Seconds(t) => t,
        b => panic!("{b:?}"),
    };
    // √(0.08 t) in all, four renders: 6 s of 450 s, 0.8 s of 8 s; at least 0.6 s.
    assert!((seconds(pilot_budget(Budget::Seconds(450.0))) - 1.5).abs() < 1e-12);
    assert!((seconds(pilot_budget(Budget::Seconds(8.0))) - 0.2).abs() < 1e-12);
    assert_eq!(pilot_budget(Budget::Seconds(1.0)), Budget::Seconds(0.6 / 4.0));
    assert_eq!(pilot_budget(Budget::MutationsPerPixel(64.0)), Budget::MutationsPerPixel(8.0));
    assert_eq!(remaining_budget(Budget::Seconds(60.0), 6.5), Budget::Seconds(53.5));
    assert_eq!(remaining_budget(Budget::Seconds(4.0), 3.5), Budget::Seconds(1.0));
    assert_eq!(remaining_budget(Budget::MutationsPerPixel(64.0), 3.0), Budget::MutationsPerPixel(64.0));
}

/// The prediction weighs the light missing against the render ahead: a candidate with little
/// noise that misses a little light is the better choice for a short render and the worse for
/// a long one (its variance shrinks, the light it misses stays), and for a large image the
/// less noisy one gains (fewer samples a pixel).
#[test]
fn missing_light_counts_more_the_longer_the_render() {
    let a = |method, halves_relmse, missing_relmse| Assessment {
        method,
        seconds: 1.0,
        halves_relmse,
        missing_relmse,
        firefly_share: 0.0,
    };
    let assessed = [a(PT, 0.01, 0.001), a(NAIVE, 0.04, 0.0)];
    assert_eq!(most_efficient(&assessed, 1.0, 1.0), PT, "0.011 against 0.04");
    assert_eq!(most_efficient(&assessed, 100.0, 1.0), NAIVE, "0.0011 against 0.0004");
    assert_eq!(most_efficient(&assessed, 100.0, 100.0), PT, "0.011 against 0.04");
    assert!((assessed[0].predicted_relmse(10.0, 4.0) - (0.01 * 0.4 + 0.001)).abs() < 1e-12);
}

/// Pooled images weigh each by its candidates: for a path tracer's, whose pixels are sample
/// means, the mean of all the samples; an image with none is left out.
#[test]
fn pooled_images_are_their_samples_mean() {
    // Three images of two values, the means of 1, 3 and 4 samples.
    let samples: [&[[f32; 2]]; 3] = [&[[1.0, 2.0]], &[[2.0, 0.0], [4.0, 1.0], [0.0, 2.0]], &[[1.0, 1.0]; 4]];
    let mean = |s: &[[f32; 2]]| -> Vec<f32> {
        (0..2).map(|c| s.iter().map(|v| v[c]).sum::<f32>() / s.len() as f32).collect()
    };
    let images: Vec<(Vec<f32>, u64)> = samples.iter().map(|s| (mean(s), s.len() as u64)).collect();
    let refs: Vec<(&[f32], u64)> = images.iter().map(|(rgb, c)| (&rgb[..], *c)).collect();
    let all: Vec<[f32; 2]> = samples.iter().flat_map(|s| s.iter().copied()).collect();
    for (p, m) in pooled(&refs).iter().zip(mean(&all)) {
        assert!((p - m).abs() < 1e-6, "{p} vs {m}");
    }
    assert_eq!(pooled(&[(&[5.0, 6.0], 0), (&[1.0, 2.0], 3)]), vec![1.0, 2.0]);
    assert_eq!(pooled(&[(&[5.0, 6.0], 0)]), vec![0.0, 0.0]);
}

/// The chosen candidate's pilot is kept where it rendered the render's pixels — a whole render
/// at most PILOT_WIDTH wide — pooled from its halves by their candidates, and pooled into the
/// render's image by its own.
#[test]
fn the_pilot_is_kept_where_it_rendered_the_renders_pixels() {
    let runs = [PT, NAIVE].map(|method| PilotRun {
        method,
        halves: [vec![1.0, 4.0, 0.0], vec![3.0, 0.0, 0.0]],
        seconds: 1.0,
        candidates: if method == PT { [10, 30] } else { [1, 1] },
    });
    let s = Settings { width: 1, height: 1, ..Settings::default() };
    let kept = KeptPilot::of(&runs, PT, &s, 1, 1).expect("kept");
    assert_eq!((kept.rgb.as_slice(), kept.candidates), (&[2.5, 1.0, 0.0][..], 40));
    assert_eq!(kept.pooled_with(&[0.5, 1.0, 2.0], 40), vec![1.5, 1.0, 1.0]);
    assert_eq!(KeptPilot::of(&runs, NAIVE, &s, 1, 1).unwrap().rgb, vec![2.0, 2.0, 0.0]);
    // A larger render than its pilot, or a shard of one: not kept.
    assert!(KeptPilot::of(&runs, PT, &Settings { width: 2, ..s.clone() }, 1, 1).is_none());
    let shard = Settings { shard: Shard { index: 1, count: 2 }, ..s.clone() };
    assert!(KeptPilot::of(&runs, PT, &shard, 1, 1).is_none());
}
