//! The colours and finishes of a made asset's parts, read from its description.
//!
//! A generator names the material of each part ([`Material`]); the description decides the
//! part the thing is mostly made of (its *main* part): a material word (`oak`, `black metal`,
//! `linen`) replaces the generator's default where the two are of one family (a wooden shelf may
//! be metal, a mirror's pane stays glass), and the first colour word of the description
//! (`resolve::colors`, the same names and modifiers as the walls' designs) tints it. Every
//! other part keeps its material's own colour, unless the description names a second colour
//! (`white with grey trim`): that tints the accents.

use crate::resolve::colors;

/// What a part is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Material {
    /// Wood (oak unless the description names another).
    Wood,
    /// Painted wood or board (white unless a colour is named).
    Painted,
    /// Metal (steel unless the description names another).
    Metal,
    /// Plastic.
    Plastic,
    /// Clear glass.
    Glass,
    /// A mirror's silvered pane.
    Mirror,
    /// Woven or knitted cloth.
    Fabric,
    /// Carpet covering of a cat tree.
    Carpet,
    /// Sisal rope of a scratching post.
    Sisal,
    /// Glazed ceramic.
    Ceramic,
    /// A whiteboard's enamel.
    Whiteboard,
    /// A blackboard's slate.
    Slate,
    /// Cork of a pin board.
    Cork,
    /// A projection screen's matte white cloth.
    Screen,
    /// Rubber or a rubber-backed mat.
    Rubber,
    /// Cat litter.
    Litter,
    /// Paper (a photo, a clock face).
    Paper,
    /// Black glass or plastic of a display or control panel.
    Panel,
    /// Stone or solid surface (a counter top).
    Stone,
}

impl Material {
    /// Its colour when nothing is asked, red, green, blue in 0…1.
    fn default_rgb(self) -> [f64; 3] {
        match self {
            Material::Wood => WOODS[0].1,
            Material::Painted => [0.93, 0.93, 0.91],
            Material::Metal => [0.62, 0.63, 0.65],
            Material::Plastic => [0.85, 0.85, 0.84],
            Material::Glass => [0.78, 0.86, 0.88],
            Material::Mirror => [0.86, 0.89, 0.92],
            Material::Fabric => [0.62, 0.6, 0.56],
            Material::Carpet => [0.72, 0.68, 0.62],
            Material::Sisal => [0.78, 0.68, 0.5],
            Material::Ceramic => [0.94, 0.93, 0.9],
            Material::Whiteboard => [0.97, 0.97, 0.97],
            Material::Slate => [0.16, 0.2, 0.18],
            Material::Cork => [0.72, 0.55, 0.36],
            Material::Screen => [0.95, 0.95, 0.95],
            Material::Rubber => [0.2, 0.2, 0.2],
            Material::Litter => [0.8, 0.76, 0.68],
            Material::Paper => [0.96, 0.95, 0.92],
            Material::Panel => [0.08, 0.08, 0.09],
            Material::Stone => [0.86, 0.85, 0.82],
        }
    }

    /// Its metalness and roughness (glTF's metallic-roughness model, 0…1).
    fn surface(self) -> (f64, f64) {
        match self {
            Material::Metal => (0.9, 0.35),
            Material::Mirror => (1.0, 0.05),
            Material::Glass | Material::Panel => (0.0, 0.1),
            Material::Ceramic | Material::Whiteboard => (0.0, 0.2),
            Material::Plastic | Material::Stone => (0.0, 0.45),
            Material::Wood | Material::Painted => (0.0, 0.6),
            _ => (0.0, 0.9),
        }
    }

    /// The family a description's material word may move it to (`None`: it keeps its
    /// material).
    fn family(self) -> Option<u8> {
        match self {
            Material::Wood | Material::Painted | Material::Metal | Material::Plastic => Some(0),
            Material::Fabric | Material::Carpet => Some(1),
            _ => None,
        }
    }

    /// Its name in the report and the glTF materials.
    pub fn name(self) -> &'static str {
        match self {
            Material::Wood => "wood",
            Material::Painted => "painted",
            Material::Metal => "metal",
            Material::Plastic => "plastic",
            Material::Glass => "glass",
            Material::Mirror => "mirror",
            Material::Fabric => "fabric",
            Material::Carpet => "carpet",
            Material::Sisal => "sisal",
            Material::Ceramic => "ceramic",
            Material::Whiteboard => "whiteboard",
            Material::Slate => "slate",
            Material::Cork => "cork",
            Material::Screen => "screen",
            Material::Rubber => "rubber",
            Material::Litter => "litter",
            Material::Paper => "paper",
            Material::Panel => "panel",
            Material::Stone => "stone",
        }
    }
}

/// Woods by name with their colour (oak first: the default).
const WOODS: &[(&str, [f64; 3])] = &[
    ("oak", [0.7, 0.53, 0.34]),
    ("walnut", [0.36, 0.24, 0.16]),
    ("pine", [0.85, 0.7, 0.48]),
    ("birch", [0.88, 0.78, 0.6]),
    ("maple", [0.86, 0.72, 0.52]),
    ("cherry", [0.55, 0.28, 0.18]),
    ("teak", [0.6, 0.42, 0.24]),
    ("mahogany", [0.42, 0.2, 0.13]),
    ("bamboo", [0.84, 0.74, 0.5]),
    ("ash", [0.82, 0.74, 0.6]),
];

/// Metals by name with their colour.
const METALS: &[(&str, [f64; 3])] = &[
    ("steel", [0.62, 0.63, 0.65]),
    ("stainless", [0.7, 0.71, 0.72]),
    ("chrome", [0.8, 0.81, 0.83]),
    ("silver", [0.77, 0.78, 0.8]),
    ("aluminum", [0.75, 0.76, 0.78]),
    ("aluminium", [0.75, 0.76, 0.78]),
    ("iron", [0.25, 0.25, 0.26]),
    ("brass", [0.78, 0.64, 0.32]),
    ("gold", [0.83, 0.68, 0.3]),
    ("copper", [0.72, 0.45, 0.3]),
    ("bronze", [0.55, 0.4, 0.24]),
];

/// Material words of a description and the material they make the main part of.
const MATERIAL_WORDS: &[(&str, Material)] = &[
    ("wood", Material::Wood),
    ("wooden", Material::Wood),
    ("timber", Material::Wood),
    ("plywood", Material::Wood),
    ("metal", Material::Metal),
    ("metallic", Material::Metal),
    ("wire", Material::Metal),
    ("plastic", Material::Plastic),
    ("acrylic", Material::Plastic),
    ("painted", Material::Painted),
    ("lacquered", Material::Painted),
    ("fabric", Material::Fabric),
    ("linen", Material::Fabric),
    ("cotton", Material::Fabric),
    ("velvet", Material::Fabric),
    ("wool", Material::Fabric),
    ("woolen", Material::Fabric),
    ("knit", Material::Fabric),
    ("knitted", Material::Fabric),
    ("fleece", Material::Fabric),
    ("plush", Material::Carpet),
    ("faux", Material::Carpet),
    ("carpeted", Material::Carpet),
];

/// One swatch of a made asset's palette: a part's colour and finish.
#[derive(Clone, Debug, PartialEq)]
pub struct Swatch {
    /// The material it shows.
    pub material: Material,
    /// Red, green, blue, 0…1.
    pub rgb: [f64; 3],
    /// glTF metalness, 0…1.
    pub metallic: f64,
    /// glTF roughness, 0…1.
    pub roughness: f64,
}

impl Swatch {
    /// The colour as `#rrggbb`.
    pub fn hex(&self) -> String {
        let b = |c: f64| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
        format!("#{:02x}{:02x}{:02x}", b(self.rgb[0]), b(self.rgb[1]), b(self.rgb[2]))
    }
}

/// What a description says of how a thing looks.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// The description's words, lower case.
    pub words: Vec<String>,
    /// The first colour it names.
    pub colour: Option<colors::Color>,
    /// A second colour it names, for accents.
    pub second: Option<colors::Color>,
    /// The material its words name for the main part.
    pub material: Option<Material>,
    /// The wood it names.
    pub wood: Option<[f64; 3]>,
    /// The metal it names.
    pub metal: Option<[f64; 3]>,
}

impl Look {
    /// Reads a description.
    pub fn of(text: &str) -> Look {
        let words: Vec<String> = text
            .split(|c: char| !c.is_alphanumeric())
            .filter(|w| !w.is_empty())
            .map(str::to_lowercase)
            .collect();
        // The colours named, in order, leaving out names that are materials here (`linen`,
        // `walnut`, `gold`): the first tints the main part, the second the accents.
        // Searched in the words joined by single spaces, as colour phrases are written
        // (`off-white` is the name `off white`).
        let lower = format!(" {} ", words.join(" "));
        let mut found = Vec::new();
        let mut at = 0;
        while let Some(c) = colors::find(&lower[at..]) {
            let Some(start) = lower[at..].find(&format!(" {} ", c.phrase)) else { break };
            at += start + c.phrase.len() + 1;
            if !is_material_name(&c.words) {
                found.push(c);
            }
            if found.len() == 2 || at >= lower.len() {
                break;
            }
        }
        let mut found = found.into_iter();
        let (colour, second) = (found.next(), found.next());
        let find = |table: &[(&str, [f64; 3])]| {
            words.iter().find_map(|w| table.iter().find(|(n, _)| n == w).map(|(_, c)| *c))
        };
        let wood = find(WOODS);
        let metal = find(METALS);
        let material = words
            .iter()
            .find_map(|w| MATERIAL_WORDS.iter().find(|(n, _)| n == w).map(|(_, m)| *m))
            .or(wood.map(|_| Material::Wood))
            .or(metal.map(|_| Material::Metal));
        Look { words, colour, second, material, wood, metal }
    }

    /// Whether the description has this word.
    pub fn has(&self, word: &str) -> bool {
        self.words.iter().any(|w| w == word)
    }

    /// Whether the description has any of these words.
    pub fn any(&self, words: &[&str]) -> bool {
        words.iter().any(|w| self.has(w))
    }

    /// The swatch of a part: the main part (`main`) takes the description's material (within
    /// its family) and first colour; an accent (`!main`) its second colour, when it names one,
    /// and otherwise its material's colour (a named wood or metal for those).
    pub fn swatch(&self, material: Material, main: bool) -> Swatch {
        let material = match (main, self.material) {
            (true, Some(asked))
                if material.family().is_some() && asked.family() == material.family() =>
            {
                asked
            }
            _ => material,
        };
        let mut rgb = match material {
            Material::Wood => self.wood.unwrap_or(material.default_rgb()),
            Material::Metal => self.metal.unwrap_or(material.default_rgb()),
            _ => material.default_rgb(),
        };
        let tint = if main { self.colour.as_ref() } else { self.second.as_ref() };
        let tintable = !matches!(material, Material::Glass | Material::Mirror | Material::Paper);
        if let (Some(c), true) = (tint, tintable) {
            rgb = c.rgb;
        }
        let (metallic, roughness) = material.surface();
        Swatch { material, rgb, metallic, roughness }
    }
}

/// Whether a colour phrase is really a wood, metal or material name (`gold`, `walnut`,
/// `linen`…), which the material tables already read.
fn is_material_name(words: &[String]) -> bool {
    words.len() == 1
        && (WOODS.iter().any(|(n, _)| *n == words[0])
            || METALS.iter().any(|(n, _)| *n == words[0])
            || MATERIAL_WORDS.iter().any(|(n, _)| *n == words[0]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_main_part_takes_the_asked_material_and_colour() {
        let look = Look::of("black metal floating shelf");
        let s = look.swatch(Material::Wood, true);
        assert_eq!(s.material, Material::Metal);
        assert!(s.rgb.iter().all(|&c| c < 0.1), "{:?}", s.rgb);
        // A mirror's pane stays glass whatever the frame is.
        let pane = Look::of("round mirror with a brass frame").swatch(Material::Mirror, false);
        assert_eq!(pane.material, Material::Mirror);
    }

    #[test]
    fn woods_and_metals_are_materials_not_tints() {
        let look = Look::of("walnut wall shelf");
        assert!(look.colour.is_none());
        let s = look.swatch(Material::Wood, true);
        assert_eq!(s.rgb, WOODS[1].1);
        let accent =
            Look::of("grey linen curtains with a brass rod").swatch(Material::Metal, false);
        assert_eq!(accent.rgb, METALS[7].1);
    }

    #[test]
    fn a_second_colour_tints_the_accents() {
        let look = Look::of("white cat tree with grey carpet");
        assert!(look.swatch(Material::Painted, true).rgb.iter().all(|&c| c > 0.9));
        let accent = look.swatch(Material::Carpet, false);
        assert!(accent.rgb[0] < 0.7 && (accent.rgb[0] - accent.rgb[2]).abs() < 0.05);
    }
}
