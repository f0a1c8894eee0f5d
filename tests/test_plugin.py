"""The pytest plugin is registered for pytest (a user's test that uses it, in a folder outside
the repository, is the tutorial docs/tutorials/testing-your-node.md: tests/test_tutorials.py
runs it as written)."""


def test_the_plugin_is_registered_for_pytest():
    from importlib.metadata import entry_points

    (entry,) = [e for e in entry_points(group='pytest11') if e.name == 'turtle_traj']
    plugin = entry.load()
    assert {'ros_domain_id', 'rclpy_context', 'turtle_sim', 'turtle_system'} <= set(vars(plugin))
