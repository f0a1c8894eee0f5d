"""Several turtles on one drawing: its strokes shared out (`sharing`). Pure Python."""
