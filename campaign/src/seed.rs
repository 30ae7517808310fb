//! Run seeds: how a campaign seed and a run number become the seed of one run's draws.
//!
//! `run_seed(campaign_seed, run)` is output number `run` (0-based) of the SplitMix64
//! generator seeded with `campaign_seed` (Steele, Lea and Flood, "Fast splittable
//! pseudorandom number generators", OOPSLA 2014; the reference C code is Vigna's
//! `splitmix64.c`): `mix64(campaign_seed + (run + 1) * 0x9E3779B97F4A7C15)` in wrapping
//! 64-bit arithmetic. It needs no state, so any run is reachable directly, and its finaliser
//! makes neighbouring runs' seeds uncorrelated, so neighbouring ChaCha8 streams are too.
//! The run's draws then come from `ChaCha8Rng::seed_from_u64(run_seed)` (rand_core's
//! portable seed expansion), in the fixed order of [`crate::dispersion::Dispersion::draw`].

const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output finaliser (a bijection on u64).
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of run `run` of the campaign seeded with `campaign_seed`.
pub fn run_seed(campaign_seed: u64, run: u64) -> u64 {
    mix64(campaign_seed.wrapping_add(run.wrapping_add(1).wrapping_mul(GOLDEN_GAMMA)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference `splitmix64.c` state update, written out as the stateful generator.
    struct SplitMix64(u64);
    impl SplitMix64 {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(GOLDEN_GAMMA);
            mix64(self.0)
        }
    }

    #[test]
    fn run_seeds_are_the_splitmix64_sequence() {
        // Published first output of SplitMix64 seeded with 0.
        assert_eq!(run_seed(0, 0), 0xE220_A839_7B1D_CDAF);
        for campaign_seed in [0, 1, 42, u64::MAX] {
            let mut reference = SplitMix64(campaign_seed);
            for run in 0..100 {
                assert_eq!(run_seed(campaign_seed, run), reference.next());
            }
        }
    }

    #[test]
    fn distinct_runs_and_campaigns_get_distinct_seeds() {
        let mut seen = std::collections::HashSet::new();
        for campaign_seed in 0..20 {
            for run in 0..500 {
                assert!(seen.insert(run_seed(campaign_seed, run)));
            }
        }
    }
}
