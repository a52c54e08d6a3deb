//! The statistics the convergence tests share: block means of an image, and the mean and spread
//! of a block over independent renders.

/// Mean luminance of each of `blocks` × `blocks` blocks of a `width` × `height` rgb image.
pub fn block_means(rgb: &[f32], width: u32, height: u32, blocks: u32) -> Vec<f64> {
    let mut sums = vec![0.0; (blocks * blocks) as usize];
    let mut counts = vec![0u32; sums.len()];
    for y in 0..height {
        for x in 0..width {
            let i = ((x + y * width) * 3) as usize;
            let lum = shared::color::luminance(glam::Vec3::new(rgb[i], rgb[i + 1], rgb[i + 2])) as f64;
            let b = (x * blocks / width + (y * blocks / height) * blocks) as usize;
            sums[b] += lum;
            counts[b] += 1;
        }
    }
    sums.iter().zip(&counts).map(|(s, c)| s / *c as f64).collect()
}

/// For one block: its mean over independent runs and the sample variance of one run.
pub fn mean_and_variance(runs: &[Vec<f64>], block: usize) -> (f64, f64) {
    let r = runs.len() as f64;
    let m = runs.iter().map(|x| x[block]).sum::<f64>() / r;
    (m, runs.iter().map(|x| (x[block] - m).powi(2)).sum::<f64>() / (r - 1.0))
}

/// How many standard errors apart two sets of independent runs are in one block.
pub fn z_score(a: &[Vec<f64>], b: &[Vec<f64>], block: usize) -> (f64, f64, f64) {
    let (ma, va) = mean_and_variance(a, block);
    let (mb, vb) = mean_and_variance(b, block);
    let se = (va / a.len() as f64 + vb / b.len() as f64).sqrt().max(1e-9);
    (ma, mb, (ma - mb) / se)
}

/// Asserts that every block of `b` agrees with `a` (replicas' block means) within 5 standard
/// errors of the difference, naming the comparison `what` where one does not; returns the
/// worst |z|.
pub fn assert_blocks_agree(what: &str, a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let mut worst = 0.0f64;
    for block in 0..a[0].len() {
        let (ma, mb, z) = z_score(a, b, block);
        worst = worst.max(z.abs());
        assert!(z.abs() < 5.0, "{what}, block {block}: {ma:.5} vs {mb:.5} (z = {z:.2})");
    }
    worst
}
