//! Small numeric helpers over (time µs, value) points: mean and spread, a least-squares line, the time a
//! series crosses a level.

/// Mean and (population) standard deviation; `None` for no values.
pub(super) fn mean_and_sigma(values: impl Iterator<Item = f64> + Clone) -> Option<(f64, f64)> {
    let (n, sum) = values.clone().fold((0usize, 0.0), |(n, sum), v| (n + 1, sum + v));
    if n == 0 {
        return None;
    }
    let mean = sum / n as f64;
    let var = values.map(|v| (v - mean) * (v - mean)).sum::<f64>() / n as f64;
    Some((mean, var.sqrt()))
}

/// A least-squares line `value = intercept + slope × (t - t_ref)` through points (µs, value); `None` for
/// fewer than two distinct times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Line {
    pub t_ref: f64,
    pub intercept: f64,
    /// Value per µs.
    pub slope: f64,
}

impl Line {
    pub fn fit(points: impl Iterator<Item = (i64, f64)> + Clone) -> Option<Self> {
        let t_ref = points.clone().next()?.0 as f64;
        let (n, st, sv) = points
            .clone()
            .fold((0.0, 0.0, 0.0), |(n, st, sv), (t, v)| (n + 1.0, st + (t as f64 - t_ref), sv + v));
        let (mt, mv) = (st / n, sv / n);
        let (sxx, sxy) = points.fold((0.0, 0.0), |(sxx, sxy), (t, v)| {
            let dt = t as f64 - t_ref - mt;
            (sxx + dt * dt, sxy + dt * (v - mv))
        });
        if sxx <= 0.0 {
            return None;
        }
        let slope = sxy / sxx;
        Some(Self { t_ref, intercept: mv - slope * mt, slope })
    }

    /// The standard error of the slope fitted to `points` (the same points): the residuals' spread over the
    /// spread of the times; 0 for fewer than three points.
    pub fn slope_error(&self, points: impl Iterator<Item = (i64, f64)> + Clone) -> f64 {
        let (n, st) =
            points.clone().fold((0.0, 0.0), |(n, st), (t, _)| (n + 1.0, st + (t as f64 - self.t_ref)));
        if n <= 2.0 {
            return 0.0;
        }
        let mean_t = st / n;
        let (sxx, residuals) = points.fold((0.0, 0.0), |(sxx, residuals), (t, v)| {
            let dt = t as f64 - self.t_ref;
            let off = v - (self.intercept + self.slope * dt);
            (sxx + (dt - mean_t) * (dt - mean_t), residuals + off * off)
        });
        if sxx > 0.0 {
            (residuals / (n - 2.0) / sxx).sqrt()
        } else {
            0.0
        }
    }

    /// When the line reaches `level`, µs; `None` for a flat line.
    pub fn time_at(&self, level: f64) -> Option<f64> {
        (self.slope != 0.0).then(|| self.t_ref + (level - self.intercept) / self.slope)
    }
}

/// The first time, interpolated linearly between samples, at which `direction × (value - level)` reaches 0
/// going up, searching `points` in order; `None` if it never does.
pub(super) fn crossing(points: impl Iterator<Item = (i64, f64)>, level: f64, direction: f64) -> Option<f64> {
    let mut previous: Option<(i64, f64)> = None;
    for (t, v) in points {
        let above = direction * (v - level);
        if above >= 0.0 {
            return Some(match previous {
                Some((tp, vp)) if v != vp => tp as f64 + (level - vp) / (v - vp) * (t - tp) as f64,
                _ => t as f64,
            });
        }
        previous = Some((t, v));
    }
    None
}

/// The median of whole numbers (the mean of the middle two, rounded towards zero, for an even count);
/// `None` when empty. A selection, not a sort: it runs on every stretch's command gaps.
pub(super) fn median(mut values: Vec<i64>) -> Option<i64> {
    let count = values.len();
    if count == 0 {
        return None;
    }
    let (lower, &mut middle, _) = values.select_nth_unstable(count / 2);
    Some(match lower.iter().max() {
        // In i128: no overflow whatever the values.
        Some(&below) if count % 2 == 0 => ((i128::from(below) + i128::from(middle)) / 2) as i64,
        _ => middle,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slope_error_is_the_residual_spread_over_the_time_spread() {
        // Residuals +1, -1, +1, -1 around v = t: s² = 4 / 2 = 2, Sxx = 5 (times 0..3): SE = sqrt(2 / 5).
        let points = [(0i64, 1.0), (1, 0.0), (2, 3.0), (3, 2.0)];
        let line = Line::fit(points.iter().copied()).unwrap();
        assert!((line.slope - 0.6).abs() < 1e-12, "{line:?}");
        let residuals: f64 =
            points.iter().map(|&(t, v)| (v - line.intercept - line.slope * t as f64).powi(2)).sum();
        let expected = (residuals / 2.0 / 5.0).sqrt();
        assert!((line.slope_error(points.iter().copied()) - expected).abs() < 1e-12);
        let exact = [(0i64, 0.0), (1, 1.0), (2, 2.0)];
        assert_eq!(Line::fit(exact.iter().copied()).unwrap().slope_error(exact.iter().copied()), 0.0);
    }

    #[test]
    fn mean_and_sigma_of_a_few_values() {
        assert_eq!(mean_and_sigma([2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0].into_iter()), Some((5.0, 2.0)));
        assert_eq!(mean_and_sigma(std::iter::empty()), None);
    }

    #[test]
    fn a_line_through_exact_points_and_where_it_crosses_a_level() {
        let points = [(1_000_000i64, 1.0), (1_020_000, 3.0), (1_040_000, 5.0)];
        let line = Line::fit(points.iter().copied()).unwrap();
        assert!((line.slope - 1e-4).abs() < 1e-15);
        assert!((line.time_at(0.0).unwrap() - 990_000.0).abs() < 1e-6);
        assert_eq!(Line::fit([(5, 1.0), (5, 2.0)].into_iter()), None);
        assert_eq!(Line::fit(std::iter::empty()), None);
    }

    #[test]
    fn crossings_are_interpolated_in_either_direction() {
        let up = [(0i64, 0.0), (20, 0.2), (40, 0.4)];
        assert_eq!(crossing(up.iter().copied(), 0.3, 1.0), Some(30.0));
        let down = [(0i64, 0.4), (20, 0.2), (40, 0.0)];
        assert_eq!(crossing(down.iter().copied(), 0.1, -1.0), Some(30.0));
        assert_eq!(crossing(up.iter().copied(), 0.5, 1.0), None);
        // Already past the level at the first point: that point's time.
        assert_eq!(crossing(up.iter().copied(), -1.0, 1.0), Some(0.0));
    }

    #[test]
    fn medians_of_odd_and_even_counts() {
        assert_eq!(median(vec![3, 1, 2]), Some(2));
        assert_eq!(median(vec![4, 1, 2, 3]), Some(2));
        assert_eq!(median(vec![40, 10, 20, 30, 20, 20]), Some(20));
        assert_eq!(median(vec![5, 8]), Some(6));
        assert_eq!(median(vec![7]), Some(7));
        assert_eq!(median(Vec::new()), None);
    }
}
