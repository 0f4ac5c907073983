"""A labelled retrieval set for the example asset library (examples/09_asset_library.py).

Each entry is a plan object as a planner might write it — a category, a
description and a size in metres — in words that mostly differ from the
asset's own (synonyms, paraphrases), with the asset a person would pick from
the library. Where the category is a synonym ("couch", "bedside_table") the
category filter finds nothing and the embedder alone must find the asset;
where it is the library's ("bed", "chair") the embedder and the size choose
among that category's assets.

Used by tests/test_grounding.py and benchmarks/grounding.py.
"""

#: (category, description, size [w, d, h] in metres, expected asset id)
LABELLED_QUERIES: list[tuple[str, str, tuple[float, float, float], str]] = [
    ("couch", "a three-seat fabric settee", (2.0, 0.9, 0.85), "sofa_3seat"),
    ("couch", "couch", (2.2, 0.95, 0.8), "sofa_3seat"),
    ("sofa", "loveseat for two people", (1.4, 0.85, 0.8), "sofa_2seat"),
    ("bedside_table", "bedside table", (0.45, 0.4, 0.55), "nightstand_wood"),
    ("night_table", "night table next to the bed", (0.5, 0.4, 0.5), "nightstand_wood"),
    ("closet", "closet for clothes", (1.0, 0.6, 2.1), "wardrobe_2door"),
    ("armoire", "armoire", (1.2, 0.6, 2.0), "wardrobe_2door"),
    ("bureau", "bureau with drawers for clothes", (1.0, 0.5, 0.85), "dresser_4drawer"),
    ("writing_desk", "writing desk", (1.2, 0.6, 0.75), "desk_study"),
    ("chair", "computer chair with wheels", (0.6, 0.6, 1.1), "chair_office"),
    ("chair", "kitchen chair made of wood", (0.45, 0.45, 0.9), "chair_dining"),
    ("table", "circular kitchen table", (1.0, 1.0, 0.75), "table_round"),
    ("table", "big table for a family dinner", (2.0, 1.0, 0.75), "table_rect"),
    ("bookcase", "bookcase", (0.9, 0.3, 1.9), "bookshelf_tall"),
    ("houseplant", "houseplant", (0.4, 0.4, 0.9), "plant_potted"),
    ("lamp", "reading lamp for a bedside table", (0.25, 0.25, 0.45), "lamp_table"),
    ("standing_lamp", "standing lamp", (0.4, 0.4, 1.6), "lamp_floor"),
    ("fridge", "fridge", (0.6, 0.65, 1.8), "fridge_tall"),
    ("tv", "TV", (1.2, 0.08, 0.7), "tv_flat"),
    ("media_console", "media console", (1.6, 0.45, 0.5), "tv_stand_low"),
    ("buffet", "buffet cabinet for the dining room", (1.6, 0.45, 0.85), "sideboard_long"),
    ("carpet", "carpet", (2.0, 1.5, 0.01), "rug_woven"),
    ("wall_art", "wall art", (1.0, 0.04, 0.7), "painting_framed"),
    ("chandelier", "hanging ceiling lamp", (0.5, 0.5, 0.4), "light_pendant"),
    ("display", "computer screen", (0.6, 0.2, 0.45), "monitor_27"),
    ("dry_erase_board", "dry-erase board", (1.2, 0.03, 0.9), "whiteboard_wall"),
    ("vase", "vase for flowers", (0.2, 0.2, 0.35), "vase_ceramic"),
    ("file_cabinet", "cabinet for office paperwork", (0.45, 0.6, 0.7), "cabinet_filing"),
    ("bed", "twin bed", (1.0, 2.0, 0.5), "bed_single"),
    ("bed", "queen-size bed", (1.6, 2.0, 0.55), "bed_double"),
    ("end_table", "end table", (0.5, 0.5, 0.55), "side_table_round"),
    ("cocktail_table", "cocktail table in front of the couch", (1.2, 0.6, 0.4),
     "coffee_table_low"),
    ("easy_chair", "easy chair", (0.85, 0.85, 0.9), "armchair_club"),
    ("armchair", "wing chair for reading", (0.75, 0.75, 1.1), "armchair_wing"),
]
