//! Colour words in floor and wall designs (`deep blue drywall`, `sage green`, `light blue
//! paint`): the colour a design names, as AI2-THOR's material `color` (r, g, b in 0…1).
//!
//! The names are `data/catalog/colors.tsv`, made by `scripts/gen_color_table.py` from CSS Color
//! Level 4 (where CSS and X11 disagree, and the names X11 lacks), X11's `rgb.txt`, and a few
//! interior names of the xkcd colour survey (`sage`, `terracotta`, `taupe`, …). A phrase that is
//! not a name itself may be a name with modifiers in front (`deep blue`, `pale sage`): each
//! modifier changes the colour as [`MODIFIERS`] says. The longest name wins, and the first
//! colour of the design is the one asked (`blue and white tiles` asks for blue).

/// `COLORS`: the names of `data/catalog/colors.tsv` with their colours, sorted by name, made
/// by `build.rs` (nothing of the file is parsed at run time).
#[allow(clippy::all, clippy::pedantic, reason = "generated code")]
mod table {
    include!(concat!(env!("OUT_DIR"), "/color_table.rs"));

    /// The colours by name.
    pub(super) fn all() -> &'static [(&'static str, [f64; 3])] {
        &COLORS
    }
}

/// A colour a design asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct Color {
    /// The words that name it, as the design writes them (lower case): `deep blue`.
    pub phrase: String,
    /// Each word of the phrase (`deep`, `blue`).
    pub words: Vec<String>,
    /// Red, green, blue, 0…1.
    pub rgb: [f64; 3],
}

impl Color {
    /// Whether the colour is white or nearly (every channel at least 0.94): a white design is
    /// a white material, never a tint (`white drywall` stays a white drywall).
    pub fn is_white(&self) -> bool {
        self.rgb.iter().all(|&c| c >= 0.94)
    }

    /// The colour as `#rrggbb`.
    pub fn hex(&self) -> String {
        let byte = |c: f64| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
        format!("#{:02x}{:02x}{:02x}", byte(self.rgb[0]), byte(self.rgb[1]), byte(self.rgb[2]))
    }
}

/// How a modifier in front of a colour name changes it, when the whole phrase is no name of
/// the table: `light` and `pale` mix it with white (half, and two thirds), `dark` and `deep`
/// darken it (to 60 % and 50 %), `soft`, `muted` and `dusty` mix it a third with mid grey,
/// `pastel` mixes it 60 % with white; `bright` and `vivid` keep it.
pub const MODIFIERS: &[(&str, Modifier)] = &[
    ("light", Modifier::Mix(1.0, 0.5)),
    ("pale", Modifier::Mix(1.0, 0.65)),
    ("pastel", Modifier::Mix(1.0, 0.6)),
    ("dark", Modifier::Scale(0.6)),
    ("deep", Modifier::Scale(0.5)),
    ("soft", Modifier::Mix(0.5, 0.33)),
    ("muted", Modifier::Mix(0.5, 0.33)),
    ("dusty", Modifier::Mix(0.5, 0.33)),
    ("bright", Modifier::Scale(1.0)),
    ("vivid", Modifier::Scale(1.0)),
];

/// One modifier's change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Modifier {
    /// Mix with the grey level `.0` (1 = white) by the share `.1`.
    Mix(f64, f64),
    /// Multiply every channel.
    Scale(f64),
}

impl Modifier {
    fn apply(self, rgb: [f64; 3]) -> [f64; 3] {
        match self {
            Modifier::Mix(level, share) => rgb.map(|c| c + (level - c) * share),
            Modifier::Scale(k) => rgb.map(|c| c * k),
        }
    }
}

/// The number of names (for the book and the tests).
pub fn len() -> usize {
    table::all().len()
}

/// The colour of a name of the table (`navy blue`), if it is one.
pub fn named(name: &str) -> Option<[f64; 3]> {
    let all = table::all();
    all.binary_search_by(|(n, _)| n.cmp(&name)).ok().map(|i| all[i].1)
}

/// The longest run of words a name may have.
const MAX_WORDS: usize = 4;

/// The first colour a text names, with the modifiers written just before it; `None` when no
/// word of the text names a colour (`light oak`, `dark wood` name none).
pub fn find(text: &str) -> Option<Color> {
    let words: Vec<String> = text
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(str::to_lowercase)
        .collect();
    for start in 0..words.len() {
        let found = (1..=MAX_WORDS.min(words.len() - start)).rev().find_map(|n| {
            let name = words[start..start + n].join(" ");
            named(&name).map(|rgb| (n, rgb))
        });
        let Some((n, mut rgb)) = found else { continue };
        // Modifiers just before the name, nearest first.
        let mut first = start;
        while first > 0 {
            let Some((_, m)) = MODIFIERS.iter().find(|(w, _)| *w == words[first - 1]) else {
                break;
            };
            rgb = m.apply(rgb);
            first -= 1;
        }
        let phrase_words = words[first..start + n].to_vec();
        return Some(Color { phrase: phrase_words.join(" "), words: phrase_words, rgb });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
    }

    #[test]
    fn static_table_is_the_file_read_at_run_time() {
        // The file read as the run-time reader read it: rows of four fields, a later row of a
        // name replacing an earlier one, numbers that do not read as 0.
        let mut map = std::collections::BTreeMap::new();
        for line in include_str!("../../data/catalog/colors.tsv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        {
            let f: Vec<&str> = line.split('\t').collect();
            if f.len() == 4 {
                let num = |s: &str| s.parse::<f64>().unwrap_or(0.0);
                map.insert(f[0], [num(f[1]), num(f[2]), num(f[3])]);
            }
        }
        assert_eq!(map.len(), len());
        for ((name, rgb), (static_name, static_rgb)) in map.iter().zip(table::all()) {
            assert_eq!(name, static_name);
            assert_eq!(rgb.map(f64::to_bits), static_rgb.map(f64::to_bits), "{name}");
            assert_eq!(named(name), Some(*rgb));
        }
        assert_eq!(named("no such colour"), None);
    }

    #[test]
    fn names_and_modifiers() {
        let c = find("deep blue drywall, textured").expect("a colour");
        assert_eq!(c.phrase, "deep blue");
        assert!(close(c.rgb, [0.0, 0.0, 0.5]));
        // A whole phrase of the table wins over a modifier: X11's light blue.
        let c = find("light blue paint").expect("a colour");
        assert_eq!(c.phrase, "light blue");
        assert_eq!(c.hex(), "#add8e6");
        let c = find("sage green").expect("a colour");
        assert_eq!(c.phrase, "sage green");
        assert_eq!(c.hex(), "#88b378");
        // CSS's green, not X11's.
        assert_eq!(find("green walls").map(|c| c.hex()).as_deref(), Some("#008000"));
        let c = find("pale sage walls").expect("a colour");
        assert_eq!(c.phrase, "pale sage");
        assert!(len() > 200);
    }

    #[test]
    fn woods_and_shades_are_no_colours() {
        assert_eq!(find("light oak hardwood"), None);
        assert_eq!(find("dark walnut parquet"), None);
        assert_eq!(find("red brick"), find("red"));
        assert_eq!(find("polished concrete"), None);
        assert!(find("white drywall").is_some_and(|c| c.is_white()));
        assert!(!find("beige carpet").is_some_and(|c| c.is_white()));
    }
}
