//! Shards: which jobs of a manifest one task of a cluster array runs.
//!
//! A job's shard is a function of its own identity alone: rendezvous (highest random weight)
//! hashing of the job's hash, where every shard `i` of `N` draws a score from the pair
//! (hash, `i`) and the job goes to the shard with the highest score. Nothing else of the
//! manifest enters: editing, adding or removing a line moves at most that line (an edited job
//! has a new hash, so it may land in another shard); comments, blank lines and the order of the
//! lines change nothing; a job listed twice is one job, in one shard. Re-submitting some
//! indices of an array gives each the same slice as the first time, and `holoc batch merge`
//! names the shard of a line that is still missing.
//!
//! The price of that stability is balance by chance rather than by construction: each shard
//! gets `jobs / N` jobs on average with the spread of a fair draw (about `sqrt(jobs / N)`), so
//! the largest shard is within 1.2× of the mean by count once a shard holds about 150 jobs or
//! more, and by CPU weight when no single job dominates. A line that is not a job is placed the
//! same way by the hash of its text.

use std::collections::HashMap;

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

    /// Whether the job (or the line that is not a job) with this identity is in this shard.
    pub fn takes(self, hash: &str) -> bool {
        shard_of(hash, self.count) == self.index
    }

    /// Whether a manifest line that is not a job is reported by this shard: by the hash of its
    /// text (see [`line_identity`]), so that editing other lines does not move it.
    pub fn takes_line(self, raw: &str) -> bool {
        self.takes(&line_identity(raw))
    }
}

/// The identity of a manifest line that is not a job: the hash of its trimmed text.
pub fn line_identity(raw: &str) -> String {
    crate::resolve::sha256_hex(raw.trim().as_bytes())[..16].to_string()
}

/// A job as the split sees it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Planned {
    /// The job's hash (its identity).
    pub hash: String,
    /// Its estimated work (not used for the split; kept for the balance figures).
    pub weight: u64,
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// 64 bits of a job's identity: its hash read as hex (the first 16 digits), or, for a text that
/// is not hex, an FNV-1a of its bytes.
fn key_of(hash: &str) -> u64 {
    let digits = hash.get(..hash.len().min(16)).unwrap_or("");
    if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        if let Ok(k) = u64::from_str_radix(digits, 16) {
            return k;
        }
    }
    hash.bytes()
        .fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3))
}

/// The shard (of `count`) of the job with this hash: rendezvous hashing, so it depends on the
/// hash and `count` alone.
pub fn shard_of(hash: &str, count: usize) -> usize {
    let key = key_of(hash);
    let mut best = (0u64, 0usize);
    for i in 0..count.max(1) {
        let score = mix(key ^ mix(i as u64 ^ 0x5348_4152_4421));
        if i == 0 || score > best.0 {
            best = (score, i);
        }
    }
    best.1
}

/// The shard of every distinct job, by hash.
pub fn assign(jobs: &[Planned], count: usize) -> HashMap<String, usize> {
    jobs.iter().map(|j| (j.hash.clone(), shard_of(&j.hash, count))).collect()
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
    fn a_jobs_shard_depends_on_its_own_hash_alone() {
        let jobs = planned(300, 5);
        let split = assign(&jobs, 32);
        // Another job added, one removed, the order reversed: nobody else moves.
        let mut other = jobs[1..].to_vec();
        other.push(Planned { hash: "0123456789abcdef".into(), weight: 9 });
        other.reverse();
        let again = assign(&other, 32);
        for job in &jobs[1..] {
            assert_eq!(split[&job.hash], again[&job.hash]);
        }
    }

    #[test]
    fn large_manifests_are_balanced_within_a_fifth() {
        for count in [2, 4, 8, 32] {
            let jobs = planned(count * 200, 1);
            let split = assign(&jobs, count);
            let mut sizes = vec![0usize; count];
            for job in &jobs {
                sizes[split[&job.hash]] += 1;
            }
            let largest = sizes.iter().copied().max().unwrap_or(0) as f64;
            assert!(largest / 200.0 <= 1.2, "{count} shards: {sizes:?}");
            assert!(sizes.iter().all(|&s| s > 0));
        }
    }

    #[test]
    fn growing_the_array_moves_only_jobs_to_the_new_shard() {
        let jobs = planned(500, 1);
        let (small, large) = (assign(&jobs, 8), assign(&jobs, 9));
        for job in &jobs {
            let (a, b) = (small[&job.hash], large[&job.hash]);
            assert!(a == b || b == 8, "{} moved from {a} to {b}", job.hash);
        }
    }

    proptest::proptest! {
        /// Any hash: a shard below the count, the same each time.
        #[test]
        fn the_shard_is_below_the_count_and_stable(hash in "[0-9a-f]{16}|.{0,20}", count in 1usize..64) {
            let s = shard_of(&hash, count);
            proptest::prop_assert!(s < count);
            proptest::prop_assert_eq!(s, shard_of(&hash, count));
        }
    }

    #[test]
    fn the_shard_index_is_below_the_count() {
        assert!(Shard::parse("3/2").is_err());
        assert!(Shard::parse("2/2").is_err());
        assert_eq!(Shard::parse("1/2"), Ok(Shard { index: 1, count: 2 }));
    }
}
