"""The controllers shipped beside the exact follower, each a `controller.Controller`."""
