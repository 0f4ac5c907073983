"""Plans shared by several test modules."""

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
