//! Latency: the inputs of past communication points, so a group can show the value of
//! `n` steps ago. After the step from `t_k`, the history holds the inputs at
//! `t_k-L+1 .. t_k` (`L` the longest latency); at `t_k+1` a group late by `n` steps reads
//! the input at `t_k+1-n`, the `n`-th most recent. Before the run has that much past, the
//! first input stands in for the inputs before it (the history starts full of it).
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct History<T> {
    samples: VecDeque<T>,
    capacity: usize,
}

impl<T: Copy> History<T> {
    /// A history of the last `capacity` inputs (0: none kept).
    pub fn new(capacity: usize) -> Self {
        History {
            samples: VecDeque::new(),
            capacity,
        }
    }

    /// Records the input of the communication point a step starts from.
    pub fn record(&mut self, input: T) {
        if self.capacity == 0 {
            return;
        }
        if self.samples.is_empty() {
            self.samples.resize(self.capacity, input);
            return;
        }
        if self.samples.len() == self.capacity {
            self.samples.pop_front();
        }
        self.samples.push_back(input);
    }

    /// Whether this could be a history of `capacity` inputs: empty before the first step,
    /// full after it.
    pub fn holds(&self, capacity: usize) -> bool {
        self.capacity == capacity && (self.samples.is_empty() || self.samples.len() == capacity)
    }

    pub fn samples(&self) -> impl Iterator<Item = &T> {
        self.samples.iter()
    }

    /// The input of `steps` communication points ago; `current` for 0 steps or before the
    /// first step. A request beyond the capacity (refused by validation) reads the oldest.
    pub fn delayed(&self, steps: usize, current: T) -> T {
        if steps == 0 || self.samples.is_empty() {
            return current;
        }
        let back = steps.min(self.samples.len());
        self.samples[self.samples.len() - back]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_comes_out_exactly_n_steps_later() {
        let mut history = History::new(3);
        // Before any step, the current input.
        assert_eq!(history.delayed(3, 0), 0);
        for k in 0..10 {
            history.record(k);
            let now = k + 1;
            for n in 0..=3 {
                let expected = if n == 0 { now } else { (now - n as i32).max(0) };
                assert_eq!(history.delayed(n, now), expected, "k = {k}, n = {n}");
            }
        }
    }

    #[test]
    fn no_capacity_keeps_nothing() {
        let mut history = History::new(0);
        history.record(1.0);
        assert_eq!(history.delayed(0, 2.0), 2.0);
        assert_eq!(history.samples.len(), 0);
    }

    #[test]
    fn a_history_holds_its_capacity_only_empty_or_full() {
        let mut history = History::new(3);
        assert!(history.holds(3) && !history.holds(2));
        history.record(1);
        assert!(history.holds(3));
        history.samples.pop_back();
        assert!(!history.holds(3));
    }
}
