"""Several turtles on one drawing: its pieces shared out (`sharing`). Pure Python."""
