#!/usr/bin/env python3
"""Writes data/catalog/kinds.tsv: words for kinds of things, each with the AI2-THOR object
types that are that kind of thing (`chaise longue` is a kind of sofa, `wristwatch` a kind of
watch).

Source: WordNet 3.0 (Princeton University, WordNet 3.0 license), read from Debian's
`wordnet-base` package (/usr/share/wordnet). For each AI2-THOR type, SYNSETS below names the
WordNet senses that are that type (chosen by hand from their glosses); the table holds the
lemmas of those synsets and, where `+` marks it, of their hyponyms up to DEPTH levels, minus
the lemmas in EXCLUDE (reviewed: they are kinds in WordNet's sense but not things a person
would accept as the AI2-THOR type, e.g. a wheelchair for a Chair). EXTRA adds reviewed words
WordNet does not relate (each with its reason). Every row says where it came from.

Run: python3 scripts/gen_kind_table.py > data/catalog/kinds.tsv
"""
import sys

WN = "/usr/share/wordnet/"
DEPTH = 3

# type -> senses `lemma.n` (n-th noun sense in WordNet's order); `+` also takes hyponyms.
SYNSETS = {
    "Chair": ["chair.1+"],
    "ArmChair": ["armchair.1+", "easy_chair.1+", "recliner.1"],
    "Sofa": ["sofa.1+", "chaise.1"],
    "Bed": ["bed.1+"],
    "Desk": ["desk.1+", "writing_table.1", "worktable.1+"],
    "DiningTable": ["dining_table.1+", "kitchen_table.1", "breakfast_table.1", "conference_table.1", "trestle_table.1", "drop-leaf_table.1", "gateleg_table.1", "pedestal_table.1", "refectory_table.1", "round_table.2"],
    "SideTable": ["console.1", "stand.4", "tea_table.1", "pier_table.1"],
    "CoffeeTable": ["coffee_table.1"],
    "Dresser": ["dresser.1+", "dressing_table.1"],
    "ShelvingUnit": ["bookcase.1", "bookshelf.1", "etagere.1"],
    "Painting": ["painting.1+", "photograph.1", "poster.1"],
    "Statue": ["statue.1", "sculpture.1", "figurine.1", "bust.3", "trophy.2", "award.2"],
    "FloorLamp": ["floor_lamp.1"],
    "DeskLamp": ["lamp.2", "table_lamp.1", "reading_lamp.1+"],
    "Book": ["book.2+", "book.1+", "notebook.1+", "notepad.1", "pad.1", "binder.3", "album.2+", "diary.1"],
    "Cup": ["cup.1+", "glass.2+", "tumbler.2", "goblet.1", "teacup.2"],
    "Mug": ["mug.4+"],
    "Bowl": ["bowl.3+", "bowl.1"],
    "Plate": ["plate.4+", "platter.1", "tray.1", "saucer.2"],
    "Box": ["box.1", "carton.2", "crate.1", "jewel_casket.1", "casket.2", "shoebox.1", "cigar_box.1", "toy_box.1"],
    "Bottle": ["bottle.1+", "flask.1", "jug.1+", "decanter.1", "carafe.1"],
    "Vase": ["vase.1", "urn.1"],
    "Pot": ["pot.1", "saucepot.1", "stockpot.1", "dutch_oven.2", "caldron.1", "pot.4"],
    "Pan": ["pan.1+", "wok.1"],
    "Kettle": ["kettle.1+", "teapot.1"],
    "Candle": ["candle.1", "candlestick.1+"],
    "AlarmClock": ["clock.1+"],
    "Watch": ["watch.1+"],
    "GarbageCan": ["garbage_can.1", "wastebasket.1", "bin.1", "recycling_bin.1", "litterbin.1"],
    "Pillow": ["pillow.1+", "cushion.3"],
    "Television": ["television_receiver.1"],
    "Laptop": ["laptop.1", "notebook.2"],
    "Desktop": ["desktop_computer.1", "computer_monitor.1", "personal_computer.1"],
    "Towel": ["towel.1+"],
    "HandTowel": ["hand_towel.1"],
    "Knife": ["knife.1+"],
    "ButterKnife": ["butter_knife.1", "table_knife.1"],
    "Fork": ["fork.1+"],
    "Spoon": ["spoon.1+"],
    "Ladle": ["ladle.1+"],
    "Spatula": ["spatula.1", "turner.4"],
    "Toaster": ["toaster.2"],
    "Microwave": ["microwave.2"],
    "Fridge": ["refrigerator.1", "fridge.1", "freezer.1"],
    "CoffeeMachine": ["coffee_maker.1+", "percolator.1"],
    "WashingMachine": ["washing_machine.1"],
    "ClothesDryer": ["clothes_dryer.1", "tumble-dryer.1"],
    "VacuumCleaner": ["vacuum_cleaner.1+"],
    "Sink": ["sink.1+", "washbasin.2"],
    "Toilet": ["toilet.2"],  # `pot`, `stool`, `throne` are left to their own types
    "Faucet": ["faucet.1", "mixing_faucet.1", "water_faucet.1"],
    "ShowerHead": ["showerhead.1"],
    "ShowerCurtain": ["shower_curtain.1"],
    "Blinds": ["window_blind.1+"],
    "HousePlant": ["houseplant.1", "pot_plant.1", "succulent.1", "cactus.1", "fern.1", "bonsai.1", "aloe_vera.1"],
    "Apple": ["apple.1+"],
    "Bread": ["bread.1", "loaf_of_bread.1", "baguet.1", "french_bread.1", "brown_bread.1", "white_bread.1", "rye_bread.1", "sourdough.1"],
    "Egg": ["egg.2"],
    "Lettuce": ["lettuce.3+"],
    "Potato": ["potato.1"],
    "Tomato": ["tomato.1+"],
    "Newspaper": ["newspaper.1+", "newspaper.3", "magazine.2", "magazine.1"],
    "Pen": ["pen.1+"],
    "Pencil": ["pencil.1+"],
    "CellPhone": ["cellular_telephone.1"],
    "RemoteControl": ["remote_control.1"],
    "CD": ["compact_disk.1+"],
    "Dumbbell": ["dumbbell.1", "barbell.1"],
    "BasketBall": ["basketball.2"],
    "BaseballBat": ["baseball_bat.1"],
    "TennisRacket": ["tennis_racket.1", "racket.4"],
    "TeddyBear": ["teddy_bear.1"],
    "Footstool": ["footstool.1"],
    "Ottoman": ["ottoman.3"],
    "Stool": ["stool.1+"],
    "Safe": ["safe.1", "strongbox.1"],
    "LaundryHamper": ["hamper.2", "clothes_hamper.1"],
    "Cart": ["handcart.1", "serving_cart.1", "tea_cart.1"],
    "Boots": ["boot.1"],
    "SoapBar": ["bar_soap.1", "soap.1"],
    "SoapBottle": ["soap_dispenser.1"],
    "ToiletPaper": ["toilet_roll.1", "toilet_tissue.1"],
    "PaperTowelRoll": ["paper_towel.1"],
    "DishSponge": ["sponge.1"],
    "ScrubBrush": ["scrub_brush.1"],
    "SprayBottle": ["atomizer.1"],
    "WateringCan": ["watering_can.1"],
    "WineBottle": ["wine_bottle.1"],
    "SaltShaker": ["salt_shaker.1"],
    "PepperShaker": ["pepper_shaker.1", "pepper_mill.1"],
    "KeyChain": ["key_ring.1"],
    "CreditCard": ["credit_card.1"],
    "AluminumFoil": ["aluminum_foil.1"],
    "Plunger": ["plunger.3"],
    "GarbageBag": [],
    "CounterTop": ["countertop.1", "work_surface.1"],
    "TowelHolder": ["towel_rack.1", "towel_rail.1"],
    "LightSwitch": [],
}

# Hyponyms WordNet counts as kinds that a person would not accept as the type.
EXCLUDE = {
    "Chair": {"wheelchair", "motorized wheelchair", "throne", "peacock-throne", "bishop's throne", "cathedra", "chair of state", "mercy seat", "musnud", "barber chair", "electric chair", "highchair", "feeding chair", "fighting chair", "shoofly", "daybed", "chaise", "chaise longue", "armchair", "easy chair", "recliner", "reclining chair", "lounger", "lounge chair", "morris chair", "wing chair", "overstuffed chair", "fauteuil", "captain's chair", "bath chair"},
    "Sofa": {"convertible", "squab", "vis-a-vis", "tete-a-tete", "lower", "upper"},
    "Bed": {"couch", "berth", "lower berth", "upper berth", "lower", "upper", "sack", "deathbed", "sickbed", "plank-bed", "hammock", "hospital bed", "marriage bed", "truckle", "trundle"},
    "Desk": {"davenport", "lab bench", "laboratory bench", "drafting table", "drawing table"},
    "Dresser": {"commode"},
    "Painting": {"abstraction", "canvass", "daub", "distemper", "fresco", "icon", "ikon", "illumination", "mural", "wall painting", "nude", "pentimento", "sand painting", "tanka", "wash", "miniature", "monochrome", "finger-painting", "semi-abstraction", "trompe l'oeil", "exposure", "pic"},
    "Book": {"volume", "record", "album", "ledger", "order book", "playbook", "daybook", "folio", "book", "pocketbook", "pocket book", "phonograph album", "record album", "blog", "web log", "tablet", "pad of paper", "authority", "bible", "christian bible", "good book", "holy scripture", "holy writ", "scripture", "word of god", "word", "koran", "quran", "al-qur'an", "prayer book", "prayerbook", "missal", "breviary", "hymnal", "hymnbook", "hymnary", "songbook", "book of psalms", "psalter", "libretto", "script", "playscript"},
    "Cup": {"cylix", "kylix", "grace cup", "grail", "holy grail", "sangraal", "scyphus", "bumper", "pony", "jigger", "tea maker", "flute", "schooner", "rummer", "seidel"},
    "Mug": {"toby", "toby fillpot jug", "toby jug"},
    "Bowl": {"slop basin", "slop bowl", "porringer", "jorum", "mazer", "toilet bowl", "fish bowl", "fishbowl", "goldfish bowl", "finger bowl"},
    "Plate": {"salad bowl", "steel plate", "alms dish", "alms tray", "icetray", "inkstand", "turntable"},
    "Bottle": {"ampoule", "ampul", "ampule", "ampulla", "bellarmine", "bota", "calabash", "carboy", "demijohn", "dewar", "dewar flask", "double-magnum", "erlenmeyer flask", "round-bottom flask", "gourd", "greybeard", "long-beard", "longbeard", "jeroboam", "lota", "magnum", "nebuchadnezzar", "phial", "vial", "smelling bottle", "specimen bottle", "pill bottle", "catsup bottle", "ketchup bottle", "ink bottle", "inkpot", "crewet", "cruet", "thermos", "thermos bottle", "thermos flask", "vacuum bottle", "vacuum flask", "canteen", "hipflask", "pocket flask", "wine bottle", "whiskey jug", "beer bottle"},
    "Pan": {"roaster", "spider", "drip pan", "dripping pan", "patty-pan", "double boiler", "double saucepan"},
    "Kettle": {"boiler"},
    "Candle": {"chandlery", "dip", "rush candle", "rushlight", "girandola", "girandole", "menorah"},
    "AlarmClock": {"big ben", "chronometer", "clepsydra", "water clock", "water glass", "system clock", "time clock", "turret clock", "grandfather clock", "longcase clock"},
    "Watch": {"hunter", "hunting watch", "stem-winder", "ticker"},
    "Pillow": {"long pillow"},
    "Towel": {"paper towel", "roller towel", "hand towel", "face towel"},
    "Knife": {"barong", "bolo", "bolo knife", "bowie knife", "catling", "lance", "lancet", "linoleum cutter", "linoleum knife", "parang", "scalpel", "surgical knife", "switchblade", "switchblade knife", "flick-knife", "flick knife", "drawknife", "drawshave", "letter opener", "paper knife", "paperknife", "pruning knife", "sheath knife", "hunting knife", "butter knife", "table knife", "case knife", "jackknife", "penknife", "pocket knife", "pocketknife", "clasp knife"},
    "Fork": {"toasting fork"},
    "Spoon": {"runcible spoon", "sugar shell", "tea maker", "wooden spoon"},
    "Ladle": {"dipper", "scoop"},
    "Sink": {"lavatory", "washstand", "basin"},
    "Apple": {"baldwin", "cortland", "delicious", "empire", "jonathan", "macoun", "prima", "stayman", "winesap", "pippin", "pearmain", "rome beauty", "northern spy", "newtown wonder", "lane's prince albert", "grimes' golden", "crab apple", "crabapple"},
    "Lettuce": {"cos", "iceberg", "buttercrunch"},
    "Newspaper": {"daily", "rag", "sheet", "paper"},
    "Pen": {"quill", "biro", "sharpie", "magic marker"},
    "Pencil": {"slate pencil"},
    "CD": {"cd-wo", "compact disc write-once", "cd-r", "compact disc recordable"},
    "TennisRacket": {"bat", "crosse", "battledore", "racquet", "racket"},
    "Stool": {"step stool", "taboret", "tabouret"},
    "Blinds": {"window shade"},
    "Tomato": {"beefsteak tomato"},
    "SoapBar": {"soap"},
    "Toilet": {"pot", "stool", "potty", "commode"},
    "DeskLamp": {"student lamp"},
}

# Reviewed words WordNet does not give, each with the reason a person accepts the type.
EXTRA = [
    ("picture frame", "Painting", "a framed picture on a wall or shelf is what AI2-THOR's paintings are"),
    ("photo frame", "Painting", "a framed photograph"),
    ("photograph frame", "Painting", "a framed photograph"),
    ("frame", "Painting", "a picture frame, as people write it"),
    ("artwork", "Painting", "a flat work of art on the wall"),
    ("wall art", "Painting", "a flat work of art on the wall"),
    ("print", "Painting", "a framed print"),
    ("hand soap", "SoapBottle,SoapBar", "soap for washing hands, in a bottle or a bar"),
    ("liquid soap", "SoapBottle", "soap in a dispenser bottle"),
    ("soap", "SoapBar,SoapBottle", "soap, a bar or a bottle"),
    ("statuette", "Statue", "a small statue"),
    ("sculpture", "Statue", "a sculpture (WordNet's sense 1)"),
    ("award", "Statue", "an award on a shelf is a trophy, a small statue"),
    ("wristwatch", "Watch", "a watch worn on the wrist"),
    ("wall clock", "AlarmClock", "a clock; AI2-THOR's clocks are its alarm clocks"),
    ("clock", "AlarmClock", "a clock; AI2-THOR's clocks are its alarm clocks"),
    ("notebook", "Book,Laptop", "a paper notebook (or a notebook computer)"),
    ("novel", "Book", "a book"),
    ("textbook", "Book", "a book"),
    ("cookbook", "Book", "a book"),
    ("binder", "Book", "a ring binder looks and is used like a book"),
    ("journal", "Book", "a bound notebook"),
    ("succulent", "HousePlant", "a potted plant"),
    ("orchid", "HousePlant", "a potted flowering plant"),
    ("bonsai", "HousePlant", "a potted tree"),
    ("fern", "HousePlant", "a potted plant"),
    ("cactus", "HousePlant", "a potted plant"),
    ("tumbler", "Cup", "a drinking glass"),
    ("glass", "Cup", "a drinking glass"),
    ("wine glass", "Cup", "a drinking glass"),
    ("tray", "Plate", "a flat serving dish"),
    ("candle holder", "Candle", "a candle in its holder"),
    ("recycling bin", "GarbageCan", "a bin for waste"),
    ("bin", "GarbageCan", "a waste bin"),
    ("wastebasket", "GarbageCan", "a bin for waste"),
    ("lamp", "DeskLamp,FloorLamp", "a lamp: on furniture a desk lamp, on the floor a floor lamp"),
    ("bedside lamp", "DeskLamp", "a small lamp on a nightstand"),
    ("reading light", "DeskLamp,FloorLamp", "a lamp to read by"),
    ("table", "DiningTable,SideTable", "a table of no kind AI2-THOR knows is a table to sit at"),
    ("console", "SideTable", "a console table"),
    ("chaise lounge", "Sofa,ArmChair", "a long chair for reclining (a chaise longue)"),
    ("workbench", "Desk,CounterTop", "a strong worktable"),
    ("work bench", "Desk,CounterTop", "a strong worktable"),
    ("jewelry box", "Box", "a small box"),
    ("jewellery box", "Box", "a small box"),
    ("storage box", "Box", "a box"),
    ("decorative box", "Box", "a box"),
    ("floor vase", "Vase", "a tall vase stands on the floor"),
    ("water bottle", "Bottle", "a bottle"),
    ("perfume bottle", "Bottle,SprayBottle", "a small bottle, often with a spray"),
    ("flowers", "Vase", "cut flowers stand in a vase"),
    ("flower vase", "Vase", "a vase"),
    ("mixing bowl", "Bowl", "a bowl"),
    ("fruit bowl", "Bowl", "a bowl"),
    ("salad bowl", "Bowl", "a bowl"),
    ("coffee mug", "Mug", "a mug"),
    ("teapot", "Kettle", "a pot with a spout for tea"),
    ("tv", "Television", "a television set"),
    ("smartphone", "CellPhone", "a mobile phone"),
    ("tablet", "Laptop", "a portable computer"),
    ("computer", "Desktop,Laptop", "a computer"),
    ("monitor", "Desktop", "a computer screen on a desk"),
    ("keychain", "KeyChain", "keys on a ring"),
    ("keys", "KeyChain", "keys on a ring"),
    ("bath towel", "Towel", "a towel"),
    ("dish towel", "Towel,HandTowel", "a towel"),
    ("magazine", "Newspaper", "a periodical on paper"),
    ("kettlebell", "Dumbbell", "a hand weight"),
    ("weights", "Dumbbell", "hand weights"),
    ("stuffed animal", "TeddyBear", "a plush toy"),
    ("plush toy", "TeddyBear", "a plush toy"),
    ("cushion", "Pillow", "a cushion"),
    ("throw pillow", "Pillow", "a cushion"),
    ("spray bottle", "SprayBottle", "a bottle with a trigger spray"),
    ("bean bag", "Ottoman,ArmChair", "a soft seat without a frame, like a pouf"),
    ("beanbag", "Ottoman,ArmChair", "a soft seat without a frame, like a pouf"),
    ("bean bag chair", "Ottoman,ArmChair", "a soft seat without a frame, like a pouf"),
]

# Reviewed phrases that end in a known kind's word but are other things (`reading glasses` are
# not drinking glasses): the table maps them to no type, so the lookup stops there.
NOT_KINDS = [
    "reading glasses", "eyeglasses", "sunglasses", "glasses", "spectacles", "magnifying glass",
    "hourglass", "cutting board", "chopping board", "sound bar", "soundbar", "grab bar",
    "air hockey table", "pool table", "billiard table", "snooker table", "ping pong table",
    "ping-pong table", "table tennis table", "foosball table", "massage table",
    "operating table", "examination table", "exam table", "changing table", "turntable",
    "vital signs monitor", "baby monitor", "heart monitor", "patient monitor",
    "security camera monitor", "cat tree", "cat tower", "scratching post", "dog house",
    "fish tank", "aquarium", "lamp post", "lamppost", "street lamp", "lava lamp",
    "light box", "lightbox", "music box", "jukebox", "juke box", "fuse box", "letter box",
    "mailbox", "post box", "litter box", "sandbox", "toolbox", "tool box", "bread box",
    "breadbox", "lunch box", "lunchbox", "pill box", "pillbox", "sound box", "cable box",
    "set-top box", "water cooler", "wine cooler", "paper shredder", "pencil sharpener",
    "pencil case", "pen holder", "key holder", "knife block", "knife sharpener",
    "dumbbell rack", "shoe rack", "coat rack", "hat rack", "bike rack", "bicycle rack",
    "towel warmer", "clothes rack", "clothes horse", "bedding", "bed sheet", "bedspread",
    "bed frame",
]

# Lemmas of the chosen senses that name other things in everyday use (a `board`, a `stand`, a
# `counter`), or written works rather than objects: never looked up.
NEVER = {
    "board", "bench", "bill", "card", "notice", "posting", "can", "crapper", "throne", "closet",
    "counter", "lumber", "plastic", "cell", "murphy", "frederick jackson turner", "turner",
    "stand", "pad", "accolade", "honor", "honour", "laurels", "annual", "red herring",
    "last word", "introduction", "capital", "das kapital", "erewhon", "gloss", "text", "reader",
    "guide", "reference", "directory", "catalog", "catalogue", "course catalog",
    "course catalogue", "crammer", "curiosa", "mcguffey eclectic readers", "review copy",
    "preliminary prospectus", "prospectus", "onomasticon", "ephemeris", "formulary",
    "pharmacopeia", "synonym finder", "reckoner", "ready reckoner", "blue book", "hornbook",
    "enchiridion", "bestiary", "map collection", "farmer's calendar", "trade edition",
    "text edition", "school text", "source book", "press", "spray", "alarm", "chest", "mag",
    "utopia", "yearly", "vocabulary", "voider", "vanity",
}


def read_wordnet():
    data = {}
    for line in open(WN + "data.noun", encoding="latin-1"):
        if line.startswith("  "):
            continue
        head = line.split(" | ")[0].split()
        offset, words_count = head[0], int(head[3], 16)
        words = [head[4 + 2 * i].lower() for i in range(words_count)]
        i = 4 + 2 * words_count
        pointers = []
        for _ in range(int(head[i])):
            symbol, target, pos = head[i + 1], head[i + 2], head[i + 3]
            i += 4
            if pos == "n":
                pointers.append((symbol, target))
        data[offset] = (words, pointers)
    index = {}
    for line in open(WN + "index.noun", encoding="latin-1"):
        if line.startswith("  "):
            continue
        f = line.split()
        index[f[0]] = f[4 + int(f[3]) + 2:]
    return data, index


def clean(lemma):
    # WordNet marks adjective position with `(a)`/`(p)`; words joined by `_`.
    return lemma.split("(")[0].replace("_", " ")


def main():
    data, index = read_wordnet()
    rows = {}  # word -> (types list, source)

    def add(word, types, source):
        word = word.strip().lower()
        if not word or word in NEVER:
            return
        if word in rows:
            old_types, old_source = rows[word]
            for t in types:
                if t not in old_types:
                    old_types.append(t)
            return
        rows[word] = (list(types), source)

    for word in NOT_KINDS:
        add(word, ["-"], "reviewed: not a kind of any AI2-THOR type")
    for word, types, reason in EXTRA:
        add(word, types.split(","), "reviewed: " + reason)
    for object_type, senses in SYNSETS.items():
        excluded = EXCLUDE.get(object_type, set())
        for spec in senses:
            with_hyponyms = spec.endswith("+")
            lemma, number = spec.rstrip("+").rsplit(".", 1)
            offsets = index.get(lemma, [])
            if len(offsets) < int(number):
                sys.exit(f"{object_type}: WordNet has no sense {spec}")
            root = offsets[int(number) - 1]
            todo, seen = [(root, 0)], set()
            while todo:
                offset, depth = todo.pop()
                if offset in seen:
                    continue
                seen.add(offset)
                words, pointers = data[offset]
                for w in words:
                    w = clean(w)
                    if w not in excluded:
                        add(w, [object_type], f"wordnet: {lemma}.{number}")
                if with_hyponyms and depth < DEPTH:
                    for symbol, target in pointers:
                        if symbol in ("~", "~i"):
                            todo.append((target, depth + 1))
    print("# holoc kinds of things (generated by scripts/gen_kind_table.py; do not edit).")
    print("# Source: WordNet 3.0 (Princeton University; WordNet 3.0 license), Debian's wordnet-base,")
    print("# senses chosen and hyponyms reviewed by hand; `reviewed:` rows are our own.")
    print("# word\ttypes (best first; `-`: known to be no type)\tsource")
    for word in sorted(rows):
        types, source = rows[word]
        print(f"{word}\t{','.join(types)}\t{source}")


main()
