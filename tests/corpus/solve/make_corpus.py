#!/usr/bin/env python3
"""Writes the layout benchmark/test corpus (tests/corpus/solve/*.json).

Hand-authored room problems in the scene types of the Holodeck paper. Sizes are in metres.
Run from the repository root: python3 tests/corpus/solve/make_corpus.py
"""
import json, os

OUT = os.path.dirname(os.path.abspath(__file__))

def rect(w, d):
    return [[0, 0], [0, d], [w, d], [w, 0]]

def door(x0, z0, x1, z1):
    return [[x0, z0], [x1, z1]]

def obj(i, size, glob="edge", rel=()):
    return {"id": i, "size": size, "global": glob, "rel": [list(r) for r in rel]}

def chairs(n, table, prefix="chair", size=(0.5, 0.5, 0.9), rel="around"):
    return [obj(f"{prefix}-{k}", list(size), "middle", [(rel, table)]) for k in range(n)]

rooms = {}

def room(name, outline, objects, keep_out=(), holes=(), wall_objects=(), small=(), ceiling=None, h=2.7):
    rooms[name] = {
        "name": name, "outline": outline, "wall_height": h, "keep_out": list(keep_out),
        "holes": list(holes), "objects": objects, "wall_objects": list(wall_objects),
        "small": list(small), "ceiling": ceiling,
    }

room("bedroom", rect(4, 5), [
    obj("bed-0", [1.6, 2.0, 0.6]),
    obj("nightstand-0", [0.5, 0.4, 0.5], "edge", [("left of", "bed-0"), ("near", "bed-0"), ("face same as", "bed-0")]),
    obj("nightstand-1", [0.5, 0.4, 0.5], "edge", [("right of", "bed-0"), ("near", "bed-0"), ("face same as", "bed-0")]),
    obj("wardrobe-0", [1.2, 0.6, 2.0], "edge", [("far", "bed-0")]),
    obj("desk-0", [1.2, 0.6, 0.75], "edge"),
    obj("chair-0", [0.5, 0.5, 0.9], "middle", [("in front of", "desk-0"), ("near", "desk-0"), ("face to", "desk-0")]),
], keep_out=[door(0, 0, 1, 1)], holes=[{"wall": 1, "from": 1.5, "to": 2.7, "bottom": 0.9, "top": 2.1, "window": True}],
   wall_objects=[{"id": "painting-0", "size": [1.0, 0.05, 0.7], "above": "bed-0", "height": 1.4}],
   small=[{"id": "lamp-0", "size": [0.25, 0.25, 0.4], "on": "nightstand-0"}, {"id": "book-0", "size": [0.2, 0.15, 0.04], "on": "desk-0"}],
   ceiling={"id": "ceiling-light", "size": [0.5, 0.5, 0.2]})

room("living_room", rect(5, 7), [
    obj("sofa-0", [2.2, 0.9, 0.85]),
    obj("coffee_table-0", [1.2, 0.6, 0.45], "middle", [("near", "sofa-0"), ("in front of", "sofa-0"), ("center aligned", "sofa-0"), ("face to", "sofa-0")]),
    obj("tv_stand-0", [1.6, 0.45, 0.6], "edge", [("far", "sofa-0"), ("in front of", "sofa-0"), ("center aligned", "sofa-0"), ("face to", "sofa-0")]),
    obj("armchair-0", [0.8, 0.8, 0.9], "middle", [("near", "coffee_table-0"), ("side of", "coffee_table-0"), ("face to", "coffee_table-0")]),
    obj("armchair-1", [0.8, 0.8, 0.9], "middle", [("near", "coffee_table-0"), ("side of", "coffee_table-0"), ("face to", "coffee_table-0")]),
    obj("side_table-0", [0.5, 0.5, 0.55], "edge", [("near", "sofa-0"), ("side of", "sofa-0")]),
    obj("bookshelf-0", [1.0, 0.35, 1.9], "edge", [("far", "tv_stand-0")]),
    obj("plant-0", [0.4, 0.4, 1.2], "edge"),
], keep_out=[door(4, 0, 5, 1)], holes=[{"wall": 0, "from": 2.5, "to": 4.0, "bottom": 0.5, "top": 2.0, "window": True}],
   wall_objects=[{"id": "painting-0", "size": [1.2, 0.05, 0.8], "above": "sofa-0", "height": 1.5},
                 {"id": "clock-0", "size": [0.4, 0.08, 0.4], "height": 1.8}],
   small=[{"id": "remote-0", "size": [0.18, 0.06, 0.03], "on": "coffee_table-0"},
          {"id": "book-0", "size": [0.25, 0.18, 0.04], "on": "coffee_table-0"},
          {"id": "book-1", "size": [0.25, 0.18, 0.04], "on": "coffee_table-0"}],
   ceiling={"id": "ceiling-light", "size": [0.6, 0.6, 0.3], "above": "coffee_table-0"})

room("kitchen", rect(3.5, 4), [
    obj("fridge-0", [0.8, 0.75, 1.8]),
    obj("counter-0", [1.8, 0.6, 0.9], "edge", [("near", "fridge-0"), ("face same as", "fridge-0")]),
    obj("stove-0", [0.75, 0.65, 0.9], "edge", [("near", "counter-0"), ("side of", "counter-0")]),
    obj("dining_table-0", [1.2, 0.8, 0.75], "middle", [("far", "stove-0")]),
] + chairs(4, "dining_table-0"), keep_out=[door(0, 1.5, 1, 2.5)],
   small=[{"id": "kettle-0", "size": [0.25, 0.2, 0.25], "on": "counter-0"}, {"id": "bowl-0", "size": [0.2, 0.2, 0.1], "on": "dining_table-0"}])

room("bathroom", rect(2.5, 3), [
    obj("bathtub-0", [1.6, 0.75, 0.6]),
    obj("toilet-0", [0.4, 0.7, 0.8], "edge", [("far", "bathtub-0")]),
    obj("vanity-0", [0.8, 0.5, 0.85], "edge", [("near", "toilet-0")]),
], keep_out=[door(1.5, 0, 2.5, 1)],
   wall_objects=[{"id": "mirror-0", "size": [0.6, 0.03, 0.8], "above": "vanity-0", "height": 1.2},
                 {"id": "towel_rack-0", "size": [0.6, 0.1, 0.1], "height": 1.1}])

room("home_office", rect(3.5, 4), [
    obj("desk-0", [1.4, 0.7, 0.75]),
    obj("office_chair-0", [0.6, 0.6, 1.0], "middle", [("in front of", "desk-0"), ("near", "desk-0"), ("face to", "desk-0")]),
    obj("bookshelf-0", [0.9, 0.35, 1.9], "edge", [("side of", "desk-0")]),
    obj("filing_cabinet-0", [0.45, 0.6, 0.7], "edge", [("near", "desk-0")]),
    obj("armchair-0", [0.8, 0.8, 0.9], "edge", [("far", "desk-0")]),
    obj("floor_lamp-0", [0.35, 0.35, 1.6], "edge", [("near", "armchair-0")]),
], keep_out=[door(2.5, 0, 3.5, 1)])

office = [obj("reception_desk-0", [1.8, 0.8, 1.0])]
for k in range(10):
    office.append(obj(f"desk-{k}", [1.4, 0.7, 0.75], "edge" if k < 6 else "middle", [("far", "reception_desk-0")] if k == 0 else [("near", f"desk-{k-1}"), ("face same as", f"desk-{k-1}")]))
    office.append(obj(f"chair-{k}", [0.55, 0.55, 1.0], "middle", [("in front of", f"desk-{k}"), ("near", f"desk-{k}"), ("face to", f"desk-{k}")]))
office += [obj(f"cabinet-{k}", [0.8, 0.45, 1.2]) for k in range(6)]
office += [obj(f"plant-{k}", [0.4, 0.4, 1.2]) for k in range(5)]
office += [obj("meeting_table-0", [2.0, 1.0, 0.75], "middle")] + chairs(4, "meeting_table-0", "meeting_chair")
office += [obj("printer-0", [0.6, 0.5, 1.0]), obj("sofa-0", [2.0, 0.85, 0.85]), obj("water_cooler-0", [0.35, 0.35, 1.1])]
room("open_office_40", rect(10, 14), office, keep_out=[door(0, 6, 1, 7), door(9, 0, 10, 1)])

classroom = [obj("teacher_desk-0", [1.5, 0.75, 0.75]), obj("teacher_chair-0", [0.55, 0.55, 1.0], "middle", [("behind", "teacher_desk-0"), ("near", "teacher_desk-0"), ("face same as", "teacher_desk-0")])]
for k in range(11):
    classroom.append(obj(f"student_desk-{k}", [0.7, 0.5, 0.7], "middle", [("far", "teacher_desk-0"), ("face to", "teacher_desk-0")] if k == 0 else [("near", f"student_desk-{k-1}"), ("face same as", f"student_desk-{k-1}")]))
    classroom.append(obj(f"student_chair-{k}", [0.45, 0.45, 0.85], "middle", [("behind", f"student_desk-{k}"), ("near", f"student_desk-{k}"), ("face same as", f"student_desk-{k}")]))
classroom.append(obj("bookshelf-0", [1.0, 0.35, 1.8]))
room("classroom_25", rect(7, 8), classroom, keep_out=[door(0, 0, 1, 1), door(6, 7, 7, 8)],
     wall_objects=[{"id": "whiteboard-0", "size": [2.4, 0.05, 1.2], "above": "teacher_desk-0", "height": 1.0}])

room("meeting_room", rect(5, 6), [obj("table-0", [2.4, 1.2, 0.75], "middle")] + chairs(8, "table-0") + [
    obj("tv_stand-0", [1.6, 0.45, 0.6], "edge", [("far", "table-0")]),
    obj("cabinet-0", [1.0, 0.45, 1.0], "edge"),
], keep_out=[door(0, 0, 1, 1)], ceiling={"id": "ceiling-light", "size": [0.6, 0.6, 0.2], "above": "table-0"})

room("dining_room", rect(4, 5), [obj("dining_table-0", [1.8, 0.9, 0.75], "middle")] + chairs(6, "dining_table-0") + [
    obj("sideboard-0", [1.6, 0.45, 0.9], "edge", [("near", "dining_table-0")]),
    obj("cabinet-0", [0.9, 0.45, 1.9], "edge"),
], keep_out=[door(3, 0, 4, 1)], small=[{"id": "vase-0", "size": [0.2, 0.2, 0.3], "on": "dining_table-0"}])

rest = [obj("counter-0", [3.0, 0.7, 1.1])]
for t in range(6):
    rest.append(obj(f"table-{t}", [0.9, 0.9, 0.75], "middle", [("far", "counter-0")] if t == 0 else [("near", f"table-{t-1}"), ("center aligned", f"table-{t-1}")]))
    rest += [obj(f"chair-{t}{c}", [0.45, 0.45, 0.9], "middle", [("around", f"table-{t}")]) for c in range(4)]
rest += [obj(f"plant-{k}", [0.5, 0.5, 1.4]) for k in range(3)]
room("restaurant_34", rect(10, 12), rest, keep_out=[door(4.5, 0, 5.5, 1), door(9, 10, 10, 11)],
     holes=[{"wall": 0, "from": 3, "to": 6, "bottom": 0.6, "top": 2.2, "window": True}])

room("gym", rect(8, 10), [obj(f"treadmill-{k}", [0.9, 2.0, 1.4], "edge", [] if k == 0 else [("near", f"treadmill-{k-1}"), ("face same as", f"treadmill-{k-1}")]) for k in range(4)] + [
    obj("bench-0", [0.6, 1.4, 0.5], "middle", [("far", "treadmill-0")]),
    obj("bench-1", [0.6, 1.4, 0.5], "middle", [("near", "bench-0"), ("face same as", "bench-0")]),
    obj("rack-0", [1.8, 0.6, 1.6], "edge", [("near", "bench-0")]),
    obj("rack-1", [1.8, 0.6, 1.6], "edge", [("near", "rack-0")]),
] + [obj(f"bike-{k}", [0.6, 1.2, 1.2], "edge", [] if k == 0 else [("near", f"bike-{k-1}")]) for k in range(3)],
   keep_out=[door(0, 0, 1, 1)], wall_objects=[{"id": "mirror-0", "size": [2.0, 0.03, 1.5], "height": 0.4}])

room("music_room", rect(5, 6), [
    obj("grand_piano-0", [1.5, 2.0, 1.0], "middle"),
    obj("piano_bench-0", [0.8, 0.4, 0.5], "middle", [("in front of", "grand_piano-0"), ("near", "grand_piano-0"), ("face to", "grand_piano-0")]),
    obj("drum_kit-0", [1.6, 1.4, 1.2], "edge", [("far", "grand_piano-0")]),
    obj("guitar_stand-0", [0.4, 0.4, 1.0], "edge", [("near", "drum_kit-0")]),
    obj("guitar_stand-1", [0.4, 0.4, 1.0], "edge", [("near", "guitar_stand-0")]),
    obj("amplifier-0", [0.5, 0.3, 0.5], "edge", [("near", "guitar_stand-0")]),
    obj("sofa-0", [1.8, 0.85, 0.85], "edge", [("far", "drum_kit-0")]),
    obj("bookshelf-0", [1.0, 0.35, 1.8], "edge"),
], keep_out=[door(0, 2, 1, 3)])

room("arcade", rect(8, 8), [obj(f"arcade_machine-{k}", [0.8, 0.9, 1.8], "edge", [] if k == 0 else [("near", f"arcade_machine-{k-1}"), ("face same as", f"arcade_machine-{k-1}")]) for k in range(10)] + [
    obj("pool_table-0", [2.5, 1.4, 0.8], "middle"),
    obj("air_hockey-0", [2.0, 1.1, 0.8], "middle", [("far", "pool_table-0")]),
    obj("sofa-0", [2.0, 0.85, 0.85], "edge", [("far", "arcade_machine-0")]),
], keep_out=[door(3.5, 0, 4.5, 1)])

room("daycare", rect(6, 7), [obj("play_table-0", [1.2, 0.8, 0.5], "middle")] + chairs(4, "play_table-0", "kid_chair", (0.35, 0.35, 0.55)) + [
    obj("play_table-1", [1.2, 0.8, 0.5], "middle", [("far", "play_table-0")])] + [obj(f"kid_chair-1{k}", [0.35, 0.35, 0.55], "middle", [("around", "play_table-1")]) for k in range(4)] + [
    obj(f"toy_shelf-{k}", [1.0, 0.4, 1.0]) for k in range(3)] + [obj("play_mat-0", [2.0, 1.5, 0.02], "middle")],
   keep_out=[door(0, 0, 1, 1)])

room("reading_room", rect(5, 6), [obj(f"bookshelf-{k}", [1.0, 0.35, 2.0], "edge", [] if k == 0 else [("near", f"bookshelf-{k-1}"), ("face same as", f"bookshelf-{k-1}")]) for k in range(6)] + [
    obj("reading_table-0", [1.6, 0.9, 0.75], "middle")] + chairs(4, "reading_table-0") + [
    obj(f"armchair-{k}", [0.8, 0.8, 0.9], "edge", [("far", "reading_table-0")]) for k in range(3)],
   keep_out=[door(2, 0, 3, 1)], ceiling={"id": "ceiling-light", "size": [0.5, 0.5, 0.3]})

room("bakery", rect(5, 6), [
    obj("display_counter-0", [1.8, 0.7, 1.1], "middle"),
    obj("display_counter-1", [1.8, 0.7, 1.1], "middle", [("near", "display_counter-0"), ("center aligned", "display_counter-0"), ("face same as", "display_counter-0")]),
    obj("display_counter-2", [1.8, 0.7, 1.1], "edge", [("far", "display_counter-0")]),
    obj("oven-0", [0.9, 0.8, 1.6], "edge"),
    obj("oven-1", [0.9, 0.8, 1.6], "edge", [("near", "oven-0"), ("face same as", "oven-0")]),
    obj("work_table-0", [1.6, 0.8, 0.9], "middle", [("near", "oven-0")]),
    obj("shelf-0", [1.2, 0.4, 1.8], "edge"),
    obj("shelf-1", [1.2, 0.4, 1.8], "edge", [("near", "shelf-0")]),
], keep_out=[door(2, 0, 3, 1)], small=[{"id": f"bread-{k}", "size": [0.3, 0.15, 0.1], "on": "display_counter-0"} for k in range(6)])

room("museum_gallery", rect(8, 12), [obj(f"pedestal-{k}", [0.6, 0.6, 1.1], "middle", [] if k == 0 else [("far", f"pedestal-{k-1}")]) for k in range(8)] + [
    obj("bench-0", [1.6, 0.5, 0.45], "middle"), obj("bench-1", [1.6, 0.5, 0.45], "middle", [("far", "bench-0"), ("center aligned", "bench-0")])],
   keep_out=[door(3.5, 0, 4.5, 1)],
   wall_objects=[{"id": f"painting-{k}", "size": [1.2, 0.05, 0.9], "height": 1.3} for k in range(6)],
   small=[{"id": f"sculpture-{k}", "size": [0.3, 0.3, 0.5], "on": f"pedestal-{k}"} for k in range(8)])

L = [[0, 0], [0, 6], [3, 6], [3, 3], [6, 3], [6, 0]]
room("l_shaped_living", L, [
    obj("sofa-0", [2.0, 0.9, 0.85]),
    obj("coffee_table-0", [1.0, 0.6, 0.45], "middle", [("in front of", "sofa-0"), ("near", "sofa-0"), ("center aligned", "sofa-0")]),
    obj("tv_stand-0", [1.4, 0.45, 0.6], "edge", [("in front of", "sofa-0"), ("face to", "sofa-0")]),
    obj("dining_table-0", [1.4, 0.8, 0.75], "middle", [("far", "sofa-0")]),
] + chairs(4, "dining_table-0") + [obj("bookshelf-0", [1.0, 0.35, 1.9])], keep_out=[door(5, 0, 6, 1)],
   ceiling={"id": "ceiling-light", "size": [0.5, 0.5, 0.25]})

L2 = [[0, 0], [0, 8], [8, 8], [8, 5], [4, 5], [4, 0]]
room("l_shaped_office", L2, [obj(f"desk-{k}", [1.4, 0.7, 0.75], "edge", [] if k == 0 else [("near", f"desk-{k-1}")]) for k in range(5)] + [
    obj(f"chair-{k}", [0.55, 0.55, 1.0], "middle", [("in front of", f"desk-{k}"), ("face to", f"desk-{k}"), ("near", f"desk-{k}")]) for k in range(5)] + [
    obj("cabinet-0", [0.8, 0.45, 1.2])], keep_out=[door(0, 0, 1, 1), door(7, 7, 8, 8)])

room("crowded_room", rect(3, 3), [
    obj("bed-0", [1.4, 2.0, 0.6]),
    obj("desk-0", [1.2, 0.6, 0.75], "edge"),
    obj("chair-0", [0.5, 0.5, 0.9], "middle", [("in front of", "desk-0"), ("face to", "desk-0")]),
    obj("wardrobe-0", [1.0, 0.6, 2.0]),
    obj("dresser-0", [1.0, 0.5, 0.9]),
    obj("bookshelf-0", [0.8, 0.3, 1.8]),
    obj("armchair-0", [0.8, 0.8, 0.9]),
    obj("plant-0", [0.4, 0.4, 1.0]),
], keep_out=[door(0, 0, 1, 1)])

# A crowded bedroom whose objects all want a wall (the case where a hard `edge` left 4 of 14
# out): the figure for "every feasible object placed".
room("crowded_bedroom_14", rect(4, 4.5), [
    obj("bed-0", [1.6, 2.0, 0.6]),
    obj("nightstand-0", [0.45, 0.4, 0.55], "edge", [("left of", "bed-0"), ("near", "bed-0")]),
    obj("nightstand-1", [0.45, 0.4, 0.55], "edge", [("right of", "bed-0"), ("near", "bed-0")]),
    obj("wardrobe-0", [1.0, 0.6, 2.0], "edge", [("far", "bed-0")]),
    obj("dresser-0", [0.9, 0.45, 0.9], "edge"),
    obj("desk-0", [1.1, 0.55, 0.75], "edge"),
    obj("chair-0", [0.5, 0.5, 0.9], "middle", [("in front of", "desk-0"), ("face to", "desk-0")]),
    obj("bookshelf-0", [0.8, 0.3, 1.8], "edge"),
    obj("armchair-0", [0.75, 0.75, 0.9], "edge"),
    obj("floor_lamp-0", [0.35, 0.35, 1.6], "edge", [("near", "armchair-0")]),
    obj("plant-0", [0.4, 0.4, 1.0], "edge"),
    obj("laundry_hamper-0", [0.4, 0.35, 0.6], "edge"),
    obj("ottoman-0", [0.5, 0.5, 0.4], "middle", [("in front of", "armchair-0"), ("near", "armchair-0")]),
    obj("side_table-0", [0.45, 0.45, 0.55], "edge", [("near", "armchair-0")]),
], keep_out=[door(0, 0, 1, 1)], holes=[{"wall": 2, "from": 1.5, "to": 2.7, "bottom": 0.9, "top": 2.1, "window": True}])

room("infeasible", rect(2, 2), [
    obj("grand_piano-0", [1.5, 2.0, 1.0], "middle"),
    obj("stool-0", [0.4, 0.4, 0.5], "edge"),
    obj("bed-0", [1.6, 2.1, 0.6]),
    obj("plant-0", [0.3, 0.3, 0.8], "edge"),
], keep_out=[door(0.5, 0, 1.5, 0.8)])

room("windowed_bedroom", rect(4, 4), [
    obj("bed-0", [1.6, 2.0, 0.6]),
    obj("wardrobe-0", [1.2, 0.6, 2.1]),
    obj("desk-0", [1.2, 0.6, 0.75], "edge", [("far", "bed-0")]),
    obj("chair-0", [0.5, 0.5, 0.9], "middle", [("in front of", "desk-0"), ("near", "desk-0"), ("face to", "desk-0")]),
], keep_out=[door(3, 0, 4, 1)],
   holes=[{"wall": 1, "from": 0.5, "to": 3.5, "bottom": 0.8, "top": 2.2, "window": True},
          {"wall": 3, "from": 3.0, "to": 4.0, "bottom": 0.0, "top": 2.1, "window": False}],
   wall_objects=[{"id": "painting-0", "size": [0.8, 0.05, 0.6], "above": "bed-0", "height": 1.5}])

# Crowded rooms written as models write them: the anchors first, their members after (a
# restaurant's tables, then every chair), the case where tables were pulled flush against each
# other and chairs lost their table.
rest = [obj("counter-0", [2.4, 0.7, 1.1])]
for t in range(6):
    rest.append(obj(f"table-{t}", [0.9, 0.9, 0.75], "middle", [("far", "counter-0")] if t == 0 else [("near", f"table-{t-1}")]))
for t in range(6):
    rest += [obj(f"chair-{t}{c}", [0.45, 0.45, 0.9], "middle", [("around", f"table-{t}")]) for c in range(4)]
rest += [obj(f"plant-{k}", [0.45, 0.45, 1.3]) for k in range(2)]
room("restaurant_tables_first", rect(8, 9), rest, keep_out=[door(3.5, 0, 4.5, 1)],
     holes=[{"wall": 1, "from": 2, "to": 6, "bottom": 0.6, "top": 2.2, "window": True}])

# A restaurant as a model writes one: six tables, each `near` the one before (a chain), each
# with four chairs near it, around it and facing it, and a bar counter. The chain pulls the
# tables close: the case where two tables' chairs ended back to back with no way between them
# and a chair lost its seat.
rest = [obj("bar-0", [3.0, 0.7, 1.1])]
for t in range(6):
    rest.append(obj(f"table-{t}", [0.9, 0.9, 0.75], "middle", [] if t == 0 else [("near", f"table-{t-1}")]))
    rest += [obj(f"chair-{t}{c}", [0.45, 0.5, 0.9], "middle", [("near", f"table-{t}"), ("around", f"table-{t}"), ("face to", f"table-{t}")]) for c in range(4)]
room("restaurant_chain", rect(9, 8), rest, keep_out=[door(2.8, 7.0, 4.7, 8.0)])

# A classroom of 5 rows of 2 desks, the desks listed first and each chair after them: the case
# where desks were stacked into one column and no chair stood at its desk.
cls = [obj("teacher_desk-0", [1.4, 0.7, 0.75], "edge"),
       obj("teacher_chair-0", [0.55, 0.55, 1.0], "middle", [("in front of", "teacher_desk-0"), ("near", "teacher_desk-0"), ("face to", "teacher_desk-0")])]
for k in range(10):
    rel = [("far", "teacher_desk-0"), ("face to", "teacher_desk-0")] if k == 0 else [("near", f"desk-{k-1}"), ("face same as", f"desk-{k-1}")]
    cls.append(obj(f"desk-{k}", [1.0, 0.5, 0.75], "middle", rel))
for k in range(10):
    cls.append(obj(f"chair-{k}", [0.45, 0.45, 0.85], "middle", [("in front of", f"desk-{k}"), ("near", f"desk-{k}"), ("face to", f"desk-{k}")]))
cls.append(obj("bookshelf-0", [1.0, 0.35, 1.8]))
room("classroom_rows", rect(7, 8), cls, keep_out=[door(0, 0, 1, 1)],
     holes=[{"wall": 0, "from": 2, "to": 6, "bottom": 0.8, "top": 2.2, "window": True}])

# A bedroom whose furniture covers 60% of its floor.
room("packed_bedroom_60", rect(3.5, 4), [
    obj("bed-0", [1.6, 2.0, 0.6]),
    obj("nightstand-0", [0.45, 0.4, 0.55], "edge", [("left of", "bed-0"), ("near", "bed-0")]),
    obj("nightstand-1", [0.45, 0.4, 0.55], "edge", [("right of", "bed-0"), ("near", "bed-0")]),
    obj("wardrobe-0", [1.2, 0.6, 2.0], "edge", [("far", "bed-0")]),
    obj("dresser-0", [1.0, 0.5, 0.9], "edge"),
    obj("desk-0", [1.1, 0.55, 0.75], "edge"),
    obj("chair-0", [0.45, 0.45, 0.9], "middle", [("in front of", "desk-0"), ("near", "desk-0"), ("face to", "desk-0")]),
    obj("bookshelf-0", [0.8, 0.3, 1.8], "edge"),
    obj("armchair-0", [0.75, 0.75, 0.9], "edge"),
    obj("side_table-0", [0.4, 0.4, 0.55], "edge", [("near", "armchair-0")]),
    obj("floor_lamp-0", [0.35, 0.35, 1.6], "edge", [("near", "armchair-0")]),
    obj("chest-0", [0.9, 0.45, 0.5], "edge"),
    obj("plant-0", [0.4, 0.4, 1.0], "edge"),
    obj("laundry_hamper-0", [0.4, 0.35, 0.6], "edge"),
], keep_out=[door(0, 0, 1, 1)], holes=[{"wall": 2, "from": 1.2, "to": 2.4, "bottom": 0.9, "top": 2.1, "window": True}])


def generated(n, seed):
    """A room of `n` floor objects made by a fixed-seed generator: groups as scenes have them
    (a table with its chairs, a desk with its chair, a sofa with its coffee table, shelves along
    the walls), about 2.2 square metres of floor per object."""
    import random
    rng = random.Random(seed)
    objects = []
    def add(o):
        if len(objects) < n:
            objects.append(o)
    g = 0
    while len(objects) < n:
        kind = rng.choice(["dining", "desk", "lounge", "storage", "storage"])
        if kind == "dining":
            add(obj(f"table-{g}", [1.2, 0.8, 0.75], "middle"))
            for c in range(4):
                add(obj(f"chair-{g}-{c}", [0.45, 0.45, 0.9], "middle", [("around", f"table-{g}")]))
        elif kind == "desk":
            add(obj(f"desk-{g}", [1.2, 0.6, 0.75], "edge"))
            add(obj(f"desk_chair-{g}", [0.5, 0.5, 0.9], "middle", [("in front of", f"desk-{g}"), ("near", f"desk-{g}"), ("face to", f"desk-{g}")]))
        elif kind == "lounge":
            add(obj(f"sofa-{g}", [2.0, 0.9, 0.85], "edge"))
            add(obj(f"coffee_table-{g}", [1.0, 0.6, 0.45], "middle", [("in front of", f"sofa-{g}"), ("near", f"sofa-{g}"), ("face to", f"sofa-{g}")]))
            add(obj(f"side_table-{g}", [0.45, 0.45, 0.55], "edge", [("side of", f"sofa-{g}"), ("near", f"sofa-{g}")]))
        else:
            add(obj(f"shelf-{g}", [round(rng.uniform(0.6, 1.2), 2), 0.4, 1.8], "edge"))
            add(obj(f"plant-{g}", [0.4, 0.4, 1.0], "edge", [("near", f"shelf-{g}")]))
        g += 1
    area = 2.2 * n
    w = round((area * 1.25) ** 0.5, 1)
    d = round(area / w, 1)
    room(f"generated_{n}", rect(w, d), objects, keep_out=[door(0, 0, 1, 1), door(w - 1, d - 1, w, d)])


for n in (10, 20, 40, 80):
    generated(n, 26)


def write(folder, written):
    os.makedirs(folder, exist_ok=True)
    for name, r in written.items():
        with open(os.path.join(folder, name + ".json"), "w") as f:
            json.dump(r, f, indent=1)
            f.write("\n")
    print(len(written), "rooms in", os.path.relpath(folder))


write(OUT, rooms)

# The generator's rooms of 10 to 100 objects, each size once (seed 26): what layout_bench fits
# the growth of the solve's cost over (`--table`), beside the corpus. Not read by the tests.
corpus = rooms
rooms = {}
for n in range(10, 101, 10):
    generated(n, 26)
write(os.path.join(os.path.dirname(OUT), "solve-generated"), rooms)
rooms = corpus
