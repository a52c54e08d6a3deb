//! Confidence intervals over independent repeats: the bench runs every method R times with
//! independent seeds and reports each measurement as a mean with a two-sided 95 % Student t
//! interval; a method is called best only where its interval does not overlap the others'.

/// A mean and its 95 % confidence interval [low, high] (both the mean for a single value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    #[allow(missing_docs)] // of the values: named for what it is
    pub mean: f64,
    /// Lower end of the 95 % interval.
    pub low: f64,
    /// Upper end of the 95 % interval (∞ for a reciprocal whose interval reaches 0).
    pub high: f64,
    /// Number of values; below 2 the interval is the mean alone.
    pub n: usize,
}

/// The 0.975 quantile of Student's t with `dof` degrees of freedom (1.96 beyond 30).
pub fn t975(dof: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145,
        2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048,
        2.045, 2.042,
    ];
    match dof {
        0 => f64::INFINITY,
        d if d <= 30 => TABLE[d - 1],
        _ => 1.96,
    }
}

impl Interval {
    /// `mean` ± `half_width` over `n` values.
    pub fn symmetric(mean: f64, half_width: f64, n: usize) -> Interval {
        Interval { mean, low: mean - half_width, high: mean + half_width, n }
    }

    /// The interval of `values` (at least one): their mean ± t(0.975, n − 1) · s / √n.
    pub fn of(values: &[f64]) -> Interval {
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n.max(1) as f64;
        if n < 2 {
            return Interval::symmetric(mean, 0.0, n);
        }
        let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        Interval::symmetric(mean, t975(n - 1) * (variance / n as f64).sqrt(), n)
    }

    /// The interval of 1/x for this interval of a positive quantity x: 1/mean, with the ends
    /// mapped and swapped (1/low is ∞ where the interval reaches 0). The efficiency 1/(relMSE ×
    /// seconds) is taken this way from the mean relMSE × seconds over the repeats, not as the
    /// mean of each run's own 1/(relMSE × seconds): by Jensen's inequality that mean is larger,
    /// and for an estimator whose error is heavy-tailed (a few runs with a firefly or a stuck
    /// chain) it reports the lucky runs' efficiency instead of the expected error's.
    pub fn reciprocal(&self) -> Interval {
        let inv = |x: f64| if x > 0.0 { 1.0 / x } else { f64::INFINITY };
        Interval { mean: inv(self.mean), low: inv(self.high), high: inv(self.low), n: self.n }
    }

    /// Whether the two intervals share no point.
    pub fn separated_from(&self, other: &Interval) -> bool {
        self.high < other.low || other.high < self.low
    }

    /// "mean ± half-width" for a symmetric interval, "mean (low–high)" for another (the
    /// reciprocals), just the mean for a single value; with `decimals` decimals.
    pub fn show(&self, decimals: usize) -> String {
        let below = self.mean - self.low;
        let above = self.high - self.mean;
        if self.n < 2 {
            format!("{:.*}", decimals, self.mean)
        } else if self.high.is_infinite() {
            format!("{:.*} ({:.*}–∞)", decimals, self.mean, decimals, self.low)
        } else if (below - above).abs() <= 1e-9 * (below + above) {
            format!("{:.*} ± {:.*}", decimals, self.mean, decimals, above)
        } else {
            format!("{:.*} ({:.*}–{:.*})", decimals, self.mean, decimals, self.low, decimals, self.high)
        }
    }
}

/// The index of the best of `intervals` (lowest mean, or highest with `higher_is_better`) if
/// its interval is separated from every other one; None when the intervals overlap (or there
/// is only one, or the values are single runs).
pub fn clear_best(intervals: &[Interval], higher_is_better: bool) -> Option<usize> {
    if intervals.len() < 2 || intervals.iter().any(|i| i.n < 2) {
        return None;
    }
    let key = |i: &Interval| if higher_is_better { -i.mean } else { i.mean };
    let best = (0..intervals.len()).min_by(|&a, &b| key(&intervals[a]).total_cmp(&key(&intervals[b])))?;
    let separated = intervals.iter().enumerate().all(|(j, i)| j == best || intervals[best].separated_from(i));
    separated.then_some(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interval_of_known_values() {
        let i = Interval::of(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(i.mean, 2.5);
        // s = √(5/3), t(3) = 3.182
        assert!((i.high - i.mean - 3.182 * (5.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-9);
        assert!((i.mean - i.low - 3.182 * (5.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-9);
        assert_eq!(Interval::of(&[7.0]).low, 7.0);
        assert_eq!(Interval::of(&[7.0]).show(2), "7.00");
        assert_eq!(Interval::of(&[1.0, 3.0]).show(1), "2.0 ± 12.7");
    }

    /// A 95 % interval covers the true mean about 95 % of the time.
    #[test]
    fn intervals_cover_the_mean_at_their_level() {
        let mut state = 0x2545_f491u32;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f64 / u32::MAX as f64
        };
        let trials = 4000;
        let mut covered = 0;
        for _ in 0..trials {
            // Means of 12 uniforms are near normal: mean 6, variance 1.
            let values: Vec<f64> = (0..4).map(|_| (0..12).map(|_| uniform()).sum::<f64>()).collect();
            let i = Interval::of(&values);
            if i.low <= 6.0 && 6.0 <= i.high {
                covered += 1;
            }
        }
        let rate = covered as f64 / trials as f64;
        assert!((rate - 0.95).abs() < 0.015, "coverage {rate}");
    }

    /// The reciprocal of an interval maps its ends and swaps them, with ∞ where it reaches 0;
    /// for heavy-tailed values the reciprocal of the mean lies well below the mean of the
    /// reciprocals (what the efficiency table used to show).
    #[test]
    fn reciprocals_map_and_swap_the_ends() {
        let i = Interval::symmetric(0.5, 0.25, 3).reciprocal();
        assert_eq!((i.mean, i.low, i.high), (2.0, 1.0 / 0.75, 4.0));
        assert_eq!(i.show(2), "2.00 (1.33–4.00)");
        let wide = Interval::symmetric(0.5, 0.75, 3).reciprocal();
        assert_eq!(wide.high, f64::INFINITY);
        assert_eq!(wide.show(1), "2.0 (0.8–∞)");
        // relMSE of three runs, one with a firefly: 1/mean against the mean of 1/x.
        let runs = [0.0129, 0.0143, 0.0419];
        let expected = Interval::of(&runs).reciprocal().mean;
        let lucky = runs.iter().map(|r| 1.0 / r).sum::<f64>() / 3.0;
        assert!((expected - 1.0 / 0.023033).abs() < 1e-3 && lucky > 1.3 * expected, "{expected} {lucky}");
    }

    #[test]
    fn best_only_where_the_intervals_separate() {
        let a = Interval::symmetric(1.0, 0.1, 3);
        let b = Interval::symmetric(2.0, 0.1, 3);
        let c = Interval::symmetric(1.15, 0.1, 3);
        assert_eq!(clear_best(&[b, a], false), Some(1));
        assert_eq!(clear_best(&[b, a], true), Some(0));
        assert_eq!(clear_best(&[a, b, c], false), None, "a and c overlap");
        let single = Interval::symmetric(1.0, 0.0, 1);
        assert_eq!(clear_best(&[single, b], false), None, "single runs never decide");
    }
}
