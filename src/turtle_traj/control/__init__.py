"""Pure control: pose in, velocity command out."""
