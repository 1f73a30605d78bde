//! numpy's float sequences and sum, value for value: the planner's thresholds were chosen on
//! the Python planner's numbers, so its grids of points and its sums are built in numpy's
//! order (`arange`, `linspace`, and the pairwise summation of `ndarray.sum`).

/// `numpy.arange(start, stop, step)` for floats: `ceil((stop - start) / step)` values, the
/// first two `start` and `start + step`, then `start + i * delta` with `delta` the
/// difference of those two (numpy's fill).
pub fn arange(start: f64, stop: f64, step: f64) -> Vec<f64> {
    let len = ((stop - start) / step).ceil();
    let len = if len.is_finite() && len > 0.0 {
        len as usize
    } else {
        0
    };
    let mut values = Vec::with_capacity(len);
    if len == 0 {
        return values;
    }
    values.push(start);
    if len == 1 {
        return values;
    }
    let second = start + step;
    values.push(second);
    let delta = second - start;
    values.extend((2..len).map(|i| start + i as f64 * delta));
    values
}

/// `numpy.linspace(start, stop, count)`: `i * step + start` with `step = (stop - start) /
/// (count - 1)`, the last value `stop` itself.
pub fn linspace(start: f64, stop: f64, count: usize) -> Vec<f64> {
    if count <= 1 {
        return vec![start; count];
    }
    let step = (stop - start) / (count - 1) as f64;
    let mut values: Vec<f64> = (0..count).map(|i| i as f64 * step + start).collect();
    values[count - 1] = stop;
    values
}

/// numpy's pairwise summation of a contiguous float64 array (what `ndarray.sum` returns):
/// below 8 values a plain loop, up to 128 eight running sums combined as a tree, beyond
/// that the two halves (the first a multiple of 8 long) summed apart.
pub fn pairwise_sum(values: &[f64]) -> f64 {
    const BLOCK: usize = 128;
    let n = values.len();
    if n < 8 {
        return values.iter().fold(0.0, |sum, &v| sum + v);
    }
    if n <= BLOCK {
        let mut r = [0.0; 8];
        r.copy_from_slice(&values[..8]);
        let whole = n - n % 8;
        for chunk in values[8..whole].chunks_exact(8) {
            for (sum, &v) in r.iter_mut().zip(chunk) {
                *sum += v;
            }
        }
        let tree = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        return values[whole..].iter().fold(tree, |sum, &v| sum + v);
    }
    let mut half = n / 2;
    half -= half % 8;
    pairwise_sum(&values[..half]) + pairwise_sum(&values[half..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arange_has_numpys_length_and_ends() {
        assert_eq!(arange(0.0, 1.0, 0.25), vec![0.0, 0.25, 0.5, 0.75]);
        assert_eq!(arange(0.05, 1.0 + 1e-9, 0.05).len(), 20);
        assert!(arange(1.0, 0.0, 0.1).is_empty());
        assert_eq!(arange(0.3, 0.35, 0.1), vec![0.3]);
    }

    #[test]
    fn linspace_ends_exactly_at_both_ends() {
        let values = linspace(0.03, 0.115, 8);
        assert_eq!((values[0], values[7]), (0.03, 0.115));
        assert!(values.windows(2).all(|w| w[0] < w[1]));
    }

    /// Summing in numpy's order: 1,000 values whose plain loop gives 102.99749949999999
    /// sum to numpy's `ndarray.sum()` of them, 102.9974995, bit for bit.
    #[test]
    fn pairwise_sum_is_numpys_sum_not_the_plain_loops() {
        let values: Vec<f64> = (0..1000)
            .map(|i| 0.1 + (i % 7) as f64 * 1e-3 + 1e-9 * i as f64)
            .collect();
        let plain = values.iter().fold(0.0, |sum, v| sum + v);
        assert_eq!(plain, 102.99749949999999);
        assert_eq!(pairwise_sum(&values), 102.9974995);
        assert_eq!(
            pairwise_sum(&values[..5]),
            values[..5].iter().fold(0.0, |s, v| s + v)
        );
        assert_eq!(pairwise_sum(&[]), 0.0);
    }
}
