"""Pure geometry: angles, paths made of curves and in-place turns, and the shapes."""
