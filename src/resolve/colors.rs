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
/// the table. Each modifier acts on the colour's lightness and saturation (HSL, 0…1; the hue
/// stays): `light` and `pale` lighten it towards white, `dark` and `deep` darken it, `soft`,
/// `muted`, `dusty` and `dull` take saturation away, `moody` makes it dark and muted
/// (lightness at most 0.4, saturation at most 0.5: a moody blue is a dark greyish blue),
/// `rich` makes it deep and saturated, `bright` and `vivid` saturate it. The book's table
/// (`design/catalog-matching.md`) is this one.
pub const MODIFIERS: &[(&str, Modifier)] = &[
    ("light", Modifier { lightness: Shift::Toward(1.0, 0.5), saturation: Shift::Keep }),
    ("pale", Modifier { lightness: Shift::Toward(1.0, 0.65), saturation: Shift::AtMost(0.6) }),
    ("pastel", Modifier { lightness: Shift::AtLeast(0.8), saturation: Shift::AtMost(0.7) }),
    ("dark", Modifier { lightness: Shift::Times(0.6), saturation: Shift::Keep }),
    ("deep", Modifier { lightness: Shift::Times(0.5), saturation: Shift::Keep }),
    ("soft", Modifier { lightness: Shift::Toward(1.0, 0.2), saturation: Shift::Times(0.6) }),
    ("muted", Modifier { lightness: Shift::Keep, saturation: Shift::AtMost(0.4) }),
    ("dusty", Modifier { lightness: Shift::Toward(0.6, 0.3), saturation: Shift::AtMost(0.35) }),
    ("dull", Modifier { lightness: Shift::Keep, saturation: Shift::AtMost(0.25) }),
    ("moody", Modifier { lightness: Shift::AtMost(0.4), saturation: Shift::AtMost(0.5) }),
    ("rich", Modifier { lightness: Shift::AtMost(0.4), saturation: Shift::AtLeast(0.7) }),
    ("bright", Modifier { lightness: Shift::Keep, saturation: Shift::AtLeast(0.8) }),
    ("vivid", Modifier { lightness: Shift::Keep, saturation: Shift::AtLeast(0.9) }),
];

/// One modifier's change of a colour's lightness and saturation (HSL).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Modifier {
    /// The change of the lightness (0 black, 0.5 the pure hue, 1 white).
    pub lightness: Shift,
    /// The change of the saturation (0 grey, 1 the pure hue).
    pub saturation: Shift,
}

/// A change of one HSL component (0…1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shift {
    /// Left as it is.
    Keep,
    /// Multiplied.
    Times(f64),
    /// Moved towards the level `.0` by the share `.1`.
    Toward(f64, f64),
    /// Lowered to at most the value.
    AtMost(f64),
    /// Raised to at least the value.
    AtLeast(f64),
}

impl Shift {
    fn apply(self, x: f64) -> f64 {
        let y = match self {
            Shift::Keep => x,
            Shift::Times(k) => x * k,
            Shift::Toward(level, share) => x + (level - x) * share,
            Shift::AtMost(cap) => x.min(cap),
            Shift::AtLeast(floor) => x.max(floor),
        };
        y.clamp(0.0, 1.0)
    }

    /// The change as the book writes it (`× 0.6`, `≤ 0.4`, `→ 1 by 0.5`).
    pub fn describe(self) -> String {
        match self {
            Shift::Keep => "kept".to_owned(),
            Shift::Times(k) => format!("× {k}"),
            Shift::Toward(level, share) => format!("{share} of the way to {level}"),
            Shift::AtMost(cap) => format!("≤ {cap}"),
            Shift::AtLeast(floor) => format!("≥ {floor}"),
        }
    }
}

impl Modifier {
    fn apply(self, rgb: [f64; 3]) -> [f64; 3] {
        let [h, s, l] = to_hsl(rgb);
        // A grey has no hue to saturate: `bright grey` stays a grey.
        let s = if s <= f64::EPSILON { s } else { self.saturation.apply(s) };
        from_hsl([h, s, self.lightness.apply(l)])
    }
}

/// Hue (0…1 of the circle), saturation and lightness of a colour (the HSL of CSS Color 4).
pub fn to_hsl([r, g, b]: [f64; 3]) -> [f64; 3] {
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let l = f64::midpoint(max, min);
    let d = max - min;
    if d <= f64::EPSILON {
        return [0.0, 0.0, l];
    }
    let s = d / (1.0 - (2.0 * l - 1.0).abs());
    let h = if max == r {
        ((g - b) / d).rem_euclid(6.0)
    } else if max == g {
        (b - r) / d + 2.0
    } else {
        (r - g) / d + 4.0
    };
    [h / 6.0, s.clamp(0.0, 1.0), l]
}

/// The colour of a hue, saturation and lightness ([`to_hsl`] undone).
pub fn from_hsl([h, s, l]: [f64; 3]) -> [f64; 3] {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let h6 = h.rem_euclid(1.0) * 6.0;
    let x = c * (1.0 - (h6.rem_euclid(2.0) - 1.0).abs());
    let m = l - c / 2.0;
    let (r, g, b) = match h6 as u8 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    [r + m, g + m, b + m].map(|v| v.clamp(0.0, 1.0))
}

/// Whether a word names a colour with a hue (saturation at least 0.3, lightness between 0.15
/// and 0.9): `pink`, `red`, `blue`; not `grey`, `white`, `black` or `beige`, which a stone or
/// a concrete may be without a word of it.
pub fn is_hue_word(word: &str) -> bool {
    named(word).is_some_and(|rgb| {
        let [_, s, l] = to_hsl(rgb);
        s >= 0.3 && (0.15..=0.9).contains(&l)
    })
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
    fn modifiers_act_on_lightness_and_saturation() {
        // The case: a moody blue is dark and muted, its hue kept.
        let c = find("moody blue drywall, textured").expect("a colour");
        assert_eq!(c.phrase, "moody blue");
        let [h, s, l] = to_hsl(c.rgb);
        assert!(l <= 0.4 + 1e-9 && s <= 0.5 + 1e-9, "{}", c.hex());
        assert!((h - 2.0 / 3.0).abs() < 1e-9, "{}", c.hex());
        assert_eq!(c.hex(), "#333399");
        // Each modifier moves its component the way the table says.
        let blue = [0.0, 0.0, 1.0];
        let hsl = |m: &str| {
            let (_, modifier) = MODIFIERS.iter().find(|(w, _)| *w == m).expect("a modifier");
            to_hsl(modifier.apply(blue))
        };
        assert!(hsl("dark")[2] < 0.5 && hsl("deep")[2] < hsl("dark")[2]);
        assert!(hsl("light")[2] > 0.5 && hsl("pale")[2] > hsl("light")[2]);
        for m in ["muted", "dusty", "dull", "soft", "pastel", "pale"] {
            assert!(hsl(m)[1] < 0.75, "{m}");
        }
        assert!(hsl("rich")[1] >= 0.7 && hsl("rich")[2] <= 0.4 + 1e-9);
        assert!(close(from_hsl(hsl("bright")), blue));
        // A grey stays grey: no modifier invents a hue.
        for (m, modifier) in MODIFIERS {
            let [r, g, b] = modifier.apply([0.5, 0.5, 0.5]);
            assert!((r - g).abs() < 1e-9 && (g - b).abs() < 1e-9, "{m}");
        }
    }

    #[test]
    fn the_book_lists_every_modifier() {
        let page = include_str!("../../book/src/design/catalog-matching.md");
        for (m, modifier) in MODIFIERS {
            let blue = Color {
                phrase: String::new(),
                words: Vec::new(),
                rgb: modifier.apply([0.0, 0.0, 1.0]),
            };
            let row = format!(
                "| {m} | {} | {} | {} |",
                modifier.lightness.describe(),
                modifier.saturation.describe(),
                blue.hex()
            );
            assert!(page.contains(&row), "the book lacks the modifier row `{row}`");
        }
    }

    #[test]
    fn hsl_round_trips_every_named_colour() {
        for (name, rgb) in table::all() {
            assert!(close(from_hsl(to_hsl(*rgb)), *rgb), "{name}");
        }
    }

    #[test]
    fn hue_words() {
        for w in ["pink", "red", "blue", "green", "yellow", "orange", "purple"] {
            assert!(is_hue_word(w), "{w}");
        }
        for w in ["grey", "white", "black", "beige", "concrete", "smooth", "ivory"] {
            assert!(!is_hue_word(w), "{w}");
        }
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
