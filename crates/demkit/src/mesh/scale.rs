//! Scaling coordinates by powers of two.
//!
//! Multiplying by 2^k changes only the exponent of every coordinate, so it is exact (short of
//! overflow or underflow) and undone exactly. Inputs far from unit size — coordinates of
//! 1e300 or 1e-200, whose products (areas, cross products) overflow or vanish — are brought to
//! unit size this way before anything is computed, and results in input units are mapped back.

/// Coordinates whose largest magnitude lies within 2^±`FREE_RANGE` are computed as they are:
/// their areas and products are far from overflow and underflow (and results stay bit for bit
/// what they were).
pub const FREE_RANGE: i32 = 40;

/// `x · 2^k`, exact whenever the result is a normal number (in steps, so that `k` beyond the
/// exponent range of a single power of two is fine).
pub fn ldexp(mut x: f64, mut k: i32) -> f64 {
    while k > 1000 {
        x *= 2f64.powi(1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= 2f64.powi(-1000);
        k += 1000;
    }
    x * 2f64.powi(k)
}

/// The exponent `k` that brings the largest finite coordinate magnitude of `positions` into
/// [0.5, 1) when multiplied by 2^k; 0 for no finite non-zero coordinate.
pub fn unit_exponent(positions: &[[f64; 3]]) -> i32 {
    let largest = positions
        .iter()
        .flatten()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 {
        return 0;
    }
    // largest = m · 2^e with m in [0.5, 1): k = −e.
    let mut e = largest.log2().floor() as i32 + 1;
    // log2 may round across a power of two: settle e exactly.
    while ldexp(largest, -e) >= 1.0 {
        e += 1;
    }
    while ldexp(largest, -e) < 0.5 {
        e -= 1;
    }
    -e
}

/// The exponent to scale `positions` by before computing: [`unit_exponent`] when the
/// coordinates lie beyond 2^±[`FREE_RANGE`], else 0 (left as they are).
pub fn normalizing_exponent(positions: &[[f64; 3]]) -> i32 {
    let k = unit_exponent(positions);
    if k.abs() > FREE_RANGE { k } else { 0 }
}

/// Multiplies every coordinate by 2^k.
pub fn scale_positions(positions: &mut [[f64; 3]], k: i32) {
    if k == 0 {
        return;
    }
    // One power of two when it is a normal number, exact steps otherwise.
    let factor = (k.abs() <= 1000).then(|| 2f64.powi(k));
    for x in positions.iter_mut().flatten() {
        *x = match factor {
            Some(f) => *x * f,
            None => ldexp(*x, k),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unit_exponent_brings_the_largest_coordinate_into_half_to_one() {
        for (x, k) in [
            (1.0, -1),
            (0.75, 0),
            (0.5, 0),
            (3.0, -2),
            (1e308, -1024),
            (1e-200, 664),
        ] {
            let p = [[x, -0.1 * x, 0.0]];
            assert_eq!(unit_exponent(&p), k, "{x}");
            let s = ldexp(x, k);
            assert!((0.5..1.0).contains(&s), "{x}: {s}");
        }
        assert_eq!(unit_exponent(&[[0.0; 3]]), 0);
    }

    #[test]
    fn scaling_is_exact_and_undone_exactly() {
        let original = vec![[1e-190, -3.7e-200, 1e-210], [2.5e-200, 1.0e-199, -7.0e-201]];
        let k = normalizing_exponent(&original);
        assert!(k > FREE_RANGE);
        let mut p = original.clone();
        scale_positions(&mut p, k);
        assert!(p.iter().flatten().all(|x| x.abs() < 1.0));
        scale_positions(&mut p, -k);
        assert_eq!(p, original);
    }

    #[test]
    fn ordinary_sizes_are_left_alone() {
        assert_eq!(normalizing_exponent(&[[1e-6, 3e5, 2.0]]), 0);
        assert_ne!(normalizing_exponent(&[[1e-30, 0.0, 0.0]]), 0);
        assert_ne!(normalizing_exponent(&[[1e30, 0.0, 0.0]]), 0);
    }
}
