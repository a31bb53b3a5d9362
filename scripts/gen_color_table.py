#!/usr/bin/env python3
"""Writes holoc's colour-name table, data/catalog/colors.tsv.

Where the facts come from, in the order a name is taken (the first source that has it wins):

1. CSS Color Module Level 4 (W3C, "named colors", https://www.w3.org/TR/css-color-4/): the
   names where CSS and X11 differ (gray/grey, green, maroon, purple: a person's "green wall" is
   CSS green #008000, not X11's #00FF00) and the names X11 lacks (aqua, crimson, fuchsia, indigo,
   lime, olive, rebecca purple, silver, teal). Written below.
2. X11's rgb.txt (the X.Org colour database; Debian package x11-common, read from
   /usr/share/X11/rgb.txt or the file given as the first argument): every spaced, lower-case
   name without a number (`light sky blue`, `navy blue`, `forest green`).
3. Interior and paint names that neither has (`sage`, `terracotta`, `charcoal`, `taupe`,
   `mustard`, `burgundy`, `cream`, `eggshell`, `off white`, …), from the xkcd colour survey
   (Randall Munroe, 2010, https://xkcd.com/color/rgb.txt, CC0), written below. Names that are
   also materials (brick, stone, slate, sand, clay, leather, copper, bronze, wine) are left out:
   `red brick` is a material, not a colour.

Modifiers (`light`, `pale`, `dark`, `deep`, …) are applied in holoc (`resolve/colors.rs`) when the
whole phrase is not a name of the table. Run from the repository root:

    python3 scripts/gen_color_table.py [RGB_TXT]

Output: one line per name, `name<TAB>r<TAB>g<TAB>b` with r, g, b in 0…1 (6 decimals), sorted by
name. Deterministic.
"""

import os
import sys

RGB_TXT = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/X11/rgb.txt"
OUT = os.path.join("data", "catalog", "colors.tsv")

CSS4 = {
    "gray": "808080",
    "grey": "808080",
    "green": "008000",
    "maroon": "800000",
    "purple": "800080",
    "aqua": "00ffff",
    "crimson": "dc143c",
    "fuchsia": "ff00ff",
    "indigo": "4b0082",
    "lime": "00ff00",
    "olive": "808000",
    "rebecca purple": "663399",
    "silver": "c0c0c0",
    "teal": "008080",
}

XKCD = {
    "sage": "87ae73",
    "sage green": "88b378",
    "terracotta": "ca6641",
    "terra cotta": "c9643b",
    "charcoal": "343837",
    "charcoal grey": "3c4142",
    "mint": "9ffeb0",
    "mint green": "8fff9f",
    "taupe": "b9a281",
    "mustard": "ceb301",
    "mustard yellow": "d2bd0a",
    "burgundy": "610023",
    "cream": "ffffc2",
    "eggshell": "ffffd4",
    "off white": "ffffe4",
    "blush": "f29e8e",
    "blush pink": "fe828c",
    "mauve": "ae7181",
    "rust": "a83c09",
    "ochre": "bf9005",
    "emerald": "01a049",
    "emerald green": "028f1e",
    "cobalt": "1e488f",
    "cobalt blue": "030aa7",
    "periwinkle": "8e82fe",
    "lilac": "cea2fd",
    "peach": "ffb07c",
    "olive green": "677a04",
    "dusty rose": "c0737a",
    "dusty blue": "5a86ad",
    "dusty pink": "d58a94",
    "baby blue": "a2cffe",
    "baby pink": "ffb7ce",
    "pastel blue": "a2bffe",
    "pastel green": "b0ff9d",
    "pastel pink": "ffbacd",
    "pastel yellow": "fffe71",
    "duck egg blue": "c3fbf4",
    "teal blue": "01889f",
    "teal green": "25a36f",
    "sea blue": "047495",
    "ocean blue": "03719c",
    "petrol": "005f6a",
    "denim blue": "3b5b92",
    "hunter green": "0b4008",
    "bottle green": "044a05",
    "moss green": "658b38",
    "pine green": "0a481e",
    "grey green": "789b73",
    "grey blue": "6b8ba4",
    "blue grey": "607c8e",
    "warm grey": "978a84",
    "cool grey": "95a3a6",
    "mocha": "9d7651",
    "caramel": "af6f09",
    "apricot": "ffb16d",
    "amber": "feb308",
    "butter yellow": "fffd74",
    "lemon yellow": "fdff38",
    "rose": "cf6275",
    "raspberry": "b00149",
    "cherry red": "f7022a",
    "scarlet": "be0119",
    "aubergine": "3d0734",
    "eggplant": "380835",
    "plum purple": "4e0550",
    "lavender blue": "8b88f8",
    "cerulean": "0485d1",
    "turquoise blue": "06b1c4",
    "aqua blue": "02d8e9",
    "royal purple": "4b006e",
    "burnt orange": "c04e01",
    "dark teal": "014d4e",
    "deep teal": "00555a",
}

# Names of materials or things, not colours, when they stand alone in a design.
NOT_COLOURS = {"brick", "stone", "slate", "sand", "clay", "leather", "copper", "bronze", "wine"}


def hex_rgb(h):
    return tuple(int(h[i : i + 2], 16) / 255.0 for i in (0, 2, 4))


def main():
    table = {}
    for name, h in CSS4.items():
        table[name] = hex_rgb(h)
    with open(RGB_TXT, encoding="utf-8") as f:
        for line in f:
            if line.startswith("!") or not line.strip():
                continue
            parts = line.split()
            r, g, b = (int(x) for x in parts[:3])
            name = " ".join(parts[3:])
            # Spaced lower-case names only (`navy blue`, not `NavyBlue` or `gray50`).
            if name != name.lower() or any(c.isdigit() for c in name):
                continue
            table.setdefault(name, (r / 255.0, g / 255.0, b / 255.0))
    for name, h in XKCD.items():
        table.setdefault(name, hex_rgb(h))
    for name in NOT_COLOURS:
        table.pop(name, None)
    with open(OUT, "w", encoding="utf-8", newline="\n") as f:
        f.write("# holoc colour names (generated by scripts/gen_color_table.py; do not edit).\n")
        f.write("# Sources, first wins: CSS Color Module Level 4 (W3C) for the names CSS and X11\n")
        f.write("# disagree on or X11 lacks; X11 rgb.txt (X.Org, x11-common); the xkcd colour\n")
        f.write("# survey (2010, CC0) for interior names. r, g, b in 0..1.\n")
        f.write("# name\tr\tg\tb\n")
        for name in sorted(table):
            r, g, b = table[name]
            f.write("%s\t%.6f\t%.6f\t%.6f\n" % (name, r, g, b))


if __name__ == "__main__":
    main()
