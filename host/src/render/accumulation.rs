//! What a set of chains has produced, as one value with an exact merge: the f64 sums of the
//! splats per pixel (S), the total splat weight W (the chains' expected steps), the expected
//! acceptances, the candidates rejected as NaN/Inf, the candidates traced, and the moments of
//! the large-step targets that refine b. A render split over threads, adapters or machines
//! merges its parts' accumulations; the image is computed from the merged value
//! ([`super::Rendered::from_accumulation`]).

use shared::mmlt::ChainState;
use shared::normalisation::Moments;

/// The mergeable result of rendering some chains.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Accumulation {
    /// Σ splats per pixel, rgb, row-major from the top-left pixel.
    pub image: Vec<f64>,
    /// W: Σ of the splat weights (expected Markov steps).
    pub weight: f64,
    /// Expected accepted steps.
    pub accepted: f64,
    /// Candidates rejected because F was NaN or infinite (never splatted).
    pub invalid: u64,
    /// Candidates traced.
    pub candidates: u64,
    /// Targets of the large-step candidates (independent samples for b).
    pub large_steps: Moments,
}

impl Accumulation {
    /// An empty accumulation for `pixels` pixels.
    pub fn new(pixels: usize) -> Self {
        Self { image: vec![0.0; pixels * 3], ..Default::default() }
    }

    /// Moves a chain's tallies since the last drain (steps, acceptances, invalid candidates,
    /// large-step targets) into the accumulation and clears them in `state`.
    pub fn drain_chain(&mut self, state: &mut ChainState) {
        self.weight += state.steps as f64;
        self.accepted += state.accepted as f64;
        self.invalid += state.invalid as u64;
        self.large_steps.drain(state);
        state.steps = 0.0;
        state.accepted = 0.0;
        state.invalid = 0;
    }

    /// Adds `other` (another set of chains of the same render) to this one.
    pub fn merge(&mut self, other: &Accumulation) {
        assert_eq!(self.image.len(), other.image.len(), "accumulations of one image size");
        for (a, b) in self.image.iter_mut().zip(&other.image) {
            *a += b;
        }
        self.merge_tallies(other);
    }

    /// Adds `other` with each pixel's sums multiplied by its weight (`weights`, one a pixel:
    /// the pixel importance Ĩ), and empties `other` for the next drain
    /// (keeping its buffer).
    pub fn merge_weighted(&mut self, other: &mut Accumulation, weights: &[f32]) {
        assert_eq!(self.image.len(), other.image.len(), "accumulations of one image size");
        assert_eq!(self.image.len(), weights.len() * 3, "one weight a pixel");
        for ((a, b), w) in self.image.chunks_mut(3).zip(other.image.chunks_mut(3)).zip(weights) {
            for c in 0..3 {
                a[c] += b[c] * *w as f64;
                b[c] = 0.0;
            }
        }
        self.merge_tallies(other);
        let image = std::mem::take(&mut other.image);
        *other = Accumulation { image, ..Default::default() };
    }

    /// Adds every field of `other` but the image.
    fn merge_tallies(&mut self, other: &Accumulation) {
        self.weight += other.weight;
        self.accepted += other.accepted;
        self.invalid += other.invalid;
        self.candidates += other.candidates;
        self.large_steps = self.large_steps.merged(other.large_steps);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draining_a_chain_moves_its_tallies() {
        let mut acc = Accumulation::new(1);
        let mut state = ChainState {
            steps: 3.0,
            accepted: 1.5,
            invalid: 2,
            large_count: 1,
            large_sum: 0.5,
            large_sum_sq: 0.25,
            depth: 4,
            ..Default::default()
        };
        acc.drain_chain(&mut state);
        assert_eq!((acc.weight, acc.accepted, acc.invalid), (3.0, 1.5, 2));
        assert_eq!((acc.large_steps.count, acc.large_steps.sum), (1, 0.5));
        assert_eq!(state, ChainState { depth: 4, ..Default::default() });
    }

    #[test]
    fn merge_adds_every_field() {
        let a = Accumulation {
            image: vec![1.0, 2.0, 3.0],
            weight: 4.0,
            accepted: 2.0,
            invalid: 1,
            candidates: 10,
            large_steps: Moments { count: 2, sum: 1.0, sum_sq: 0.5 },
        };
        let mut m = a.clone();
        m.merge(&a);
        assert_eq!(m.image, vec![2.0, 4.0, 6.0]);
        assert_eq!((m.weight, m.accepted, m.invalid, m.candidates), (8.0, 4.0, 2, 20));
        assert_eq!(m.large_steps, Moments { count: 4, sum: 2.0, sum_sq: 1.0 });
    }

    #[test]
    fn a_weighted_merge_scales_each_pixel_and_empties_the_source() {
        let mut fresh = Accumulation {
            image: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            weight: 2.0,
            candidates: 5,
            ..Default::default()
        };
        let mut acc = Accumulation::new(2);
        acc.merge_weighted(&mut fresh, &[0.5, 2.0]);
        assert_eq!(acc.image, vec![0.5, 1.0, 1.5, 8.0, 10.0, 12.0]);
        assert_eq!((acc.weight, acc.candidates), (2.0, 5));
        assert_eq!(fresh, Accumulation::new(2));
    }
}
