"""The fleet coordinator: several turtles, each with its trajectory node, draw one request."""
