#!/usr/bin/env python3
"""Generates data/export/materials.tsv and data/export/object-types.tsv, the base colours that
`holoc export` gives AI2-THOR's materials and object types in glTF.

AI2-THOR's materials are Unity materials with textures that are not available outside Unity, so
every material gets one PBR base colour (sRGB), a roughness and a metalness, chosen from the
words of its name by the reviewed rules below; every generated row says which rules decided it.
Object types get the colour of the first of their materials (in the database's order) that a
material rule recognises.

Usage: scripts/gen_export_materials.py [../shared/data/procthor/material-database.json]
Source: ProcTHOR's material-database.json (allenai/procthor, commit 53d5bd4, Apache-2.0).
"""

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_DB = ROOT.parent / "shared" / "data" / "procthor" / "material-database.json"

# What a surface is made of: (substring of the lower-cased name, sRGB colour, roughness,
# metalness, reason). The first that matches wins.
SURFACES = [
    ("glass", (200, 225, 235), 0.05, 0.0, "glass: pale blue-grey, smooth"),
    ("mirror", (210, 215, 220), 0.05, 1.0, "mirror: light grey, polished metal"),
    ("brick", (150, 75, 55), 0.9, 0.0, "brick: red-brown clay, rough"),
    ("drywall", (236, 232, 222), 0.9, 0.0, "drywall: painted plaster, matt"),
    ("plaster", (236, 232, 222), 0.9, 0.0, "plaster: painted, matt"),
    ("wall", (236, 232, 222), 0.9, 0.0, "wall: painted plaster, matt"),
    ("marble", (232, 228, 220), 0.3, 0.0, "marble: off-white stone, polished"),
    ("granite", (120, 118, 115), 0.35, 0.0, "granite: mid grey stone, polished"),
    ("concrete", (165, 162, 155), 0.85, 0.0, "concrete: warm grey, rough"),
    ("countertop", (200, 198, 192), 0.4, 0.0, "countertop: light stone"),
    ("porcelain", (240, 238, 232), 0.2, 0.0, "porcelain: off-white glaze"),
    ("ceramic", (235, 232, 225), 0.3, 0.0, "ceramic: off-white glaze"),
    ("tile", (215, 212, 205), 0.4, 0.0, "tiles: light glazed tiles"),
    ("carpet", (140, 130, 120), 1.0, 0.0, "carpet: mid taupe pile, fully rough"),
    ("rug", (150, 110, 90), 1.0, 0.0, "rug: warm red-brown pile, fully rough"),
    ("leather", (95, 60, 40), 0.6, 0.0, "leather: dark brown, satin"),
    ("fabric", (150, 140, 130), 1.0, 0.0, "fabric: greige cloth, fully rough"),
    ("fabirc", (150, 140, 130), 1.0, 0.0, "fabric (misspelt in the database): greige cloth"),
    ("velvet", (130, 110, 120), 1.0, 0.0, "velvet: muted mauve cloth"),
    ("cushion", (150, 140, 130), 1.0, 0.0, "cushion: greige cloth"),
    ("cusion", (150, 140, 130), 1.0, 0.0, "cushion (misspelt in the database): greige cloth"),
    ("blanket", (170, 160, 150), 1.0, 0.0, "blanket: light cloth"),
    ("sheet", (235, 232, 225), 1.0, 0.0, "bed sheet: off-white cloth"),
    ("mattress", (235, 232, 225), 1.0, 0.0, "mattress: off-white cloth"),
    ("sofa", (150, 140, 130), 1.0, 0.0, "sofa: greige upholstery"),
    ("couch", (150, 140, 130), 1.0, 0.0, "couch: greige upholstery"),
    ("cardboard", (180, 140, 95), 0.9, 0.0, "cardboard: kraft brown"),
    ("cloth", (150, 140, 130), 1.0, 0.0, "cloth: greige, fully rough"),
    ("upholstery", (150, 140, 130), 1.0, 0.0, "upholstery: greige cloth"),
    ("pillow", (225, 220, 210), 1.0, 0.0, "pillow: light cloth"),
    ("wicker", (185, 150, 100), 0.9, 0.0, "wicker: pale straw"),
    ("wood", (150, 105, 65), 0.6, 0.0, "wood: medium oak brown"),
    ("floor", (150, 105, 65), 0.6, 0.0, "floor (no other word): wood-like brown"),
    ("cabinet", (150, 105, 65), 0.6, 0.0, "cabinet: wood brown"),
    ("gold", (212, 175, 55), 0.3, 1.0, "gold: yellow metal"),
    ("brass", (181, 150, 70), 0.35, 1.0, "brass: yellow metal"),
    ("copper", (184, 115, 51), 0.35, 1.0, "copper: orange metal"),
    ("chrome", (200, 200, 205), 0.1, 1.0, "chrome: bright polished metal"),
    ("steel", (180, 180, 185), 0.35, 1.0, "steel: grey metal"),
    ("aluminum", (190, 192, 195), 0.4, 1.0, "aluminium: light grey metal"),
    ("iron", (90, 90, 92), 0.5, 1.0, "iron: dark grey metal"),
    ("metal", (160, 160, 165), 0.45, 1.0, "metal: grey"),
    ("foil", (190, 190, 195), 0.3, 1.0, "foil: light metal"),
    ("plastic", (225, 225, 225), 0.5, 0.0, "plastic: light grey, satin"),
    ("plasitc", (225, 225, 225), 0.5, 0.0, "plastic (misspelt in the database): light grey"),
    ("pvc", (225, 225, 225), 0.5, 0.0, "PVC: light grey plastic"),
    ("frame", (120, 85, 55), 0.6, 0.0, "frame: dark wood"),
    ("rubber", (60, 60, 60), 0.9, 0.0, "rubber: dark grey, rough"),
    ("screen", (20, 20, 25), 0.1, 0.0, "screen: near black, glossy"),
    ("paper", (240, 238, 230), 0.9, 0.0, "paper: off-white, matt"),
    ("wax", (240, 230, 200), 0.6, 0.0, "wax: cream"),
    ("soap", (235, 235, 225), 0.5, 0.0, "soap: white"),
    ("beams", (120, 85, 55), 0.7, 0.0, "beams: dark wood"),
    ("apple", (180, 30, 35), 0.4, 0.0, "apple: red fruit"),
    ("lettuce", (120, 170, 70), 0.7, 0.0, "lettuce: leaf green"),
    ("potato", (190, 150, 95), 0.8, 0.0, "potato: tan"),
    ("bread", (200, 150, 90), 0.8, 0.0, "bread: crust brown"),
    ("plant", (70, 120, 60), 0.8, 0.0, "plant: leaf green"),
    ("leaf", (70, 120, 60), 0.8, 0.0, "leaf: green"),
    ("statue", (200, 195, 185), 0.6, 0.0, "statue: stone"),
    ("grunge", (110, 105, 95), 0.95, 0.0, "grunge: dirty grey"),
]

# Colour words, matched against the words of the name (split at case changes, digits and
# separators) or, for words of 4 letters or more, anywhere in the lower-cased name. A colour
# word replaces the surface's colour and keeps its roughness and metalness.
COLOURS = [
    ("white", (240, 240, 236), "white"),
    ("purewhite", (250, 250, 250), "pure white"),
    ("eggshell", (240, 234, 214), "eggshell: warm off-white"),
    ("cream", (238, 228, 200), "cream"),
    ("beige", (225, 210, 180), "beige"),
    ("black", (25, 25, 25), "black"),
    ("dark", None, "dark: the surface's colour at half brightness"),
    ("light", None, "light: the surface's colour lifted halfway to white"),
    ("grey", (135, 135, 135), "grey"),
    ("gray", (135, 135, 135), "grey"),
    ("red", (160, 45, 40), "red"),
    ("maroon", (110, 30, 35), "maroon"),
    ("pink", (225, 170, 170), "pink"),
    ("rose", (205, 150, 150), "rose"),
    ("orange", (220, 130, 50), "orange"),
    ("yellow", (230, 200, 80), "yellow"),
    ("tan", (200, 170, 125), "tan"),
    ("brown", (120, 80, 50), "brown"),
    ("green", (80, 140, 80), "green"),
    ("teal", (50, 140, 140), "teal"),
    ("turquoise", (60, 180, 170), "turquoise"),
    ("aqua", (90, 190, 200), "aqua"),
    ("blue", (70, 110, 180), "blue"),
    ("robinegg", (150, 210, 210), "robin's egg blue"),
    ("sand", (210, 190, 150), "sand"),
    ("pale", None, "pale: the surface's colour lifted halfway to white"),
]

# A surface word found in no rule falls back to this (reason says so).
FALLBACK = ((180, 180, 180), 0.7, 0.0, "no rule matched: neutral light grey")


def words(name):
    return [w.lower() for w in re.findall(r"[A-Z]+(?![a-z])|[A-Z]?[a-z]+|\d+", name)]


def colour_of(name):
    """(sRGB, roughness, metalness, reason) of a material name."""
    low = name.lower()
    ws = words(name)
    rgb, rough, metal, reason = FALLBACK
    for key, c, r, m, why in SURFACES:
        if key in low:
            rgb, rough, metal, reason = c, r, m, why
            break
    reasons = [reason]
    modifiers = []
    base_colour = None
    for key, c, why in COLOURS:
        hit = key in ws or (len(key) >= 4 and key in low.replace(" ", ""))
        if not hit:
            continue
        if c is None:
            modifiers.append((key, why))
        elif base_colour is None:
            base_colour = (c, why)
    if base_colour is not None:
        rgb = base_colour[0]
        if reason == FALLBACK[3]:
            reasons = ["no surface word: roughness 0.7"]
        reasons.append("colour word " + base_colour[1])
    for key, why in modifiers:
        if key == "dark":
            rgb = tuple(round(v * 0.5) for v in rgb)
        else:
            rgb = tuple(round(v + (255 - v) * 0.5) for v in rgb)
        reasons.append(why)
    return rgb, rough, metal, "; ".join(reasons)


HEADER = """# Generated by scripts/gen_export_materials.py from ProcTHOR's material-database.json
# (allenai/procthor, commit 53d5bd4, Apache-2.0). Do not edit by hand; change the rules in the
# script and re-run it. Colours are sRGB 0-255; roughness and metalness are glTF's 0-1.
"""


def main():
    db_path = Path(sys.argv[1]) if len(sys.argv) > 1 else DEFAULT_DB
    db = json.loads(db_path.read_text())
    names = sorted({n for group in db.values() for n in group})
    out = ROOT / "data" / "export"
    out.mkdir(parents=True, exist_ok=True)
    lines = [HEADER + "# name\tr\tg\tb\troughness\tmetalness\treason"]
    for n in names:
        (r, g, b), rough, metal, why = colour_of(n)
        lines.append(f"{n}\t{r}\t{g}\t{b}\t{rough}\t{metal}\t{why}")
    (out / "materials.tsv").write_text("\n".join(lines) + "\n")
    lines = [HEADER + "# object_type\tr\tg\tb\troughness\tmetalness\treason"]
    for group in sorted(db):
        # The surface most of the type's materials are made of (glass and screens are parts,
        # not the body), then its first material in the database's order.
        known = [n for n in db[group] if colour_of(n)[3] != FALLBACK[3]]
        body = [n for n in known if not any(k in n.lower() for k in ("glass", "screen"))]
        candidates = body or known
        if not candidates:
            continue
        surface = lambda n: colour_of(n)[3].split(";")[0]
        counts = {}
        for n in candidates:
            counts[surface(n)] = counts.get(surface(n), 0) + 1
        best = max(counts.values())
        first = next(n for n in candidates if counts[surface(n)] == best)
        (r, g, b), rough, metal, why = colour_of(first)
        lines.append(f"{group}\t{r}\t{g}\t{b}\t{rough}\t{metal}\tmost of its materials: {first}: {why}")
    (out / "object-types.tsv").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
