"""What a request may ask for: the bounds the planner enforces and the registry shows."""

POLYGON_SIDES = {'square': 4, 'triangle': 3, 'hexagon': 6}
MAX_SIDES = 360
MAX_FREQUENCY = 20.0  # cycles per metre: beyond this the wave is finer than the sampling
MAX_POINTS = 10_000
MIN_SIZE = 0.001  # m (or turns, cycles/m): anything smaller is noise, not a request
MAX_TIPS = 100  # star points
MAX_STROKES = 500  # of a drawing: ordering them takes under half a second at this count
MAX_PETALS = 100
MAX_FREQUENCY_RATIO = 50  # Lissajous a and b
MAX_TEXT_CHARS = 4_096  # a text, an SVG file name or path, a parameter value as text
