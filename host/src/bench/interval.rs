//! Confidence intervals over independent repeats: the bench runs every method R times with
//! independent seeds and reports each measurement as a mean with a two-sided 95 % Student t
//! interval; a method is called best only where its interval does not overlap the others'.

/// A mean and the half-width of its 95 % confidence interval (0 for a single value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    #[allow(missing_docs)] // of the values: named for what it is
    pub mean: f64,
    /// Half the width of the 95 % interval: t(0.975, n − 1) · s / √n.
    pub half_width: f64,
    /// Number of values; below 2 the half-width is 0.
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
    /// The interval of `values` (at least one).
    pub fn of(values: &[f64]) -> Interval {
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n.max(1) as f64;
        if n < 2 {
            return Interval { mean, half_width: 0.0, n };
        }
        let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        Interval { mean, half_width: t975(n - 1) * (variance / n as f64).sqrt(), n }
    }

    /// Lower end: mean − half-width.
    pub fn low(&self) -> f64 {
        self.mean - self.half_width
    }

    /// Upper end: mean + half-width.
    pub fn high(&self) -> f64 {
        self.mean + self.half_width
    }

    /// Whether the two intervals share no point.
    pub fn separated_from(&self, other: &Interval) -> bool {
        self.high() < other.low() || other.high() < self.low()
    }

    /// "mean ± half-width" (just the mean for a single value), with `decimals` decimals.
    pub fn show(&self, decimals: usize) -> String {
        if self.n < 2 {
            format!("{:.*}", decimals, self.mean)
        } else {
            format!("{:.*} ± {:.*}", decimals, self.mean, decimals, self.half_width)
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
        assert!((i.half_width - 3.182 * (5.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-9);
        assert_eq!(Interval::of(&[7.0]).half_width, 0.0);
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
            if i.low() <= 6.0 && 6.0 <= i.high() {
                covered += 1;
            }
        }
        let rate = covered as f64 / trials as f64;
        assert!((rate - 0.95).abs() < 0.015, "coverage {rate}");
    }

    #[test]
    fn best_only_where_the_intervals_separate() {
        let a = Interval { mean: 1.0, half_width: 0.1, n: 3 };
        let b = Interval { mean: 2.0, half_width: 0.1, n: 3 };
        let c = Interval { mean: 1.15, half_width: 0.1, n: 3 };
        assert_eq!(clear_best(&[b, a], false), Some(1));
        assert_eq!(clear_best(&[b, a], true), Some(0));
        assert_eq!(clear_best(&[a, b, c], false), None, "a and c overlap");
        let single = Interval { mean: 1.0, half_width: 0.0, n: 1 };
        assert_eq!(clear_best(&[single, b], false), None, "single runs never decide");
    }
}
