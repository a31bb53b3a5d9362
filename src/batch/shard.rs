//! Shards: which jobs of a manifest one task of a cluster array runs.
//!
//! Every task reads the whole manifest and works out the same split from the jobs' identities
//! alone (never from line numbers): the distinct jobs, heaviest first by their estimated weight
//! ([`super::job_weight`]) and then by hash, each go to the shard with the least weight so far
//! (the lowest index on a tie). Comments, blank lines and the order of the lines change
//! nothing; jobs of equal weight are dealt in turn, so the shards' sizes differ by at most one;
//! a job listed twice is one job, in one shard. Re-submitting some indices of an array gives
//! each the same slice as the first time. Lines that are not jobs go to shard `line mod N`.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// A slice of the manifest: shard `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which slice, from 0.
    pub index: usize,
    /// How many slices.
    pub count: usize,
}

impl Shard {
    /// Reads `I/N` (0 ≤ I < N).
    pub fn parse(text: &str) -> Result<Shard, String> {
        let (i, n) = text.split_once('/').ok_or_else(|| format!("`{text}` is not I/N"))?;
        let index: usize = i.trim().parse().map_err(|_| format!("`{i}` is not a number"))?;
        let count: usize = n.trim().parse().map_err(|_| format!("`{n}` is not a number"))?;
        if count == 0 || index >= count {
            return Err(format!(
                "the shard must be I/N with 0 <= I < N, not {index}/{count} (N is the size of the whole array, not the number of tasks submitted)"
            ));
        }
        Ok(Shard { index, count })
    }

    /// Whether a manifest line that is not a job is reported by this shard.
    pub fn takes_line(self, line: usize) -> bool {
        line % self.count == self.index
    }
}

/// A job as the split sees it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Planned {
    /// The job's hash (its identity).
    pub hash: String,
    /// Its estimated work.
    pub weight: u64,
}

/// The shard of every distinct job, by hash.
pub fn assign(jobs: &[Planned], count: usize) -> HashMap<String, usize> {
    let count = count.max(1);
    let mut distinct: Vec<&Planned> = jobs.iter().collect();
    distinct.sort_by(|a, b| b.weight.cmp(&a.weight).then_with(|| a.hash.cmp(&b.hash)));
    distinct.dedup_by(|a, b| a.hash == b.hash);
    // A job listed twice with different weights cannot happen (the weight is a function of
    // the identity), but the sort above would keep both: keep the first of each hash.
    let mut shard_of: HashMap<String, usize> = HashMap::with_capacity(distinct.len());
    let mut loads: BinaryHeap<Reverse<(u64, usize)>> =
        (0..count).map(|i| Reverse((0, i))).collect();
    for job in distinct {
        if shard_of.contains_key(&job.hash) {
            continue;
        }
        let Some(Reverse((load, index))) = loads.pop() else { break };
        shard_of.insert(job.hash.clone(), index);
        loads.push(Reverse((load.saturating_add(job.weight.max(1)), index)));
    }
    shard_of
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planned(n: usize, weight: u64) -> Vec<Planned> {
        (0..n)
            .map(|k| Planned {
                hash: crate::resolve::sha256_hex(k.to_string().as_bytes())[..16].to_string(),
                weight,
            })
            .collect()
    }

    #[test]
    fn equal_jobs_are_dealt_evenly_whatever_their_order() {
        for n in [1, 7, 40, 101] {
            for count in [1, 2, 3, 8] {
                let jobs = planned(n, 5);
                let split = assign(&jobs, count);
                let mut sizes = vec![0usize; count];
                for job in &jobs {
                    sizes[split[&job.hash]] += 1;
                }
                let (lo, hi) = (sizes.iter().min().copied(), sizes.iter().max().copied());
                assert!(hi.unwrap_or(0) - lo.unwrap_or(0) <= 1, "{n} jobs in {count}: {sizes:?}");
                let mut reversed = jobs.clone();
                reversed.reverse();
                assert_eq!(assign(&reversed, count), split);
            }
        }
    }

    #[test]
    fn heavy_jobs_are_spread() {
        let mut jobs = planned(21, 100);
        jobs.extend(planned(84, 1).into_iter().map(|mut p| {
            p.hash.push('x');
            p
        }));
        let split = assign(&jobs, 4);
        let mut heavy = [0; 4];
        for j in jobs.iter().filter(|j| j.weight == 100) {
            heavy[split[&j.hash]] += 1;
        }
        assert!(heavy.iter().all(|&h| (5..=6).contains(&h)), "{heavy:?}");
    }

    proptest::proptest! {
        /// Any set of equal jobs, in any order: the same split, sizes within one.
        #[test]
        fn the_split_of_equal_jobs_is_even_and_ignores_order(
            n in 0usize..200, count in 1usize..17, rotate in 0usize..200, weight in 1u64..1000
        ) {
            let jobs = planned(n, weight);
            let split = assign(&jobs, count);
            let mut moved = jobs.clone();
            if n > 0 {
                moved.rotate_left(rotate % n);
            }
            moved.reverse();
            proptest::prop_assert_eq!(&assign(&moved, count), &split);
            let mut sizes = vec![0usize; count];
            for job in &jobs {
                sizes[split[&job.hash]] += 1;
            }
            let (lo, hi) = (sizes.iter().min().copied().unwrap_or(0), sizes.iter().max().copied().unwrap_or(0));
            proptest::prop_assert!(hi - lo <= 1, "{:?}", sizes);
        }
    }

    #[test]
    fn the_shard_index_is_below_the_count() {
        assert!(Shard::parse("3/2").is_err());
        assert!(Shard::parse("2/2").is_err());
        assert_eq!(Shard::parse("1/2"), Ok(Shard { index: 1, count: 2 }));
    }
}
