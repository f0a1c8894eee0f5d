"""Plane geometry: poses, paths of curves and turns, shapes, text and SVG strokes."""
