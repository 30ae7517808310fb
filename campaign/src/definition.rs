//! What a campaign is: its seed, scenario, phi_cmd grid, laws, runs per point and
//! dispersion ranges, and how its flights are numbered and split into shards.
//!
//! A *run* `j` (0..runs_per_point) is one dispersion draw, seeded by
//! [`run_seed`]`(seed, j)`. Each run is flown once for every
//! (phi_cmd, law) pair, so every law and every phi_cmd point sees the same N dispersed
//! landers (common random numbers): differences between laws and along phi_cmd come from
//! the law and phi_cmd, not from different draws. A *flight* is one (run, phi_cmd, law);
//! its index is `(j * phi_count + phi_index) * law_count + law_index`, so a shard or an
//! interrupted campaign holds whole runs' worth of comparisons.
use crate::dispersion::DispersionRanges;
use crate::seed::run_seed;
use lander::laws::Law;

/// The scenario a campaign flies unless told otherwise: the paper's scenario in the flight
/// configuration (`harness/scenarios/flight.toml`), whose dispersed flights measure the laws
/// rather than the paper configuration's hover-to-descent handover (docs/results.md).
pub const DEFAULT_SCENARIO: &str = "flight";

/// The definition of a campaign: everything a flight's result depends on (with the FMUs).
#[derive(Debug, Clone, PartialEq)]
pub struct CampaignSpec {
    /// Built-in scenario name or scenario file path.
    pub scenario: String,
    pub seed: u64,
    pub phi_cmd_deg: Vec<f64>,
    pub laws: Vec<Law>,
    pub runs_per_point: u64,
    pub dispersions: DispersionRanges,
    /// `--set INSTANCE.VAR=VALUE` applied to the scenario before any draw: the nominal every
    /// flight starts from.
    pub sets: Vec<String>,
}

/// One flight of a campaign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flight {
    pub index: u64,
    pub run: u64,
    pub run_seed: u64,
    pub law: Law,
    pub phi_cmd_deg: f64,
}

impl CampaignSpec {
    pub fn flight_count(&self) -> u64 {
        // Saturating: a count beyond u64 is refused by the size check, never wrapped.
        self.runs_per_point
            .saturating_mul((self.phi_cmd_deg.len() * self.laws.len()) as u64)
    }

    /// The flight with index `index` (< [`CampaignSpec::flight_count`]).
    pub fn flight(&self, index: u64) -> Flight {
        let laws = self.laws.len() as u64;
        let phis = self.phi_cmd_deg.len() as u64;
        let law = self.laws[(index % laws) as usize];
        let phi_cmd_deg = self.phi_cmd_deg[((index / laws) % phis) as usize];
        let run = index / (laws * phis);
        Flight {
            index,
            run,
            run_seed: run_seed(self.seed, run),
            law,
            phi_cmd_deg,
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        if self.phi_cmd_deg.is_empty() || self.laws.is_empty() || self.runs_per_point == 0 {
            return Err("a campaign needs at least one phi_cmd, one law and one run".into());
        }
        if let Some(bad) = self.phi_cmd_deg.iter().find(|p| !p.is_finite()) {
            return Err(format!("phi_cmd {bad} deg is not a number"));
        }
        for (i, phi) in self.phi_cmd_deg.iter().enumerate() {
            if self.phi_cmd_deg[..i].contains(phi) {
                return Err(format!("phi_cmd {phi} deg is listed twice"));
            }
        }
        for (i, law) in self.laws.iter().enumerate() {
            if self.laws[..i].contains(law) {
                return Err(format!("law {} is listed twice", law.name()));
            }
        }
        self.runs_per_point
            .checked_mul((self.phi_cmd_deg.len() * self.laws.len()) as u64)
            .ok_or("too many flights")?;
        self.dispersions.validate()
    }
}

/// `k/N`: the flights whose index is `k - 1` modulo `N` (k is 1-based, as array-job
/// schedulers number their tasks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub k: u64,
    pub n: u64,
}

impl Shard {
    pub const WHOLE: Shard = Shard { k: 1, n: 1 };

    /// The indices of this shard among `flight_count` flights, in increasing order.
    pub fn indices(self, flight_count: u64) -> impl Iterator<Item = u64> {
        (self.k - 1..flight_count).step_by(self.n as usize)
    }

    pub fn len(self, flight_count: u64) -> u64 {
        flight_count.saturating_sub(self.k - 1).div_ceil(self.n)
    }

    pub fn is_whole(self) -> bool {
        self.n == 1
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = || format!("shard '{text}': expected k/N with 1 <= k <= N, e.g. 2/8");
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let (k, n): (u64, u64) = (
            k.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        if k == 0 || k > n || usize::try_from(n).is_err() {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> CampaignSpec {
        CampaignSpec {
            scenario: "paper".into(),
            seed: 7,
            phi_cmd_deg: vec![0.0, 90.0, 180.0],
            laws: vec![Law::COUPLED, Law::DECOUPLED],
            runs_per_point: 4,
            dispersions: DispersionRanges::default(),
            sets: Vec::new(),
        }
    }

    #[test]
    fn every_run_phi_law_triple_is_one_flight() {
        let spec = spec();
        let mut seen = std::collections::HashSet::new();
        for index in 0..spec.flight_count() {
            let f = spec.flight(index);
            assert_eq!(f.index, index);
            assert!(f.run < spec.runs_per_point);
            assert_eq!(f.run_seed, run_seed(7, f.run));
            assert!(seen.insert((f.run, f.phi_cmd_deg.to_bits(), f.law)));
        }
        assert_eq!(seen.len(), 24);
    }

    #[test]
    fn shards_partition_the_flights() {
        for count in [0, 1, 5, 24, 25] {
            for n in 1..=7 {
                let mut all: Vec<u64> = (1..=n)
                    .flat_map(|k| {
                        let shard = Shard { k, n };
                        let indices: Vec<u64> = shard.indices(count).collect();
                        assert_eq!(indices.len() as u64, shard.len(count));
                        assert!(indices.iter().all(|i| i % n == k - 1));
                        indices
                    })
                    .collect();
                all.sort_unstable();
                assert_eq!(all, (0..count).collect::<Vec<_>>());
            }
        }
    }

    #[test]
    fn shard_syntax() {
        assert_eq!("2/8".parse::<Shard>().unwrap(), Shard { k: 2, n: 8 });
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn bad_definitions_are_refused() {
        let mut s = spec();
        s.phi_cmd_deg.push(90.0);
        assert!(s.validate().unwrap_err().contains("twice"));
        let mut s = spec();
        s.runs_per_point = 0;
        assert!(s.validate().is_err());
        let mut s = spec();
        s.dispersions.mass_fraction = -0.1;
        assert!(s.validate().unwrap_err().contains("--disp-mass-frac"));
    }
}
