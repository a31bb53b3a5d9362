//! The word index of a catalog (BM25 statistics) and the ranking of assets for one query.

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};

use super::catalog::{Asset, Catalog, PlacementKind};
use super::text;

/// BM25 term-frequency saturation.
pub const BM25_K1: f64 = 1.2;
/// BM25 length normalization.
pub const BM25_B: f64 = 0.75;
/// Weight of the text relevance (0…1) in the score.
pub const RELEVANCE_WEIGHT: f64 = 10.0;
/// Weight of the size discrepancy (metres) in the score, as in the original (§18.2).
pub const SIZE_WEIGHT: f64 = 10.0;
/// Share of the relevance given by a matching head word; the rest is the BM25 part.
pub const HEAD_SHARE: f64 = 0.6;
/// The smallest relevance for an asset to be good enough to resolve an object.
pub const RELEVANCE_THRESHOLD: f64 = 0.5;

/// A word of the index: borrowed from the embedded catalog's static index, or owned.
pub(crate) type Word = Cow<'static, str>;

/// Per-asset word statistics for ranking. The embedded catalog's is made at compile time (see
/// [`StaticIndex`]); any other catalog's is [`TextIndex::build`] at run time.
#[derive(Clone, Debug, Default)]
pub(crate) struct TextIndex {
    /// Word → (asset index, term frequency), asset indexes ascending.
    postings: Postings,
    /// Number of words per asset.
    doc_len: Cow<'static, [u32]>,
    /// The head word of each asset's category.
    doc_head: Cow<'static, [Word]>,
    /// Where each asset's words in `kind_words` start (one more entry than assets).
    kind_start: Cow<'static, [u32]>,
    /// The other words of each asset's category that say what kind of thing it is (`cell` of
    /// `cell phone`), attribute words left out, asset after asset.
    kind_words: Cow<'static, [Word]>,
    /// A hash of each asset's id, for seeded tie-breaking.
    id_hash: Cow<'static, [u64]>,
    /// Bit `k` set when the asset may be placed as `PlacementKind::ALL[k]`.
    allowed: Cow<'static, [u8]>,
    avg_len: f64,
}

/// The postings of a [`TextIndex`]: a hash map when built at run time, sorted static arrays
/// when made at compile time.
#[derive(Clone, Debug)]
enum Postings {
    /// Word → (asset index, term frequency).
    Built(HashMap<String, Vec<(u32, u32)>>),
    /// The words in order, where each one's postings start in `entries` (one more than
    /// words), and the postings one word after the other.
    Static { terms: &'static [&'static str], start: &'static [u32], entries: &'static [(u32, u32)] },
}

impl Default for Postings {
    fn default() -> Postings {
        Postings::Built(HashMap::new())
    }
}

impl Postings {
    /// The (asset index, term frequency) pairs of a word, asset indexes ascending.
    fn get(&self, term: &str) -> Option<&[(u32, u32)]> {
        match self {
            Postings::Built(map) => map.get(term).map(Vec::as_slice),
            Postings::Static { terms, start, entries } => {
                let i = terms.binary_search(&term).ok()?;
                entries.get(start[i] as usize..start[i + 1] as usize)
            }
        }
    }
}

/// A [`TextIndex`] made at compile time: `build.rs` writes one for the embedded catalog, with
/// the fields [`TextIndex::build`] would compute (a test checks they agree).
pub(crate) struct StaticIndex {
    /// The words, sorted.
    pub(crate) terms: &'static [&'static str],
    /// Where each word's postings start in `postings` (one more entry than words).
    pub(crate) term_start: &'static [u32],
    /// (asset index, term frequency) pairs, word after word.
    pub(crate) postings: &'static [(u32, u32)],
    /// See [`TextIndex`].
    pub(crate) doc_len: &'static [u32],
    /// See [`TextIndex`].
    pub(crate) doc_head: &'static [Word],
    /// See [`TextIndex`].
    pub(crate) kind_start: &'static [u32],
    /// See [`TextIndex`].
    pub(crate) kind_words: &'static [Word],
    /// See [`TextIndex`].
    pub(crate) id_hash: &'static [u64],
    /// See [`TextIndex`].
    pub(crate) allowed: &'static [u8],
    /// See [`TextIndex`].
    pub(crate) avg_len: f64,
}

impl TextIndex {
    /// Indexes the assets: category words count twice, description words once.
    pub(crate) fn build(assets: &[Asset]) -> TextIndex {
        let mut postings: HashMap<String, Vec<(u32, u32)>> = HashMap::new();
        let (mut doc_len, mut doc_head, mut kind_start, mut kind_words) =
            (Vec::new(), Vec::new(), vec![0u32], Vec::new());
        let (mut id_hash, mut allowed) = (Vec::new(), Vec::new());
        let mut total = 0u64;
        for (i, asset) in assets.iter().enumerate() {
            let doc = text::doc_terms(&asset.category, &asset.description);
            let len = doc.len;
            for (t, tf) in doc.counts {
                postings.entry(t).or_default().push((i as u32, tf));
            }
            doc_len.push(len);
            kind_words.extend(doc.kind_words.into_iter().map(Word::Owned));
            kind_start.push(kind_words.len() as u32);
            doc_head.push(Word::Owned(doc.head));
            id_hash.push(fnv1a(&asset.id));
            let mut bits = 0u8;
            for (k, kind) in PlacementKind::ALL.into_iter().enumerate() {
                if asset.allows(kind) {
                    bits |= 1 << k;
                }
            }
            allowed.push(bits);
            total += u64::from(len);
        }
        let avg_len =
            if assets.is_empty() { 1.0 } else { (total as f64 / assets.len() as f64).max(1.0) };
        TextIndex {
            postings: Postings::Built(postings),
            doc_len: doc_len.into(),
            doc_head: doc_head.into(),
            kind_start: kind_start.into(),
            kind_words: kind_words.into(),
            id_hash: id_hash.into(),
            allowed: allowed.into(),
            avg_len,
        }
    }

    /// The index made at compile time, borrowed: nothing is computed or copied.
    pub(crate) fn from_static(index: &'static StaticIndex) -> TextIndex {
        TextIndex {
            postings: Postings::Static {
                terms: index.terms,
                start: index.term_start,
                entries: index.postings,
            },
            doc_len: Cow::Borrowed(index.doc_len),
            doc_head: Cow::Borrowed(index.doc_head),
            kind_start: Cow::Borrowed(index.kind_start),
            kind_words: Cow::Borrowed(index.kind_words),
            id_hash: Cow::Borrowed(index.id_hash),
            allowed: Cow::Borrowed(index.allowed),
            avg_len: index.avg_len,
        }
    }

    /// The kind words of document `d` (see [`TextIndex`]).
    fn kind_words(&self, d: usize) -> &[Word] {
        &self.kind_words[self.kind_start[d] as usize..self.kind_start[d + 1] as usize]
    }

    fn n_docs(&self) -> usize {
        self.doc_len.len()
    }

    fn df(&self, term: &str) -> usize {
        self.postings.get(term).map_or(0, <[_]>::len)
    }

    fn idf(&self, df: usize) -> f64 {
        let n = self.n_docs() as f64;
        let df = df as f64;
        (1.0 + (n - df + 0.5) / (df + 0.5)).ln()
    }

    fn contains(&self, term: &str, doc: u32) -> bool {
        self.postings.get(term).is_some_and(|p| p.binary_search_by_key(&doc, |&(d, _)| d).is_ok())
    }

    /// Every field, comparable: for the test that the compile-time index is the run-time one.
    #[cfg(test)]
    pub(crate) fn same_as(&self, other: &TextIndex) -> bool {
        let postings = |p: &Postings| -> BTreeMap<String, Vec<(u32, u32)>> {
            match p {
                Postings::Built(map) => map.iter().map(|(k, v)| (k.clone(), v.clone())).collect(),
                Postings::Static { terms, .. } => terms
                    .iter()
                    .map(|t| ((*t).to_string(), p.get(t).unwrap_or_default().to_vec()))
                    .collect(),
            }
        };
        postings(&self.postings) == postings(&other.postings)
            && self.doc_len == other.doc_len
            && self.doc_head == other.doc_head
            && self.kind_start == other.kind_start
            && self.kind_words == other.kind_words
            && self.id_hash == other.id_hash
            && self.allowed == other.allowed
            && self.avg_len.to_bits() == other.avg_len.to_bits()
    }
}

/// What to look for.
#[derive(Clone, Debug, PartialEq)]
pub struct Query {
    /// What the thing is (`dining chair`); its last word is the head.
    pub category: String,
    /// How it looks (`modern, light grey`).
    pub description: Option<String>,
    /// Desired size (any order; compared sorted), metres.
    pub size_m: Option<[f64; 3]>,
    /// Only assets that may be placed this way.
    pub kind: Option<PlacementKind>,
}

/// One ranked asset with the parts of its score.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// The asset id.
    pub asset_id: String,
    /// Its object type.
    pub object_type: String,
    /// Its bounding box, metres.
    pub bbox_m: [f64; 3],
    /// Whether its category's head word is the query's (for a generic head such as `table`, also
    /// one of the query's other category words).
    pub head_match: bool,
    /// The BM25 score over the query's words, divided by the score of an ideal match (0…1).
    pub text: f64,
    /// `HEAD_SHARE × head_match + (1 − HEAD_SHARE) × text`, 0…1.
    pub relevance: f64,
    /// Mean absolute difference of the sorted sizes, metres (`None` without a desired size).
    pub size_diff_m: Option<f64>,
    /// `RELEVANCE_WEIGHT × relevance − SIZE_WEIGHT × size_diff_m`.
    pub score: f64,
    /// For an objathor asset scored by its features: the parts of that score (then `score` is
    /// `clip + sbert − SIZE_WEIGHT × size_diff_m`).
    pub features: Option<super::objathor::FeatureScore>,
    pub(crate) idx: usize,
    pub(crate) tie: u64,
}

impl Candidate {
    /// Whether the candidate is good enough to resolve an object: its relevance, or for a
    /// candidate scored by features in CLIP's text space, its CLIP part against the original's
    /// threshold (an image-to-image CLIP part means nothing against it: then the relevance).
    pub fn is_good_enough(&self) -> bool {
        match &self.features {
            Some(f) if f.text_space => f.clip > f.threshold,
            _ => self.relevance >= RELEVANCE_THRESHOLD,
        }
    }
}

/// Ranks the catalog's assets for `query`: every asset sharing a word with it, best first;
/// exact ties are ordered by a hash of the seed and the asset id.
pub fn rank(catalog: &Catalog, query: &Query, seed: u64) -> Vec<Candidate> {
    rank_top(catalog, query, seed, usize::MAX)
}

/// The best `limit` candidates of [`rank`], in the same order, without building the rest.
pub fn rank_top(catalog: &Catalog, query: &Query, seed: u64, limit: usize) -> Vec<Candidate> {
    rank_in(catalog, catalog.index(), 0, query, seed, limit)
}

/// [`rank_top`] over another index of the catalog's assets, whose document `d` is the asset
/// `offset + d` (the objathor folder's own index).
pub(crate) fn rank_in(
    catalog: &Catalog,
    index: &TextIndex,
    offset: usize,
    query: &Query,
    seed: u64,
    limit: usize,
) -> Vec<Candidate> {
    let n_docs = index.n_docs();
    if n_docs == 0 || limit == 0 {
        return Vec::new();
    }
    // One reusable score buffer per thread: only the touched slots are reset afterwards.
    SCRATCH.with_borrow_mut(|scores| {
        if scores.len() < n_docs {
            scores.resize(n_docs, 0.0);
        }
        rank_with(catalog, index, offset, query, seed, limit, scores)
    })
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

fn rank_with(
    catalog: &Catalog,
    index: &TextIndex,
    offset: usize,
    query: &Query,
    seed: u64,
    limit: usize,
    scores: &mut [f64],
) -> Vec<Candidate> {
    // The noun phrase names the thing; what follows it (`with drawers`) only describes it.
    let (noun_phrase, rest) = text::split_phrase(&query.category);
    let category = text::normalize(&noun_phrase);
    let mut description = query.description.as_deref().map(text::normalize).unwrap_or_default();
    description.extend(text::normalize(&rest));
    let head = text::head(&category).map(str::to_string);
    let modifiers: Vec<&str> = category
        .iter()
        .map(String::as_str)
        .filter(|t| Some(*t) != head.as_deref() && !text::is_attribute(t))
        .collect();
    let mut weights: BTreeMap<&str, (f64, bool)> = BTreeMap::new();
    for t in &category {
        let w = if Some(t.as_str()) == head.as_deref() { 3.0 } else { 2.0 };
        let e = weights.entry(t).or_insert((0.0, true));
        e.0 += w;
    }
    for t in &description {
        weights.entry(t).or_insert((0.0, false)).0 += 1.0;
    }
    if weights.is_empty() {
        return Vec::new();
    }
    let kind_bit = query.kind.map(|k| {
        1u8 << PlacementKind::ALL.iter().position(|x| *x == k).expect("every kind is in ALL")
    });
    let saturated = 2.0 * (BM25_K1 + 1.0) / (2.0 + BM25_K1);
    let mut ideal = 0.0;
    let mut touched: Vec<u32> = Vec::new();
    for (term, (weight, in_category)) in &weights {
        let df = index.df(term);
        if df == 0 {
            // A category word no asset has still counts against every asset; an unknown
            // description word (`cozy`) does not.
            if *in_category {
                ideal += weight * index.idf(0) * saturated;
            }
            continue;
        }
        let idf = index.idf(df);
        ideal += weight * idf * saturated;
        if let Some(postings) = index.postings.get(term) {
            for &(doc, tf) in postings {
                if kind_bit.is_some_and(|bit| index.allowed[doc as usize] & bit == 0) {
                    continue;
                }
                let tf = f64::from(tf);
                let norm =
                    1.0 - BM25_B + BM25_B * f64::from(index.doc_len[doc as usize]) / index.avg_len;
                let slot = &mut scores[doc as usize];
                if *slot == 0.0 {
                    touched.push(doc);
                }
                *slot += weight * idf * tf * (BM25_K1 + 1.0) / (tf + BM25_K1 * norm);
            }
        }
    }

    let desired = query.size_m.map(sorted3);
    let mut light: Vec<Light> = touched
        .into_iter()
        .map(|doc| {
            let d = doc as usize;
            let bm25 = std::mem::take(&mut scores[d]);
            let head_match = head.as_deref().is_some_and(|h| {
                index.doc_head[d] == h
                    && (!text::is_generic_head(h)
                        || modifiers.is_empty()
                        || modifiers.iter().any(|m| index.contains(m, doc)))
                    && !kinds_differ(&modifiers, &category, index.kind_words(d), |m| {
                        index.contains(m, doc)
                    })
                    && !(text::is_material_head(h)
                        && modifiers.is_empty()
                        && !index.kind_words(d).is_empty())
            });
            let text = if ideal > 0.0 { (bm25 / ideal).min(1.0) } else { 0.0 };
            let relevance =
                HEAD_SHARE * f64::from(u8::from(head_match)) + (1.0 - HEAD_SHARE) * text;
            let size_diff_m = desired.map(|want| {
                let b = sorted3(catalog.asset_at(offset + d).bbox_m);
                ((want[0] - b[0]).abs() + (want[1] - b[1]).abs() + (want[2] - b[2]).abs()) / 3.0
            });
            let score = RELEVANCE_WEIGHT * relevance - SIZE_WEIGHT * size_diff_m.unwrap_or(0.0);
            Light {
                doc,
                head_match,
                text,
                relevance,
                size_diff_m,
                score,
                tie: splitmix64(seed ^ index.id_hash[d]),
            }
        })
        .collect();
    let order = |a: &Light, b: &Light| {
        b.score.total_cmp(&a.score).then(a.tie.cmp(&b.tie)).then_with(|| {
            let id = |l: &Light| &catalog.asset_at(offset + l.doc as usize).id;
            id(a).cmp(id(b))
        })
    };
    if limit < light.len() {
        light.select_nth_unstable_by(limit, order);
        light.truncate(limit);
    }
    light.sort_by(order);
    light
        .into_iter()
        .map(|l| {
            let asset = catalog.asset_at(offset + l.doc as usize);
            Candidate {
                asset_id: asset.id.to_string(),
                object_type: asset.object_type.to_string(),
                bbox_m: asset.bbox_m,
                head_match: l.head_match,
                text: l.text,
                relevance: l.relevance,
                size_diff_m: l.size_diff_m,
                score: l.score,
                features: None,
                idx: offset + l.doc as usize,
                tie: l.tie,
            }
        })
        .collect()
}

/// Whether the asset `doc` of `index` may be placed as `kind` (any kind when `None`).
#[cfg(feature = "clip")]
pub(crate) fn allows(index: &TextIndex, doc: usize, kind: Option<PlacementKind>) -> bool {
    let Some(k) = kind else { return true };
    let Some(bit) = PlacementKind::ALL.iter().position(|x| *x == k) else { return false };
    index.allowed.get(doc).is_some_and(|a| a & (1u8 << bit) != 0)
}

/// The candidate of document `doc` of `index` (the catalog's asset `offset + doc`) that shares
/// no word with the query: no relevance, its size term only; `None` when the query's placement
/// rules the asset out. For assets found by their features rather than their words.
pub(crate) fn wordless_candidate(
    catalog: &Catalog,
    index: &TextIndex,
    offset: usize,
    doc: usize,
    query: &Query,
    seed: u64,
) -> Option<Candidate> {
    if let Some(k) = query.kind {
        let bit = 1u8 << PlacementKind::ALL.iter().position(|x| *x == k)?;
        if index.allowed.get(doc)? & bit == 0 {
            return None;
        }
    }
    let asset = catalog.assets().get(offset + doc)?;
    let size_diff_m = query.size_m.map(sorted3).map(|want| {
        let b = sorted3(asset.bbox_m);
        ((want[0] - b[0]).abs() + (want[1] - b[1]).abs() + (want[2] - b[2]).abs()) / 3.0
    });
    Some(Candidate {
        asset_id: asset.id.to_string(),
        object_type: asset.object_type.to_string(),
        bbox_m: asset.bbox_m,
        head_match: false,
        text: 0.0,
        relevance: 0.0,
        size_diff_m,
        score: -SIZE_WEIGHT * size_diff_m.unwrap_or(0.0),
        features: None,
        idx: offset + doc,
        tie: splitmix64(seed ^ *index.id_hash.get(doc)?),
    })
}

/// Whether the query and an asset with the same head name different kinds of it: both say
/// which kind (`conference phone`, `cell phone`) and neither's kind word is in the other
/// (`office chair` is not an `arm chair`; `dining chair` is a `chair`).
fn kinds_differ(
    query_kind_words: &[&str],
    query_category: &[String],
    asset_kind_words: &[Word],
    asset_has: impl Fn(&str) -> bool,
) -> bool {
    !query_kind_words.is_empty()
        && !asset_kind_words.is_empty()
        && !query_kind_words.iter().any(|m| asset_has(m))
        && !asset_kind_words.iter().any(|w| query_category.iter().any(|q| *q == **w))
}

/// A candidate before its strings are copied.
struct Light {
    doc: u32,
    head_match: bool,
    text: f64,
    relevance: f64,
    size_diff_m: Option<f64>,
    score: f64,
    tie: u64,
}

fn sorted3(mut v: [f64; 3]) -> [f64; 3] {
    v.sort_by(f64::total_cmp);
    v
}

fn fnv1a(text: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The SplitMix64 finalizer: a fixed, platform-independent mix of the seed and the id hash.
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn top(category: &str, kind: PlacementKind) -> Option<String> {
        let c = Catalog::embedded();
        let q =
            Query { category: category.into(), description: None, size_m: None, kind: Some(kind) };
        rank(&c, &q, 0).into_iter().find(Candidate::is_good_enough).map(|c| c.object_type)
    }

    #[test]
    fn heads_decide_the_type() {
        assert_eq!(top("dining chair", PlacementKind::Floor).as_deref(), Some("Chair"));
        assert_eq!(top("couch", PlacementKind::Floor).as_deref(), Some("Sofa"));
        assert_eq!(top("nightstand", PlacementKind::Floor).as_deref(), Some("SideTable"));
        assert_eq!(top("tv", PlacementKind::Floor).as_deref(), Some("Television"));
        assert_eq!(top("tv stand", PlacementKind::Floor).as_deref(), Some("TVStand"));
        assert_eq!(top("armchair", PlacementKind::Floor).as_deref(), Some("ArmChair"));
        assert_eq!(top("arcade machine", PlacementKind::Floor), None);
        assert_eq!(top("grand piano", PlacementKind::Floor), None);
        assert_eq!(top("painting", PlacementKind::Wall).as_deref(), Some("Painting"));
        assert_eq!(top("book", PlacementKind::OnObject).as_deref(), Some("Book"));
    }
}
