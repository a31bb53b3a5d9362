//! Shards: which jobs of a manifest one task of a cluster array runs.
//!
//! A job's shard is a function of its own identity alone, so editing, adding or removing a line
//! moves at most that line (an edited job has a new identity, so it may land in another shard);
//! comments, blank lines and the order of the lines change nothing; a job listed twice is one
//! job, in one shard. Re-submitting some indices of an array gives each the same slice as the
//! first time, and `holoc batch merge` names the shard of a line that is still missing.
//!
//! A job's [`Place`] has two parts: its *group*, the identity of the job without its seed (the
//! same scene, settings and catalogs), and its seed. Seeds `r·N` to `r·N + N − 1` make round
//! `r` of the group; every round ranks the N shards by rendezvous (highest random weight)
//! hashing (shard `i` draws a score from the triple (group, round, `i`)) and the job with seed
//! `s` takes the shard at position `s mod N` of its round's ranking. So the consecutive seeds
//! of one scene are dealt out like cards, each shard getting one of every N, and a scene that
//! costs ten times another is split as evenly as the cheap one: the shards balance by CPU, not
//! only by count, without any estimate of a job's cost entering the split (an estimate that
//! did, a previous run's CPU say, would move jobs whenever it changed). Different groups and
//! rounds rank the shards independently, so what does not divide evenly falls on shards at
//! random, and seeds that are not consecutive (a step that shares a factor with N) fall at
//! random too: never worse than a fair draw. A job without a seed takes the first shard of
//! its group's ranking.
//!
//! A fair draw alone spreads the shards' sizes by about `sqrt(jobs / N)`, and their CPU by more
//! when a few scenes are much heavier than the rest: over the thirteen examples at seeds 1–30,
//! the largest of 16 shards would get 1.36× the mean CPU, against 1.07× dealt by seed.
//! A line that is not a job is placed by the hash of its text, as a job without a seed.
//!
//! Growing the array (N to N + 1) moves only jobs without a seed to the new shard; jobs with a
//! seed change position in their ranking too (a new N is a new array).

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

    /// Whether the job (or the line that is not a job) with this identity and no seed is in
    /// this shard.
    pub fn takes(self, hash: &str) -> bool {
        shard_of(hash, self.count) == self.index
    }

    /// Whether the job with this place is in this shard.
    pub fn takes_place(self, place: Place) -> bool {
        place.shard(self.count) == self.index
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
    /// Where it goes.
    pub place: Place,
    /// Its estimated work (not used for the split; kept for the balance figures).
    pub weight: u64,
}

/// Where a job goes: its group (the identity of the job without its seed) and its seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Place {
    /// 64 bits of the group's identity.
    pub group: u64,
    /// The job's seed, if it names one.
    pub seed: Option<u64>,
}

impl Place {
    /// The place of a job of this identity (hex) in its group of one: no seed.
    pub fn of_hash(hash: &str) -> Place {
        Place { group: key_of(hash), seed: None }
    }

    /// The place of a job of this group identity (hex) and seed.
    pub fn of_group(group: &str, seed: Option<u64>) -> Place {
        Place { group: key_of(group), seed }
    }

    /// The shard of `count` that takes the job: the shard at the seed's position in the
    /// group's rendezvous ranking (the first one without a seed).
    pub fn shard(self, count: usize) -> usize {
        let count = count.max(1);
        match self.seed {
            None => nth_best(self.group, count, 0),
            Some(seed) => {
                // Seeds `r·N` to `r·N + N - 1` are round `r`: one ranking per round, each
                // position of it taken once.
                let n = count as u64;
                let round = mix(self.group ^ mix((seed / n) ^ 0x52_4f55_4e44));
                nth_best(round, count, (seed % n) as usize)
            }
        }
    }
}

/// The score shard `i` draws for a group.
fn score(key: u64, i: usize) -> u64 {
    mix(key ^ mix(i as u64 ^ 0x5348_4152_4421))
}

/// The shard at `position` (0: the best) of the group's ranking of `count` shards, by their
/// scores (highest first; a tie, which takes two equal 64-bit draws, goes to the lower index).
fn nth_best(key: u64, count: usize, position: usize) -> usize {
    if position == 0 {
        let mut best = (0u64, 0usize);
        for i in 0..count {
            let s = score(key, i);
            if i == 0 || s > best.0 {
                best = (s, i);
            }
        }
        return best.1;
    }
    let mut ranked: Vec<(std::cmp::Reverse<u64>, usize)> =
        (0..count).map(|i| (std::cmp::Reverse(score(key, i)), i)).collect();
    ranked.select_nth_unstable(position);
    ranked[position].1
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

/// The shard (of `count`) of the job with this hash and no seed (or of a line that is not a
/// job): rendezvous hashing, so it depends on the hash and `count` alone.
pub fn shard_of(hash: &str, count: usize) -> usize {
    Place::of_hash(hash).shard(count)
}

/// The shard of every distinct job, by hash.
pub fn assign(jobs: &[Planned], count: usize) -> HashMap<String, usize> {
    jobs.iter().map(|j| (j.hash.clone(), j.place.shard(count))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planned(n: usize, weight: u64) -> Vec<Planned> {
        (0..n)
            .map(|k| {
                let hash = crate::resolve::sha256_hex(k.to_string().as_bytes())[..16].to_string();
                Planned { place: Place::of_hash(&hash), hash, weight }
            })
            .collect()
    }

    /// `scenes` groups (scene `g` weighing `weights[g]`), each at seeds `1..=seeds`.
    fn seeded(weights: &[u64], seeds: u64) -> Vec<Planned> {
        let mut jobs = Vec::new();
        for (g, &weight) in weights.iter().enumerate() {
            let group = crate::resolve::sha256_hex(format!("scene {g}").as_bytes());
            for seed in 1..=seeds {
                jobs.push(Planned {
                    hash: crate::resolve::sha256_hex(format!("{g}/{seed}").as_bytes())[..16]
                        .to_string(),
                    place: Place::of_group(&group[..16], Some(seed)),
                    weight,
                });
            }
        }
        jobs
    }

    /// The largest shard's summed weight against the mean.
    fn imbalance(jobs: &[Planned], count: usize) -> f64 {
        let split = assign(jobs, count);
        let mut sums = vec![0u64; count];
        for job in jobs {
            sums[split[&job.hash]] += job.weight;
        }
        let mean = sums.iter().sum::<u64>() as f64 / count as f64;
        sums.iter().copied().max().unwrap_or(0) as f64 / mean
    }

    /// The CPU per job of the thirteen examples, in tenths of a millisecond (release build,
    /// one core, 30 seeds each): the dining room and the classroom cost ten times the bathroom,
    /// and the dining room's is not in its size (790 bytes, the classroom 4,650).
    const EXAMPLES: [u64; 13] = [68, 10, 28, 37, 99, 102, 18, 15, 34, 25, 32, 24, 38];

    #[test]
    fn the_seeds_of_a_scene_are_spread_so_shards_balance_by_cpu() {
        let jobs = seeded(&EXAMPLES, 30);
        for count in [2, 3, 4, 5, 6, 8, 10, 16, 32] {
            let ratio = imbalance(&jobs, count);
            assert!(ratio <= 1.2, "{count} shards: the largest is {ratio:.3}x the mean");
        }
        // A fair draw of the same jobs: 16 shards of about 24 jobs are 1.36x by CPU.
        let drawn: Vec<Planned> =
            jobs.iter().map(|j| Planned { place: Place::of_hash(&j.hash), ..j.clone() }).collect();
        assert!(imbalance(&drawn, 16) > 1.2);
    }

    #[test]
    fn consecutive_seeds_are_dealt_one_per_shard_and_others_drawn() {
        let group = Place::of_group("00112233aabbccdd", None).group;
        // Seeds 0 to 49 over 10 shards: five rounds, each shard one job of each.
        let mut sizes = vec![0usize; 10];
        for seed in 0..50u64 {
            sizes[Place { group, seed: Some(seed) }.shard(10)] += 1;
        }
        assert_eq!(sizes, vec![5; 10]);
        // Seeds 10, 20, ..., 300 over 10 shards: one position of thirty rankings, a draw (a
        // seed modulo the count alone would put them all in one shard).
        let mut sizes = vec![0usize; 10];
        for k in 1..=30u64 {
            sizes[Place { group, seed: Some(k * 10) }.shard(10)] += 1;
        }
        assert!(sizes.iter().filter(|&&n| n > 0).count() >= 6, "{sizes:?}");
        assert!(sizes.iter().all(|&n| n <= 8), "{sizes:?}");
    }

    #[test]
    fn an_edited_or_added_seeded_job_moves_no_other() {
        let jobs = seeded(&EXAMPLES, 30);
        let split = assign(&jobs, 8);
        // One job's seed edited, a job added, one removed, the order reversed.
        let mut other = jobs[1..].to_vec();
        other[40].place.seed = Some(999);
        other[40].hash = "0123456789abcdef".into();
        other.push(Planned {
            hash: "fedcba9876543210".into(),
            place: Place::of_group("0011223344556677", Some(31)),
            weight: 7,
        });
        other.reverse();
        let again = assign(&other, 8);
        for job in jobs[1..].iter().filter(|j| j.hash != jobs[41].hash) {
            assert_eq!(split[&job.hash], again[&job.hash]);
        }
    }

    #[test]
    fn a_jobs_shard_depends_on_its_own_hash_alone() {
        let jobs = planned(300, 5);
        let split = assign(&jobs, 32);
        // Another job added, one removed, the order reversed: nobody else moves.
        let mut other = jobs[1..].to_vec();
        other.push(Planned {
            hash: "0123456789abcdef".into(),
            place: Place::of_hash("0123456789abcdef"),
            weight: 9,
        });
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

    /// Jobs without a seed (and lines that are not jobs).
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
        fn the_shard_is_below_the_count_and_stable(hash in "[0-9a-f]{16}|.{0,20}", count in 1usize..64, seed in proptest::option::of(proptest::num::u64::ANY)) {
            let s = shard_of(&hash, count);
            proptest::prop_assert!(s < count);
            proptest::prop_assert_eq!(s, shard_of(&hash, count));
            let place = Place::of_group(&hash, seed);
            proptest::prop_assert!(place.shard(count) < count);
            proptest::prop_assert_eq!(place.shard(count), place.shard(count));
        }
    }

    #[test]
    fn the_shard_index_is_below_the_count() {
        assert!(Shard::parse("3/2").is_err());
        assert!(Shard::parse("2/2").is_err());
        assert_eq!(Shard::parse("1/2"), Ok(Shard { index: 1, count: 2 }));
    }
}
