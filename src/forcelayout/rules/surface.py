"""Surface rules: objects placed off the floor (on a parent's top, on a wall, on the ceiling)."""
