//! `--shard K/N`: the K-th of N parts of a list of traces, so that the
//! parallel jobs of a CI system replay a corpus between them (decision 311).

use std::fmt;

/// One part of a deterministic split: part `k` (from 1) of `n`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    k: usize,
    n: usize,
}

impl Shard {
    /// Part `k` of `n`; `None` unless 1 <= k <= n.
    pub fn new(k: usize, n: usize) -> Option<Self> {
        (k >= 1 && k <= n).then_some(Self { k, n })
    }

    /// The items of this part: those at positions k-1, k-1+n, k-1+2n ...
    /// of the list, in their order. Every job given the same list gets
    /// parts that are disjoint and together the whole list, each within
    /// one item of the same length.
    pub fn pick<T>(&self, items: Vec<T>) -> Vec<T> {
        items
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % self.n == self.k - 1)
            .map(|(_, t)| t)
            .collect()
    }
}

/// A `--shard` that is not `K/N` with `1 <= K <= N`.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
#[error("`{0}` is not K/N with 1 <= K <= N (e.g. 2/4)")]
pub(crate) struct BadShard(String);

/// Reads `--shard K/N`.
pub(crate) fn parse_shard(s: &str) -> Result<Shard, BadShard> {
    let bad = || BadShard(s.to_string());
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let k = k.trim().parse().map_err(|_| bad())?;
    let n = n.trim().parse().map_err(|_| bad())?;
    Shard::new(k, n).ok_or_else(bad)
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_disjoint_and_make_the_whole() {
        for len in [0usize, 1, 5, 17, 100] {
            for n in 1..=7 {
                let items: Vec<usize> = (0..len).collect();
                let mut seen = vec![0u32; len];
                let mut sizes = Vec::new();
                for k in 1..=n {
                    let part = Shard::new(k, n).unwrap().pick(items.clone());
                    assert!(part.windows(2).all(|w| w[0] < w[1]), "order kept");
                    sizes.push(part.len());
                    for i in part {
                        seen[i] += 1;
                    }
                }
                assert!(seen.iter().all(|&c| c == 1), "len {len} n {n}: {seen:?}");
                let (lo, hi) = (sizes.iter().min(), sizes.iter().max());
                assert!(hi.unwrap() - lo.unwrap() <= 1, "balanced: {sizes:?}");
            }
        }
    }

    #[test]
    fn parses_k_of_n_and_refuses_the_rest() {
        assert_eq!(parse_shard("2/4"), Ok(Shard { k: 2, n: 4 }));
        assert_eq!(parse_shard("1/1").unwrap().to_string(), "1/1");
        for bad in ["0/4", "5/4", "2", "a/b", "2/0", "-1/3", ""] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
    }
}
