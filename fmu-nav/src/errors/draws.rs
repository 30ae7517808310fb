//! The standard normal draws of one communication interval, counter-based: the draws of
//! interval `k` are a function of `(seed, k)` alone. So a restored state needs only its
//! interval number to continue the sequence, no reading or other call can shift it, and
//! any master that steps the same grid sees the same numbers, bit for bit.
//!
//! Interval `k` uses ChaCha12 keyed by the seed (rand_core's portable `seed_from_u64`
//! expansion) on stream `k`, and always draws the same values in the same order: per group
//! (position, velocity, attitude, rate, mass), per axis, the white-noise value then the
//! random-walk value. Switching one error on therefore changes no other group's numbers.
use super::normal::standard_normal;
use super::parameters::Group;
use rand::SeedableRng;
use rand_chacha::ChaCha12Rng;

/// Standard normal values of one interval, per group (indexed by [`Group`]) and axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Draws {
    pub white: [[f64; 3]; 5],
    pub walk: [[f64; 3]; 5],
}

impl Draws {
    pub fn of_interval(seed: u64, interval: u64) -> Draws {
        let mut rng = ChaCha12Rng::seed_from_u64(seed);
        rng.set_stream(interval);
        let mut draws = Draws {
            white: [[0.0; 3]; 5],
            walk: [[0.0; 3]; 5],
        };
        for g in Group::ALL {
            for axis in 0..3 {
                draws.white[g as usize][axis] = standard_normal(&mut rng);
                draws.walk[g as usize][axis] = standard_normal(&mut rng);
            }
        }
        draws
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_interval_draws_the_same_values_whenever_it_is_asked() {
        assert_eq!(Draws::of_interval(7, 123), Draws::of_interval(7, 123));
    }

    #[test]
    fn intervals_and_seeds_draw_different_values() {
        let a = Draws::of_interval(7, 123);
        assert_ne!(a.white, Draws::of_interval(7, 124).white);
        assert_ne!(a.white, Draws::of_interval(8, 123).white);
        assert_ne!(a.white[0], a.walk[0]);
    }
}
