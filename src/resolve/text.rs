//! Words: tokenizing descriptions, the synonym table, attribute words and generic heads.
//!
//! Both the catalog's words and a query's words go through [`normalize`], so that `couch`,
//! `sofas` and `sofa` meet as the same token. The tables here are documented in the book
//! (`design/catalog-matching.md`); change both together.

/// Words that carry no meaning for matching.
const STOPWORDS: &[&str] = &[
    "a", "an", "the", "of", "with", "and", "or", "for", "in", "on", "to", "at", "by", "from",
    "its", "it", "is", "that", "this", "as", "3d", "model", "some", "one", "two", "three", "x",
];

/// Phrase synonyms, applied longest first, after lower-casing and singularizing. Each maps a
/// word sequence to the catalog's words for the same thing.
const SYNONYMS: &[(&str, &str)] = &[
    ("couch", "sofa"),
    ("sectional", "sofa"),
    ("loveseat", "sofa"),
    ("love seat", "sofa"),
    ("settee", "sofa"),
    ("tv", "television"),
    ("flat screen", "television"),
    ("flatscreen", "television"),
    ("nightstand", "side table"),
    ("night stand", "side table"),
    ("bedside table", "side table"),
    ("end table", "side table"),
    ("sidetable", "side table"),
    ("fridge", "fridge"),
    ("refrigerator", "fridge"),
    ("armchair", "arm chair"),
    ("accent chair", "arm chair"),
    ("lounge chair", "arm chair"),
    ("recliner", "arm chair"),
    ("bookshelf", "shelving unit"),
    ("bookcase", "shelving unit"),
    ("bookshelve", "shelving unit"),
    ("book shelf", "shelving unit"),
    ("shelf", "shelving unit"),
    ("shelve", "shelving unit"),
    ("shelves", "shelving unit"),
    ("trash can", "garbage can"),
    ("trash bin", "garbage can"),
    ("waste bin", "garbage can"),
    ("garbage bin", "garbage can"),
    ("wastebasket", "garbage can"),
    ("dustbin", "garbage can"),
    ("trashcan", "garbage can"),
    ("table lamp", "desk lamp"),
    ("reading lamp", "desk lamp"),
    ("standing lamp", "floor lamp"),
    ("houseplant", "house plant"),
    ("potted plant", "house plant"),
    ("plant", "house plant"),
    ("house house plant", "house plant"),
    ("picture", "painting"),
    ("poster", "painting"),
    ("artwork", "painting"),
    ("wall art", "painting"),
    ("framed print", "painting"),
    ("canvas", "painting"),
    ("coffee maker", "coffee machine"),
    ("espresso machine", "coffee machine"),
    ("washer", "washing machine"),
    ("dryer", "clothes dryer"),
    ("computer", "desktop"),
    ("pc", "desktop"),
    ("computer monitor", "desktop"),
    ("plant pot", "house plant"),
    ("flower pot", "house plant"),
    ("flowerpot", "house plant"),
    ("cellphone", "cell phone"),
    ("smartphone", "cell phone"),
    ("remote", "remote control"),
    ("remote control control", "remote control"),
    ("cushion", "pillow"),
    ("countertop", "counter top"),
    ("counter", "counter top"),
    ("counter top top", "counter top"),
    ("kitchen island", "counter top"),
    ("chest of drawer", "dresser"),
    ("drawer", "dresser"),
    ("footrest", "ottoman"),
    ("pouf", "ottoman"),
    ("sculpture", "statue"),
    ("figurine", "statue"),
    ("media console", "television stand"),
    ("tv cabinet", "television stand"),
    ("tv console", "television stand"),
    ("tv table", "television stand"),
    ("kitchen table", "dining table"),
    ("work table", "desk"),
    ("study table", "desk"),
    ("writing desk", "desk"),
    ("office desk", "desk"),
    ("entertainment center", "television stand"),
    ("clock", "alarm clock"),
    ("alarm alarm clock", "alarm clock"),
    ("basin", "sink"),
    ("washbasin", "sink"),
    ("tap", "faucet"),
    ("shower", "shower head"),
    ("shower head head", "shower head"),
    ("shower shower curtain", "shower curtain"),
    ("shower head curtain", "shower curtain"),
    ("laundry basket", "laundry hamper"),
    ("hamper", "laundry hamper"),
    ("laundry laundry hamper", "laundry hamper"),
    ("weight", "dumbbell"),
    ("coffee cup", "mug"),
    ("teapot", "kettle"),
    ("frying pan", "pan"),
    ("skillet", "pan"),
    ("saucepan", "pot"),
    ("dish", "plate"),
    ("knive", "knife"),
    ("tissue", "tissue box"),
    ("tissue box box", "tissue box"),
    ("stuffed animal", "teddy bear"),
    ("plush", "teddy bear"),
    ("basketball", "basket ball"),
    ("trolley", "cart"),
    ("vacuum", "vacuum cleaner"),
    ("vacuum cleaner cleaner", "vacuum cleaner"),
    ("pet bed", "dog bed"),
    ("cat bed", "dog bed"),
    // One thing under WordNet's `cat_tree.n.01` and the names shops give it.
    ("cat tower", "cat tree"),
    ("cat condo", "cat tree"),
    ("kitty tower", "cat tree"),
    ("cat climbing tree", "cat tree"),
    ("magazine", "newspaper"),
    ("gray", "grey"),
    ("chandelier", "chandelier light"),
    ("ceiling lamp", "ceiling light"),
    ("pendant lamp", "pendant light"),
    ("light fixture", "light"),
];

/// Words that describe how a thing looks rather than what it is (colours, materials, sizes,
/// styles). They are ignored when finding a category's head word.
const ATTRIBUTE_WORDS: &[&str] = &[
    "small",
    "large",
    "big",
    "tall",
    "short",
    "long",
    "wide",
    "narrow",
    "tiny",
    "huge",
    "mini",
    "round",
    "square",
    "rectangular",
    "oval",
    "modern",
    "contemporary",
    "vintage",
    "antique",
    "rustic",
    "classic",
    "industrial",
    "minimalist",
    "scandinavian",
    "traditional",
    "cozy",
    "comfortable",
    "elegant",
    "simple",
    "sleek",
    "stylish",
    "new",
    "old",
    "wooden",
    "wood",
    "metal",
    "metallic",
    "plastic",
    "glass",
    "fabric",
    "leather",
    "marble",
    "steel",
    "iron",
    "velvet",
    "wicker",
    "ceramic",
    "white",
    "black",
    "grey",
    "brown",
    "beige",
    "cream",
    "red",
    "blue",
    "green",
    "yellow",
    "orange",
    "pink",
    "purple",
    "dark",
    "light",
    "tan",
    "navy",
    "golden",
    "gold",
    "silver",
    "upholstered",
    "padded",
    "soft",
    "hard",
    "low",
    "high",
    "double",
    "single",
    "king",
    "queen",
    "twin",
    "size",
    "sized",
    "style",
    "styled",
];

/// Head words too general to identify a thing alone: `arcade machine` is not a coffee machine.
/// When a category's head is one of these and it has other words, one of them must match too.
const GENERIC_HEADS: &[&str] = &[
    "machine",
    "stand",
    "unit",
    "holder",
    "table",
    "set",
    "station",
    "system",
    "equipment",
    "device",
    "rack",
    "case",
    "box",
    "center",
    "console",
    "can",
    "bag",
    "decor",
    "top",
    "item",
    "thing",
    "object",
    "furniture",
    "piece",
    "cabinet",
    "ball",
    "bar",
    "panel",
];

/// Words that end the noun phrase of a category (`writing desk with drawers`: the thing is a
/// desk; `side tables to complement the sofa`: side tables).
const PHRASE_ENDS: &[&str] = &[
    "with",
    "for",
    "of",
    "to",
    "on",
    "in",
    "from",
    "near",
    "by",
    "that",
    "which",
    "and",
    "featuring",
    "including",
    "under",
    "above",
    "beside",
    "next",
];

/// Words that, before `of`, count a thing rather than name it (`stack of books`: books).
const COUNTING_NOUNS: &[&str] = &[
    "stack",
    "stacks",
    "pile",
    "piles",
    "set",
    "sets",
    "pair",
    "pairs",
    "bar",
    "bunch",
    "collection",
    "row",
    "rows",
    "couple",
    "handful",
    "assortment",
    "selection",
    "variety",
    "head",
    "heads",
    "loaf",
    "loaves",
    "bouquet",
];

/// Splits a category the way a person reads it: the noun phrase that names the thing, and the
/// rest (what it has, what it is for), which only describes it. `writing desk with drawers` →
/// (`writing desk`, `with drawers`); `stack of books` → (`books`, `stack of`).
pub(crate) fn split_phrase(text: &str) -> (String, String) {
    let words: Vec<&str> = text.split_whitespace().collect();
    let clean = |w: &str| w.trim_matches(|c: char| !c.is_alphanumeric()).to_lowercase();
    let Some(i) = words.iter().position(|w| PHRASE_ENDS.contains(&clean(w).as_str())) else {
        // `paper cup stack`, `glass set`: a counting noun at the end counts what is before it.
        if let [before @ .., last] = words.as_slice() {
            if !before.is_empty() && COUNTING_NOUNS.contains(&clean(last).as_str()) {
                return (before.join(" "), (*last).to_string());
            }
        }
        return (text.to_string(), String::new());
    };
    if clean(words[i]) == "of" && i > 0 && COUNTING_NOUNS.contains(&clean(words[i - 1]).as_str()) {
        let after = &words[i + 1..];
        let end = after
            .iter()
            .position(|w| PHRASE_ENDS.contains(&clean(w).as_str()))
            .unwrap_or(after.len());
        if end > 0 {
            let rest: Vec<&str> = words[..=i].iter().chain(&after[end..]).copied().collect();
            return (after[..end].join(" "), rest.join(" "));
        }
    }
    if i == 0 {
        return (text.to_string(), String::new());
    }
    (words[..i].join(" "), words[i..].join(" "))
}

/// Lower-cases, splits on anything that is not a letter or digit, drops stopwords,
/// singularizes and applies the synonym table.
pub(crate) fn normalize(text: &str) -> Vec<String> {
    let words: Vec<String> = text
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(|w| singular(&w.to_lowercase()))
        .filter(|w| !STOPWORDS.contains(&w.as_str()))
        .collect();
    apply_synonyms(&words)
}

/// What the catalog's word index holds of one asset (`resolve::index`, and `build.rs` for the
/// embedded catalog, which both call this): each word with its count, category words counting
/// twice and description words once (in word order), the document's length in those units, the
/// category's head word, and its other words that are not attributes (its kind words).
pub(crate) struct DocTerms {
    pub counts: Vec<(String, u32)>,
    pub len: u32,
    pub head: String,
    pub kind_words: Vec<String>,
}

/// [`DocTerms`] of an asset's category and description.
pub(crate) fn doc_terms(category: &str, description: &str) -> DocTerms {
    let category = normalize(category);
    let description = normalize(description);
    let mut counts: std::collections::BTreeMap<&str, u32> = std::collections::BTreeMap::new();
    for t in &category {
        *counts.entry(t).or_default() += 2;
    }
    for t in &description {
        *counts.entry(t).or_default() += 1;
    }
    let head = head(&category).unwrap_or_default().to_string();
    DocTerms {
        counts: counts.into_iter().map(|(t, n)| (t.to_string(), n)).collect(),
        len: (2 * category.len() + description.len()) as u32,
        kind_words: category.iter().filter(|t| **t != head && !is_attribute(t)).cloned().collect(),
        head,
    }
}

/// Splits an identifier such as `SideTable` or `TVStand` into words (`side table`, `tv stand`).
pub(crate) fn camel_words(name: &str) -> String {
    let chars: Vec<char> = name.chars().collect();
    let mut out = String::new();
    for (i, &c) in chars.iter().enumerate() {
        if !c.is_alphanumeric() {
            if !out.ends_with(' ') && !out.is_empty() {
                out.push(' ');
            }
            continue;
        }
        let prev = i.checked_sub(1).map(|j| chars[j]);
        let next = chars.get(i + 1).copied();
        let boundary = match prev {
            Some(p) if c.is_uppercase() => {
                p.is_lowercase() || (p.is_uppercase() && next.is_some_and(char::is_lowercase))
            }
            Some(p) if c.is_ascii_digit() => !p.is_ascii_digit(),
            _ => false,
        };
        if boundary && !out.ends_with(' ') {
            out.push(' ');
        }
        out.extend(c.to_lowercase());
    }
    out.trim().to_string()
}

pub(crate) fn singular(word: &str) -> String {
    let n = word.chars().count();
    if !word.is_ascii() {
        return word.to_string();
    }
    // Plural abbreviations: `cds`, `tvs` (no vowel before the `s`).
    if n == 3 && word.ends_with('s') && !word[..2].contains(['a', 'e', 'i', 'o', 'u', 'y']) {
        return word[..2].to_string();
    }
    if n <= 3 {
        return word.to_string();
    }
    if let Some(stem) = word.strip_suffix("ies") {
        return format!("{stem}y");
    }
    // `tomatoes`, `potatoes`, `mangoes`, `heroes`: the `e` belongs to the plural.
    if n > 5
        && ["toes", "goes", "roes", "does"].iter().any(|s| word.ends_with(s))
        && !word.ends_with("shoes")
    {
        return word[..word.len() - 2].to_string();
    }
    for suffix in ["sses", "shes", "ches", "xes"] {
        if word.ends_with(suffix) {
            return word[..word.len() - 2].to_string();
        }
    }
    if word.ends_with('s')
        && !word.ends_with("ss")
        && !word.ends_with("us")
        && !word.ends_with("is")
    {
        return word[..word.len() - 1].to_string();
    }
    word.to_string()
}

/// A synonym entry split into words.
struct Rule {
    from: Vec<&'static str>,
    to: Vec<&'static str>,
}

/// The synonym table indexed by the first word of each phrase, longest phrase first.
fn rules() -> &'static std::collections::BTreeMap<&'static str, Vec<Rule>> {
    static RULES: std::sync::OnceLock<std::collections::BTreeMap<&'static str, Vec<Rule>>> =
        std::sync::OnceLock::new();
    RULES.get_or_init(|| {
        let mut map: std::collections::BTreeMap<&'static str, Vec<Rule>> =
            std::collections::BTreeMap::new();
        for (from, to) in SYNONYMS {
            let from: Vec<&'static str> = from.split(' ').collect();
            let to: Vec<&'static str> = to.split(' ').collect();
            map.entry(from[0]).or_default().push(Rule { from, to });
        }
        for list in map.values_mut() {
            // Longest first; the table order decides among equal lengths.
            list.sort_by_key(|r| std::cmp::Reverse(r.from.len()));
        }
        map
    })
}

fn apply_synonyms(words: &[String]) -> Vec<String> {
    let once = rewrite(words, |_| true);
    if once == words {
        return once;
    }
    // A second pass folds doubled words that the first can create (`house house plant`), with
    // only the shrinking rules, so that it cannot loop.
    rewrite(&once, |r| r.from.len() > r.to.len())
}

fn rewrite(words: &[String], allowed: impl Fn(&Rule) -> bool) -> Vec<String> {
    let rules = rules();
    let mut out: Vec<String> = Vec::with_capacity(words.len());
    let mut i = 0;
    while i < words.len() {
        let hit = rules.get(words[i].as_str()).and_then(|list| {
            list.iter().find(|r| {
                allowed(r)
                    && i + r.from.len() <= words.len()
                    && r.from.iter().zip(&words[i..]).all(|(a, b)| *a == b.as_str())
            })
        });
        if let Some(rule) = hit {
            out.extend(rule.to.iter().map(|w| (*w).to_string()));
            i += rule.from.len();
        } else {
            out.push(words[i].clone());
            i += 1;
        }
    }
    out
}

/// Whether a (normalized) word is an attribute word.
pub(crate) fn is_attribute(word: &str) -> bool {
    ATTRIBUTE_WORDS.contains(&word)
}

/// Head words that name a material or a general thing, so that a thing named by one alone is
/// not the thing a compound names: `papers` (documents) are not `toilet paper`, `curtains` over
/// a window are not a `shower curtain`.
const MATERIAL_HEADS: [&str; 3] = ["paper", "foil", "curtain"];

/// Whether a (normalized) head word names a material: an asset whose category says which
/// thing of that material it is (`toilet paper`) matches only a query that says so too.
pub(crate) fn is_material_head(word: &str) -> bool {
    MATERIAL_HEADS.contains(&word)
}

/// Whether a (normalized) head word is too general to match alone.
pub(crate) fn is_generic_head(word: &str) -> bool {
    GENERIC_HEADS.contains(&word)
}

/// The head of a normalized category: its last word that is not an attribute word (or its last
/// word when all are attributes).
pub(crate) fn head(tokens: &[String]) -> Option<&str> {
    // `light` ends `ceiling light` as a noun, though it is an attribute in `light grey`.
    if tokens.last().is_some_and(|t| t == "light") {
        return tokens.last().map(String::as_str);
    }
    tokens
        .iter()
        .rev()
        .find(|t| !is_attribute(t) && !t.chars().all(|c| c.is_ascii_digit()))
        .or_else(|| tokens.last())
        .map(String::as_str)
}

/// The number of synonym entries (for the book and the tests).
#[cfg(test)]
pub(crate) fn synonym_table() -> &'static [(&'static str, &'static str)] {
    SYNONYMS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn synonyms_and_plurals_meet() {
        assert_eq!(normalize("Couches"), vec!["sofa"]);
        assert_eq!(normalize("a TV"), vec!["television"]);
        assert_eq!(normalize("nightstand"), vec!["side", "table"]);
        assert_eq!(normalize("Night stands"), vec!["side", "table"]);
        assert_eq!(normalize("refrigerator"), vec!["fridge"]);
        assert_eq!(normalize("bookshelves"), vec!["shelving", "unit"]);
        assert_eq!(normalize("shower curtain"), vec!["shower", "curtain"]);
        assert_eq!(normalize("potted plant"), vec!["house", "plant"]);
        assert_eq!(normalize("house plant"), vec!["house", "plant"]);
        assert_eq!(normalize("countertop"), vec!["counter", "top"]);
        assert_eq!(normalize("counter top"), vec!["counter", "top"]);
        assert_eq!(normalize("grey"), vec!["grey"]);
        assert_eq!(normalize("glasses"), vec!["glass"]);
        assert_eq!(normalize("gray café"), vec!["grey", "café"]);
    }

    #[test]
    fn camel_case_splits() {
        assert_eq!(camel_words("SideTable"), "side table");
        assert_eq!(camel_words("TVStand"), "tv stand");
        assert_eq!(camel_words("Sofa_1"), "sofa 1");
        assert_eq!(camel_words("ArmChair"), "arm chair");
    }

    #[test]
    fn the_noun_phrase_names_the_thing() {
        let split = |t: &str| {
            let (a, b) = split_phrase(t);
            (a, b)
        };
        assert_eq!(
            split("writing desk with drawers"),
            ("writing desk".into(), "with drawers".into())
        );
        assert_eq!(split("kitchen island with sink").0, "kitchen island");
        assert_eq!(split("side tables to complement the sofa").0, "side tables");
        assert_eq!(split("stack of books"), ("books".into(), "stack of".into()));
        assert_eq!(split("bar of soap on the sink").0, "soap");
        assert_eq!(split("grey sofa").0, "grey sofa");
        assert_eq!(split("with love").0, "with love");
    }

    #[test]
    fn plurals_that_end_in_oes_or_are_abbreviations() {
        assert_eq!(singular("tomatoes"), "tomato");
        assert_eq!(singular("potatoes"), "potato");
        assert_eq!(singular("cds"), "cd");
        assert_eq!(singular("shoes"), "shoe");
        assert_eq!(singular("bus"), "bus");
    }

    #[test]
    fn heads_skip_attributes() {
        let t = normalize("modern light grey sofa");
        assert_eq!(head(&t), Some("sofa"));
        let t = normalize("semi-flush mount ceiling light");
        assert_eq!(head(&t), Some("light"));
        let t = normalize("round");
        assert_eq!(head(&t), Some("round"));
        assert!(synonym_table().iter().all(|(a, _)| !a.is_empty()));
    }
}
