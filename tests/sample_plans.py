"""Plans shared by several test modules."""

import math

#: Eight tall shelves, each bound to a wall, in a 3 x 2.4 m room: more wall than there is.
SHELVES = {
    "name": "shelves",
    "room": {"polygon": [[0, 0], [3, 0], [3, 2.4], [0, 2.4]],
             "doors": [{"wall": 0, "offset": 0.6, "width": 0.8}],
             "windows": [{"wall": 2, "offset": 1.5, "width": 1.0}]},
    "objects": [{"id": f"shelf_{k}", "category": "bookshelf", "size": [1.2, 0.35, 2.0]}
                for k in range(8)],
    "rules": [{"rule": "at_wall", "object": f"shelf_{k}"} for k in range(8)],
}

#: A 1.6 x 0.9 m table in the middle of a 5 x 4 m room and four chairs around it.
TABLE_FOR_FOUR = {
    "name": "table", "room": {"polygon": [[0, 0], [5, 0], [5, 4], [0, 4]], "height": 2.7,
                              "doors": [{"wall": 0, "offset": 0.8, "width": 0.9}]},
    "objects": [{"id": "table", "category": "table", "size": [1.6, 0.9, 0.75]}]
    + [{"id": f"chair_{k}", "category": "chair", "size": [0.45, 0.45, 0.9]} for k in range(4)],
    "rules": [{"rule": "in_middle", "object": "table"}]
    + [{"rule": "around", "object": f"chair_{k}", "target": "table"} for k in range(4)],
}


#: A bed at a wall with a nightstand bound to it by `next_to` only (no wall rule of its own).
BED_AND_NIGHTSTAND = {
    "name": "bed and nightstand",
    "room": {"polygon": [[0, 0], [3.6, 0], [3.6, 3.4], [0, 3.4]], "height": 2.6,
             "doors": [{"wall": 0, "offset": 0.6, "width": 0.85}],
             "windows": [{"wall": 2, "offset": 1.8, "width": 1.2}]},
    "objects": [
        {"id": "bed", "category": "bed", "size": [1.6, 2.0, 0.5], "primary": True},
        {"id": "nightstand", "category": "nightstand", "size": [0.45, 0.4, 0.55]},
        {"id": "wardrobe", "category": "wardrobe", "size": [1.2, 0.6, 2.0], "primary": True},
    ],
    "rules": [
        {"rule": "at_wall", "object": "bed"},
        {"rule": "next_to", "object": "nightstand", "target": "bed"},
        {"rule": "at_wall", "object": "wardrobe"},
    ],
}


def backs_offset(bed: tuple[float, float, float], other: tuple[float, float, float],
                 bed_depth: float, other_depth: float) -> float:
    """How far (metres) ``other``'s back stands in front of the bed's back, along the bed;
    poses are ``(x, y, yaw)``."""
    front = (-math.sin(bed[2]), math.cos(bed[2]))
    along = (other[0] - bed[0]) * front[0] + (other[1] - bed[1]) * front[1]
    return (along - 0.5 * other_depth) - (-0.5 * bed_depth)

#: A lobby: a reception desk near the door, its chair in front of it against the wall,
#: five chairs in a row along a wall, a coffee table and two plants; 21 rules.
RECEPTION = {
    "name": "reception",
    "room": {"polygon": [[0, 0], [6.0, 0], [6.0, 5.0], [0, 5.0]], "height": 2.8,
             "doors": [{"wall": 0, "offset": 1.0, "width": 1.0},
                       {"wall": 2, "offset": 1.0, "width": 0.9}]},
    "objects": [
        {"id": "desk", "category": "reception_desk", "size": [1.8, 0.7, 1.05]},
        {"id": "desk_chair", "category": "office_chair", "size": [0.6, 0.6, 1.0]},
        *({"id": f"chair_{k}", "category": "chair", "size": [0.55, 0.55, 0.85]}
          for k in range(5)),
        {"id": "table", "category": "coffee_table", "size": [1.0, 0.5, 0.42]},
        {"id": "plant_1", "category": "plant", "size": [0.5, 0.5, 1.4]},
        {"id": "plant_2", "category": "plant", "size": [0.5, 0.5, 1.4]}],
    "rules": [
        {"rule": "at_wall", "object": "desk_chair"},
        {"rule": "in_front_of", "object": "desk_chair", "target": "desk",
         "params": {"distance": 0.6}},
        {"rule": "facing", "object": "desk_chair", "target": "desk"},
        {"rule": "near_door", "object": "desk", "params": {"door": 0, "distance": 2.8}},
        *({"rule": "at_wall", "object": f"chair_{k}"} for k in range(5)),
        *({"rule": "next_to", "object": f"chair_{k + 1}", "target": f"chair_{k}",
           "params": {"distance": 0.08}} for k in range(4)),
        *({"rule": "face_same_as", "object": f"chair_{k + 1}", "target": f"chair_{k}"}
          for k in range(4)),
        {"rule": "in_front_of", "object": "table", "target": "chair_2",
         "params": {"distance": 0.7}},
        {"rule": "in_corner", "object": "plant_1"},
        {"rule": "in_corner", "object": "plant_2"},
        {"rule": "far_from", "object": "plant_2", "target": "plant_1",
         "params": {"distance": 2.0}}]}
