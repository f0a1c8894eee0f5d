"""rosbag2 bags of runs: types, writer, reader, recorder, player and plots."""
