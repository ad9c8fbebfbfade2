//! Measurement noise on reported values: Gaussian, from a small seeded generator (splitmix64 and
//! Box-Muller), so a run with the same seed gives the same frames.

#[derive(Clone, Debug)]
pub(super) struct Noise {
    /// Standard deviation in units of each field's resolution; 0 draws nothing.
    sigma: f64,
    state: u64,
    /// Box-Muller gives two values; the second waits here.
    spare: Option<f64>,
}

impl Noise {
    pub fn new(sigma: f64, seed: u64) -> Self {
        Self { sigma, state: seed, spare: None }
    }

    /// `value` plus Gaussian noise with a standard deviation of `sigma` × `resolution`; `value` itself
    /// (and no draw) when there is no noise.
    pub fn add(&mut self, value: f64, resolution: f64) -> f64 {
        if self.sigma == 0.0 {
            return value;
        }
        value + self.gaussian() * self.sigma * resolution
    }

    /// A standard normal value.
    fn gaussian(&mut self) -> f64 {
        if let Some(spare) = self.spare.take() {
            return spare;
        }
        // u1 in (0, 1], so the logarithm is finite.
        let u1 = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let u1 = 1.0 - u1;
        let u2 = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let radius = (-2.0 * u1.ln()).sqrt();
        let angle = std::f64::consts::TAU * u2;
        self.spare = Some(radius * angle.sin());
        radius * angle.cos()
    }

    /// splitmix64 (Steele, Lea, Flood 2014).
    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // The reference implementation seeded with 0 starts with these.
        let mut noise = Noise::new(1.0, 0);
        assert_eq!(noise.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(noise.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    }

    #[test]
    fn gaussian_has_mean_0_and_the_standard_deviation_asked_for() {
        let mut noise = Noise::new(2.0, 7);
        let samples: Vec<f64> = (0..100_000).map(|_| noise.add(10.0, 0.5)).collect();
        let mean = samples.iter().sum::<f64>() / samples.len() as f64;
        let variance = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / samples.len() as f64;
        assert!((mean - 10.0).abs() < 0.01, "{mean}");
        assert!((variance.sqrt() - 1.0).abs() < 0.01, "{}", variance.sqrt());
        assert!(samples.iter().all(|x| x.is_finite()));
    }

    #[test]
    fn no_noise_is_the_value_itself_and_the_same_seed_repeats() {
        let mut quiet = Noise::new(0.0, 3);
        assert_eq!(quiet.add(0.1234, 0.001), 0.1234);
        let draw = |seed| {
            let mut noise = Noise::new(1.0, seed);
            (0..5).map(|_| noise.add(0.0, 1.0)).collect::<Vec<_>>()
        };
        assert_eq!(draw(42), draw(42));
        assert_ne!(draw(42), draw(43));
    }
}
