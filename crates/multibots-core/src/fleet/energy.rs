//! Energy (spec section 2 and phases 5–7): comparisons with ε, consumption and charging.

/// Tolerance of every energy comparison.
pub const EPS: f64 = 1e-9;

/// "Below threshold" is energy < threshold − ε.
#[inline]
#[must_use]
pub fn below(energy: f64, threshold: f64) -> bool {
    energy < threshold - EPS
}

/// "Full" is energy ≥ full − ε.
#[inline]
#[must_use]
pub fn is_full(energy: f64, full: f64) -> bool {
    energy >= full - EPS
}

/// A robot whose energy is ≤ ε is stranded.
#[inline]
#[must_use]
pub fn exhausted(energy: f64) -> bool {
    energy <= EPS
}

/// Energy after one step of consumption; never below zero.
#[inline]
#[must_use]
pub fn consume(energy: f64, rate: f64) -> f64 {
    (energy - rate).max(0.0)
}

/// Energy after one step of charging, capped at full.
#[inline]
#[must_use]
pub fn charge(energy: f64, rate: f64, full: f64) -> f64 {
    (energy + rate).min(full)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threshold_uses_epsilon() {
        assert!(!below(3.5, 3.5));
        assert!(!below(3.5 - 0.5e-9, 3.5));
        assert!(below(3.5 - 2e-9, 3.5));
        // 1300 steps of 0.005 from 10 land within rounding of 3.5: that is not below it.
        let mut e = 10.0;
        for _ in 0..1300 {
            e = consume(e, 0.005);
        }
        assert!((e - 3.5).abs() < 1e-9, "accumulated rounding: {e}");
        assert!(!below(e, 3.5));
        assert!(below(consume(e, 0.005), 3.5));
    }

    #[test]
    fn full_uses_epsilon_and_charging_caps() {
        assert!(is_full(10.0 - 0.5e-9, 10.0));
        assert!(!is_full(10.0 - 2e-9, 10.0));
        assert_eq!(charge(9.99, 0.05, 10.0), 10.0);
        let mut e = 3.49;
        let mut steps = 0;
        while !is_full(e, 10.0) {
            e = charge(e, 0.05, 10.0);
            steps += 1;
        }
        assert_eq!(steps, 131);
    }

    #[test]
    fn stranding_and_the_floor() {
        assert!(exhausted(0.0));
        assert!(exhausted(1e-10));
        assert!(!exhausted(0.004));
        assert_eq!(consume(0.003, 0.005), 0.0);
    }
}
