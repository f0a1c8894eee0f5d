"""Text as strokes of a single-stroke Hershey font (the `Hershey-Fonts` package ships them).

Strokes come out in metres in the drawing frame: x along the line of text, y up, the origin
on the baseline where the first character begins. The height is the cap height (the baseline
to the top of a capital H).
"""

from __future__ import annotations

from functools import cache

import numpy as np
from HersheyFonts import HersheyFonts

from turtle_traj.core.geometry.shapes import ShapeError

FONT = 'futural'  # Futura light: plain single-stroke letters
MAX_CHARACTERS = 200


@cache
def _font() -> HersheyFonts:
    font = HersheyFonts()
    font.load_default_font(FONT)
    return font


def known_characters() -> str:
    return ''.join(sorted(set(_font().all_glyphs) - {'\x7f'}))


def unknown_characters(text: str) -> list[str]:
    known = set(known_characters())
    return sorted({character for character in text if character not in known})


def text_strokes(text: str, height: float) -> list[np.ndarray]:
    """The strokes writing `text` with capitals `height` metres tall; ShapeError for empty
    text, too long a text or characters the font lacks (all of them named)."""
    if not text.strip():
        raise ShapeError('the text is empty: give at least one visible character')
    if len(text) > MAX_CHARACTERS:
        raise ShapeError(f'the text has {len(text)} characters; at most {MAX_CHARACTERS}')
    unknown = unknown_characters(text)
    if unknown:
        raise ShapeError(f'the font {FONT} has no glyph for {", ".join(map(repr, unknown))}; '
                         'it writes printable ASCII (space to ~)')
    font = _font()
    cap, base = font.render_options['cap_line'], font.render_options['base_line']
    scale = height / (base - cap)
    return [np.array(stroke, dtype=float) * (scale, -scale) + (0.0, base * scale)
            for stroke in font.strokes_for_text(text) if len(stroke) > 1]
