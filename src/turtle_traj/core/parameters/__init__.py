"""The trajectory node's parameters: the table (names, ranges) and the settings."""
